//! The rotary-axis ballbar test of Jiang 2014 from its four files, end to end, and the sensitivity of
//! its method, with the documents of `trueaxis ballbar identify --json` and `trueaxis ballbar
//! sensitivity --json`. The command line and the Python package both call [`identify_pige_files`]
//! and [`sensitivity_report`].
//!
//! Units: bar lengths, offsets and positions in mm; readings, noise and uncertainties of the
//! setup in um; PIGEs reported in um (translations) and urad (rotations), kept in mm and rad inside.

use super::pige::{
    angle_span_deg, compensation_residual, identify_piges, pige_uncertainty, repeatability, start_angle_error, DbbTrace, Piges,
    Repeatability, MIN_READINGS, MIN_SPAN_DEG,
};
use super::pige_sensitivity::{method_sensitivity, MethodSensitivity};
use super::IdentifyError;
use crate::error::{Error, ErrorKind, Result};
use crate::instruments::ballbar::{method_step, read_trace, BarLengths, JiangStep, Method, RotaryGeometry, RotaryPair, TraceFile};
use crate::machine::{Machine, ParameterId};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Bad input (a file, an option), by its message.
fn input(e: impl std::fmt::Display) -> Error {
    Error::input(e.to_string())
}

/// An error of the identification: bad input stays bad input, the rest failed.
fn identify_failure(e: IdentifyError) -> Error {
    let kind = if matches!(e, IdentifyError::Input(_)) { ErrorKind::Input } else { ErrorKind::Computation };
    Error::new(kind, e.to_string())
}

fn round(v: f64, digits: i32) -> f64 {
    let f = 10f64.powi(digits);
    (v * f).round() / f
}

/// User value and unit of a PIGE (mm or rad inside): um or urad.
pub fn pige_user_value(id: &ParameterId, v: f64) -> (f64, &'static str) {
    match id {
        ParameterId::Location { component, .. } if component.is_rotation() => (v * 1e6, "urad"),
        _ => (v * 1e3, "um"),
    }
}

/// The bar lengths of a test: normal `R` and extended `L_e` (mm), `L_e > R > 0`.
pub fn bar_lengths(normal: f64, extended: f64) -> Result<BarLengths> {
    if !(normal > 0.0 && extended > normal) {
        return Err(input("--extended-length must exceed --normal-length > 0 (mm)"));
    }
    Ok(BarLengths { normal, extended })
}

/// The method of the four steps by name (`extended-bar`, `two-pivot`, `four-setup`; Jiang 2014 ch.
/// 5, 4, 6) with its geometry: the outer offset (mm) of two-pivot, the positions p1, p2 (mm) along
/// the outer and the inner axis of four-setup.
pub fn method_of(
    name: &str,
    outer_offset: Option<f64>,
    outer_positions: Option<[f64; 2]>,
    inner_positions: Option<[f64; 2]>,
) -> Result<Method> {
    let need = |what: &str| input(format!("this --method needs {what}"));
    Ok(match name {
        "extended-bar" => Method::ExtendedBar,
        "two-pivot" => Method::TwoPivot { outer_offset: outer_offset.ok_or_else(|| need("--outer-offset MM (two-pivot)"))? },
        "four-setup" => Method::FourSetup {
            outer: outer_positions.ok_or_else(|| need("--outer-positions P1,P2 (four-setup, mm)"))?,
            inner: inner_positions.ok_or_else(|| need("--inner-positions P1,P2 (four-setup, mm)"))?,
        },
        other => return Err(input(format!("--method `{other}`: expected extended-bar, two-pivot or four-setup"))),
    })
}

/// A misplaced pivot (Eq. 4.1) must be small against the bar: the correction is an angle about the
/// nominal centre, meaningless once the pivot is a sizeable part of the radius away.
pub const MAX_PIVOT_OFFSET: f64 = 0.1;

