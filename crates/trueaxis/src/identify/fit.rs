//! Fitting a parametric error function to direct measurements of one error along its axis
//! (Soons 1993 §3.2: laser, levels, straightedge data), with stepwise selection, diagnostics, aliasing
//! detection for periodic terms (§3.2.4) and nonlinear refinement of a periodic wavelength.

use super::least_squares::{fit_linear, LinearFit};
use super::stepwise::stepwise;
use super::IdentifyError;
use crate::error_model::{Basis, BasisSpec, ErrorFunction};
use nalgebra::DMatrix;

/// How to fit.
#[derive(Clone, Debug)]
pub struct FitOptions {
    /// The candidate basis.
    pub spec: BasisSpec,
    /// Stepwise selection at this confidence (e.g. 0.9999), or keep every function.
    pub stepwise_level: Option<f64>,
    /// Confidence of the prediction intervals (0.95).
    pub prediction_level: f64,
}

/// A fitted error function with its statistics.
#[derive(Clone, Debug)]
pub struct FittedFunction {
    /// The function to use in an error-values file: the full candidate basis (reproducible from
    /// its spec) with zero coefficients for the functions stepwise selection removed.
    pub function: ErrorFunction,
    /// The selected functions only (for predictions with their intervals).
    pub selected: Basis,
    /// Names of the kept basis functions, their coefficients and standard uncertainties.
    pub names: Vec<String>,
    pub coefficients: Vec<f64>,
    pub std_uncertainties: Vec<f64>,
    /// Names of the candidate functions removed by stepwise selection.
    pub removed: Vec<String>,
    pub fit: LinearFit,
    /// Root mean square and largest absolute residual (units of the data).
    pub rms: f64,
    pub max_abs_residual: f64,
    /// Largest Cook's distance and its observation index.
    pub max_cooks_distance: (usize, f64),
    /// Largest half-width of the prediction interval over the observations (units of the data).
    pub max_prediction_half_width: f64,
}

impl FittedFunction {
    /// Value of the fitted function and the prediction-interval half-width at position `x`.
    pub fn predict(&self, x: f64, level: f64) -> (f64, f64) {
        let mut g = vec![0.0; self.selected.len()];
        self.selected.eval_into(x, &mut g);
        self.fit.prediction(&g, level)
    }
}

/// Apparent wavelength of a periodic error of `wavelength` sampled every `spacing` (same units):
/// the alias `1 / |1/wavelength - k/spacing|` with the nearest integer `k`, or `None` when the
/// sampling resolves it (spacing below half the wavelength). Soons 1993 §3.2.4: 0.635025 mm sampled
/// every 10 mm appears as about 40 mm.
pub fn alias_wavelength(wavelength: f64, spacing: f64) -> Option<f64> {
    if spacing < 0.5 * wavelength {
        return None;
    }
    let (f, fs) = (1.0 / wavelength, 1.0 / spacing);
    let alias = (f - (f / fs).round() * fs).abs();
    Some(if alias > 0.0 { 1.0 / alias } else { f64::INFINITY })
}

