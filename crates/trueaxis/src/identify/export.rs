//! Writing an indirect identification: the error-values file `predict` and `compensate` read, and
//! the JSON document of docs/design.md, Command line (`trueaxis identify --json`).

use super::campaign::Campaign;
use super::indirect::Identification;
use super::unknowns::UnknownKind;
use super::IdentifyError;
use crate::error_model::{set_error_function, set_uncertainty, ErrorFunction, ErrorModel};
use crate::machine::ParameterId;
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;

/// The error-values TOML with the identified values set: `nominal_text` (the campaign's
/// `nominal_errors` file, its comments kept; empty for none) with every identified parameter
/// replaced. Constants go to `[constant]`; identified powers of a motion error make it a
/// `[polynomial.NAME]` whose other coefficients come from the nominal errors; a motion error
/// identified as a basis is written as `[basis.NAME]` with the campaign's basis and the identified
/// coefficients.
pub fn error_values_text(
    result: &Identification,
    campaign: &Campaign,
    nominal: &ErrorModel,
    nominal_text: &str,
) -> Result<String, IdentifyError> {
    let mut by_id: BTreeMap<ParameterId, Vec<(u32, f64)>> = BTreeMap::new();
    let mut uncertainty: BTreeMap<ParameterId, f64> = BTreeMap::new();
    for ((u, value), std) in campaign.unknowns.iter().zip(&result.values).zip(&result.std_uncertainty) {
        if let UnknownKind::Model { id, power, .. } = u.kind {
            by_id.entry(id).or_default().push((power, *value));
            if let (0, Some(std)) = (power, std) {
                uncertainty.insert(id, *std);
            }
        }
    }
    let mut names: Vec<String> = by_id.keys().chain(campaign.bases.iter().map(|b| &b.id)).map(ToString::to_string).collect();
    names.sort();
    let header = format!("# Parameters {} identified by `trueaxis identify` from {}\n", names.join(" "), campaign.origin);
    let mut text = nominal_text.to_string();
    let nominal_file = |m: crate::Error| IdentifyError::Input(format!("nominal errors file: {m}"));
    for b in &campaign.bases {
        let coefficients = result.values[b.first..b.first + b.basis.len()].to_vec();
        let function = ErrorFunction::basis(b.basis.clone(), coefficients).map_err(nominal_file)?;
        text = set_error_function(&text, &b.id, None, &function).map_err(nominal_file)?;
    }
    for (id, powers) in by_id {
        let existing = nominal.entries().find(|(i, _)| **i == id).map(|(_, f)| f.clone());
        let constant = powers.iter().all(|(k, _)| *k == 0) && !matches!(existing, Some(ErrorFunction::Polynomial { .. }));
        if let Some(u) = uncertainty.get(&id).filter(|u| constant && u.is_finite()) {
            // the standard uncertainty of an identified constant goes with it (compensate states what it
            // means for the error left)
            text = set_uncertainty(&text, &id, *u).map_err(nominal_file)?;
        }
        let function = if constant {
            ErrorFunction::Constant(powers[0].1)
        } else {
            let mut coefficients = match existing {
                Some(ErrorFunction::Polynomial { coefficients }) => coefficients,
                Some(ErrorFunction::Constant(c)) => vec![c],
                _ => vec![0.0],
            };
            for (k, v) in powers {
                if coefficients.len() <= k as usize {
                    coefficients.resize(k as usize + 1, 0.0);
                }
                coefficients[k as usize] = v;
            }
            ErrorFunction::Polynomial { coefficients }
        };
        text = set_error_function(&text, &id, None, &function).map_err(nominal_file)?;
    }
    Ok(format!("{header}{text}"))
}

fn number(v: f64) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        Value::Null
    }
}

/// The JSON document of `trueaxis identify --json` (docs/design.md, Command line; extra keys documented in
/// docs/identification.md).
pub fn identification_json(result: &Identification, campaign: &Campaign) -> Value {
    let report = &result.identifiability;
    let mut parameters = Map::new();
    let mut nuisance = Map::new();
    for (j, u) in campaign.unknowns.iter().enumerate() {
        let mut entry = json!({
            "value": number(result.values[j]),
            "unit": u.unit,
            "std_uncertainty": result.std_uncertainty[j].map_or(Value::Null, number),
            "nominal": number(result.nominal[j]),
            "delta": number(result.delta[j]),
            "identifiable": report.identifiable[j],
            "sensitivity_um": number(report.sensitivity[j]),
            "independence": number(report.independence[j]),
        });
        if let Some(function) = &u.function {
            entry["function"] = json!(function);
        }
        if u.is_model() {
            parameters.insert(u.name.clone(), entry);
        } else {
            nuisance.insert(u.name.clone(), entry);
        }
    }
    let unidentifiable: Vec<Value> = report
        .unidentifiable
        .iter()
        .map(|c| {
            let combination: Map<String, Value> = c.parameters.iter().zip(&c.coefficients).map(|(n, v)| (n.clone(), number(*v))).collect();
            json!({"parameters": c.parameters, "combination": combination, "units": c.units, "message": c.message})
        })
        .collect();
    let correlations: Vec<Value> = report
        .strong_correlations(0.9)
        .iter()
        .map(|(i, j, r)| json!({"a": result.names[*i], "b": result.names[*j], "r": number(*r)}))
        .collect();
    let channels: Vec<Value> = result
        .channels
        .iter()
        .map(|c| json!({"name": c.name, "count": c.count, "mean_um": number(c.mean), "rms_um": number(c.rms), "max_abs_um": number(c.max_abs), "sigma_um": number(c.sigma)}))
        .collect();
    let correlation_matrix: Vec<Vec<Value>> = (0..report.correlation.nrows())
        .map(|i| (0..report.correlation.ncols()).map(|j| number(report.correlation[(i, j)])).collect())
        .collect();
    json!({
        "parameters": parameters,
        "nuisance": nuisance,
        "residual_rms_um": number(result.residual_rms_um),
        "condition_number": report.condition_number.map_or(Value::Null, number),
        "condition_scaling": "rows weighted by 1/sigma, columns scaled to unit length",
        "singular_values": report.singular_values.iter().map(|s| number(*s)).collect::<Vec<_>>(),
        "rank": report.rank,
        "unidentifiable": unidentifiable,
        "strong_correlations": correlations,
        "correlation": {"names": result.names, "matrix": correlation_matrix},
        "sigma0": number(result.sigma0),
        "observations": result.residuals.len(),
        "dof": result.dof,
        "channels": channels,
        "solver": result.solver.name(),
        "refinement": result.refinement.as_ref().map_or(Value::Null, |r| json!({
            "iterations": r.iterations,
            "initial_weighted_rms": number(r.initial_weighted_rms),
            "final_weighted_rms": number(r.final_weighted_rms),
            "largest_change_in_u": number(r.largest_change_in_u),
        })),
    })
}
