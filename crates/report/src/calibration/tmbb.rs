//! The two-length rotary-table test of Zhu (2008) in a calibration report: the tilts `E_x`, `E_y` of
//! the table (ISO 230-1 `EAC`, `EBC`, urad) and its axial error `D_z` (`EZC`, um), identified by
//! `trueaxis::identify::tmbb_report` (the code of `trueaxis ballbar tmbb`) from a short and a long
//! bar. Each is quoted as the least-squares (l2) estimate with one expanded uncertainty U = 2 u
//! (k = 2), u from the residual scatter of the differenced squared lengths (GUM annex H.3); the
//! minimax (l-infinity) estimate is shown beside it, rounded to the place of U. The readings of each
//! bar are drawn as measured and with the identified errors and the centring removed, with what is
//! left (um).

use super::super::html::{Cell, Section};
use super::conformity::{DecisionRule, Item};
use super::quantity::{decimals_for, fixed};
use super::rotary_ballbar::{before_and_after, file_name, identified_conformity, um, IdentifiedError};
use super::CalibrationError;
use std::collections::BTreeMap;
use std::path::Path;
use trueaxis::identify::tmbb::{TmbbEstimate, TmbbSetup, UNIDENTIFIABLE};
use trueaxis::identify::tmbb_report::{tmbb_files, TmbbBar, TmbbReport};
use trueaxis::identify::IdentifyError;

/// A two-length rotary-table test and what it identified.
pub struct TmbbPart {
    pub report: TmbbReport,
    /// The polar plot of each bar (SVG): short, long.
    pub plots: Vec<String>,
}

/// `E_x`, `E_y`, `D_z` of an estimate in the report's units: (ISO name, value, unit).
fn user_values(f: &TmbbEstimate) -> [(&'static str, f64, &'static str); 3] {
    [("EAC", f.ex * 1e6, "urad"), ("EBC", f.ey * 1e6, "urad"), ("EZC", f.dz * 1e3, "um")]
}

impl TmbbPart {
    /// Evaluates the test of the short- and long-bar files with `setup`.
    pub fn evaluate(setup: &TmbbSetup, short: &Path, long: &Path) -> Result<TmbbPart, CalibrationError> {
        let report = tmbb_files(setup, short, long).map_err(|e| match e {
            IdentifyError::RankDeficient { .. } => CalibrationError::Computation(e.to_string()),
            _ => CalibrationError::Input(e.to_string()),
        })?;
        let mut part = TmbbPart { report, plots: Vec::new() };
        part.plots = part.report.bars.iter().map(|b| part.plot(b)).collect::<Result<_, _>>()?;
        Ok(part)
    }

    /// The l2 estimates, each with U = 2 u.
    pub fn errors(&self) -> Vec<IdentifiedError> {
        let u = self.report.std_uncertainty;
        let u = [u[0] * 1e6, u[1] * 1e6, u[2] * 1e3];
        user_values(&self.report.l2)
            .iter()
            .zip(u)
            .map(|(&(name, value, unit), u)| IdentifiedError {
                name: name.into(),
                value,
                expanded: (u.is_finite() && u > 0.0).then_some(2.0 * u),
                unit,
            })
            .collect()
    }

    /// Toleranced errors by ISO name (`[tolerances.parameters]`: EAC, EBC in urad, EZC in um).
    pub fn conformity(&self, tolerances: &BTreeMap<String, f64>, rule: DecisionRule) -> Vec<Item> {
        let how = "the readings fit the model exactly (no residual scatter); repeat the test or state U";
        identified_conformity(self.errors(), tolerances, rule, ("rotary table (two-length ballbar)", "tmbb", how))
    }

    fn plot(&self, bar: &TmbbBar) -> Result<String, CalibrationError> {
        let lines = [format!("without the identified errors and the centring: RMS {}, band {}", um(bar.rms_um), um(bar.band_um))];
        let title = format!("Two-length test of Zhu (2008), {} mm bar: {}", bar.length_mm, file_name(&bar.path));
        let removed = ("identified errors and centring removed", &bar.left_um[..]);
        before_and_after(&title, ("+X", "+Y"), &self.report.angles, &bar.trace.dl_um, removed, &lines)
    }

    pub fn section(&self) -> Section {
        let r = &self.report;
        let s = &r.setup;
        let (h1, h2) = s.heights().unwrap_or((f64::NAN, f64::NAN));
        let what = ["tilt of the table about X (E_x)", "tilt of the table about Y (E_y)", "axial error of the table (D_z)"];
        let rows: Vec<Vec<Cell>> = self
            .errors()
            .iter()
            .zip(user_values(&r.linf))
            .zip(what)
            .map(|((e, (_, minimax, unit)), what)| {
                let places = e.expanded.and_then(decimals_for).unwrap_or(2);
                let mut row = e.row();
                row.insert(1, Cell::from(what));
                row.push(Cell::from(format!("{} {unit}", fixed(minimax, places))));
                row
            })
            .collect();
        let bars: Vec<Vec<String>> =
            r.bars.iter().map(|b| vec![format!("{} mm", b.length_mm), file_name(&b.path), um(b.rms_um), um(b.band_um)]).collect();
        let mut section = Section::new("tmbb", "Rotary table: two-length ballbar test")
            .paragraph(format!(
                "The tilts and the axial error of the rotary table from a short and a long telescopic ballbar, the method of Zhu (2008) ch. 5: the table ball at R_x = {} mm (height R_z = {} mm), the spindle ball on the table axis {:.3} mm higher for the {} mm bar than for the {} mm bar, {} table angles. The squared-length changes of the two bars are differenced, which removes the centring of the spindle ball with the radial errors, and E_x, E_y, D_z follow by least squares (l2), as `trueaxis ballbar tmbb` computes them. U (k = 2): 2 x the standard uncertainty of the least-squares estimate from the residual scatter of the differenced data; the minimax (l-infinity) estimate is shown for comparison.",
                s.rx, s.rz, h2 - h1, s.l2, s.l1, r.angles.len()
            ))
            .cells(
                "Errors of the rotary table (ISO 230-1 names; least squares)",
                &["error", "what", "value ± U (k = 2)", "minimax estimate"],
                rows,
            )
            .table(
                "What is left of each bar once the identified errors and the centring are removed",
                &["bar", "file", "RMS", "band"],
                bars,
            );
        for (name, parameter, why) in UNIDENTIFIABLE {
            section = section.note(format!("Not identified by this test: {name} ({parameter}), {why}."));
        }
        for w in r.warnings() {
            section = section.note(w);
        }
        for (plot, bar) in self.plots.iter().zip(&r.bars) {
            section = section.figure(
                format!("The {} mm bar: readings as measured and with the identified errors and the centring removed.", bar.length_mm),
                plot.clone(),
            );
        }
        section
    }
}
