//! Thermal error regression models (Zhu 2008 §3.3.2, eqs. 3.12-3.15, with the intercepts of the
//! Sodick models eqs. 4.3-4.5), and the selection of temperatures by correlation and stepwise
//! regression (NISTIR 5236 §3.6).
//!
//! `E(P, T) = sum_(k=0..degree) P^k (c_k0 + sum_i c_ki T_i)`:
//! - PITE (position-independent, eq. 3.12): `degree = 0`;
//! - PDTE (position-dependent, eq. 3.13): `degree >= 1`, P the nominal axis position (mm);
//! - `intercept = false` drops every `c_k0` (the thesis's eqs. 3.12-3.13 as printed).
//!
//! Temperatures are sensor readings in degC, as in eqs. 4.3-4.5 (not rises); E in um.
//! Least squares by QR with unit-length scaling (`identify::fit_linear`, eq. 3.15 without the
//! normal equations).

use crate::error::Error;
use crate::identify::{fit_linear, stepwise, LinearFit};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

/// A fitted (or given) thermal error model; its TOML form is the fitted-model file of
/// `trueaxis thermal fit`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegressionModel {
    /// Name of the modelled error (a CSV column such as `dz`, or a parameter such as `EZZ`).
    pub error: String,
    /// Sensor columns `T:<name>`, in the order of the coefficients.
    pub sensors: Vec<String>,
    /// Axis letter whose position P enters (PDTE), or none (PITE).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<String>,
    /// Whether `c_k0` are part of the model.
    pub intercept: bool,
    /// Row k: `[c_k0, c_k1, .., c_kN]` multiplying `P^k` (um, um/degC, per mm^k).
    pub coefficients: Vec<Vec<f64>>,
}

impl RegressionModel {
    /// Highest power of the position.
    pub fn degree(&self) -> usize {
        self.coefficients.len().saturating_sub(1)
    }

    /// Checks shapes and numbers.
    pub fn validate(&self) -> Result<(), Error> {
        if self.coefficients.is_empty() {
            return Err(Error::input("`coefficients` must have at least one row"));
        }
        if let Some(k) = self.coefficients.iter().position(|row| row.len() != self.sensors.len() + 1) {
            return Err(Error::input(format!(
                "coefficient row {} has {} entries; expected 1 + {} sensors",
                k + 1,
                self.coefficients[k].len(),
                self.sensors.len()
            )));
        }
        if self.coefficients.iter().flatten().any(|c| !c.is_finite()) {
            return Err(Error::input("coefficients must be finite numbers"));
        }
        if self.degree() > 0 && self.position.is_none() {
            return Err(Error::input("a model with powers of the position needs `position` (the axis letter)"));
        }
        for s in &self.sensors {
            match crate::error_model::InputKind::parse(s) {
                Ok(crate::error_model::InputKind::Lag { .. }) | Err(_) => {
                    return Err(Error::input(format!(
                        "input `{s}` must be a temperature `T:<name>` (degC) or another input column: a spindle speed `S:<name>` (rpm), a force `F:<name>` (N)"
                    )))
                }
                Ok(_) => {}
            }
        }
        Ok(())
    }

    /// `E(P, T)` (um) at position `p` (mm or deg; ignored for PITE) and temperatures `t` (degC) in
    /// the order of `sensors`.
    pub fn evaluate(&self, p: f64, t: &[f64]) -> f64 {
        let mut power = 1.0;
        let mut e = 0.0;
        for row in &self.coefficients {
            let v = row[0] + row[1..].iter().zip(t).map(|(c, x)| c * x).sum::<f64>();
            e += power * v;
            power *= p;
        }
        e
    }

