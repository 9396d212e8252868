//! Ballbar diagnostics of a planar circular test, identified by a linear least-squares fit of the
//! first-order model on the machine's own kinematic model (the `dL` row of the Jacobian, Soons 1993
//! eq. 2.24, at every sample) rather than by lookup rules on the plot shape.
//!
//! Each diagnostic is an error function of one axis of the plane (positions `a`, `b` about the
//! programmed centre, radius `R`, direction of motion `s = sign(v)`) whose value at a sample is
//! multiplied by the Jacobian column of the ISO parameter it acts on:
//!
//! Own-axis terms (scale, backlash, spikes, cyclic, servo) are errors `u` along the direction in which
//! the axis moves (`E<a><a> = u` times the sign of the axis direction along its coordinate: a slide
//! that carries the workpiece with direction `-x` has `EXX = -u`); cross terms (lateral play,
//! straightness) and the squareness are the ISO parameters themselves (machine coordinates, actual
//! minus nominal of the carried body).
//!
//! | diagnostic | parameter | error function |
//! |---|---|---|
//! | centre offset | `W<a>`, `W<b>` | constant (reported as the path centre relative to the pivot, `-W`) |
//! | radius change | (bar length) | constant `dL` |
//! | squareness | `EC0Y` (xy), `EA0Z` (yz), `EB0Z` (zx); `EC0X`, `EA0Y`, `EB0X` when the second axis carries the first | constant |
//! | scale mismatch `m` | `E<a><a>`, `E<b><b>` | `u = +m a / 2`, `-m b / 2` |
//! | backlash (lost motion) `B` | `E<a><a>` | `u = -B s / 2` |
//! | lateral play `p` | `E<b><a>` | `+p s / 2` |
//! | reversal spike `h` | `E<a><a>` | `u = -h s exp(-phi / w)`, `phi` the path angle since the axis reversed |
//! | cyclic error (pitch `P`) | `E<a><a>` | `u = c cos(2 pi q / P) + d sin(2 pi q / P)`, `q` the axis position |
//! | servo mismatch `delta` | `E<a><a>` | `u = -delta v_a / omega`: the lag of axis a behind b as a path angle |
//! | straightness `t` | `E<b><a>` | `t (1 - (a / R)^2)`: bow at the centre relative to the ends |
//!
//! Positive backlash is lost motion (the axis lags on reversal; ISO 230-2's reversal value of the
//! axis is `-B`); a positive reversal spike is a lag right after reversal (a spike outward on the
//! plot); positive servo mismatch means axis a lags axis b. The common scale error of both axes
//! cannot be told from a bar-length error and is part of the radius change. Direction-dependent
//! terms need CW and CCW runs to be separated from the direction-independent ones; the servo
//! mismatch is only fitted when both are present.

use crate::identify::{fit_linear, IdentifyError};
use crate::instruments::ballbar::{BallbarTest, Plane, Rotation};
use crate::machine::Machine;
use nalgebra::DMatrix;

/// One run of a circular test: the test (poses, angles) and the bar readings `dl` (mm).
#[derive(Clone, Debug)]
pub struct CircularRun {
    pub rotation: Rotation,
    pub test: BallbarTest,
    pub dl: Vec<f64>,
}

/// Settings of the diagnostics fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiagnosticOptions {
    pub plane: Plane,
    /// Test radius (mm).
    pub radius: f64,
    /// Programmed centre in the plane's two axes (mm).
    pub centre: [f64; 2],
    /// Pitch of the ball screws (mm) for the cyclic-error terms; none: not fitted.
    pub pitch: Option<f64>,
    /// Decay angle of reversal spikes (rad).
    pub spike_width: f64,
    /// Feed rate (mm/min), to state the servo mismatch in ms.
    pub feed: Option<f64>,
}

/// One identified diagnostic: a term of the fit whose value is at least its standard
/// uncertainty (weaker terms are refitted out and listed in [`Diagnostics::omitted`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// e.g. `squareness`, `backlash X`.
    pub name: String,
    /// The ISO parameter it acts on (`EC0Y`, `EXX`), or empty.
    pub parameter: String,
    pub value: f64,
    pub std_uncertainty: f64,
    pub unit: &'static str,
    /// Peak-to-valley of its fitted effect on the bar reading (um) and its share of the sum of the
    /// effects of at least [`RESOLUTION_UM`] (%; 0 below it).
    pub effect_um: f64,
    pub share_percent: f64,
}

