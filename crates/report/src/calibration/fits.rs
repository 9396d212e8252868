//! Direct measurements in a calibration report: one error motion of an axis (ISO 230-1 names such
//! as `EXX`, `EBX`, `EYX`; um or urad) measured along its travel with a laser interferometer or a
//! level and fitted as a parametric function by `trueaxis::identify::run_direct_fit` (the code of
//! `trueaxis fit`; Soons (1993) §3.2: least squares, stepwise selection).
//!
//! Quoted with one expanded uncertainty U = 2 u (k = 2) each, u from the least-squares covariance
//! `C = s^2 (G^T G)^-1` of the fit (s the residual standard deviation):
//! - each coefficient of the kept basis functions, in the parameter's unit per mm^k (per m^k when
//!   per mm needs zeros), U = 2 sqrt(C_kk), the numbers of `trueaxis fit --json`;
//! - the fitted function at 11 positions across the measured travel, U(x) = 2 sqrt(g(x)^T C g(x));
//! - its range over the travel (largest minus smallest of the function at 401 nodes), which a
//!   tolerance on the parameter is decided on; for a straightness (a translation across the
//!   axis: `EYX`, `EZX` ...) about its least-squares reference line (ISO 230-1), so that the
//!   line's slope, the alignment of the setup, is not counted. U of the range from the
//!   difference of the two extreme nodes' rows, `2 sqrt(d^T C d)`.
//!
//! Figures: the readings with the fitted function and its U band, and the residuals with the band
//! of twice the residual standard deviation.

use super::super::html::{Cell, Section};
use super::conformity::{DecisionRule, Item};
use super::quantity::{quantity, with_uncertainty};
use super::rotary_ballbar::file_name;
use super::CalibrationError;
use crate::{fit_plot_svg, FitPlot};
use nalgebra::{DMatrix, DVector};
use serde_json::json;
use std::collections::BTreeMap;
use std::path::PathBuf;
use trueaxis::identify::DirectFitReport;
use trueaxis::machine::ParameterId;

/// Positions of the table of the fitted function, and nodes of its range and plots.
const TABLE_POSITIONS: usize = 11;
const NODES: usize = 401;

/// One fitted error motion.
pub struct FitPart {
    /// The data file the readings came from.
    pub file: PathBuf,
    /// `+` or `-` when one direction of approach was fitted.
    pub direction: Option<char>,
    /// mm (a linear axis) or deg (a rotary one).
    pub position_unit: &'static str,
    pub report: DirectFitReport,
    /// What reading the file said (plausibility, temperature correction).
    pub notes: Vec<String>,
    plots: Vec<String>,
}

/// The fitted function's range over the travel with its U (k = 2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    pub value: f64,
    pub expanded: Option<f64>,
    /// Taken about the least-squares line (a straightness).
    pub about_line: bool,
}

impl FitPart {
    /// The part of one fit, with its two figures.
    pub fn new(
        file: PathBuf,
        direction: Option<char>,
        position_unit: &'static str,
        report: DirectFitReport,
        notes: Vec<String>,
    ) -> Result<FitPart, CalibrationError> {
        let mut part = FitPart { file, direction, position_unit, report, notes, plots: Vec::new() };
        part.plots = vec![part.fit_plot()?, part.residual_plot()?];
        Ok(part)
    }

    /// The parameter with its direction: `EXX`, `EXX+`.
    pub fn name(&self) -> String {
        format!("{}{}", self.report.parameter, self.direction.map(String::from).unwrap_or_default())
    }