    /// Reads the TOML form; `origin` names it in messages.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<RegressionModel, Error> {
        #[derive(Deserialize)]
        struct File {
            kind: String,
            #[serde(flatten)]
            model: toml::Table,
        }
        crate::io::toml_numbers::refuse_underflow(text).map_err(|e| e.in_file(origin))?;
        let file: File = toml::from_str(text).map_err(|e| Error::input(format!("{origin}: {}", one_line(&e.to_string()))))?;
        if file.kind != "regression" {
            return Err(Error::input(format!("{origin}: kind `{}` is not a thermal error model (kind = \"regression\")", file.kind)));
        }
        let model: RegressionModel = toml::Value::Table(file.model)
            .try_into()
            .map_err(|e: toml::de::Error| Error::input(format!("{origin}: {}", one_line(&e.to_string()))))?;
        model.validate().map_err(|m| Error::input(format!("{origin}: {m}")))?;
        Ok(model)
    }

    /// The TOML form (`kind = "regression"` plus the fields).
    pub fn to_toml(&self) -> String {
        let body = toml::to_string(self).expect("a regression model serialises");
        format!("# thermal error model E(P, T) = sum_k P^k (c_k0 + sum_i c_ki T_i), E in um, T in degC, P in mm or deg\nkind = \"regression\"\n{body}")
    }
}

/// The design matrix: per sample the columns `P^k` (if intercept) and `T_i P^k`, k = 0..=degree.
pub fn design_matrix(temperatures: &[Vec<f64>], positions: Option<&[f64]>, degree: usize, intercept: bool) -> DMatrix<f64> {
    let n = temperatures.first().map_or(0, Vec::len);
    let per = temperatures.len() + usize::from(intercept);
    DMatrix::from_fn(n, per * (degree + 1), |row, col| {
        let (k, j) = (col / per, col % per);
        let pk = positions.map_or(1.0, |p| p[row].powi(k as i32));
        if intercept && j == 0 {
            pk
        } else {
            temperatures[j - usize::from(intercept)][row] * pk
        }
    })
}

/// Fits `E = T B` (eq. 3.14-3.15) for sensor series `temperatures[i][sample]` (degC), optional
/// positions (mm) and the error `error[sample]` (um).
pub fn fit_regression(
    error_name: &str,
    sensors: &[String],
    temperatures: &[Vec<f64>],
    position: Option<(&str, &[f64])>,
    degree: usize,
    intercept: bool,
    error: &[f64],
) -> Result<(RegressionModel, LinearFit), Error> {
    let (design, names) = checked_design(sensors, temperatures, position, degree, intercept, error)?;
    let fit = fit_linear(&design, error, None, &names).map_err(|e| fit_failure(error_name, e))?;
    let model = model_from_columns(error_name, sensors, position.map(|p| p.0), degree, intercept, &fit.coefficients, None);
    Ok((model, fit))
}

/// As [`fit_regression`] by M-estimation (robust regression, Huber 1981; `screen::irls`):
/// iteratively reweighted least squares with Huber (k = 1.345) or Tukey (c = 4.685) weights of the
/// residuals in units of their MAD-based scale, so that a few gross errors in the error column (a
/// probe that missed, a logger glitch) pull the model by their clipped size only, or not at all.
/// The returned fit's covariance is the M-estimator's (`RobustWeights::covariance_factor` times
/// (X^T X)^-1), its `sigma` the robust scale; the weights of every sample come with it.
#[allow(clippy::too_many_arguments)]
pub fn fit_regression_robust(
    error_name: &str,
    sensors: &[String],
    temperatures: &[Vec<f64>],
    position: Option<(&str, &[f64])>,
    degree: usize,
    intercept: bool,
    error: &[f64],
    weighting: crate::screen::irls::Weighting,
) -> Result<(RegressionModel, LinearFit, crate::screen::irls::RobustWeights), Error> {
    let (design, names) = checked_design(sensors, temperatures, position, degree, intercept, error)?;
    let unweighted = fit_linear(&design, error, None, &names).map_err(|e| fit_failure(error_name, e))?;
    let (mut fit, weights) = crate::screen::irls::irls(weighting, &vec![1.0; error.len()], |extra| {
        let fit = fit_linear(&design, error, Some(extra), &names).map_err(|e| fit_failure(error_name, e))?;
        let (c, r) = (fit.coefficients.clone(), fit.residuals.clone());
        Ok::<_, Error>((fit, c, r))
    })?;
    fit.covariance = &unweighted.unscaled_covariance * weights.covariance_factor(names.len());
    fit.unscaled_covariance = unweighted.unscaled_covariance;
    fit.sigma = weights.scale;
    let model = model_from_columns(error_name, sensors, position.map(|p| p.0), degree, intercept, &fit.coefficients, None);
    Ok((model, fit, weights))
}