/// A step's trace must hold enough of a circle for the fit: `MIN_READINGS` readings over at least
/// `MIN_SPAN_DEG` of rotation (`identify::pige`).
pub fn check_trace(angles: &[f64]) -> Result<()> {
    let span = angle_span_deg(angles);
    if angles.len() < MIN_READINGS || span < MIN_SPAN_DEG {
        return Err(Error::input(format!(
            "{} readings over {span:.1} deg of rotation; a circle fit needs at least {MIN_READINGS} readings over at least {MIN_SPAN_DEG} deg \
             (is this the file of this step?)",
            angles.len()
        )));
    }
    Ok(())
}

/// The inputs of a rotary-axis ballbar test (Jiang 2014 ch. 4, 5, 6).
#[derive(Clone, Debug)]
pub struct PigeRequest {
    /// The files of the steps A1, A2 (outer axis) and C1, C2 (inner axis): the swept axis position
    /// (column of its letter or `angle`, deg), `dL` (um), an optional integer `run`.
    pub files: [PathBuf; 4],
    pub method: Method,
    pub bars: BarLengths,
    /// Misplacement of the outer-axis pivot from a centring test: radial, tangential (mm), Eq. 4.1.
    pub pivot_offset_outer: Option<[f64; 2]>,
    /// Misplacement of the inner-axis pivot (mm).
    pub pivot_offset_inner: Option<[f64; 2]>,
    /// Expected noise of the bar readings (um, standard deviation): a step whose compensation
    /// residual RMS exceeds 3 times it is warned about.
    pub noise_um: f64,
}

/// One step of the last run after the identification: its readings and what is left of them once
/// the identified PIGEs are compensated (simulated on the exact chain).
#[derive(Clone, Debug)]
pub struct StepResidual {
    pub step: JiangStep,
    pub path: PathBuf,
    pub geometry: RotaryGeometry,
    /// Axis positions (rad) and readings (mm) of the last run.
    pub angles: Vec<f64>,
    pub dl: Vec<f64>,
    /// The readings minus the identified PIGEs' effect (mm).
    pub residual: Vec<f64>,
    pub rms_um: f64,
    pub band_um: f64,
}

/// The PIGEs of every run, their repeatability and single-run uncertainty, and the compensation
/// residual of the last run.
#[derive(Clone, Debug)]
pub struct PigeReport {
    pub machine: String,
    pub method: Method,
    /// The run numbers, in order of the files.
    pub runs: Vec<i64>,
    /// The PIGEs of each run (mm, rad).
    pub results: Vec<Piges>,
    /// Standard uncertainty of the last run's PIGEs (mm, rad) from the scatter of its traces about
    /// their circles; none when a trace has too few readings to say.
    pub single_u: Option<Vec<f64>>,
    pub stats: Repeatability,
    pub steps: Vec<StepResidual>,
    /// The files' metadata, by step.
    pub metadata: Vec<(JiangStep, crate::io::Metadata)>,
    /// Plausibility warnings of the files, then compensation residuals above 3 times the noise.
    pub warnings: Vec<String>,
}

impl PigeReport {
    /// The PIGEs of the last run.
    pub fn last(&self) -> &Piges {
        // `identify_pige_files` returns one result per run, and at least one run
        &self.results[self.results.len() - 1]
    }

    /// True when the files hold more than one run (the repeatability is then reported).
    pub fn repeated(&self) -> bool {
        self.runs.len() > 1
    }

