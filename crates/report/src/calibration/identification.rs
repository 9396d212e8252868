//! The identification part of a calibration report: a campaign solved as `trueaxis identify` solves
//! it (weighted least squares on the first-order Jacobian of the exact chain, Soons 1993 eq. 2.24 /
//! Andolfatto et al. 2011 eq. 2), its residuals per channel, the parameters each with one expanded uncertainty
//! and the method that gave it, and the identifiability report.

use super::super::html::{Cell, Section};
use super::super::residuals_svg;
use super::quantity::{decimals_for, display_unit, quantity, with_uncertainty};
use super::uncertainty::UncertaintyPart;
use super::{number, CalibrationError};
use std::path::Path;
use trueaxis::error_model::ErrorModel;
use trueaxis::identify::{self, error_values_text, Campaign, DesignMatrix, Identification, IndirectOptions};
use trueaxis::machine::Machine;

/// A campaign and its identification.
pub struct IdentificationPart {
    pub campaign: Campaign,
    pub design: DesignMatrix,
    pub result: Identification,
    /// The identified values as an error-values TOML (what `identify --out` writes) and as a model.
    pub errors_text: String,
    pub errors: ErrorModel,
    /// Known values of the unknowns (a simulation), shown beside the identified ones.
    pub truth: Option<Vec<f64>>,
    /// Paragraphs that describe the campaign (how it was measured or simulated).
    pub description: Vec<String>,
    /// Remarks on the identifiability beyond the automatic report (e.g. which combinations a
    /// machine's geometry hides and why).
    pub notes: Vec<String>,
}

/// One row of the parameter table: identified value (user units), its least-squares standard
/// uncertainty, the Monte Carlo coverage interval when the uncertainty was evaluated, the known
/// value when there is one.
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterRow {
    pub name: String,
    pub unit: String,
    pub truth: Option<f64>,
    pub value: f64,
    pub std_uncertainty: Option<f64>,
    pub interval: Option<(f64, f64)>,
    /// The one expanded uncertainty quoted (k = 2): twice the Monte Carlo standard uncertainty with
    /// all sources when evaluated, else twice the least-squares standard uncertainty.
    pub expanded: Option<f64>,
    /// How `expanded` was obtained.
    pub method: UncertaintyMethod,
}

/// Where a parameter's expanded uncertainty comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UncertaintyMethod {
    /// Adaptive Monte Carlo (JCGM 101) with every source of the sources file.
    MonteCarlo,
    /// The least-squares covariance scaled by the residuals (the noise seen in this campaign only).
    LeastSquares,
    None,
}

impl ParameterRow {
    /// The parameter as every JSON of a run states it: one uncertainty, the report's `U` (k = 2)
    /// with the method that gave it, so that `value ± U` reads the same in the report, its PDF and
    /// its JSON; the least-squares standard uncertainty (the residual scatter of this campaign only)
    /// and the Monte Carlo 95 % interval are kept under names that say what they are.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "unit": self.unit, "value": self.value, "true": self.truth,
            "expanded_uncertainty": self.expanded, "coverage_factor": 2, "uncertainty_method": self.method.describe(),
            "reported": with_uncertainty(self.value, self.expanded, &self.unit, 2),
            "least_squares_std_uncertainty": self.std_uncertainty, "interval95": self.interval.map(|(lo, hi)| [lo, hi]),
        })
    }
}

impl UncertaintyMethod {
    pub fn describe(self) -> &'static str {
        match self {
            UncertaintyMethod::MonteCarlo => "Monte Carlo, all sources (JCGM 101)",
            UncertaintyMethod::LeastSquares => "least squares, residual scatter only",
            UncertaintyMethod::None => "not evaluated",
        }
    }
}