/// The fit: diagnostics sorted by effect, residual RMS (um), samples used.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostics {
    pub items: Vec<Diagnostic>,
    pub residual_rms_um: f64,
    pub samples: usize,
    /// Terms left out, with why.
    pub omitted: Vec<String>,
    /// The fitted model of the bar reading (um), per run and sample.
    pub model_um: Vec<Vec<f64>>,
}

/// Column builder: name, parameter, unit, factor from the fitted value to the user unit, and the
/// regressor values over all samples.
struct Column {
    name: String,
    parameter: String,
    unit: &'static str,
    to_user: f64,
    values: Vec<f64>,
    /// Nuisance columns (centre, radius) are not ranked.
    ranked: bool,
}

/// Candidate squareness parameters of a plane: the orientation error of the second axis about the
/// normal (ISO 230-7 with the first axis as reference), or of the first axis when the second carries
/// it (then the first has the signal: a rotation of the carrying axis turns the whole stack).
fn squareness_candidates(plane: Plane) -> [&'static str; 2] {
    match plane {
        Plane::Xy => ["EC0Y", "EC0X"],
        Plane::Yz => ["EA0Z", "EA0Y"],
        Plane::Zx => ["EB0Z", "EB0X"],
    }
}

/// Per-sample quantities of one axis of the plane: offset from the centre (mm), position (mm),
/// direction sign, path angle since its last reversal (rad), velocity per unit path angle (mm/rad).
struct AxisSample {
    offset: f64,
    position: f64,
    sign: f64,
    since_reversal: f64,
    velocity: f64,
}

fn axis_sample(theta: f64, phase: f64, rotation: Rotation, radius: f64, centre: f64) -> AxisSample {
    // a = R cos(theta - phase); da/dtheta = -R sin(theta - phase)
    let sigma = rotation.sign();
    let offset = radius * (theta - phase).cos();
    let velocity = -sigma * radius * (theta - phase).sin();
    let sign = if velocity > 1e-12 * radius {
        1.0
    } else if velocity < -1e-12 * radius {
        -1.0
    } else {
        0.0
    };
    // reversals at theta - phase = 0, pi; angle travelled since the last one
    let since_reversal = (sigma * (theta - phase)).rem_euclid(std::f64::consts::PI);
    AxisSample { offset, position: centre + offset, sign, since_reversal, velocity }
}

/// Effects (peak to valley on the trace) below this (um) get no share: the resolution of a
/// ballbar (0.1 um for the QC20-W, Jiang 2014 Table 4.1).
pub const RESOLUTION_UM: f64 = 0.1;

/// Value and standard uncertainty of a term from its fitted coefficients: one coefficient, or the
/// amplitude `sqrt(c^2 + s^2)` of a cos/sin pair (first-order propagation).
fn term_value(coefficients: &[f64], u: &[f64]) -> (f64, f64) {
    match (coefficients, u) {
        ([c, s], [uc, us]) => {
            let amp = c.hypot(*s);
            let ua = if amp > 0.0 { ((c * uc).powi(2) + (s * us).powi(2)).sqrt() / amp } else { uc.max(*us) };
            (amp, ua)
        }
        _ => (coefficients[0].abs(), u[0]),
    }
}

/// Whether the unit-scaled columns `cols` are linearly independent (smallest singular value above
/// 1e-6 of the largest).
fn independent(columns: &[Column], cols: &[usize]) -> bool {
    let n = columns[cols[0]].values.len();
    let mut m = DMatrix::from_fn(n, cols.len(), |i, k| columns[cols[k]].values[i]);
    for mut col in m.column_iter_mut() {
        let norm = col.norm();
        col /= norm;
    }
    let s = m.svd(false, false).singular_values;
    let max = s.iter().copied().fold(0.0, f64::max);
    s.iter().all(|v| *v > 1e-6 * max)
}

