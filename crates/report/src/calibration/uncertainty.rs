//! The uncertainty part of a calibration report: adaptive Monte Carlo (JCGM 101 §7.9, several
//! outputs per JCGM 102) of an identification with the sources of a sources file, each source alone
//! and all together (the budget of Andolfatto et al. 2011 Table 5), as `trueaxis uncertainty` computes it.

use super::super::html::Section;
use super::super::{interval_of, uncertainty_figures};
use super::identification::IdentificationPart;
use super::quantity::{display_unit, uncertainty};
use super::CalibrationError;
use trueaxis::uncertainty::{self, from_identification, run_budget, Budget, ControlVariables, Evaluation, IdentificationMap, Sources};

/// The evaluated uncertainty of an identification.
pub struct UncertaintyPart {
    pub sources: Sources,
    /// The design the Monte Carlo maps through (what `uncertainty --design` reads).
    pub design: uncertainty::DesignMatrix,
    pub budget: Budget,
    pub histograms_svg: String,
    pub convergence_svg: Option<String>,
    /// Where the sources came from (a file name).
    pub origin: String,
    /// Time between two records of the campaign (s), for the drift sources.
    pub point_time_s: f64,
}

impl UncertaintyPart {
    /// The budget of `identification` with `sources`, record k of the campaign read at
    /// `k * point_time_s` (for the drift sources); `progress(stage, sequence)` after each sequence.
    pub fn evaluate(
        identification: &IdentificationPart,
        sources: Sources,
        origin: &str,
        point_time_s: f64,
        progress: &mut dyn FnMut(Option<&str>, usize),
    ) -> Result<UncertaintyPart, CalibrationError> {
        let design = from_identification(&identification.design, point_time_s)?;
        sources.check_channels(&design).map_err(|e| CalibrationError::Input(format!("{origin}: {e}")))?;
        let map = IdentificationMap::new(design.clone())?;
        let mut report = |stage: Option<&str>, sequence: usize, _: Option<&ControlVariables>| progress(stage, sequence);
        let budget = run_budget(&map, &sources.sources, &sources.settings, Evaluation::Reduced, true, &mut report)?;
        let (histograms_svg, convergence_svg) = uncertainty_figures(&budget, &sources.settings)?;
        Ok(UncertaintyPart { sources, design, budget, histograms_svg, convergence_svg, origin: origin.into(), point_time_s })
    }

    /// The coverage interval of a parameter with all sources, if it is one of the outputs.
    pub fn interval(&self, parameter: &str) -> Option<(f64, f64)> {
        let k = self.budget.rows.iter().position(|row| row.parameter == parameter)?;
        Some(interval_of(self.sources.settings.interval, &self.budget.total.outputs[k]))
    }

    /// The Monte Carlo standard uncertainty of a parameter with all sources.
    pub fn std_uncertainty(&self, parameter: &str) -> Option<f64> {
        let k = self.budget.rows.iter().position(|row| row.parameter == parameter)?;
        Some(self.budget.total.outputs[k].std_uncertainty)
    }

    pub fn section(&self) -> Section {
        let b = &self.budget;
        let settings = &self.sources.settings;
        let mut header: Vec<String> = vec!["parameter".into()];
        header.extend(b.source_names.iter().map(|n| format!("{n} alone")));
        header.extend(["root-sum-square".into(), "all sources".into(), "U (k = 2)".into()]);
        let rows = b
            .rows
            .iter()
            .enumerate()
            .map(|(k, row)| {
                let mut cells = vec![row.parameter.clone()];
                // in the unit the parameter table quotes it (per metre for a tiny per-millimetre term)
                let (factor, unit) = display_unit(2.0 * b.total.outputs[k].std_uncertainty, &row.unit);
                let two_digits = |w: f64| format!("{} {unit}", uncertainty(w * factor));
                cells.extend(row.widths.iter().map(|w| two_digits(*w)));
                cells.extend([two_digits(row.rss), two_digits(row.total), two_digits(2.0 * b.total.outputs[k].std_uncertainty)]);
                cells
            })
            .collect();
        let header_refs: Vec<&str> = header.iter().map(String::as_str).collect();
        let mut s = Section::new("uncertainty", "Uncertainty budget (adaptive Monte Carlo, JCGM 101 and 102)")
            .paragraph(format!(
                "Sources of {}: {} (record k of the campaign read at k x {} s). Each trial draws every source and maps the disturbed readings to the parameters through the identification's precomputed pseudo-inverse. Adaptive procedure of JCGM 101: sequences of {} trials until the means, standard uncertainties and interval endpoints are stable to {} um or urad; {} sequences, {} trials{}. Random seed {}: the same numbers on any number of threads (docs/uncertainty.md).",
                self.origin,
                b.source_names.join(", "),
                self.point_time_s,
                settings.trials_per_sequence,
                settings.tolerance,
                b.total.sequences,
                b.total.trials,
                if b.total.converged { "" } else { " (NOT converged within the sequence limit)" },
                settings.seed
            ))
            .table(
                format!(
                    "Budget: width of the {} % coverage interval with each source alone, their root-sum-square and with all sources together; U (k = 2) is twice the Monte Carlo standard uncertainty with all sources, the uncertainty quoted with the identified parameters",
                    100.0 * settings.coverage
                ),
                &header_refs,
                rows,
            )
            .figure(
                "Monte Carlo distributions of the parameters with their coverage intervals and the GUM Gaussians.",
                self.histograms_svg.clone(),
            );
        if let Some(svg) = &self.convergence_svg {
            s = s.figure("Convergence of the adaptive loop: the control variables fall below the tolerance.", svg.clone());
        }
        s
    }
}