impl IdentificationPart {
    /// Loads the campaign at `path` and identifies its unknowns with the options of `trueaxis
    /// identify` (QR; a rank-deficient set is an error unless `allow_rank_deficient`).
    pub fn identify(machine: &Machine, path: &Path, allow_rank_deficient: bool) -> Result<IdentificationPart, CalibrationError> {
        let campaign = Campaign::load(path, machine)?;
        let nominal = campaign.nominal_errors(machine)?;
        let design = campaign.design_matrix(machine, &nominal)?;
        let start = campaign.nominal_values(&nominal)?;
        let options = IndirectOptions { allow_rank_deficient, ..IndirectOptions::default() };
        let result = identify::solve(&design, &start, &options)?;
        if result.values.iter().chain(&result.residuals).any(|v| !v.is_finite()) {
            return Err(CalibrationError::Computation(format!(
                "{}: the identification produced numbers that are not finite",
                campaign.origin
            )));
        }
        let nominal_text = match &campaign.nominal_errors {
            Some(p) => trueaxis::files::inputs::read_to_string(p)
                .map_err(|source| trueaxis::data::DataError::Read { path: p.display().to_string(), source })?,
            None => String::new(),
        };
        let errors_text = error_values_text(&result, &campaign, &nominal, &nominal_text)?;
        let errors = ErrorModel::from_toml_str(&errors_text, &format!("errors identified from {}", campaign.origin), machine)?;
        Ok(IdentificationPart { campaign, design, result, errors_text, errors, truth: None, description: Vec::new(), notes: Vec::new() })
    }

    /// Per unknown: the known value (if any), the identified value, its least-squares standard
    /// uncertainty and the Monte Carlo interval of `uncertainty` (if evaluated).
    pub fn parameter_rows(&self, uncertainty: Option<&UncertaintyPart>) -> Vec<ParameterRow> {
        let r = &self.result;
        (0..r.names.len())
            .map(|j| {
                let monte_carlo = uncertainty.and_then(|u| u.std_uncertainty(&r.names[j])).filter(|u| u.is_finite() && *u > 0.0);
                let least_squares = r.std_uncertainty[j].filter(|u| u.is_finite() && *u > 0.0);
                let (expanded, method) = match (monte_carlo, least_squares) {
                    (Some(u), _) => (Some(2.0 * u), UncertaintyMethod::MonteCarlo),
                    (None, Some(u)) => (Some(2.0 * u), UncertaintyMethod::LeastSquares),
                    (None, None) => (None, UncertaintyMethod::None),
                };
                ParameterRow {
                    name: r.names[j].clone(),
                    unit: r.units[j].clone(),
                    truth: self.truth.as_ref().map(|t| t[j]),
                    value: r.values[j],
                    std_uncertainty: r.std_uncertainty[j],
                    interval: uncertainty.and_then(|u| u.interval(&r.names[j])),
                    expanded,
                    method,
                }
            })
            .collect()
    }

    /// The campaign: what was measured, the residuals per channel (table and plot).
    pub fn campaign_section(&self) -> Section {
        let r = &self.result;
        let stats = r
            .channels
            .iter()
            .map(|c| {
                vec![
                    c.name.clone(),
                    c.count.to_string(),
                    quantity(c.mean, 2, "um"),
                    quantity(c.rms, 2, "um"),
                    quantity(c.max_abs, 2, "um"),
                    quantity(c.sigma, 2, "um"),
                ]
            })
            .collect();
        let d = &self.design;
        let residuals: Vec<(String, Vec<f64>)> = d
            .channel_names
            .iter()
            .enumerate()
            .map(|(c, name)| (name.clone(), (0..d.rows()).filter(|&i| d.channels[i] == c).map(|i| r.residuals[i]).collect()))
            .collect();
        let title = format!("Measurement campaign: {}", self.campaign.name.as_deref().unwrap_or(&self.campaign.origin));
        let mut s = Section::new("campaign", &title).paragraph(format!(
            "{}: {} measurement(s), {} readings, {} unknowns.",
            self.campaign.origin,
            self.campaign.measurements.len(),
            r.residuals.len(),
            r.names.len()
        ));
        for p in &self.description {
            s = s.paragraph(p.clone());
        }
        s = s.table(
            "Residuals per channel after identification",
            &["channel", "readings", "mean", "RMS", "largest", "stated noise"],
            stats,
        );
        if let Ok(svg) = residuals_svg("Residuals of the identification (um)", &residuals) {
            s = s.figure("Residuals against the reading number: noise shows as a band, a drift or an unmodelled error as a pattern.", svg);
        }
        s
    }