/// The period (within `[min_period, max_period]`) of the sinusoid that best fits `values` at
/// `positions` (a least-squares periodogram), with its amplitude.
pub fn dominant_period(positions: &[f64], values: &[f64], min_period: f64, max_period: f64) -> Option<(f64, f64)> {
    let (lo, hi) = positions.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(*x), b.max(*x)));
    let span = hi - lo;
    if !(span > 0.0 && min_period > 0.0 && max_period > min_period) {
        return None;
    }
    let (f_lo, f_hi) = (1.0 / max_period, 1.0 / min_period);
    let step = 0.25 / span;
    let count = (((f_hi - f_lo) / step).ceil() as usize).clamp(2, 200_000);
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let mut best: Option<(f64, f64)> = None;
    let mut best_gain = 0.0;
    for k in 0..=count {
        let f = f_lo + (f_hi - f_lo) * k as f64 / count as f64;
        let w = 2.0 * std::f64::consts::PI * f;
        let (mut cc, mut cs, mut ss, mut yc, mut ys) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (x, v) in positions.iter().zip(values) {
            let (s, c) = (w * (x - lo)).sin_cos();
            let y = v - mean;
            cc += c * c;
            cs += c * s;
            ss += s * s;
            yc += y * c;
            ys += y * s;
        }
        let det = cc * ss - cs * cs;
        if det.abs() < 1e-12 * (cc * ss).max(1e-300) {
            continue;
        }
        let a = (ss * yc - cs * ys) / det;
        let b = (cc * ys - cs * yc) / det;
        let gain = a * yc + b * ys;
        if gain > best_gain {
            best_gain = gain;
            best = Some((1.0 / f, (a * a + b * b).sqrt()));
        }
    }
    best
}

/// The typical sampling step of `positions`: the median gap between distinct sorted positions
/// (same units), or `None` with fewer than two distinct positions.
pub fn sampling_step(positions: &[f64]) -> Option<f64> {
    let mut xs = positions.to_vec();
    xs.sort_by(f64::total_cmp);
    xs.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    let mut gaps: Vec<f64> = xs.windows(2).map(|w| w[1] - w[0]).collect();
    if gaps.is_empty() {
        return None;
    }
    gaps.sort_by(f64::total_cmp);
    Some(gaps[gaps.len() / 2])
}

/// The strongest sinusoid left in the residuals of a fit, with what it can and cannot mean.
///
/// Periods are searched from the sampling limit (twice the typical sampling step, the Nyquist
/// period) to the span of the data. A sinusoid found there may also be the alias of a shorter
/// period: with samples every `step`, the periods `1 / |1/period ± k/step|` (k = 1, 2, ...), all
/// below the limit, give the same samples (Soons 1993 §3.2.4: a 0.635025 mm scale error sampled every
/// 10 mm appears at 39.59 mm). The data cannot tell them apart; only knowing the wavelength (a
/// `--periodic` term, refused with its alias when unresolvable) or sampling at finer or random
/// intervals can.
#[derive(Clone, Debug, PartialEq)]
pub struct ResidualPeriod {
    /// Period (mm or deg) and amplitude (units of the data) of the best-fitting sinusoid.
    pub period: f64,
    pub amplitude: f64,
    /// The amplitude exceeds the 1 % false-alarm level of white noise of the residual standard
    /// deviation over the frequencies searched.
    pub significant: bool,
    /// Shortest period searched: twice the typical sampling step.
    pub limit: f64,
    /// The sampling step when the positions are equally spaced (then the aliases are exact).
    pub uniform_step: Option<f64>,
}

impl ResidualPeriod {
    /// The periods (below the sampling limit) that equally spaced samples cannot tell from
    /// [`ResidualPeriod::period`]: `1 / |k/step -+ 1/period|` for k = 1 ..= `orders`, longest
    /// first; empty for irregular sampling.
    pub fn aliases(&self, orders: usize) -> Vec<f64> {
        let Some(step) = self.uniform_step else { return Vec::new() };
        let (f, fs) = (1.0 / self.period, 1.0 / step);
        let mut out: Vec<f64> =
            (1..=orders).flat_map(|k| [k as f64 * fs - f, k as f64 * fs + f]).filter(|g| *g > 0.0).map(|g| 1.0 / g).collect();
        out.sort_by(|a, b| b.total_cmp(a));
        out
    }
}

