//! The rotary-axis ballbar test of a five-axis machine in a calibration report: the location errors
//! of its two rotary axes (ISO 230-1 names: EY0A EZ0A EB0A EC0A of the outer axis, EX0C EY0C EA0C
//! EB0C of the inner one, um and urad) identified from the four steps A1, A2, C1, C2 of Jiang (2014)
//! by any of its methods (ch. 5 extended bar, ch. 4 two pivots, ch. 6 four setups after Lee and Yang)
//! by `trueaxis::identify::pige_report` (the code of `trueaxis ballbar identify`), each quoted with
//! one expanded uncertainty U = 2 u (k = 2). u is what `ballbar identify --out` writes in
//! `[uncertainty]`: the single-run standard uncertainty from the scatter of each trace about its
//! circle, or, over several runs, the larger of it and their standard deviation. The traces are
//! drawn before and after the identified errors are removed (simulated on the exact chain), and the
//! residual per step is stated.

use super::super::html::{Cell, Section};
use super::conformity::{DecisionRule, Item};
use super::quantity::{quantity, with_uncertainty};
use super::CalibrationError;
use crate::{polar_svg, PolarPlot, PolarSeries};
use std::collections::BTreeMap;
use trueaxis::identify::pige_report::{identify_pige_files, pige_user_value, PigeReport, PigeRequest};
use trueaxis::instruments::ballbar::{Method, RotaryGeometry};
use trueaxis::machine::{Component, Machine};

/// One error identified by a ballbar test: ISO name, value and U (k = 2) in its unit (um or urad).
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifiedError {
    pub name: String,
    pub value: f64,
    pub expanded: Option<f64>,
    pub unit: &'static str,
}

impl IdentifiedError {
    /// `value ± U unit`, rounded by U, as the report prints it.
    pub fn reported(&self) -> String {
        with_uncertainty(self.value, self.expanded, self.unit, 2)
    }

    /// Its entry in `report --json`: the numbers and the text the report prints.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({"value": self.value, "unit": self.unit, "expanded_uncertainty": self.expanded, "coverage_factor": 2,
                           "reported": self.reported()})
    }

    /// Its row of a results table: the name and `value ± U`.
    pub fn row(&self) -> Vec<Cell> {
        vec![Cell::from(self.name.clone()), Cell::from(self.reported())]
    }
}

/// The toleranced errors of `errors` (`[tolerances.parameters]`, by ISO name, um or urad), each
/// decided under `rule`; `test` names the test in the item, `section` links to it, `without_u`
/// says how a U not evaluated will be.
pub(super) fn identified_conformity(
    errors: Vec<IdentifiedError>,
    tolerances: &BTreeMap<String, f64>,
    rule: DecisionRule,
    (test, section, without_u): (&str, &str, &str),
) -> Vec<Item> {
    errors
        .into_iter()
        .filter_map(|e| {
            let tol = *tolerances.get(&e.name)?;
            let item = Item::new(format!("{test}: {}", e.name), section, e.value, e.expanded, tol, e.unit, rule);
            Some(match e.expanded {
                Some(_) => item,
                None => item.without_u(without_u),
            })
        })
        .collect()
}

/// A rotary-axis ballbar test and what it identified.
pub struct RotaryBallbarPart {
    pub request: PigeRequest,
    pub report: PigeReport,
    /// The polar plot of each step (SVG), in the order A1, A2, C1, C2.
    pub plots: Vec<String>,
}

impl RotaryBallbarPart {
    /// Identifies the location errors of `machine`'s rotary axes from the four files of `request`.
    pub fn evaluate(machine: &Machine, request: PigeRequest) -> Result<RotaryBallbarPart, CalibrationError> {
        let report = identify_pige_files(machine, &request).map_err(|e| match e.kind() {
            trueaxis::ErrorKind::Input => CalibrationError::Input(e.to_string()),
            _ => CalibrationError::Computation(e.to_string()),
        })?;
        let mut part = RotaryBallbarPart { request, report, plots: Vec::new() };
        part.plots = part.report.steps.iter().map(|s| part.plot(s)).collect::<Result<_, _>>()?;
        Ok(part)
    }

    /// The location errors of the last run, each with U = 2 u.
    pub fn errors(&self) -> Vec<IdentifiedError> {
        let r = &self.report;
        r.last()
            .values
            .iter()
            .zip(&r.stats.parameters)
            .enumerate()
            .map(|(k, ((id, v), (_, _, sd)))| {
                let (value, unit) = pige_user_value(id, *v);
                let single = r.single_u.as_ref().map(|s| pige_user_value(id, s[k]).0);
                let spread = r.repeated().then(|| pige_user_value(id, *sd).0);
                let u = single.into_iter().chain(spread).reduce(f64::max).filter(|u| u.is_finite() && *u > 0.0);
                IdentifiedError { name: id.to_string(), value, expanded: u.map(|u| 2.0 * u), unit }
            })
            .collect()
    }