/// Fits the geometric/thermal split (Zhu 2008 §4.4.2: "the measured thermal errors were first
/// separated into geometric errors and thermal errors. The geometric errors are usually modeled by
/// high-order polynomials. Thermal errors are modeled by the linear regression"):
/// `E(P, T) = sum_(k<=g) a_k P^k + sum_(k<=h) P^k sum_i c_ki T_i`, a polynomial of degree g in the
/// position for the geometric part (the intercepts) and of degree h times the temperatures for the
/// thermal part, in one least-squares fit. The model has `max(g, h) + 1` rows, with zeros where a
/// part has no term.
pub fn fit_split(
    error_name: &str,
    sensors: &[String],
    temperatures: &[Vec<f64>],
    position: (&str, &[f64]),
    geometric_degree: usize,
    thermal_degree: usize,
    error: &[f64],
) -> Result<(RegressionModel, LinearFit), Error> {
    let degree = geometric_degree.max(thermal_degree);
    let (design, names) = checked_design(sensors, temperatures, Some(position), degree, true, error)?;
    let per = sensors.len() + 1;
    let kept: Vec<usize> =
        (0..design.ncols()).filter(|c| if c % per == 0 { c / per <= geometric_degree } else { c / per <= thermal_degree }).collect();
    let sub = DMatrix::from_fn(design.nrows(), kept.len(), |r, c| design[(r, kept[c])]);
    let sub_names: Vec<String> = kept.iter().map(|&c| names[c].clone()).collect();
    let fit = fit_linear(&sub, error, None, &sub_names).map_err(|e| fit_failure(error_name, e))?;
    let model = model_from_columns(error_name, sensors, Some(position.0), degree, true, &fit.coefficients, Some(&kept));
    Ok((model, fit))
}

/// The design matrix of a fit and the names of its columns, once the shapes of the inputs are
/// checked: at least one sensor, one value per sample in every series.
fn checked_design(
    sensors: &[String],
    temperatures: &[Vec<f64>],
    position: Option<(&str, &[f64])>,
    degree: usize,
    intercept: bool,
    error: &[f64],
) -> Result<(DMatrix<f64>, Vec<String>), Error> {
    if degree > 0 && position.is_none() {
        return Err(Error::input("a position-dependent model (degree >= 1) needs the position column"));
    }
    if temperatures.is_empty() || sensors.len() != temperatures.len() {
        return Err(Error::input("a thermal error model needs at least one temperature sensor (one series per sensor name)"));
    }
    let n = error.len();
    if let Some(i) = temperatures.iter().position(|t| t.len() != n) {
        return Err(Error::input(format!("sensor {} has {} samples for {n} error values", sensors[i], temperatures[i].len())));
    }
    if position.is_some_and(|p| p.1.len() != n) {
        return Err(Error::input(format!("the position column has a length other than the {n} error values")));
    }
    let design = design_matrix(temperatures, position.map(|p| p.1), degree, intercept);
    Ok((design, column_names(sensors, position.map(|p| p.0), degree, intercept)))
}

/// A rank-deficient design (a sensor constant or proportional to another) is a failed computation
/// (as in `identify`); anything else is bad input.
fn fit_failure(error_name: &str, e: crate::identify::IdentifyError) -> Error {
    match e {
        crate::identify::IdentifyError::RankDeficient { .. } => {
            Error::computation(format!("{error_name}: {e}; leave that sensor out (--sensors) or select sensors (--select)"))
        }
        e => Error::input(format!("{error_name}: {e}")),
    }
}

pub(crate) fn column_names(sensors: &[String], position: Option<&str>, degree: usize, intercept: bool) -> Vec<String> {
    let mut names = Vec::new();
    for k in 0..=degree {
        let p = match (k, position) {
            (0, _) | (_, None) => String::new(),
            (1, Some(a)) => format!("*{a}"),
            (k, Some(a)) => format!("*{a}^{k}"),
        };
        if intercept {
            names.push(if k == 0 { "intercept".into() } else { p[1..].to_string() });
        }
        names.extend(sensors.iter().map(|s| format!("{s}{p}")));
    }
    names
}

