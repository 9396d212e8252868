//! The JSON summary of a calibration report (`trueaxis report --json`): the sections, the inputs
//! with their SHA-256, the conformity decisions, and the key numbers of each part with their
//! expanded uncertainties (k = 2); lengths in um, as the report states them.

use super::{CalibrationReport, FitPart};
use serde_json::{json, Map, Value};
use std::path::Path;

/// The summary of `report`, written to `out` (`bytes` of HTML) and to `pdf` if given.
pub fn summary_json(out: &Path, report: &CalibrationReport, sections: &[String], bytes: usize, pdf: Option<&Path>) -> Value {
    let parameters = report
        .identification
        .as_ref()
        .map(|id| id.parameter_rows(report.uncertainty.as_ref()).into_iter().map(|p| (p.name.clone(), p.json())).collect::<Map<_, _>>());
    let conformity: Vec<_> = report
        .conformity_items()
        .iter()
        .map(|i| json!({"item": i.name, "value": i.value, "expanded_uncertainty": i.expanded, "tolerance": i.tolerance, "unit": i.unit, "decision": i.mark.word()}))
        .collect();
    let volumetric = report.volume.as_ref().map(|v| {
        json!({"poses": v.poses, "max_before_um": v.before_um.0, "rms_before_um": v.before_um.1,
               "max_after_um": v.after_um.0, "rms_after_um": v.after_um.1, "controller": v.controller,
               "max_after_tables_um": v.after_tables_um.0, "rms_after_tables_um": v.after_tables_um.1})
    });
    let inputs: Vec<_> = report
        .traceability
        .inputs
        .iter()
        .map(|f| json!({"role": f.role, "path": f.path, "bytes": f.bytes, "sha256": f.sha256, "recorded": f.recorded}))
        .collect();
    json!({
        "out": out.display().to_string(), "bytes": bytes, "pdf": pdf.map(|p| p.display().to_string()), "sections": sections, "inputs": inputs,
        "conformity": conformity, "decision_rule": report.certificate.decision.rule.name(),
        "controller": report.controller.as_ref().map(|c| json!({"format": c.format, "worst_um": c.residual.worst_um, "rms_um": c.residual.rms_um, "worst_error_um": c.residual.worst_error_um, "rms_error_um": c.residual.rms_error_um, "leaves_more_than_it_removes": c.residual.leaves_more_than_it_removes(), "left_out": c.left_out, "kinematics": c.kinematics})),
        "parameters": parameters, "volumetric": volumetric, "positioning": positioning(report), "ballbar": ballbar(report),
        "rotary_ballbar": rotary_ballbar(report), "tmbb": tmbb(report),
        "fits": report.fits.iter().map(FitPart::json).collect::<Vec<_>>(),
        "thermal_modes": thermal_modes(report), "thermal_drift": thermal_drift(report),
        "data_quality": report.data_quality.as_ref().map(|d| d.to_json()),
        "compensation": report.compensation.as_ref().map(|c| json!({"max_correction_um": c.extent.max_um, "max_correction_urad": c.extent.max_urad})),
    })
}

/// Per circle: G, F max and F min of each run, H, the diagnostics with U.
fn ballbar(report: &CalibrationReport) -> Vec<Value> {
    report
        .circles
        .iter()
        .map(|c| {
            let diagnostics: Map<String, Value> = c
                .result
                .diagnostics
                .items
                .iter()
                .map(|d| (d.name.clone(), json!({"value": d.value, "unit": d.unit, "expanded_uncertainty": 2.0 * d.std_uncertainty})))
                .collect();
            json!({"file": c.input.path.display().to_string(), "G_um": c.result.runs.iter().map(|r| r.g_um).collect::<Vec<_>>(),
                   "F_max_um": c.result.runs.iter().map(|r| r.f_max_um).collect::<Vec<_>>(),
                   "F_min_um": c.result.runs.iter().map(|r| r.f_min_um).collect::<Vec<_>>(),
                   "H_um": c.result.hysteresis_um, "reading_expanded_uncertainty_um": c.reading_u_um,
                   "feed_mm_per_min": c.feed_mm_per_min, "diagnostics": diagnostics})
        })
        .collect()
}

/// Per positioning test: the ISO 230-2 results with U and the budget of standard uncertainties.
fn positioning(report: &CalibrationReport) -> Vec<Value> {
    report
        .positioning
        .iter()
        .map(|p| {
            let results: Map<String, Value> = p
                .test
                .result
                .axis_table()
                .iter()
                .map(|(symbol, _, value)| (symbol.to_string(), json!({"value": value, "expanded_uncertainty": p.uncertainty.of(symbol)})))
                .collect();
            let budget: Map<String, Value> =
                p.uncertainty.budget.iter().map(|c| (c.name.to_string(), json!(c.standard_uncertainty))).collect();
            json!({"file": p.path.display().to_string(), "axis": p.axis(), "unit": p.test.result.unit, "coverage_factor": 2,
                   "length": p.uncertainty.length, "results": results, "budget": budget,
                   "temperature_correction": p.test.temperature_correction})
        })
        .collect()
}

fn rotary_ballbar(report: &CalibrationReport) -> Option<Value> {
    report.rotary_ballbar.as_ref().map(|r| {
        let errors: Map<String, Value> = r.errors().iter().map(|e| (e.name.clone(), e.json())).collect();
        json!({"method": r.report.method.name(), "runs": r.report.runs.len(), "uncertainty_method": r.uncertainty_method(), "errors": errors,
               "residual_rms_um": r.report.steps.iter().map(|s| s.rms_um).collect::<Vec<_>>()})
    })
}

fn tmbb(report: &CalibrationReport) -> Option<Value> {
    report.tmbb.as_ref().map(|t| {
        let errors: Map<String, Value> = t.errors().iter().map(|e| (e.name.clone(), e.json())).collect();
        json!({"method": "two-length ballbar, Zhu (2008)", "estimator": "least squares (l2)", "errors": errors,
               "left_rms_um": t.report.bars.iter().map(|b| b.rms_um).collect::<Vec<_>>()})
    })
}

fn thermal_modes(report: &CalibrationReport) -> Option<Value> {
    report.thermal_modes.as_ref().map(|m| {
        json!({"tau_min": m.weights.iter().map(|w| w.tau_s / 60.0).collect::<Vec<_>>(),
               "share": m.weights.iter().map(|w| w.share).collect::<Vec<_>>(),
               "dominant": m.dominant.iter().map(|d| d + 1).collect::<Vec<_>>()})
    })
}

fn thermal_drift(report: &CalibrationReport) -> Option<Value> {
    report.thermal_drift.as_ref().map(|d| {
        let runs: Map<String, Value> = d.runs.iter().map(|(run, s)| (run.clone(), json!(s))).collect();
        json!({"error": d.error, "residuals_um": runs})
    })
}