    /// How U was obtained, in words.
    pub fn uncertainty_method(&self) -> &'static str {
        match (self.report.repeated(), self.report.single_u.is_some()) {
            (true, _) => "2 x the larger of the single-run standard uncertainty and the standard deviation of the runs",
            (false, true) => "2 x the single-run standard uncertainty (scatter of each trace about its circle)",
            (false, false) => "not evaluated: the traces have too few readings; repeat the test (several runs) to state U",
        }
    }

    /// The method with its chapter of Jiang (2014) and its setup: bar lengths, pivot offset or the
    /// positions along the axes (mm).
    pub fn method_text(&self) -> String {
        let b = &self.request.bars;
        let bars = format!("normal bar R = {} mm and extended bar L_e = {} mm", b.normal, b.extended);
        match self.request.method {
            Method::ExtendedBar => format!("the extended-bar method of Jiang (2014) ch. 5 ({bars})"),
            Method::TwoPivot { outer_offset } => {
                format!("the two-pivot method of Jiang (2014) ch. 4 ({bars}; the outer-axis pivot {outer_offset} mm along the outer axis)")
            }
            Method::FourSetup { outer, inner } => format!(
                "the four-setup method of Lee and Yang as in Jiang (2014) ch. 6 (normal bar R = {} mm only; the outer axis at {} and {} mm along it, the inner at {} and {} mm)",
                b.normal, outer[0], outer[1], inner[0], inner[1]
            ),
        }
    }

    /// Toleranced location errors by ISO name (`[tolerances.parameters]`, um or urad).
    pub fn conformity(&self, tolerances: &BTreeMap<String, f64>, rule: DecisionRule) -> Vec<Item> {
        let how = "repeat the ballbar test (several runs in the files) to state U";
        identified_conformity(self.errors(), tolerances, rule, ("rotary axes (ballbar)", "rotary-ballbar", how))
    }

    fn plot(&self, s: &trueaxis::identify::pige_report::StepResidual) -> Result<String, CalibrationError> {
        let raw: Vec<f64> = s.dl.iter().map(|v| v * 1e3).collect();
        let left: Vec<f64> = s.residual.iter().map(|v| v * 1e3).collect();
        let (u1, u2) = plane_labels(&s.geometry);
        let lines = [format!("after removing the identified errors: RMS {}, band {}", um(s.rms_um), um(s.band_um))];
        let title = format!("Step {} of Jiang (2014): {}", s.step.name(), file_name(&s.path));
        before_and_after(&title, (&u1, &u2), &s.angles, &raw, ("identified errors removed", &left), &lines)
    }

    pub fn section(&self) -> Section {
        let r = &self.report;
        let rows: Vec<Vec<Cell>> = self.errors().iter().map(IdentifiedError::row).collect();
        let steps: Vec<Vec<String>> =
            r.steps.iter().map(|s| vec![s.step.name().to_string(), file_name(&s.path), um(s.rms_um), um(s.band_um)]).collect();
        let mut s = Section::new("rotary-ballbar", "Rotary axes: ballbar test (location errors)")
            .paragraph(format!(
                "The location errors of {}'s two rotary axes from the four ballbar steps A1, A2 (outer axis) and C1, C2 (inner axis) of {}, {} run(s): circle fits of each trace, the axis lines and the start-angle correction, as `trueaxis ballbar identify --method {}` computes them. U (k = 2): {}.",
                r.machine,
                self.method_text(),
                r.runs.len(),
                r.method.name(),
                self.uncertainty_method()
            ))
            .cells("Location errors of the rotary axes (ISO 230-1 names)", &["error", "value ± U (k = 2)"], rows)
            .table(
                "What is left of each step once the identified errors are removed (simulated on the exact chain)",
                &["step", "file", "RMS", "band"],
                steps,
            );
        for w in &r.warnings {
            s = s.note(w.clone());
        }
        for (plot, step) in self.plots.iter().zip(&r.steps) {
            s = s.figure(
                format!("Step {}: the bar readings as measured and with the identified errors removed.", step.step.name()),
                plot.clone(),
            );
        }
        s
    }
}

pub(super) fn um(v: f64) -> String {
    quantity(v, 2, "um")
}

pub(super) fn file_name(path: &std::path::Path) -> String {
    path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned())
}

/// The signed machine axes closest to the two in-plane directions of a step: `("+X", "+Y")`.
fn plane_labels(g: &RotaryGeometry) -> (String, String) {
    let name = |v: &trueaxis::geometry::Vec3| {
        let k = (0..3).max_by(|&i, &j| v[i].abs().total_cmp(&v[j].abs())).unwrap_or(0);
        format!("{}{}", if v[k] < 0.0 { '-' } else { '+' }, Component::from_index(k).letter())
    };
    (name(&g.u1), name(&g.u2))
}

/// The polar plot of a ballbar trace as measured and with what was identified removed (`removed`:
/// its label and trace, um, at the same `angles`), the RMS and band left in `lines`.
pub(super) fn before_and_after(
    title: &str,
    axes: (&str, &str),
    angles: &[f64],
    measured: &[f64],
    removed: (&str, &[f64]),
    lines: &[String],
) -> Result<String, CalibrationError> {
    Ok(polar_svg(&PolarPlot {
        title,
        axes,
        series: vec![
            PolarSeries { label: "measured".into(), angles, dl_um: measured },
            PolarSeries { label: removed.0.into(), angles, dl_um: removed.1 },
        ],
        um_per_division: None,
        lines,
        conditions: &[],
    })?)
}
