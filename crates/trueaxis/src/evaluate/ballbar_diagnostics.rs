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

use crate::identify::{fit_linear, IdentifyError, LinearFit};
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

/// mm -> um.
const UM: f64 = 1e3;

/// Fits the diagnostics to `runs` on `machine` (all runs in the same plane, radius and centre):
/// the regressors of every term at every sample, the terms the data can separate, the fit of the
/// significant ones, and the report of each.
pub fn diagnose(machine: &Machine, runs: &[CircularRun], options: &DiagnosticOptions) -> Result<Diagnostics, IdentifyError> {
    let parameters = Parameters::of(machine, runs, options.plane)?;
    let both = runs.iter().any(|r| r.rotation == Rotation::Ccw) && runs.iter().any(|r| r.rotation == Rotation::Cw);
    let (mut columns, terms) = Terms::columns(options.plane, &parameters, both, options.pitch);
    let y = regressors(machine, runs, options, &parameters, &terms, &mut columns)?;
    let mut omitted = Vec::new();
    if !both {
        omitted.push("servo mismatch: needs a CW and a CCW run".to_string());
    }
    if options.pitch.is_none() {
        omitted.push("cyclic error: give the ball-screw pitch".to_string());
    }
    let mut keep = separable(&columns, &mut omitted);
    let (design, fit, u) = significant_fit(&columns, &mut keep, &y, &mut omitted)?;
    let items = report(&columns, &keep, &design, &fit, &u, options);
    let n = y.len();
    Ok(Diagnostics {
        items,
        residual_rms_um: (fit.rss / n as f64).sqrt() * UM,
        samples: n,
        omitted,
        model_um: model_per_run(runs, &y, &fit.residuals),
    })
}

/// The ISO parameters the diagnostics act on, by name and by index in the machine's parameter
/// vector: `E<a><a>`, `E<b><b>` (own axes), `E<b><a>`, `E<a><b>` (cross: of the motion of a, of b),
/// the squareness and `W<a>`, `W<b>` (centre).
struct Parameters {
    own: [(String, usize); 2],
    cross: [(String, usize); 2],
    squareness: (&'static str, usize),
    centre: [usize; 2],
    /// +1, or -1 for an axis that moves against its machine coordinate (a workpiece slide): own-axis
    /// terms are errors along the direction of motion, `E<a><a>` is along the coordinate.
    own_sign: [f64; 2],
}

impl Parameters {
    fn of(machine: &Machine, runs: &[CircularRun], plane: Plane) -> Result<Parameters, IdentifyError> {
        let (a, b, _) = plane.letters();
        let id =
            |name: &str| -> Result<usize, IdentifyError> { machine.parse_parameter(name).map(|(_, i)| i).map_err(IdentifyError::input) };
        let named = |name: String| id(&name).map(|i| (name, i));
        let own = [named(format!("E{a}{a}"))?, named(format!("E{b}{b}"))?];
        let cross = [named(format!("E{b}{a}"))?, named(format!("E{a}{b}"))?];
        // the squareness parameter with a signal on this machine (the first candidate that has one)
        let first_run = runs.first().ok_or_else(|| IdentifyError::Input("no runs".into()))?;
        let first_jac = first_run.test.dl_jacobian(machine);
        let n_par = machine.parameter_count();
        let has_signal = |i: usize| first_jac.chunks(n_par).any(|row| row[i].abs() > 1e-9);
        let candidates = squareness_candidates(plane);
        let squareness = candidates
            .iter()
            .map(|n| id(n).map(|i| (*n, i)))
            .collect::<Result<Vec<_>, _>>()?
            .into_iter()
            .find(|(_, i)| has_signal(*i))
            .unwrap_or((candidates[0], id(candidates[0])?));
        let centre = [id(&format!("W{a}"))?, id(&format!("W{b}"))?];
        let own_sign = [a, b].map(|l| {
            let axis = &machine.axes()[machine.axis_index(l).expect("checked by parse_parameter")];
            if axis.direction["XYZ".find(l).unwrap_or(0)] < 0.0 {
                -1.0
            } else {
                1.0
            }
        });
        Ok(Parameters { own, cross, squareness, centre, own_sign })
    }
}

/// The column of each term in the list of candidate columns, in the order of selection (nuisance
/// terms first); `[axis a, axis b]` for the per-axis terms.
struct Terms {
    centre: [usize; 2],
    radius: usize,
    squareness: usize,
    scale: usize,
    backlash: [usize; 2],
    play: [usize; 2],
    spike: [usize; 2],
    straightness: [usize; 2],
    servo: Option<usize>,
    /// `[[a cos, a sin], [b cos, b sin]]`.
    cyclic: Option<[[usize; 2]; 2]>,
}

impl Terms {
    /// The candidate columns (without values) of a test in `plane`: the servo mismatch when `both`
    /// directions were run, the cyclic errors when the pitch is given.
    fn columns(plane: Plane, p: &Parameters, both: bool, pitch: Option<f64>) -> (Vec<Column>, Terms) {
        let (a, b, _) = plane.letters();
        let [(aa, _), (bb, _)] = &p.own;
        let [(ba, _), (ab, _)] = &p.cross;
        let mut columns: Vec<Column> = Vec::new();
        let mut add = |name: String, parameter: &str, unit: &'static str, to_user: f64, ranked: bool| {
            columns.push(Column { name, parameter: parameter.to_string(), unit, to_user, values: Vec::new(), ranked });
            columns.len() - 1
        };
        let centre = [add(format!("centre offset {a}"), "", "um", -UM, false), add(format!("centre offset {b}"), "", "um", -UM, false)];
        let radius = add("radius change".into(), "", "um", UM, false);
        let squareness = add("squareness".into(), p.squareness.0, "urad", 1e6, true);
        let scale = add("scale mismatch".into(), &format!("{aa}-{bb}"), "um/m", 1e6, true);
        let backlash = [add(format!("backlash {a}"), aa, "um", UM, true), add(format!("backlash {b}"), bb, "um", UM, true)];
        let play = [add(format!("lateral play {a}"), ba, "um", UM, true), add(format!("lateral play {b}"), ab, "um", UM, true)];
        let spike = [add(format!("reversal spike {a}"), aa, "um", UM, true), add(format!("reversal spike {b}"), bb, "um", UM, true)];
        let straightness = [add(format!("straightness {a}"), ba, "um", UM, true), add(format!("straightness {b}"), ab, "um", UM, true)];
        let servo = both.then(|| add("servo mismatch".into(), &format!("{aa}-{bb}"), "urad", 1e6, true));
        let cyclic = pitch.map(|_| {
            [(a, aa), (b, bb)].map(|(l, own)| {
                [add(format!("cyclic error {l} cos"), own, "um", UM, true), add(format!("cyclic error {l} sin"), own, "um", UM, true)]
            })
        });
        let terms = Terms { centre, radius, squareness, scale, backlash, play, spike, straightness, servo, cyclic };
        (columns, terms)
    }
}