/// The strongest periodic component of `residuals` at `positions` (see [`ResidualPeriod`]), with
/// `sigma` the residual standard deviation for the significance test: a sinusoid of amplitude `A`
/// fitted to white noise has a periodogram ordinate `z = n A^2 / (4 sigma^2)` distributed as
/// Exp(1); over `M` independent frequencies (half the distinct positions) the 1 % false-alarm
/// level is `z > ln(100 M)`.
pub fn residual_period(positions: &[f64], residuals: &[f64], sigma: f64) -> Option<ResidualPeriod> {
    let step = sampling_step(positions)?;
    let (lo, hi) = positions.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(*x), b.max(*x)));
    let limit = 2.0 * step;
    let (period, amplitude) = dominant_period(positions, residuals, limit, hi - lo)?;
    let mut distinct = positions.to_vec();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    let frequencies = (distinct.len() as f64 / 2.0).max(1.0);
    let z = residuals.len() as f64 * amplitude * amplitude / (4.0 * sigma * sigma);
    let significant = sigma > 0.0 && z > (100.0 * frequencies).ln();
    Some(ResidualPeriod { period, amplitude, significant, limit, uniform_step: uniform_spacing(positions) })
}

fn uniform_spacing(positions: &[f64]) -> Option<f64> {
    let mut xs = positions.to_vec();
    xs.sort_by(f64::total_cmp);
    xs.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    if xs.len() < 3 {
        return None;
    }
    let gaps: Vec<f64> = xs.windows(2).map(|w| w[1] - w[0]).collect();
    let mean = gaps.iter().sum::<f64>() / gaps.len() as f64;
    let spread = gaps.iter().map(|g| (g - mean).abs()).fold(0.0, f64::max);
    (spread < 0.01 * mean).then_some(mean)
}

fn design(basis: &Basis, positions: &[f64]) -> DMatrix<f64> {
    let mut row = vec![0.0; basis.len()];
    let mut x = DMatrix::zeros(positions.len(), basis.len());
    for (i, p) in positions.iter().enumerate() {
        basis.eval_into(*p, &mut row);
        for (j, v) in row.iter().enumerate() {
            x[(i, j)] = *v;
        }
    }
    x
}

/// Fits `values` (um or urad) at `positions` (mm or deg) with the basis of `options.spec`
/// (Soons 1993 eqs. 3.1-3.15), optionally selecting functions stepwise (§3.2.2).
///
/// Refuses a periodic term that a uniform sampling cannot resolve (aliasing, §3.2.4), naming the
/// apparent wavelength.
pub fn fit_error_function(positions: &[f64], values: &[f64], options: &FitOptions) -> Result<FittedFunction, IdentifyError> {
    if positions.len() != values.len() {
        return Err(IdentifyError::Input(format!("{} positions but {} values", positions.len(), values.len())));
    }
    if let Some(spacing) = uniform_spacing(positions) {
        for p in &options.spec.periodic {
            if let Some(alias) = alias_wavelength(p.wavelength, spacing) {
                return Err(IdentifyError::Input(format!(
                    "the periodic term of wavelength {} cannot be resolved from samples every {spacing}: it would appear with an apparent \
                     wavelength of {alias:.4} (aliasing); sample at intervals below {} or at random intervals",
                    p.wavelength,
                    0.5 * p.wavelength
                )));
            }
        }
    }
    let basis = Basis::new(options.spec.clone()).map_err(IdentifyError::input)?;
    if basis.is_empty() {
        return Err(IdentifyError::Input("the basis has no functions".into()));
    }
    let names = basis.names();
    let x = design(&basis, positions);
    let (kept, fit) = match options.stepwise_level {
        Some(level) => {
            // a requested constant is never removed (it is the first function of the basis)
            let forced: Vec<usize> = if options.spec.constant && options.spec.family != "none" { vec![0] } else { vec![] };
            let r = stepwise(&x, values, None, &names, level, &forced)?;
            (r.kept, r.fit)
        }
        None => ((0..basis.len()).collect(), fit_linear(&x, values, None, &names)?),
    };
    let selected = basis.select(&kept);
    let removed = (0..basis.len()).filter(|i| !kept.contains(i)).map(|i| names[i].clone()).collect();
    let n = values.len() as f64;
    let rms = (fit.residuals.iter().map(|e| e * e).sum::<f64>() / n).sqrt();
    let max_abs_residual = fit.residuals.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    let cooks = fit.cooks_distance();
    let max_cooks_distance = cooks.iter().copied().enumerate().fold((0, 0.0), |m, (i, d)| if d > m.1 { (i, d) } else { m });
    let mut g = vec![0.0; selected.len()];
    let max_prediction_half_width = positions
        .iter()
        .map(|p| {
            selected.eval_into(*p, &mut g);
            fit.prediction(&g, options.prediction_level).1
        })
        .fold(0.0, f64::max);
    let coefficients = fit.coefficients.clone();
    let mut full = vec![0.0; basis.len()];
    for (k, c) in kept.iter().zip(&coefficients) {
        full[*k] = *c;
    }
    Ok(FittedFunction {
        function: ErrorFunction::basis(basis, full).map_err(IdentifyError::input)?,
        names: selected.names(),
        selected,
        std_uncertainties: fit.standard_uncertainties(),
        coefficients,
        removed,
        fit,
        rms,
        max_abs_residual,
        max_cooks_distance,
        max_prediction_half_width,
    })
}