    fn unit(&self) -> &'static str {
        self.report.parameter.unit()
    }

    /// The rows `g(x)` of the kept basis functions at each of `xs`.
    fn rows(&self, xs: &[f64]) -> DMatrix<f64> {
        let basis = &self.report.fitted.selected;
        let mut rows = DMatrix::zeros(xs.len(), basis.len());
        let mut g = vec![0.0; basis.len()];
        for (i, x) in xs.iter().enumerate() {
            basis.eval_into(*x, &mut g);
            rows.row_mut(i).copy_from_slice(&g);
        }
        rows
    }

    /// `n` positions evenly across the measured travel.
    fn positions(&self, n: usize) -> Vec<f64> {
        let p = &self.report.positions;
        let (lo, hi) = p.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(*x), b.max(*x)));
        (0..n).map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64).collect()
    }

    /// The fitted function and its expanded uncertainty at each of `xs`.
    pub fn function_at(&self, xs: &[f64]) -> Vec<(f64, f64)> {
        let fit = &self.report.fitted.fit;
        let g = self.rows(xs);
        let c = DVector::from_column_slice(&fit.coefficients);
        (0..xs.len())
            .map(|i| {
                let row = g.row(i).transpose();
                ((row.transpose() * &c)[0], 2.0 * (row.transpose() * &fit.covariance * &row)[0].max(0.0).sqrt())
            })
            .collect()
    }

    /// True for a straightness: a translation across the axis (EYX, EZX ...).
    fn is_straightness(&self) -> bool {
        match self.report.parameter {
            ParameterId::Motion { axis, component } => !component.is_rotation() && component.letter() != axis,
            _ => false,
        }
    }

    /// The range of the fitted function over the measured travel, with U; a straightness about its
    /// least-squares line.
    pub fn range(&self) -> Range {
        let xs = self.positions(NODES);
        let mut g = self.rows(&xs);
        let about_line = self.is_straightness();
        if about_line {
            // every column minus its least-squares line over the nodes: the same linear map for the
            // function and for its gradient
            let a = DMatrix::from_fn(NODES, 2, |i, k| if k == 0 { 1.0 } else { xs[i] });
            if let Some(inverse) = (a.transpose() * &a).try_inverse() {
                g = &g - &a * (inverse * (a.transpose() * &g));
            }
        }
        let fit = &self.report.fitted.fit;
        let v = &g * DVector::from_column_slice(&fit.coefficients);
        let (imin, imax) = (v.argmin().0, v.argmax().0);
        let d = (g.row(imax) - g.row(imin)).transpose();
        let u = (d.transpose() * &fit.covariance * &d)[0].max(0.0).sqrt();
        Range { value: v[imax] - v[imin], expanded: (u.is_finite() && u > 0.0).then_some(2.0 * u), about_line }
    }

    /// The unit of the coefficient of a basis function named like `x^2` or `(x+100)_+^2`: the
    /// parameter's unit per position unit to its power.
    fn term_unit(&self, function: &str) -> String {
        let power = function.rsplit_once('^').and_then(|(_, p)| p.parse::<u32>().ok()).filter(|_| function.contains('x')).unwrap_or(0);
        match power {
            0 => self.unit().to_string(),
            1 => format!("{}/{}", self.unit(), self.position_unit),
            k => format!("{}/{}^{k}", self.unit(), self.position_unit),
        }
    }

    /// Each kept function with its coefficient `value ± U` (U = 2 u of `trueaxis fit --json`).
    pub fn terms(&self) -> Vec<(String, f64, f64, String)> {
        let f = &self.report.fitted;
        f.names
            .iter()
            .zip(&f.coefficients)
            .zip(&f.std_uncertainties)
            .map(|((n, c), u)| {
                let unit = self.term_unit(n);
                (n.clone(), *c, 2.0 * u, with_uncertainty(*c, Some(2.0 * u), &unit, 2))
            })
            .collect()
    }

    /// A tolerance on the parameter (`[tolerances.parameters]`, by its ISO name) decided on the range.
    pub fn conformity(&self, tolerances: &BTreeMap<String, f64>, rule: DecisionRule) -> Vec<Item> {
        let Some(&tol) = tolerances.get(&self.report.parameter.to_string()) else { return Vec::new() };
        let r = self.range();
        let what = if r.about_line { "straightness about its least-squares line" } else { "range over the travel" };
        vec![Item::new(format!("{} ({what}, {})", self.name(), file_name(&self.file)), "fits", r.value, r.expanded, tol, self.unit(), rule)]
    }

    /// Its entry in `report --json`: the numbers of `trueaxis fit --json` and what the report prints.
    pub fn json(&self) -> serde_json::Value {
        let r = self.range();
        let terms: Vec<_> = self
            .terms()
            .into_iter()
            .map(|(n, c, u, text)| json!({"function": n, "coefficient": c, "expanded_uncertainty": u, "coverage_factor": 2, "reported": text}))
            .collect();
        let f = &self.report.fitted;
        json!({"file": self.file.display().to_string(), "parameter": self.report.parameter.to_string(), "direction": self.direction.map(String::from),
               "unit": self.unit(), "observations": self.report.positions.len(), "terms": terms, "residual_std": f.fit.sigma,
               "residual_rms": f.rms, "max_abs_residual": f.max_abs_residual,
               "range": {"value": r.value, "expanded_uncertainty": r.expanded, "about_least_squares_line": r.about_line,
                         "reported": with_uncertainty(r.value, r.expanded, self.unit(), 2)}})
    }

    fn fit_plot(&self) -> Result<String, CalibrationError> {
        let xs = self.positions(NODES);
        let curve: Vec<(f64, f64, f64)> = xs.iter().zip(self.function_at(&xs)).map(|(x, (v, u))| (*x, v, u)).collect();
        let points: Vec<(f64, f64)> = self.report.positions.iter().copied().zip(self.report.values.iter().copied()).collect();
        Ok(fit_plot_svg(&FitPlot {
            title: &format!("{} fitted to {}", self.name(), file_name(&self.file)),
            x_label: &format!("position ({})", self.position_unit),
            y_label: &format!("{} ({})", self.report.parameter, self.unit()),
            points: &points,
            curve: &curve,
            band_label: "U of the fitted function (k = 2)",
        })?)
    }

    fn residual_plot(&self) -> Result<String, CalibrationError> {
        let r = &self.report;
        let points: Vec<(f64, f64)> = r.positions.iter().copied().zip(r.fitted.fit.residuals.iter().copied()).collect();
        let s = r.fitted.fit.sigma;
        let curve: Vec<(f64, f64, f64)> = self.positions(2).into_iter().map(|x| (x, 0.0, 2.0 * s)).collect();
        Ok(fit_plot_svg(&FitPlot {
            title: &format!("{}: residuals of the fit", self.name()),
            x_label: &format!("position ({})", self.position_unit),
            y_label: &format!("residual ({})", self.unit()),
            points: &points,
            curve: &curve,
            band_label: "± 2 s (residual standard deviation)",
        })?)
    }

    /// Its subsection: what was fitted, the function, the coefficients, the residuals, the figures.
    fn add_to(&self, mut section: Section) -> Section {
        let r = &self.report;
        let f = &r.fitted;
        let unit = self.unit();
        let direction = self.direction.map_or(String::new(), |d| format!(", readings approached in the {d} direction"));
        let range = self.range();
        let range_text = with_uncertainty(range.value, range.expanded, unit, 2);
        section = section
            .paragraph(format!(
                "{} from {}{direction}: {} readings, {} basis functions kept{}. Range of the fitted function over the measured travel{}: {range_text}.",
                self.name(),
                file_name(&self.file),
                r.positions.len(),
                f.names.len(),
                if f.removed.is_empty() { String::new() } else { format!(" ({} removed by stepwise selection)", f.removed.len()) },
                if range.about_line { " about its least-squares line (straightness, ISO 230-1)" } else { "" },
            ))
            .cells(
                format!("{}: the fitted function across the travel", self.name()),
                &["position", "value ± U (k = 2)"],
                self.positions(TABLE_POSITIONS)
                    .iter()
                    .zip(self.function_at(&self.positions(TABLE_POSITIONS)))
                    .map(|(x, (v, u))| vec![Cell::from(quantity(*x, 1, self.position_unit)), Cell::from(with_uncertainty(v, Some(u), unit, 2))])
                    .collect(),
            )
            .cells(
                format!("{}: coefficients of the kept basis functions (x: position in {})", self.name(), self.position_unit),
                &["function", "coefficient ± U (k = 2)"],
                self.terms().into_iter().map(|(n, _, _, text)| vec![Cell::from(n), Cell::from(text)]).collect(),
            )
            .table(
                format!("{}: residuals of the fit", self.name()),
                &["residual standard deviation s", "RMS", "largest |residual|", "95 % prediction interval, half-width"],
                vec![vec![
                    quantity(f.fit.sigma, 2, unit),
                    quantity(f.rms, 2, unit),
                    quantity(f.max_abs_residual, 2, unit),
                    quantity(f.max_prediction_half_width, 2, unit),
                ]],
            );
        for n in &self.notes {
            section = section.note(n.clone());
        }
        section
            .figure(format!("{}: the readings, the fitted function and its U band.", self.name()), self.plots[0].clone())
            .figure(format!("{}: the residuals of the fit.", self.name()), self.plots[1].clone())
    }
}

/// The section of every fit.
pub fn section(fits: &[FitPart]) -> Section {
    let s = Section::new("fits", "Direct measurements: fitted error motions").paragraph(
        "Each error motion measured along its axis (laser interferometer, level) fitted as a parametric function of the axis position by least squares with stepwise selection, the method of Soons (1993) §3.2, as `trueaxis fit` computes it (docs/laser.md). U (k = 2): twice the standard uncertainty from the least-squares covariance of the fit (the scatter of the readings about it). A tolerance on the parameter is decided on the range of the fitted function over the measured travel; for a straightness, about its least-squares reference line (ISO 230-1).",
    );
    fits.iter().fold(s, |s, f| f.add_to(s))
}
