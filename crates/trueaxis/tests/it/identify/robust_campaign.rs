//! Robust identification (`identify --robust huber|tukey`) of the KX8-Five CapBall campaign
//! (examples/campaigns/kx8five, 807 poses, 2,421 readings): with 1 % of the readings gross
//! (100 times their stated sigma, alternating signs) the robust values lie within their stated
//! uncertainty of the clean least-squares values while least squares does not; the damaged readings
//! are the ones listed as downweighted; on the clean campaign robust and least squares agree to
//! within the spread the 95 % efficiency of both weightings allows, and the robust uncertainty is
//! sqrt(1 / 0.95) of the least-squares one.

use super::campaign_screening::{value, with_capball, DATA};
use crate::support::damage::{example, Csv};
use trueaxis::identify::campaign_screening::{identify_screened, ScreenedIdentification};
use trueaxis::identify::robust_campaign::identify_robust;
use trueaxis::identify::IndirectOptions;
use trueaxis::screen::irls::Weighting;

const CHANNELS: [(&str, f64); 3] = [("dx", 0.28), ("dy", 0.28), ("dz", 0.40)];

fn robust(name: &str, capball: &str, weighting: Weighting) -> ScreenedIdentification {
    with_capball(name, capball, |c, m, n| identify_robust(c, m, n, &IndirectOptions::default(), weighting)).unwrap()
}

fn least_squares(name: &str, capball: &str) -> ScreenedIdentification {
    with_capball(name, capball, |c, m, n| identify_screened(c, m, n, &IndirectOptions::default(), false)).unwrap()
}

/// Reading c of record i is gross when (3 i + c) mod 100 = 37: 1 % of the readings, spread over
/// the trajectory and the three channels; +100 sigma and -100 sigma in turn. Returns the text and
/// the damaged (line, channel) pairs.
fn gross_outliers() -> (String, Vec<(u64, String)>) {
    let mut csv = Csv::parse(&example(DATA));
    let mut damaged = Vec::new();
    for i in 0..csv.rows.len() {
        for (c, (name, sigma)) in CHANNELS.iter().enumerate() {
            if (3 * i + c) % 100 == 37 {
                let sign = if damaged.len() % 2 == 0 { 1.0 } else { -1.0 };
                let v = csv.value(i, name) + sign * 100.0 * sigma;
                csv.set(i, name, v);
                damaged.push((csv.line(i), format!("capball:{name}")));
            }
        }
    }
    (csv.text(), damaged)
}

/// Largest |a - b| / u over the parameters, u the uncertainty of `a`.
fn largest_difference_in_u(a: &ScreenedIdentification, b: &ScreenedIdentification) -> (String, f64) {
    a.result
        .names
        .iter()
        .map(|p| {
            let ((va, ua), (vb, _)) = (value(a, p), value(b, p));
            (p.clone(), (va - vb).abs() / ua)
        })
        .max_by(|x, y| x.1.total_cmp(&y.1))
        .unwrap()
}

#[test]
fn robust_fits_give_the_clean_values_with_one_percent_gross_readings() {
    let clean = least_squares("robust-clean", &example(DATA));
    let (text, damaged) = gross_outliers();
    assert_eq!(damaged.len(), 24, "1 % of 2,421 readings");
    let ls = least_squares("robust-ls", &text);
    let (p, worst) = largest_difference_in_u(&ls, &clean);
    assert!(worst > 1.0, "least squares is off by {worst:.2} u at most ({p}): the damage is too small to show");
    for weighting in [Weighting::Huber, Weighting::Tukey] {
        let r = robust(&format!("robust-{}", weighting.name()), &text, weighting);
        let (p, worst) = largest_difference_in_u(&r, &clean);
        eprintln!(
            "{weighting:?}: largest change from the clean values {worst:.3} u ({p}); least squares {:.2} u",
            largest_difference_in_u(&ls, &clean).1
        );
        assert!(worst < 1.0, "{weighting:?}: {p} is {worst:.2} u from the clean value");
        let fit = r.robust.as_ref().unwrap();
        let listed: Vec<(u64, String)> = fit.downweighted.iter().map(|d| (d.line, d.channel.clone())).collect();
        assert_eq!(listed, damaged, "{weighting:?}");
        // the robust scale is that of the clean readings (s0 about 1), not the 10 of least squares
        assert!((0.8..1.2).contains(&fit.weights.scale), "{weighting:?}: s = {}", fit.weights.scale);
        assert!(ls.result.sigma0 > 5.0, "least squares s0 = {}", ls.result.sigma0);
        // the robust uncertainty is that of clean data: within 10 % of the clean least squares
        for p in &clean.result.names {
            let ((_, u), (_, u0)) = (value(&r, p), value(&clean, p));
            assert!((u / u0 - 1.0).abs() < 0.1, "{weighting:?} {p}: u {u} against clean {u0}");
        }
    }
}

#[test]
fn on_clean_data_robust_and_least_squares_agree() {
    let clean = least_squares("robust-agree-ls", &example(DATA));
    for weighting in [Weighting::Huber, Weighting::Tukey] {
        let r = robust(&format!("robust-agree-{}", weighting.name()), &example(DATA), weighting);
        let (p, worst) = largest_difference_in_u(&r, &clean);
        eprintln!("{weighting:?} on clean data: largest difference from least squares {worst:.3} u ({p})");
        assert!(worst < 0.5, "{weighting:?}: {p} differs by {worst:.2} u");
        assert!(r.robust.as_ref().unwrap().downweighted.is_empty());
        // both weightings are 95 % efficient: u = sqrt(1 / 0.95) = 1.026 of least squares
        for p in &clean.result.names {
            let ratio = value(&r, p).1 / value(&clean, p).1;
            assert!((ratio - 1.026).abs() < 0.05, "{weighting:?} {p}: u ratio {ratio}");
        }
    }
}
