//! The demo's CapBall campaign: simulation with noise and cyclic drift, identification, Monte Carlo
//! uncertainty, the volumetric error before and after compensation, compensation tables.

use super::maps::{magnitudes_um, statistics, VolumeMap};
use super::{DemoError, Output, CAMPAIGN_POSES_CSV, CAMPAIGN_TOML, SOURCES_TOML};
use crate::compensate::export::{self, ExportInput, Limits};
use crate::compensate::{axis_tables, volumetric_grid, Corrector, TableSpec};
use crate::errors::ErrorModel;
use crate::identify::{self, error_values_text, measurement_csv, simulate_campaign, Campaign, Identification, IndirectOptions};
use crate::machine::Machine;
use crate::report::uncertainty_figures;
use crate::uncertainty::{from_identification, run_budget, Budget, Evaluation, IdentificationMap, McSettings, SourceKind, Sources};
use std::path::PathBuf;

/// Seed of the simulated noise (ChaCha8) and start phase of the simulated drift.
const SEED: u64 = 2011;
/// Time per CapBall point (s): the 807 points take 10 minutes.
pub const POINT_TIME_S: f64 = 0.75;
/// Phase of the simulated drift cycle at the first point (deg).
const DRIFT_PHASE_DEG: f64 = 40.0;

pub struct Simulated {
    pub campaign_path: PathBuf,
    /// Peak-to-valley of the simulated drift per channel (um) and its period (s).
    pub drift: Vec<(String, f64)>,
    pub drift_period_s: f64,
    pub noise_um: Vec<f64>,
    pub records: usize,
}

pub struct Identified {
    pub campaign: Campaign,
    pub design: identify::DesignMatrix,
    pub result: Identification,
    /// The identified error model (what compensation uses).
    pub errors: ErrorModel,
    /// The values the identification gives on the same poses without noise and drift: the true
    /// errors expressed in the campaign's parameter set (where the set cannot separate two true
    /// errors, their combination; see the identifiability report).
    pub equivalent_truth: Vec<f64>,
}

pub struct UncertaintyOutcome {
    pub sources: Sources,
    pub budget: Budget,
    pub histograms_svg: String,
    pub convergence_svg: Option<String>,
}

pub struct Volume {
    pub poses: usize,
    /// `(largest, RMS)` of `|d|` (um) before and after compensation.
    pub before: (f64, f64),
    pub after: (f64, f64),
    pub max_pose: Vec<(char, f64)>,
    pub before_svg: String,
    pub after_svg: String,
}

pub struct Tables {
    pub files: Vec<PathBuf>,
    /// Largest correction of a linear axis (um) and of a rotary axis (urad) in the tables.
    pub max_um: f64,
    pub max_urad: f64,
}

fn sources() -> Result<Sources, DemoError> {
    Ok(Sources::from_toml_str(SOURCES_TOML, "built-in kx8five_cyclic.toml")?)
}

/// Writes the campaign and its 807 poses, simulates the readings on the exact chain with the true
/// errors, the Table 3 sensor noise and the cyclic drift of the sources file (drift added at
/// `t = k POINT_TIME_S` for point `k`), and writes them as the campaign data.
pub fn simulate(machine: &Machine, truth: &ErrorModel, out: &mut Output) -> Result<Simulated, DemoError> {
    let campaign_path = out.write("campaign/campaign.toml", CAMPAIGN_TOML.as_bytes())?;
    out.write("campaign/capball.csv", CAMPAIGN_POSES_CSV.as_bytes())?;
    let campaign = Campaign::load(&campaign_path, machine)?;
    let mut readings = simulate_campaign(&campaign, machine, truth, Some(SEED))?;
    let sources = sources()?;
    let mut drift = Vec::new();
    let mut drift_period_s = 0.0;
    for s in &sources.sources {
        if let SourceKind::CyclicDrift(cyclic) = &s.kind {
            drift_period_s = cyclic.period();
            let phase_s = DRIFT_PHASE_DEG / 360.0 * drift_period_s;
            for (channel, function) in &cyclic.channels {
                let c = ["x", "y", "z"].iter().position(|n| n == channel).unwrap_or(0);
                for (k, record) in readings[0].chunks_mut(3).enumerate() {
                    record[c] += function.value(phase_s + k as f64 * POINT_TIME_S);
                }
                drift.push((channel.clone(), function.peak_to_valley()));
            }
        }
    }
    let m = &campaign.measurements[0];
    let csv = measurement_csv(machine, m, &readings[0]);
    out.write("campaign/capball.csv", csv.as_bytes())?;
    Ok(Simulated { campaign_path, drift, drift_period_s, noise_um: m.sigma_um.clone(), records: m.records() })
}