/// Fills the columns with each term's regressor at every sample of every run (the term's error
/// function times the Jacobian column of its parameter) and returns the bar readings `y` (mm) in
/// the same order.
fn regressors(
    machine: &Machine,
    runs: &[CircularRun],
    options: &DiagnosticOptions,
    p: &Parameters,
    terms: &Terms,
    columns: &mut [Column],
) -> Result<Vec<f64>, IdentifyError> {
    let n_par = machine.parameter_count();
    let mut y = Vec::new();
    for run in runs {
        if run.dl.len() != run.test.len() {
            return Err(IdentifyError::Input(format!("{} readings for {} samples", run.dl.len(), run.test.len())));
        }
        let jac = run.test.dl_jacobian(machine);
        for (i, (&theta, &dl)) in run.test.angles.iter().zip(&run.dl).enumerate() {
            let s = [
                axis_sample(theta, 0.0, run.rotation, options.radius, options.centre[0]),
                axis_sample(theta, std::f64::consts::FRAC_PI_2, run.rotation, options.radius, options.centre[1]),
            ];
            push_sample(columns, terms, p, &jac[i * n_par..(i + 1) * n_par], &s, options);
            y.push(dl);
        }
    }
    Ok(y)
}

/// Pushes the regressors of one sample (Jacobian row `row`, axis quantities `s`) onto the columns
/// (the error functions of the module table).
fn push_sample(columns: &mut [Column], t: &Terms, p: &Parameters, row: &[f64], s: &[AxisSample; 2], options: &DiagnosticOptions) {
    // own-axis terms are errors along the axis's own direction of motion
    let j_own = [row[p.own[0].1] * p.own_sign[0], row[p.own[1].1] * p.own_sign[1]];
    let j_cross = [row[p.cross[0].1], row[p.cross[1].1]];
    let mut set = |c: usize, v: f64| columns[c].values.push(v);
    set(t.centre[0], row[p.centre[0]]);
    set(t.centre[1], row[p.centre[1]]);
    set(t.radius, 1.0);
    set(t.squareness, row[p.squareness.1]);
    set(t.scale, 0.5 * (j_own[0] * s[0].offset - j_own[1] * s[1].offset));
    for k in 0..2 {
        set(t.backlash[k], -0.5 * j_own[k] * s[k].sign);
        set(t.play[k], 0.5 * j_cross[k] * s[k].sign);
        set(t.spike[k], -j_own[k] * s[k].sign * (-s[k].since_reversal / options.spike_width).exp());
        set(t.straightness[k], j_cross[k] * (1.0 - (s[k].offset / options.radius).powi(2)));
    }
    if let Some(c) = t.servo {
        // lag of a by a path angle delta: E_aa = -v_a delta (v per unit path angle)
        set(c, -j_own[0] * s[0].velocity);
    }
    if let (Some(cy), Some(pitch)) = (t.cyclic, options.pitch) {
        for k in 0..2 {
            let phase = 2.0 * std::f64::consts::PI * s[k].position / pitch;
            set(cy[k][0], j_own[k] * phase.cos());
            set(cy[k][1], j_own[k] * phase.sin());
        }
    }
}

