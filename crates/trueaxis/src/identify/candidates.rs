//! The records of a campaign as the candidates of an optimal measurement design (Soons 1993 §4.3):
//! each record (one 3D-ball pose, one length, ...) is a block of rows of the campaign's design
//! matrix weighted by `1/sigma`, chosen or left out as a whole; and the `trueaxis design optimal
//! --json` document of a chosen design.

use super::design_units::{criteria_units, CriteriaUnits};
use super::optimal_design::{CandidateSet, Criterion, DesignCriteria};
use super::{Campaign, IdentifyError};
use crate::error_model::ErrorModel;
use crate::machine::Machine;
use serde_json::{json, Value};

/// A campaign's candidate set with, for each candidate, its measurement and record indices.
#[derive(Clone, Debug)]
pub struct CampaignCandidates {
    pub set: CandidateSet,
    /// `(measurement index, record index)` of each candidate.
    pub records: Vec<(usize, usize)>,
    /// Names of the unknowns (the columns) and their units (um, urad, ...).
    pub parameters: Vec<String>,
    pub units: Vec<String>,
}

impl CampaignCandidates {
    /// The candidates of `campaign` on `machine` about the nominal errors: a planned campaign needs
    /// no readings (the design matrix depends only on the poses and setups). `origin` names the
    /// campaign in messages.
    pub fn new(campaign: &Campaign, machine: &Machine, nominal: &ErrorModel) -> Result<CampaignCandidates, IdentifyError> {
        let mut planned = campaign.clone();
        for m in &mut planned.measurements {
            if m.readings.is_none() {
                m.readings = Some(vec![0.0; m.records() * m.instrument.channels().len()]);
            }
        }
        let design = planned.design_matrix(machine, nominal)?;
        let mut blocks: Vec<(usize, usize, Vec<usize>)> = Vec::new();
        for (row, record) in design.records.iter().enumerate() {
            match blocks.last_mut() {
                Some((m, r, rows)) if (*m, *r) == *record => rows.push(row),
                _ => blocks.push((record.0, record.1, vec![row])),
            }
        }
        let candidates = blocks
            .iter()
            .map(|(_, _, rows)| {
                nalgebra::DMatrix::from_fn(rows.len(), design.matrix.ncols(), |i, j| design.matrix[(rows[i], j)] / design.sigma_um[rows[i]])
            })
            .collect();
        let set = CandidateSet::new(candidates)
            .map_err(|m| IdentifyError::Input(format!("{}: {m}", campaign.origin)))?
            .with_names(&design.names, &design.units);
        Ok(CampaignCandidates {
            set,
            records: blocks.iter().map(|(m, r, _)| (*m, *r)).collect(),
            parameters: design.names,
            units: design.units,
        })
    }

    /// The chosen records as CSV: `measurement,line` and the axis positions of the record's first
    /// pose (mm, deg).
    pub fn chosen_csv(&self, campaign: &Campaign, machine: &Machine, chosen: &[usize]) -> String {
        let letters: Vec<String> = machine.axes().iter().map(|a| a.letter.to_string()).collect();
        let mut text = format!("measurement,line,{}\n", letters.join(","));
        for &c in chosen {
            let (mi, r) = self.records[c];
            let m = &campaign.measurements[mi];
            let k = m.instrument.poses_per_record();
            let n = machine.axis_count();
            let pose = &m.poses[r * k * n..r * k * n + n];
            text += &format!("{},{},{}\n", m.name, m.lines[r], pose.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(","));
        }
        text
    }
}

fn criteria_json(c: &DesignCriteria) -> Value {
    json!({"d": c.d, "a": c.a, "e": c.e, "g": c.g, "average_variance": c.average_variance, "max_reading_variance": c.max_reading_variance})
}

/// The document of `trueaxis design optimal --json`: the criterion, the chosen records
/// (measurement and line), the criteria of the chosen design and of all candidates.
pub fn optimal_design_json(
    campaign: &Campaign,
    candidates: &CampaignCandidates,
    criterion: Criterion,
    count: usize,
    chosen: &[usize],
    criteria: &DesignCriteria,
    all: &DesignCriteria,
) -> Value {
    let records: Vec<Value> = chosen
        .iter()
        .map(|&c| {
            let (mi, r) = candidates.records[c];
            json!({"measurement": campaign.measurements[mi].name, "line": campaign.measurements[mi].lines[r]})
        })
        .collect();
    json!({
        "criterion": format!("{criterion:?}").to_lowercase(),
        "count": count,
        "parameters": candidates.parameters,
        "chosen": records,
        "criteria": criteria_json(criteria),
        "all_candidates": criteria_json(all),
        "candidates": candidates.set.len(),
        "units": units_json(&candidates.parameters, &candidates.units, &criteria_units(&candidates.units), criteria),
    })
}

/// The units the criteria are computed in, and their values in Soons 1993's units where the
/// unknowns allow (`identify::design_units`).
pub fn units_json(names: &[String], units: &[String], u: &CriteriaUnits, chosen: &DesignCriteria) -> Value {
    let parameters: serde_json::Map<String, Value> = names.iter().zip(units).map(|(n, u)| (n.clone(), json!(u))).collect();
    json!({
        "sigma": "readings weighted by 1/sigma with sigma in um: variances per sigma^2 = 1 um^2",
        "parameters": parameters,
        "d": u.d,
        "a": u.a_e,
        "e": u.a_e,
        "g": "1 (reading variances over sigma^2)",
        "seed000": {
            "d_factor": u.d_to_seed000,
            "a_e_factor": u.a_e_to_seed000,
            "d": u.d_to_seed000.map(|f| f * chosen.d),
            "a": u.a_e_to_seed000.map(|f| f * chosen.a),
            "e": u.a_e_to_seed000.map(|f| f * chosen.e),
        },
    })
}