/// Fits the diagnostics to `runs` on `machine` (all runs in the same plane, radius and centre).
pub fn diagnose(machine: &Machine, runs: &[CircularRun], options: &DiagnosticOptions) -> Result<Diagnostics, IdentifyError> {
    let (a_letter, b_letter, _) = options.plane.letters();
    let id = |name: &str| -> Result<usize, IdentifyError> { machine.parse_parameter(name).map(|(_, i)| i).map_err(IdentifyError::Input) };
    let [aa, bb] = [format!("E{a_letter}{a_letter}"), format!("E{b_letter}{b_letter}")];
    let [ba, ab] = [format!("E{b_letter}{a_letter}"), format!("E{a_letter}{b_letter}")];
    let (i_aa, i_bb, i_ba, i_ab) = (id(&aa)?, id(&bb)?, id(&ba)?, id(&ab)?);
    // the squareness parameter with a signal on this machine (the first candidate that has one)
    let first_run = runs.first().ok_or_else(|| IdentifyError::Input("no runs".into()))?;
    let first_jac = first_run.test.dl_jacobian(machine);
    let n_par = machine.parameter_count();
    let has_signal = |i: usize| first_jac.chunks(n_par).any(|row| row[i].abs() > 1e-9);
    let candidates = squareness_candidates(options.plane);
    let (sq_name, i_sq) = candidates
        .iter()
        .map(|n| id(n).map(|i| (*n, i)))
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .find(|(_, i)| has_signal(*i))
        .unwrap_or((candidates[0], id(candidates[0])?));
    let (i_wa, i_wb) = (id(&format!("W{a_letter}"))?, id(&format!("W{b_letter}"))?);
    // E<a><a> is along the machine coordinate; the axis may move the other way (a workpiece slide)
    let own_sign = [a_letter, b_letter].map(|l| {
        let axis = &machine.axes()[machine.axis_index(l).expect("checked by parse_parameter")];
        let k = "XYZ".find(l).unwrap_or(0);
        if axis.direction[k] < 0.0 {
            -1.0
        } else {
            1.0
        }
    });
    let both = runs.iter().any(|r| r.rotation == Rotation::Ccw) && runs.iter().any(|r| r.rotation == Rotation::Cw);
    let r = options.radius;
    let um = 1e3; // mm -> um
    let mut columns: Vec<Column> = Vec::new();
    let mut add = |name: String, parameter: String, unit: &'static str, to_user: f64, ranked: bool| {
        columns.push(Column { name, parameter, unit, to_user, values: Vec::new(), ranked });
        columns.len() - 1
    };
    let c_wa = add(format!("centre offset {a_letter}"), String::new(), "um", -um, false);
    let c_wb = add(format!("centre offset {b_letter}"), String::new(), "um", -um, false);
    let c_r = add("radius change".into(), String::new(), "um", um, false);
    let c_sq = add("squareness".into(), sq_name.into(), "urad", 1e6, true);
    let c_scale = add("scale mismatch".into(), format!("{aa}-{bb}"), "um/m", 1e6, true);
    let c_back =
        [add(format!("backlash {a_letter}"), aa.clone(), "um", um, true), add(format!("backlash {b_letter}"), bb.clone(), "um", um, true)];
    let c_play = [
        add(format!("lateral play {a_letter}"), ba.clone(), "um", um, true),
        add(format!("lateral play {b_letter}"), ab.clone(), "um", um, true),
    ];
    let c_spike = [
        add(format!("reversal spike {a_letter}"), aa.clone(), "um", um, true),
        add(format!("reversal spike {b_letter}"), bb.clone(), "um", um, true),
    ];
    let c_straight = [
        add(format!("straightness {a_letter}"), ba.clone(), "um", um, true),
        add(format!("straightness {b_letter}"), ab.clone(), "um", um, true),
    ];
    let c_servo = both.then(|| add("servo mismatch".into(), format!("{aa}-{bb}"), "urad", 1e6, true));
    let c_cyclic = options.pitch.map(|_| {
        [
            [
                add(format!("cyclic error {a_letter} cos"), aa.clone(), "um", um, true),
                add(format!("cyclic error {a_letter} sin"), aa.clone(), "um", um, true),
            ],
            [
                add(format!("cyclic error {b_letter} cos"), bb.clone(), "um", um, true),
                add(format!("cyclic error {b_letter} sin"), bb.clone(), "um", um, true),
            ],
        ]
    });

    let mut y = Vec::new();
    for run in runs {
        if run.dl.len() != run.test.len() {
            return Err(IdentifyError::Input(format!("{} readings for {} samples", run.dl.len(), run.test.len())));
        }
        let jac = run.test.dl_jacobian(machine);
        for (i, (&theta, &dl)) in run.test.angles.iter().zip(&run.dl).enumerate() {
            let row = &jac[i * n_par..(i + 1) * n_par];
            let s = [
                axis_sample(theta, 0.0, run.rotation, r, options.centre[0]),
                axis_sample(theta, std::f64::consts::FRAC_PI_2, run.rotation, r, options.centre[1]),
            ];
            // own-axis terms are errors along the axis's own direction of motion
            let j_own = [row[i_aa] * own_sign[0], row[i_bb] * own_sign[1]];
            let j_cross = [row[i_ba], row[i_ab]];
            let mut set = |c: usize, v: f64| columns[c].values.push(v);
            set(c_wa, row[i_wa]);
            set(c_wb, row[i_wb]);
            set(c_r, 1.0);
            set(c_sq, row[i_sq]);
            set(c_scale, 0.5 * (j_own[0] * s[0].offset - j_own[1] * s[1].offset));
            for k in 0..2 {
                set(c_back[k], -0.5 * j_own[k] * s[k].sign);
                set(c_play[k], 0.5 * j_cross[k] * s[k].sign);
                set(c_spike[k], -j_own[k] * s[k].sign * (-s[k].since_reversal / options.spike_width).exp());
                set(c_straight[k], j_cross[k] * (1.0 - (s[k].offset / r).powi(2)));
            }
            if let Some(c) = c_servo {
                // lag of a by a path angle delta: E_aa = -v_a delta (v per unit path angle)
                set(c, -j_own[0] * s[0].velocity);
            }
            if let (Some(cy), Some(p)) = (c_cyclic, options.pitch) {
                for k in 0..2 {
                    let phase = 2.0 * std::f64::consts::PI * s[k].position / p;
                    set(cy[k][0], j_own[k] * phase.cos());
                    set(cy[k][1], j_own[k] * phase.sin());
                }
            }
            y.push(dl);
        }
    }
    let mut omitted = Vec::new();
    if !both {
        omitted.push("servo mismatch: needs a CW and a CCW run".to_string());
    }
    if options.pitch.is_none() {
        omitted.push("cyclic error: give the ball-screw pitch".to_string());
    }
    // Columns without signal (an axis that never reverses on a partial arc), or that the data cannot
    // separate from those already kept (in the order above: nuisance terms first), are left out.
    let mut keep: Vec<usize> = Vec::new();
    for c in 0..columns.len() {
        if !columns[c].values.iter().any(|v| v.abs() > 1e-9) {
            omitted.push(format!("{}: no signal in this test", columns[c].name));
            continue;
        }
        let mut trial = keep.clone();
        trial.push(c);
        if independent(&columns, &trial) {
            keep = trial;
        } else {
            omitted.push(format!("{}: not separable from the other terms with these data", columns[c].name));
        }
    }
    let n = y.len();
    // Terms whose standard uncertainty exceeds their value cannot be told from noise or from the
    // other terms with these data (a partial arc): the worst is dropped and the rest refitted,
    // until every ranked term is at least its uncertainty.
    let (design, fit, u) = loop {
        let design = DMatrix::from_fn(n, keep.len(), |i, k| columns[keep[k]].values[i]);
        let names: Vec<String> = keep.iter().map(|&c| columns[c].name.clone()).collect();
        let fit = fit_linear(&design, &y, None, &names)?;
        let u = fit.standard_uncertainties();
        // (position in keep, columns of the term, |value| / u); a cyclic pair is one term
        let mut worst: Option<(Vec<usize>, f64, f64, f64)> = None;
        let mut k = 0;
        while k < keep.len() {
            let pair = columns[keep[k]].name.ends_with(" cos") && k + 1 < keep.len() && columns[keep[k + 1]].name.ends_with(" sin");
            let width = if pair { 2 } else { 1 };
            if columns[keep[k]].ranked {
                let (value, sd) = term_value(&fit.coefficients[k..k + width], &u[k..k + width]);
                let ratio = if sd > 0.0 { value / sd } else { f64::INFINITY };
                if ratio < 1.0 && worst.as_ref().is_none_or(|w| ratio < w.1 / w.2.max(f64::MIN_POSITIVE)) {
                    worst = Some(((k..k + width).collect(), value, sd, columns[keep[k]].to_user.abs()));
                }
            }
            k += width;
        }
        let Some((drop, value, sd, to_user)) = worst else { break (design, fit, u) };
        let col = &columns[keep[drop[0]]];
        omitted.push(format!(
            "{}: not significant (|value| {:.3} < its standard uncertainty {:.3} {}); refitted without it",
            col.name.trim_end_matches(" cos"),
            value * to_user,
            sd * to_user,
            col.unit
        ));
        for &d in drop.iter().rev() {
            keep.remove(d);
        }
    };

    // Fitted effects (mm) of each kept column.
    let effect = |k: usize| -> Vec<f64> { design.column(k).iter().map(|v| v * fit.coefficients[k]).collect() };
    let range = |v: &[f64]| v.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b)) - v.iter().fold(f64::INFINITY, |a, &b| a.min(b));
    let mut items: Vec<Diagnostic> = Vec::new();
    let mut k = 0;
    while k < keep.len() {
        let col = &columns[keep[k]];
        // the cos/sin pair of a cyclic error is reported as one amplitude
        if col.name.ends_with(" cos") && k + 1 < keep.len() && columns[keep[k + 1]].name.ends_with(" sin") {
            let (amp, ua) = term_value(&fit.coefficients[k..k + 2], &u[k..k + 2]);
            let e: Vec<f64> = effect(k).iter().zip(effect(k + 1)).map(|(a, b)| a + b).collect();
            items.push(Diagnostic {
                name: col.name.trim_end_matches(" cos").to_string(),
                parameter: col.parameter.clone(),
                value: amp * col.to_user,
                std_uncertainty: ua * col.to_user,
                unit: col.unit,
                effect_um: range(&e) * um,
                share_percent: 0.0,
            });
            k += 2;
            continue;
        }
        let mut value = fit.coefficients[k] * col.to_user;
        let mut std_uncertainty = u[k] * col.to_user.abs();
        let mut unit = col.unit;
        if col.name == "servo mismatch" {
            if let Some(feed) = options.feed.filter(|f| *f > 0.0) {
                // path angle -> time: delta / omega, omega = feed / (60 R) rad/s; in ms
                let omega = feed / 60.0 / r;
                value = fit.coefficients[k] / omega * 1e3;
                std_uncertainty = u[k] / omega * 1e3;
                unit = "ms";
            }
        }
        let effect_um = if col.ranked { range(&effect(k)) * um } else { 0.0 };
        items.push(Diagnostic {
            name: col.name.clone(),
            parameter: col.parameter.clone(),
            value,
            std_uncertainty,
            unit,
            effect_um,
            share_percent: 0.0,
        });
        k += 1;
    }
    // Shares only among effects the bar resolves: an error-free trace has rounding-level effects
    // whose shares would be noise.
    let resolved = |d: &Diagnostic| d.effect_um >= RESOLUTION_UM;
    let total: f64 = items.iter().filter(|d| resolved(d)).map(|d| d.effect_um).sum();
    for d in &mut items {
        d.share_percent = if resolved(d) && total > 0.0 { 100.0 * d.effect_um / total } else { 0.0 };
    }
    // nuisance terms first, then by decreasing effect
    items.sort_by(|a, b| (a.effect_um > 0.0).cmp(&(b.effect_um > 0.0)).then(b.effect_um.total_cmp(&a.effect_um)));
    let fitted: Vec<f64> = y.iter().zip(&fit.residuals).map(|(y, e)| (y - e) * um).collect();
    let mut model_um = Vec::with_capacity(runs.len());
    let mut start = 0;
    for run in runs {
        model_um.push(fitted[start..start + run.dl.len()].to_vec());
        start += run.dl.len();
    }
    let residual_rms_um = (fit.rss / n as f64).sqrt() * um;
    Ok(Diagnostics { items, residual_rms_um, samples: n, omitted, model_um })
}