/// Refines the wavelength of periodic term `index` of `spec` by minimising the residual sum of
/// squares over `[w (1 - rel), w (1 + rel)]` (a scan fine enough for the number of periods in the
/// data, then golden-section search): the nonlinear step of Soons 1993 §3.2.4, after which the
/// wavelength is fixed. Returns the spec with the refined wavelength.
pub fn refine_wavelength(positions: &[f64], values: &[f64], spec: &BasisSpec, index: usize, rel: f64) -> Result<BasisSpec, IdentifyError> {
    let w0 = spec.periodic.get(index).ok_or_else(|| IdentifyError::Input(format!("no periodic term number {}", index + 1)))?.wavelength;
    let rss = |w: f64| -> f64 {
        let mut s = spec.clone();
        s.periodic[index].wavelength = w;
        match Basis::new(s) {
            Ok(b) => fit_linear(&design(&b, positions), values, None, &b.names()).map(|f| f.rss).unwrap_or(f64::INFINITY),
            Err(_) => f64::INFINITY,
        }
    };
    let (lo, hi) = positions.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(*x), b.max(*x)));
    let periods = ((hi - lo) / w0).max(1.0);
    // a wavelength change of w0 / (8 * periods) shifts the phase at the far end by 1/8 period
    let steps = ((2.0 * rel * periods * 8.0).ceil() as usize).clamp(8, 20_000);
    let (a, b) = (w0 * (1.0 - rel), w0 * (1.0 + rel));
    let grid: Vec<f64> = (0..=steps).map(|k| a + (b - a) * k as f64 / steps as f64).collect();
    let values_on_grid: Vec<f64> = grid.iter().map(|w| rss(*w)).collect();
    let best = values_on_grid.iter().copied().enumerate().fold((0, f64::INFINITY), |m, (i, v)| if v < m.1 { (i, v) } else { m }).0;
    let (mut lo_w, mut hi_w) = (grid[best.saturating_sub(1)], grid[(best + 1).min(steps)]);
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = hi_w - phi * (hi_w - lo_w);
    let mut d = lo_w + phi * (hi_w - lo_w);
    let (mut fc, mut fd) = (rss(c), rss(d));
    for _ in 0..80 {
        if fc < fd {
            hi_w = d;
            d = c;
            fd = fc;
            c = hi_w - phi * (hi_w - lo_w);
            fc = rss(c);
        } else {
            lo_w = c;
            c = d;
            fc = fd;
            d = lo_w + phi * (hi_w - lo_w);
            fd = rss(d);
        }
        if (hi_w - lo_w) < 1e-12 * w0 {
            break;
        }
    }
    let mut refined = spec.clone();
    refined.periodic[index].wavelength = 0.5 * (lo_w + hi_w);
    Ok(refined)
}
