//! The direct fit (`trueaxis fit`) of the ISO 230-2 test examples/data/iso230_2_x.csv screened
//! (`identify::direct_screening`): a beam-interruption reading named by run and target in the
//! residuals of the fit of both directions or of its own.

use crate::evaluate::positioning_screening::{number_after, FILE};
use crate::support::damage::{example, Csv};
use trueaxis::data::CsvTable;
use trueaxis::screen::Kind;

/// `trueaxis fit` of the test's readings (EXX, piecewise cubic with a knot every 100 mm, the
/// command's defaults otherwise) of one direction or both, with its screening.
pub fn direct_fit_of(text: &str, direction: Option<char>) -> trueaxis::identify::DirectFitReport {
    use trueaxis::error_model::BasisSpec;
    use trueaxis::identify::{run_direct_fit, DirectFitRequest, FitOptions};
    let table = CsvTable::from_text(text, "damaged.csv").unwrap();
    let spec = BasisSpec {
        family: "piecewise".into(),
        degree: 3,
        knots: vec![100.0, 200.0, 300.0, 400.0],
        continuity: vec![2],
        constant: true,
        constraint: "none".into(),
        domain: [0.0, 500.0],
        periodic: Vec::new(),
    };
    let request = DirectFitRequest {
        parameter: trueaxis::machine::ParameterId::parse("EXX").unwrap(),
        position_column: "target".into(),
        value_column: "dev".into(),
        direction,
        remove_drift: false,
        refine_wavelength: None,
        options: FitOptions { spec, stepwise_level: None, prediction_level: 0.95 },
        model: None,
        corrections: vec![],
    };
    run_direct_fit(&table, &request).unwrap()
}

/// One function fitted to both directions leaves the backlash (2 ... 2.8 um here) in its residuals:
/// the 50 um interruption is flagged there; 10 and -5 um ones in the fit of their direction
/// (`--direction`), whose residuals are the 0.25 um noise.
#[test]
fn the_direct_fit_names_a_beam_interruption_by_run_and_target() {
    for (row, size, both) in [(13usize, 50.0, true), (13, 50.0, false), (40, 10.0, false), (77, -5.0, false)] {
        let mut csv = Csv::parse(&example(FILE));
        let v = csv.value(row, "dev");
        csv.set(row, "dev", v + size);
        let cell = |name: &str| csv.rows[row][csv.col(name)].clone();
        let (line, run, target, dir) = (csv.line(row), cell("run"), cell("target"), cell("dir"));
        let direction = (!both).then(|| dir.chars().next().unwrap());
        let clean = direct_fit_of(&example(FILE), direction);
        assert!(clean.findings.is_empty(), "{:?}", clean.findings);
        let report = direct_fit_of(&csv.text(), direction);
        assert_eq!(report.findings.len(), 1, "{size} um: {:?}", report.findings);
        let f = &report.findings[0];
        assert_eq!((f.kind, f.lines.clone()), (Kind::Outlier, vec![line]), "{}", f.line());
        assert!(f.message.contains(&format!("line {line} (run {run}, target {target}, dir {dir})")), "{}", f.message);
        // the fit without it has the clean residual standard deviation (within 5 %)
        let without = number_after(&f.consequence, "would be");
        assert!((without / clean.fitted.fit.sigma - 1.0).abs() < 0.05, "{without} against clean {}", clean.fitted.fit.sigma);
    }
}