/// Identifies the campaign's parameters from the simulated data and writes the identified errors.
pub fn identify(machine: &Machine, truth: &ErrorModel, simulated: &Simulated, out: &mut Output) -> Result<Identified, DemoError> {
    let campaign = Campaign::load(&simulated.campaign_path, machine)?;
    let nominal = campaign.nominal_errors(machine)?;
    let design = campaign.design_matrix(machine, &nominal)?;
    let start = campaign.nominal_values(&nominal)?;
    let options = IndirectOptions::default();
    let result = identify::solve(&design, &start, &options)?;
    let mut exact = campaign.clone();
    for (m, readings) in exact.measurements.iter_mut().zip(simulate_campaign(&campaign, machine, truth, None)?) {
        m.readings = Some(readings);
    }
    let equivalent_truth = identify::solve(&exact.design_matrix(machine, &nominal)?, &start, &options)?.values;
    let text = error_values_text(&result, &campaign, &nominal, "")?;
    out.write("identified.toml", text.as_bytes())?;
    out.write("identification.json", format!("{:#}\n", identify::identification_json(&result, &campaign)).as_bytes())?;
    let errors = ErrorModel::from_toml_str(&text, "identified errors", machine)?;
    Ok(Identified { campaign, design, result, errors, equivalent_truth })
}

/// Adaptive Monte Carlo with all sources and each alone (seed 004 Table 5), and its figures.
pub fn uncertainty(identified: &Identified, out: &mut Output) -> Result<UncertaintyOutcome, DemoError> {
    let sources = sources()?;
    let design = from_identification(&identified.design, POINT_TIME_S)?;
    sources.check_channels(&design)?;
    out.write("uncertainty/design.csv", design.to_csv().as_bytes())?;
    out.write("uncertainty/sources.toml", SOURCES_TOML.as_bytes())?;
    let map = IdentificationMap::new(design)?;
    let settings: McSettings = sources.settings.clone();
    let budget = run_budget(&map, &sources.sources, &settings, Evaluation::Reduced, true, &mut |_, _, _| {})?;
    let (histograms_svg, convergence_svg) = uncertainty_figures(&budget, &settings)?;
    out.write("uncertainty/histograms.svg", histograms_svg.as_bytes())?;
    if let Some(svg) = &convergence_svg {
        out.write("uncertainty/convergence.svg", svg.as_bytes())?;
    }
    Ok(UncertaintyOutcome { sources, budget, histograms_svg, convergence_svg })
}

/// The volumetric error over the work volume with the true errors (before compensation) and what
/// is left when the identified errors are compensated: `e_true - e_identified` at each pose (the
/// compensation cancels the identified error exactly on its model; evaluating the true errors at
/// the corrected set-points instead changes the result by the variation of the errors over the
/// correction, below 1e-3 um for these corrections of tens of micrometres).
pub fn volume(machine: &Machine, truth: &ErrorModel, identified: &Identified, out: &mut Output) -> Result<Volume, DemoError> {
    let map = VolumeMap::new(machine);
    let before = map.predict(machine, truth);
    let model = map.predict(machine, &identified.errors);
    let after: Vec<_> = before
        .iter()
        .zip(&model)
        .map(|(b, m)| crate::model::VolumetricError {
            position: b.position - m.position,
            orientation: b.orientation - m.orientation,
            length: b.length - m.length,
        })
        .collect();
    let (mb, ma) = (magnitudes_um(&before), magnitudes_um(&after));
    let (max_b, imax, rms_b) = statistics(&mb);
    let (max_a, _, rms_a) = statistics(&ma);
    let n = machine.axis_count();
    let max_pose = machine.axes().iter().map(|a| a.letter).zip(map.poses_user[imax * n..(imax + 1) * n].iter().copied()).collect();
    let before_svg = map.heatmap(&format!("Before compensation: |d| (machine frame), {}", machine.name), &mb)?;
    let after_svg = map.heatmap("After compensation with the identified errors: |d| (machine frame)", &ma)?;
    out.write("volumetric_map.csv", map.csv(machine, &before)?.as_bytes())?;
    out.write("volumetric_map.svg", before_svg.as_bytes())?;
    out.write("volumetric_map_compensated.csv", map.csv(machine, &after)?.as_bytes())?;
    out.write("volumetric_map_compensated.svg", after_svg.as_bytes())?;
    Ok(Volume { poses: map.len(machine), before: (max_b, rms_b), after: (max_a, rms_a), max_pose, before_svg, after_svg })
}

/// Own-axis and cross-axis correction tables (33 points per axis) and a 9 x 9 x 6 volumetric grid
/// from the identified errors, as plain CSV (`trueaxis compensate --format csv`).
pub fn compensation_tables(machine: &Machine, identified: &Identified, out: &mut Output) -> Result<Tables, DemoError> {
    let corrector = Corrector::new(machine, &identified.errors);
    let spec = TableSpec { points: 33, reference: None, temperatures: Vec::new() };
    let tables = axis_tables(&corrector, &spec)?;
    let grid = volumetric_grid(&corrector, [9, 9, 6], &spec)?;
    let input = ExportInput { machine, errors: &identified.errors, tables: &tables, grid: Some(&grid), limits: Limits::default() };
    let mut files = Vec::new();
    for f in export::plain::export_csv(&input)? {
        files.push(out.write(&format!("compensation/{}", f.name), f.contents.as_bytes())?);
    }
    let (mut max_um, mut max_urad) = (0.0f64, 0.0f64);
    for t in &tables.tables {
        let v = export::to_micro(machine, t.corrected, t.max_abs());
        if export::micro_unit(machine, t.corrected) == "um" {
            max_um = max_um.max(v);
        } else {
            max_urad = max_urad.max(v);
        }
    }
    Ok(Tables { files, max_um, max_urad })
}