    /// The identified parameters, each with one expanded uncertainty (k = 2) rounded by it, the
    /// method that gave it (linked to its budget), and the identifiability report.
    pub fn parameter_section(&self, uncertainty: Option<&UncertaintyPart>) -> Section {
        let r = &self.result;
        let ident = &r.identifiability;
        let rows = self.parameter_rows(uncertainty);
        let with_truth = self.truth.is_some();
        let mut header = vec!["parameter"];
        if with_truth {
            header.push("true value");
        }
        header.extend(["identified value ± U (k = 2)", "uncertainty from"]);
        if with_truth {
            header.push("true value within U");
        }
        header.push("independence");
        let table = rows
            .iter()
            .zip(&ident.independence)
            .map(|(p, independence)| {
                let mut cells = vec![Cell::from(p.name.clone())];
                // the true value in the unit and to the place of the identified one
                let (factor, unit) = display_unit(p.expanded.unwrap_or(p.value.abs()), &p.unit);
                let decimals = p.expanded.and_then(|u| decimals_for(u * factor)).unwrap_or(2);
                if let Some(t) = p.truth {
                    cells.push(Cell::from(quantity(t * factor, decimals, &unit)));
                }
                cells.push(Cell::from(with_uncertainty(p.value, p.expanded, &p.unit, 2)));
                cells.push(match p.method {
                    UncertaintyMethod::MonteCarlo => Cell::link(p.method.describe(), "uncertainty"),
                    _ => Cell::from(p.method.describe()),
                });
                if let Some(t) = p.truth {
                    let within = p.expanded.is_some_and(|u| (p.value - t).abs() <= u);
                    cells.push(Cell::from(if within { "yes" } else { "no" }));
                }
                cells.push(Cell::from(number(*independence, 2)));
                cells
            })
            .collect();
        let header_refs: Vec<&str> = header.clone();
        let mut s = Section::new("identification", "Identified parameters")
            .paragraph(format!(
                "Weighted least squares ({} factorisation) on the linearised model of the exact kinematic chain (docs/identification.md): {} unknowns from {} readings, rank {}, condition number {} (columns scaled to unit length), residual RMS {}, standard deviation of unit weight {:.2} (1 when the residuals match the stated noise).",
                r.solver.name().to_uppercase(),
                r.names.len(),
                r.residuals.len(),
                ident.rank,
                ident.condition_number.map_or("infinite".into(), |c| format!("{c:.1}")),
                quantity(r.residual_rms_um, 3, "um"),
                r.sigma0
            ))
            .paragraph(match uncertainty {
                Some(_) => "Each value is quoted with one expanded uncertainty U (coverage factor k = 2, about 95 %): twice the standard deviation of its Monte Carlo distribution with every uncertainty source (see the uncertainty budget), rounded to two significant digits, the value to the same decimal place.",
                None => "Each value is quoted with one expanded uncertainty U (coverage factor k = 2, about 95 %): twice its least-squares standard uncertainty, which reflects only the scatter of this campaign's residuals (no uncertainty sources were given), rounded to two significant digits, the value to the same decimal place.",
            })
            .cells(
                "Parameters, and the independence index of each (1: orthogonal to all other parameters, 0: a combination of them)",
                &header_refs,
                table,
            );
        for c in &ident.unidentifiable {
            s = s.note(format!("Not identifiable: {}", c.message));
        }
        for (i, j, rho) in ident.strong_correlations(0.9) {
            s = s.note(format!("Strongly correlated: {} and {} (r = {rho:+.3}).", r.names[i], r.names[j]));
        }
        for n in &self.notes {
            s = s.note(n.clone());
        }
        s
    }
}
