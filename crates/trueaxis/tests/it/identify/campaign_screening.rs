//! Identification of the KX8-Five CapBall campaign (examples/campaigns/kx8five, 807 poses,
//! Andolfatto et al. 2011) with one damage each: the dz column in mm, a stuck sensor, every pose
//! recorded twice, 1 % gross outliers. With --exclude-outliers (`exclude = true`) the damaged
//! records give the clean values within their uncertainty.

use crate::support::damage::{example, example_path, Csv};
use trueaxis::error_model::ErrorModel;
use trueaxis::identify::campaign_screening::{identify_screened, ScreenedIdentification};
use trueaxis::identify::{Campaign, IdentifyError, IndirectOptions};
use trueaxis::machine::Machine;
use trueaxis::screen::Kind;

pub const DATA: &str = "examples/campaigns/kx8five/capball.csv";

/// The campaign with `capball` as its data file, written to a folder of its own, given to `fit`
/// with the machine and the nominal errors.
pub fn with_capball<R>(
    name: &str,
    capball: &str,
    fit: impl FnOnce(&Campaign, &Machine, &ErrorModel) -> Result<R, IdentifyError>,
) -> Result<R, String> {
    let dir = std::env::temp_dir().join(format!("trueaxis-screening-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("campaign.toml"), example("examples/campaigns/kx8five/campaign.toml")).unwrap();
    std::fs::write(dir.join("capball.csv"), capball).unwrap();
    let machine = Machine::load(example_path("examples/machines/kx8five.toml")).unwrap();
    let loaded = Campaign::load(dir.join("campaign.toml"), &machine).and_then(|c| c.nominal_errors(&machine).map(|n| (c, n)));
    let out = loaded.and_then(|(campaign, nominal)| fit(&campaign, &machine, &nominal)).map_err(|e| e.to_string());
    let _ = std::fs::remove_dir_all(&dir);
    out
}

/// The campaign with `capball` as its data file identified with screening.
fn identify(name: &str, capball: &str, exclude: bool) -> Result<ScreenedIdentification, String> {
    with_capball(name, capball, |c, m, n| identify_screened(c, m, n, &IndirectOptions::default(), exclude))
}

pub fn value(s: &ScreenedIdentification, name: &str) -> (f64, f64) {
    let j = s.result.names.iter().position(|n| n == name).unwrap();
    (s.result.values[j], s.result.std_uncertainty[j].unwrap())
}

#[test]
fn the_clean_campaign_gives_no_finding() {
    let clean = identify("clean", &example(DATA), false).unwrap();
    assert!(clean.findings.is_empty(), "{:?}", clean.findings);
    assert!(clean.other.is_none());
}

#[test]
fn a_column_in_mm_is_refused() {
    for column in ["dz", "dx"] {
        let text = Csv::parse(&example(DATA)).map(column, crate::support::damage::all, |v| v / 1000.0).text();
        let e = identify(&format!("mm-{column}"), &text, false).unwrap_err();
        assert!(e.contains(&format!("capball.csv: column {column}: unit:")) && e.contains("mm among um"), "{e}");
    }
}

#[test]
fn a_stuck_sensor_is_flagged_and_left_out_on_request() {
    let clean = identify("clean-stuck", &example(DATA), false).unwrap();
    for (start, len) in [(300usize, 79usize), (600, 12)] {
        let mut csv = Csv::parse(&example(DATA));
        let v = csv.value(start, "dz");
        for i in start..start + len {
            csv.set(i, "dz", v);
        }
        let lines = (csv.line(start), csv.line(start + len - 1));
        let s = identify(&format!("stuck-{len}"), &csv.text(), true).unwrap();
        let f = s.findings.iter().find(|f| f.kind == Kind::Stuck).unwrap_or_else(|| panic!("{:?}", s.findings));
        assert!(f.place.starts_with(&format!("column dz, lines {}-{}", lines.0, lines.1)), "{}", f.place);
        assert!(s.excluded_records >= len - 1);
        for p in ["TZ", "TX", "EB0Z"] {
            let ((a, u), (b, _)) = (value(&s, p), value(&clean, p));
            assert!((a - b).abs() < 2.0 * u, "{p}: {a} vs clean {b} (u {u})");
        }
    }
}

#[test]
fn repeated_poses_are_flagged() {
    let mut csv = Csv::parse(&example(DATA));
    let rows = csv.rows.clone();
    csv.rows = rows.iter().flat_map(|r| [r.clone(), r.clone()]).collect();
    let s = identify("twice", &csv.text(), false).unwrap();
    let f = s.findings.iter().find(|f| f.kind == Kind::Duplicate).unwrap_or_else(|| panic!("{:?}", s.findings));
    assert!(f.message.starts_with("807 of 1614 records repeat"), "{}", f.message);
    assert!(f.consequence.contains("1.41 times"), "{}", f.consequence);
}

#[test]
fn gross_outliers_are_listed_and_excluded_on_request() {
    let clean = identify("clean-outliers", &example(DATA), false).unwrap();
    for (every, size) in [(100usize, 40.0), (37, 10.0)] {
        let csv = Csv::parse(&example(DATA)).map("dy", |_, i| i % every == 7, |v| v + size);
        let damaged: Vec<u64> = (0..csv.rows.len()).filter(|i| i % every == 7).map(|i| csv.line(i)).collect();
        let flagged = identify(&format!("outliers-{every}"), &csv.text(), false).unwrap();
        let f = flagged.findings.iter().find(|f| f.kind == Kind::Outlier).unwrap_or_else(|| panic!("{:?}", flagged.findings));
        assert_eq!(f.lines, damaged, "{}", f.line());
        assert!(f.consequence.contains("times its uncertainty"), "{}", f.consequence);
        let excluded = identify(&format!("outliers-x-{every}"), &csv.text(), true).unwrap();
        assert_eq!(excluded.excluded_records, damaged.len());
        for (j, p) in clean.result.names.iter().enumerate() {
            let ((a, u), b) = (value(&excluded, p), clean.result.values[j]);
            assert!((a - b).abs() < 2.0 * u, "{p}: {a} vs clean {b} (u {u})");
        }
        // every reading kept beside it
        assert!(excluded.other.is_some());
    }
}