/// The columns to fit: columns without signal (an axis that never reverses on a partial arc), or
/// that the data cannot separate from those already kept (in their order: nuisance terms first),
/// are left out, with why, onto `omitted`.
fn separable(columns: &[Column], omitted: &mut Vec<String>) -> Vec<usize> {
    let mut keep: Vec<usize> = Vec::new();
    for c in 0..columns.len() {
        if !columns[c].values.iter().any(|v| v.abs() > 1e-9) {
            omitted.push(format!("{}: no signal in this test", columns[c].name));
            continue;
        }
        let mut trial = keep.clone();
        trial.push(c);
        if independent(columns, &trial) {
            keep = trial;
        } else {
            omitted.push(format!("{}: not separable from the other terms with these data", columns[c].name));
        }
    }
    keep
}

/// The number of columns of the term at position `k` of `keep`: 2 for the cos/sin pair of a cyclic
/// error, else 1.
fn term_width(columns: &[Column], keep: &[usize], k: usize) -> usize {
    let pair = columns[keep[k]].name.ends_with(" cos") && k + 1 < keep.len() && columns[keep[k + 1]].name.ends_with(" sin");
    if pair {
        2
    } else {
        1
    }
}

/// Fits the kept columns. Terms whose standard uncertainty exceeds their value cannot be told from
/// noise or from the other terms with these data (a partial arc): the worst is dropped (onto
/// `omitted`) and the rest refitted, until every ranked term is at least its uncertainty. Returns
/// the design, the fit and the standard uncertainties of its coefficients.
fn significant_fit(
    columns: &[Column],
    keep: &mut Vec<usize>,
    y: &[f64],
    omitted: &mut Vec<String>,
) -> Result<(DMatrix<f64>, LinearFit, Vec<f64>), IdentifyError> {
    loop {
        let design = DMatrix::from_fn(y.len(), keep.len(), |i, k| columns[keep[k]].values[i]);
        let names: Vec<String> = keep.iter().map(|&c| columns[c].name.clone()).collect();
        let fit = fit_linear(&design, y, None, &names)?;
        let u = fit.standard_uncertainties();
        let Some((drop, value, sd, to_user)) = weakest(columns, keep, &fit, &u) else { return Ok((design, fit, u)) };
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
    }
}

/// The ranked term of the fit with the smallest ratio of value to standard uncertainty below 1, if
/// any: its positions in `keep`, its value, its uncertainty and the factor to its user unit.
fn weakest(columns: &[Column], keep: &[usize], fit: &LinearFit, u: &[f64]) -> Option<(Vec<usize>, f64, f64, f64)> {
    let mut worst: Option<(Vec<usize>, f64, f64, f64)> = None;
    let mut k = 0;
    while k < keep.len() {
        let width = term_width(columns, keep, k);
        if columns[keep[k]].ranked {
            let (value, sd) = term_value(&fit.coefficients[k..k + width], &u[k..k + width]);
            let ratio = if sd > 0.0 { value / sd } else { f64::INFINITY };
            if ratio < 1.0 && worst.as_ref().is_none_or(|w| ratio < w.1 / w.2.max(f64::MIN_POSITIVE)) {
                worst = Some(((k..k + width).collect(), value, sd, columns[keep[k]].to_user.abs()));
            }
        }
        k += width;
    }
    worst
}