    /// The error-values TOML of the last run's PIGEs (`trueaxis ballbar identify --out`): each in
    /// `[constant]` (um, urad) and, where the traces allow it, its single-run standard uncertainty
    /// (or, over several runs, the larger of it and their standard deviation) in `[uncertainty]`, so
    /// that `compensate`, `predict` and `report` read the identified values and `compensate` states
    /// what their uncertainty leaves.
    pub fn error_values_text(&self, origin: &str) -> Result<String> {
        // the PIGEs are numbers of the fit: a document that cannot hold them is a failed computation
        let failed = |e: Error| Error::computation(e.message());
        let mut text = format!(
            "# The PIGEs of the rotary axes identified by `trueaxis ballbar identify` ({} method of Jiang (2014), {} run(s)) from {origin}\n\
             name = \"PIGEs of {}\"\n",
            self.method.name(),
            self.runs.len(),
            self.machine.replace('"', "'")
        );
        for (k, ((id, v), (_, _, sd))) in self.last().values.iter().zip(&self.stats.parameters).enumerate() {
            text = crate::error_model::set_error_function(
                &text,
                id,
                None,
                &crate::error_model::ErrorFunction::Constant(pige_user_value(id, *v).0),
            )
            .map_err(failed)?;
            let single = self.single_u.as_ref().map(|s| pige_user_value(id, s[k]).0);
            let spread = self.repeated().then(|| pige_user_value(id, *sd).0);
            if let Some(u) = single.into_iter().chain(spread).reduce(f64::max).filter(|u| u.is_finite()) {
                text = crate::error_model::set_uncertainty(&text, id, u).map_err(failed)?;
            }
        }
        Ok(text)
    }

    /// The document of `trueaxis ballbar identify --json`: per PIGE the last run's value, the mean
    /// and standard deviation over runs (um or urad, rounded to 1e-4), the single-run standard
    /// uncertainty; the repeatability verdict, the compensation residual per step, warnings and
    /// the files' metadata.
    pub fn to_json(&self) -> Value {
        let repeated = self.repeated();
        let mut params = serde_json::Map::new();
        for (k, ((id, v), (_, mean, sd))) in self.last().values.iter().zip(&self.stats.parameters).enumerate() {
            let (u, unit) = pige_user_value(id, *v);
            let sd = repeated.then(|| round(pige_user_value(id, *sd).0, 4));
            let std_uncertainty = self.single_u.as_ref().map(|s| round(pige_user_value(id, s[k]).0, 4));
            params.insert(
                id.to_string(),
                json!({"value": round(u, 4), "unit": unit, "mean": round(pige_user_value(id, *mean).0, 4), "std": sd,
                       "std_uncertainty": std_uncertainty}),
            );
        }
        let comp: Vec<_> = self
            .steps
            .iter()
            .map(|s| json!({"step": s.step.name(), "rms_um": round(s.rms_um, 4), "band_um": round(s.band_um, 4)}))
            .collect();
        let metadata: serde_json::Map<String, Value> =
            self.metadata.iter().map(|(step, m)| (step.name().to_string(), m.to_json())).collect();
        json!({"machine": self.machine, "method": self.method.name(), "runs": self.runs.len(), "parameters": params,
            "repeatability_ok": repeated.then_some(self.stats.within_tolerance), "compensation_residual": comp, "warnings": self.warnings,
            "metadata": metadata})
    }
}