/// Builds the model from the coefficients of the design columns; `kept` maps the coefficients to
/// a subset of the columns (stepwise), the others being zero.
fn model_from_columns(
    error_name: &str,
    sensors: &[String],
    position: Option<&str>,
    degree: usize,
    intercept: bool,
    coefficients: &[f64],
    kept: Option<&[usize]>,
) -> RegressionModel {
    let per = sensors.len() + usize::from(intercept);
    let mut full = vec![0.0; per * (degree + 1)];
    match kept {
        Some(k) => k.iter().zip(coefficients).for_each(|(&c, v)| full[c] = *v),
        None => full.copy_from_slice(coefficients),
    }
    let rows = (0..=degree)
        .map(|k| {
            let block = &full[k * per..(k + 1) * per];
            let mut row = vec![if intercept { block[0] } else { 0.0 }];
            row.extend_from_slice(&block[usize::from(intercept)..]);
            row
        })
        .collect();
    RegressionModel {
        error: error_name.into(),
        sensors: sensors.to_vec(),
        position: position.map(String::from),
        intercept,
        coefficients: rows,
    }
}

/// Pearson correlation of each sensor series with the error, and the range of each series.
/// Sorted by decreasing `|r|` (NISTIR 5236 §3.6: "the temperatures with the highest correlation and
/// significant variation"). Returns `(sensor index, r, range)`.
pub fn correlation_ranking(temperatures: &[Vec<f64>], error: &[f64]) -> Vec<(usize, f64, f64)> {
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let ey = mean(error);
    let syy: f64 = error.iter().map(|y| (y - ey).powi(2)).sum();
    let mut out: Vec<(usize, f64, f64)> = temperatures
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let et = mean(t);
            let stt: f64 = t.iter().map(|x| (x - et).powi(2)).sum();
            let sty: f64 = t.iter().zip(error).map(|(x, y)| (x - et) * (y - ey)).sum();
            let r = if stt > 0.0 && syy > 0.0 { sty / (stt * syy).sqrt() } else { 0.0 };
            let range = t.iter().copied().fold(f64::NEG_INFINITY, f64::max) - t.iter().copied().fold(f64::INFINITY, f64::min);
            (i, r, range)
        })
        .collect();
    out.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()).then(a.0.cmp(&b.0)));
    out
}

/// Selects sensors by correlation: the `count` best-correlated series whose range is at least
/// `min_range` (degC). Returns sensor indices in ranking order.
pub fn select_by_correlation(temperatures: &[Vec<f64>], error: &[f64], count: usize, min_range: f64) -> Vec<usize> {
    correlation_ranking(temperatures, error).into_iter().filter(|r| r.2 >= min_range).take(count).map(|r| r.0).collect()
}

/// Stepwise selection (partial F tests at `level`, `identify::stepwise`) of the PITE/PDTE
/// columns, the intercepts forced. Returns the model with the dropped terms at zero, and the names
/// of the kept columns.
#[allow(clippy::too_many_arguments)]
pub fn fit_stepwise(
    error_name: &str,
    sensors: &[String],
    temperatures: &[Vec<f64>],
    position: Option<(&str, &[f64])>,
    degree: usize,
    intercept: bool,
    error: &[f64],
    level: f64,
) -> Result<(RegressionModel, LinearFit, Vec<String>), Error> {
    let (design, names) = checked_design(sensors, temperatures, position, degree, intercept, error)?;
    let per = sensors.len() + usize::from(intercept);
    let forced: Vec<usize> = if intercept { (0..=degree).map(|k| k * per).collect() } else { Vec::new() };
    let result = stepwise(&design, error, None, &names, level, &forced).map_err(|e| fit_failure(error_name, e))?;
    let model =
        model_from_columns(error_name, sensors, position.map(|p| p.0), degree, intercept, &result.fit.coefficients, Some(&result.kept));
    let kept = result.kept.iter().map(|&c| names[c].clone()).collect();
    Ok((model, result.fit, kept))
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