/// Peak to valley of `v`.
fn peak_to_valley(v: &[f64]) -> f64 {
    v.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b)) - v.iter().fold(f64::INFINITY, |a, &b| a.min(b))
}

/// The diagnostics of the fitted terms in the user's units, with their effects and shares: nuisance
/// terms first, then by decreasing effect.
fn report(
    columns: &[Column],
    keep: &[usize],
    design: &DMatrix<f64>,
    fit: &LinearFit,
    u: &[f64],
    options: &DiagnosticOptions,
) -> Vec<Diagnostic> {
    // fitted effect (mm) of each kept column
    let effect = |k: usize| -> Vec<f64> { design.column(k).iter().map(|v| v * fit.coefficients[k]).collect() };
    let mut items: Vec<Diagnostic> = Vec::new();
    let mut k = 0;
    while k < keep.len() {
        let col = &columns[keep[k]];
        let width = term_width(columns, keep, k);
        if width == 2 {
            // the cos/sin pair of a cyclic error is reported as one amplitude
            let (amp, ua) = term_value(&fit.coefficients[k..k + 2], &u[k..k + 2]);
            let e: Vec<f64> = effect(k).iter().zip(effect(k + 1)).map(|(a, b)| a + b).collect();
            let name = col.name.trim_end_matches(" cos").to_string();
            items.push(Diagnostic {
                name,
                value: amp * col.to_user,
                std_uncertainty: ua * col.to_user,
                ..item(col, peak_to_valley(&e) * UM)
            });
        } else {
            let effect_um = if col.ranked { peak_to_valley(&effect(k)) * UM } else { 0.0 };
            items.push(single(col, fit.coefficients[k], u[k], effect_um, options));
        }
        k += width;
    }
    share(&mut items);
    items.sort_by(|a, b| (a.effect_um > 0.0).cmp(&(b.effect_um > 0.0)).then(b.effect_um.total_cmp(&a.effect_um)));
    items
}

/// The diagnostic of `col` with its effect, value and uncertainty still to be set.
fn item(col: &Column, effect_um: f64) -> Diagnostic {
    Diagnostic {
        name: col.name.clone(),
        parameter: col.parameter.clone(),
        value: 0.0,
        std_uncertainty: 0.0,
        unit: col.unit,
        effect_um,
        share_percent: 0.0,
    }
}

/// The diagnostic of a term of one column, fitted as `coefficient` with standard uncertainty `u`;
/// a servo mismatch in ms when the feed is known.
fn single(col: &Column, coefficient: f64, u: f64, effect_um: f64, options: &DiagnosticOptions) -> Diagnostic {
    let (mut value, mut std_uncertainty, mut unit) = (coefficient * col.to_user, u * col.to_user.abs(), col.unit);
    if col.name == "servo mismatch" {
        if let Some(feed) = options.feed.filter(|f| *f > 0.0) {
            // path angle -> time: delta / omega, omega = feed / (60 R) rad/s; in ms
            let omega = feed / 60.0 / options.radius;
            (value, std_uncertainty, unit) = (coefficient / omega * 1e3, u / omega * 1e3, "ms");
        }
    }
    Diagnostic { value, std_uncertainty, unit, ..item(col, effect_um) }
}

/// Shares only among effects the bar resolves: an error-free trace has rounding-level effects
/// whose shares would be noise.
fn share(items: &mut [Diagnostic]) {
    let resolved = |d: &Diagnostic| d.effect_um >= RESOLUTION_UM;
    let total: f64 = items.iter().filter(|d| resolved(d)).map(|d| d.effect_um).sum();
    for d in items {
        d.share_percent = if resolved(d) && total > 0.0 { 100.0 * d.effect_um / total } else { 0.0 };
    }
}

/// The fitted model of the bar reading (um), `y` less the residuals, cut into the runs.
fn model_per_run(runs: &[CircularRun], y: &[f64], residuals: &[f64]) -> Vec<Vec<f64>> {
    let fitted: Vec<f64> = y.iter().zip(residuals).map(|(y, e)| (y - e) * UM).collect();
    let mut model_um = Vec::with_capacity(runs.len());
    let mut start = 0;
    for run in runs {
        model_um.push(fitted[start..start + run.dl.len()].to_vec());
        start += run.dl.len();
    }
    model_um
}