/// The 8 PIGEs of the machine's two rotary axes from the four steps of Jiang 2014 (algebraic circle
/// fits, the axis lines, the start-angle correction of Eq. 4.1), for every run of the files;
/// their repeatability over runs, the single-run uncertainty of the last run, and its simulated
/// compensation residual per step.
pub fn identify_pige_files(machine: &Machine, request: &PigeRequest) -> Result<PigeReport> {
    let m = machine;
    let pair = RotaryPair::of_machine(m).map_err(input)?;
    let bars = request.bars;
    if !(request.noise_um > 0.0 && request.noise_um.is_finite()) {
        return Err(input(format!("--noise must be a positive number of um, got {}", request.noise_um)));
    }
    for (flag, offset) in [("--pivot-offset-a", request.pivot_offset_outer), ("--pivot-offset-c", request.pivot_offset_inner)] {
        if let Some([r, t]) = offset.filter(|[r, t]| r.hypot(*t) >= MAX_PIVOT_OFFSET * bars.normal) {
            return Err(input(format!(
                "{flag} {r},{t}: the pivot is {:.3} mm from its nominal place; the start-angle correction (Eq. 4.1) is for a misplacement below {} mm ({} % of R = {} mm)",
                r.hypot(t),
                MAX_PIVOT_OFFSET * bars.normal,
                MAX_PIVOT_OFFSET * 100.0,
                bars.normal
            )));
        }
    }
    let files = [JiangStep::A1, JiangStep::A2, JiangStep::C1, JiangStep::C2].into_iter().zip(&request.files);
    let mut steps: Vec<(JiangStep, &Path, TraceFile, _)> = Vec::new();
    for (step, path) in files {
        let axis = if step.is_outer() { pair.outer } else { pair.inner };
        let trace = read_trace(path, &[&axis.to_string(), "angle"]).map_err(input)?;
        let test = method_step(m, pair, request.method, step, bars, 1.0).map_err(input)?;
        steps.push((step, path.as_path(), trace, test));
    }
    let runs = steps[0].2.run_numbers();
    if let Some((_, path, _, _)) = steps.iter().find(|s| s.2.run_numbers() != runs) {
        return Err(input(format!("{}: the run numbers differ from those of {}", path.display(), steps[0].1.display())));
    }
    let mut results: Vec<Piges> = Vec::new();
    let mut last_traces = (Vec::new(), Vec::new());
    for &run in &runs {
        let mut outer = Vec::new();
        let mut inner = Vec::new();
        for (step, path, trace, test) in &steps {
            let (angles, dl) = trace.run(run);
            let axis = if step.is_outer() { pair.outer } else { pair.inner };
            check_trace(&angles)
                .map_err(|why| input(format!("{}: step {} (axis {axis}), run {run}: {why}", path.display(), step.name())))?;
            let geometry = test.rotary.ok_or_else(|| Error::computation(format!("step {} is not a rotary-axis test", step.name())))?;
            let offset = if step.is_outer() { request.pivot_offset_outer } else { request.pivot_offset_inner };
            let start_angle = offset.map_or(0.0, |o| start_angle_error(o[0], o[1], bars.normal));
            let t = DbbTrace { geometry, angles, dl, bar_length: test.nominal_length, start_angle };
            if step.is_outer() {
                outer.push(t)
            } else {
                inner.push(t)
            }
        }
        results.push(identify_piges(m, pair, &outer, &inner).map_err(identify_failure)?);
        last_traces = (outer, inner);
    }
    let Some(last) = results.last() else {
        return Err(input(format!("{}: no readings", steps[0].1.display())));
    };
    // the standard uncertainty of the last run's PIGEs from the scatter of its traces
    let single_u = pige_uncertainty(m, pair, &last_traces.0, &last_traces.1).map_err(|e| Error::computation(e.to_string()))?;
    let stats = repeatability(&results, 1e-3, (1.0f64 / 3600.0).to_radians()).map_err(|e| Error::computation(e.to_string()))?;
    // the plausibility warnings of the files, then those of the residuals
    let mut warnings: Vec<String> = steps.iter().flat_map(|s| s.2.warnings.clone()).collect();
    let mut residuals = Vec::new();
    let last_run = runs[runs.len() - 1];
    for (step, path, trace, test) in &steps {
        let (angles, dl) = trace.run(last_run);
        let mut t = test.clone();
        let n = m.axis_count();
        let geometry = test.rotary.ok_or_else(|| Error::computation(format!("step {} is not a rotary-axis test", step.name())))?;
        let axis = geometry.axis;
        t.poses = angles.iter().flat_map(|&q| (0..n).map(move |k| if k == axis { q } else { 0.0 })).collect();
        t.angles = angles.clone();
        let r = compensation_residual(m, &t, &dl, last);
        let rms = (r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt() * 1e3;
        let band = (r.iter().copied().fold(f64::NEG_INFINITY, f64::max) - r.iter().copied().fold(f64::INFINITY, f64::min)) * 1e3;
        if rms > 3.0 * request.noise_um {
            warnings.push(format!(
                "step {} ({}): the compensation residual RMS {rms:.2} um is more than 3 x the expected bar noise {} um (--noise): \
                 the trace is not the circle of an axis line (wrong file or step, motion errors of the axis, or a loose setup)",
                step.name(),
                path.display(),
                request.noise_um
            ));
        }
        residuals.push(StepResidual {
            step: *step,
            path: path.to_path_buf(),
            geometry,
            angles,
            dl,
            residual: r,
            rms_um: rms,
            band_um: band,
        });
    }
    let metadata = steps.iter().map(|(step, _, trace, _)| (*step, trace.metadata.clone())).collect();
    Ok(PigeReport { machine: m.name.clone(), method: request.method, runs, results, single_u, stats, steps: residuals, metadata, warnings })
}

/// The sensitivity of a method to its setup and to bar noise (`identify::pige_sensitivity`) with
/// the combined standard uncertainty for the given setup, bar and noise uncertainties.
#[derive(Clone, Debug)]
pub struct SensitivityReport {
    pub machine: String,
    pub method: Method,
    pub bars: BarLengths,
    /// Standard uncertainty of each ball's placement along X, Y, Z (um).
    pub setup_u_um: f64,
    /// Standard uncertainty of each bar's calibrated length (um).
    pub bar_u_um: f64,
    /// Standard deviation of the bar readings (um).
    pub noise_um: f64,
    pub sensitivity: MethodSensitivity,
    /// Combined standard uncertainty of each PIGE (mm or rad).
    pub combined: Vec<f64>,
}

impl SensitivityReport {
    /// Change of PIGE `p` (um or urad) per um of input, from a value in mm (rad) per mm.
    pub fn per_um(&self, p: usize, v: f64) -> f64 {
        pige_user_value(&self.sensitivity.parameters[p], v).0 * 1e-3
    }

    /// The document of `trueaxis ballbar sensitivity --json`.
    pub fn to_json(&self) -> Value {
        let s = &self.sensitivity;
        let params: Vec<_> = s
            .parameters
            .iter()
            .enumerate()
            .map(|(p, id)| {
                let sources: Vec<_> = s
                    .sources
                    .iter()
                    .map(|x| json!({"step": x.step.name(), "source": x.name, "per_um": round(self.per_um(p, x.effect[p]), 6)}))
                    .collect();
                json!({"name": id.to_string(), "unit": pige_user_value(id, 0.0).1, "noise_per_um": round(self.per_um(p, s.noise[p]), 6),
                       "combined_u": round(pige_user_value(id, self.combined[p]).0, 4), "setup": sources})
            })
            .collect();
        json!({"machine": self.machine, "method": self.method.name(), "setup_u_um": self.setup_u_um, "bar_u_um": self.bar_u_um,
               "noise_um": self.noise_um, "parameters": params})
    }
}

/// How the method `method` with bars `bars` on `machine` reacts to each setup error and to bar
/// noise, before it is run; the combined uncertainty for standard uncertainties `setup_u_um`,
/// `bar_u_um` and `noise_um` (um, each between 0 and 1000).
pub fn sensitivity_report(
    machine: &Machine,
    method: Method,
    bars: BarLengths,
    setup_u_um: f64,
    bar_u_um: f64,
    noise_um: f64,
) -> Result<SensitivityReport> {
    for (flag, v) in [("--setup-u", setup_u_um), ("--bar-u", bar_u_um), ("--noise", noise_um)] {
        if !(v.is_finite() && (0.0..=1000.0).contains(&v)) {
            return Err(input(format!("{flag} {v}: give a standard uncertainty in um between 0 and 1000")));
        }
    }
    let pair = RotaryPair::of_machine(machine).map_err(input)?;
    let steps = [JiangStep::A1, JiangStep::A2, JiangStep::C1, JiangStep::C2]
        .into_iter()
        .map(|s| Ok((s, method_step(machine, pair, method, s, bars, 1.0).map_err(input)?)))
        .collect::<Result<Vec<_>>>()?;
    let sensitivity = method_sensitivity(machine, pair, &steps).map_err(identify_failure)?;
    let combined = sensitivity.combined(setup_u_um * 1e-3, bar_u_um * 1e-3, noise_um * 1e-3);
    Ok(SensitivityReport { machine: machine.name.clone(), method, bars, setup_u_um, bar_u_um, noise_um, sensitivity, combined })
}
