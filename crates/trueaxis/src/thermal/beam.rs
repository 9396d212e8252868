//! The stress-free beam model of the thermal parametric errors (Soons 1993 §3.4.3, eqs. 3.56-3.62).
//!
//! A guideway (or a scale) is a Bernoulli-Euler beam along the direction of its axis whose
//! temperature, relative to the reference state, is `T = a(x) + c(x) y + d(x) z` in each
//! cross-section (eq. 3.57): stress free, so the motion errors of the carriage at `x` follow by
//! integration from the point of the beam that does not move (eqs. 3.58-3.62, with the printed
//! `e_x` of eq. 3.62 read as `e_z`):
//!
//! `e_x = int alpha a dx`, `eps_y = int alpha d dx`, `eps_z = -int alpha c dx`,
//! `e_y = int eps_z dx`, `e_z = -int eps_y dx`.
//!
//! Sensors sit at stations along the beam, at least three per cross-section not on one line
//! ("sensors at the corners of each beam segment, so that linear temperature gradients in three
//! orthogonal directions can be estimated"); at each station `a, c, d` are fitted to the readings by
//! least squares and interpolated linearly between stations (§3.4.3: "the temperature distribution
//! is approximated by a piecewise linear interpolation between the various sensor locations"); the
//! stations span the axis travel. The scale loop (the elongation, read by the scale) and the
//! guideway loop (straightness and angular errors) may be separate beams (Fig. 3.26): `loop`.
//!
//! Everything is linear in the readings, so each error is `sum_s (T_s - 20) f_s(x)` with `f_s`
//! piecewise polynomial (quadratic for `e_x`, `eps`, cubic for `e_y`, `e_z`): the model is written
//! exactly as error terms `[[term.NAME]]` with the factors `X^k (T_s - 20)` and the station
//! intervals as position ranges, evaluated by `predict` and `compensate` at any temperatures.
//! Units: positions mm, alpha um/m/K, errors um and urad.

use super::links::ErrorTerm;
use crate::error::Error;
use crate::machine::{AxisKind, Machine};
use nalgebra::DMatrix;
use serde::Deserialize;

/// A beam file (TOML).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeamFile {
    #[serde(default)]
    pub name: Option<String>,
    /// The linear axis whose guideway (or scale) the beam is.
    pub axis: String,
    /// The beam's local y direction (unit, perpendicular to the axis); z = axis x y.
    pub y_direction: [f64; 3],
    /// Expansion coefficient (um/m/K).
    pub alpha_um_per_m_k: f64,
    /// Axis position (mm) of the point of the beam that does not move (default: the first station).
    #[serde(default)]
    pub fixed_at_mm: Option<f64>,
    /// `both` (default), `scale` (the elongation only) or `guideway` (straightness and angular).
    #[serde(default, rename = "loop")]
    pub structural_loop: Option<String>,
    #[serde(rename = "station")]
    pub stations: Vec<Station>,
}

/// A cross-section with its sensors.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Station {
    /// Axis position (mm) of the cross-section.
    pub at_mm: f64,
    pub sensors: Vec<SensorAt>,
}

/// A sensor `T:<name>` at `(y, z)` (mm) from the beam axis in the cross-section.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorAt {
    pub name: String,
    pub y: f64,
    pub z: f64,
}

/// A polynomial in the local variable `t = x - x_i` per interval, per sensor.
type Piecewise = Vec<Vec<Vec<f64>>>; // [interval][sensor][power]

fn poly_eval(p: &[f64], t: f64) -> f64 {
    p.iter().rev().fold(0.0, |acc, c| acc * t + c)
}

/// The antiderivative with value zero at t = 0.
fn poly_integral(p: &[f64]) -> Vec<f64> {
    std::iter::once(0.0).chain(p.iter().enumerate().map(|(k, c)| c / (k + 1) as f64)).collect()
}

/// The compiled beam: knots and the piecewise polynomials (per unit of `T_s - 20`) of each error.
#[derive(Clone, Debug)]
pub struct Beam {
    pub sensors: Vec<String>,
    /// Station positions (mm), increasing.
    pub knots: Vec<f64>,
    /// `e_x, e_y, e_z` (um) and `eps_y, eps_z` (urad) per unit of each sensor's `T - 20`.
    e: [Piecewise; 3],
    eps: [Piecewise; 2],
    axis: char,
    /// Axis direction, local y and z in M.
    frame: [[f64; 3]; 3],
    structural_loop: String,
}

impl Beam {
    /// Builds the beam of `file` on `machine`.
    pub fn new(file: &BeamFile, machine: &Machine, origin: &str) -> Result<Beam, Error> {
        let bad = |m: String| Error::input(format!("{origin}: {m}"));
        let mut letters = file.axis.trim().chars();
        let letter = match (letters.next(), letters.next()) {
            (Some(c), None) => c.to_ascii_uppercase(),
            _ => return Err(bad(format!("`axis` = `{}` is not an axis letter", file.axis))),
        };
        let axis = machine
            .axes()
            .iter()
            .find(|a| a.letter == letter)
            .ok_or_else(|| bad(format!("machine `{}` has no axis {letter} (axes: {})", machine.name, machine.axis_letters())))?;
        if axis.kind != AxisKind::Linear {
            return Err(bad(format!("axis {letter} is rotary; a beam is the guideway of a linear axis")));
        }
        let d = [axis.direction.x, axis.direction.y, axis.direction.z];
        let y = file.y_direction;
        let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if (norm(y) - 1.0).abs() > 1e-6 || (d[0] * y[0] + d[1] * y[1] + d[2] * y[2]).abs() > 1e-6 {
            return Err(bad(format!("`y_direction` must be a unit vector perpendicular to the direction of axis {letter}")));
        }
        let z = [d[1] * y[2] - d[2] * y[1], d[2] * y[0] - d[0] * y[2], d[0] * y[1] - d[1] * y[0]];
        if !(file.alpha_um_per_m_k.is_finite() && file.alpha_um_per_m_k > 0.0) {
            return Err(bad("`alpha_um_per_m_k` must be a positive expansion coefficient in um/m/K".into()));
        }
        let structural_loop = file.structural_loop.clone().unwrap_or_else(|| "both".into());
        if !["both", "scale", "guideway"].contains(&structural_loop.as_str()) {
            return Err(bad(format!("`loop` = `{structural_loop}`: expected both, scale or guideway")));
        }
        let mut stations = file.stations.clone();
        stations.sort_by(|a, b| a.at_mm.total_cmp(&b.at_mm));
        if stations.len() < 2 || stations.windows(2).any(|w| w[1].at_mm <= w[0].at_mm) || stations.iter().any(|s| !s.at_mm.is_finite()) {
            return Err(bad("a beam needs at least two [[station]] at distinct axis positions `at_mm`".into()));
        }
        let mut sensors: Vec<String> = Vec::new();
        for s in stations.iter().flat_map(|s| &s.sensors) {
            if !s.name.starts_with("T:") || s.name.len() < 3 {
                return Err(bad(format!("sensor `{}` must be named `T:<name>`", s.name)));
            }
            if !sensors.contains(&s.name) {
                sensors.push(s.name.clone());
            }
        }
        // per station: [a, c, d] = W T, W the least-squares map of the readings (a in K, c and d
        // in K/mm), as weights over every sensor
        let mut station_maps: Vec<[Vec<f64>; 3]> = Vec::new();
        for st in &stations {
            let x = DMatrix::from_fn(st.sensors.len(), 3, |r, c| [1.0, st.sensors[r].y, st.sensors[r].z][c]);
            let svd = x.clone().svd(true, true);
            let smallest = svd.singular_values.iter().copied().fold(f64::INFINITY, f64::min);
            if st.sensors.len() < 3 || smallest <= 1e-9 * svd.singular_values.max() {
                return Err(bad(format!(
                    "station at {} mm: a linear field a + c y + d z needs at least three sensors not on one line in the cross-section",
                    st.at_mm
                )));
            }
            let pinv = svd.pseudo_inverse(1e-12).map_err(|e| bad(e.to_string()))?;
            let mut map = [vec![0.0; sensors.len()], vec![0.0; sensors.len()], vec![0.0; sensors.len()]];
            for (r, s) in st.sensors.iter().enumerate() {
                let i = sensors.iter().position(|n| n == &s.name).expect("listed");
                for (k, m) in map.iter_mut().enumerate() {
                    m[i] += pinv[(k, r)];
                }
            }
            station_maps.push(map);
        }
        let knots: Vec<f64> = stations.iter().map(|s| s.at_mm).collect();
        let [lo, hi] = axis.range.unwrap_or([knots[0], knots[knots.len() - 1]]);
        if lo < knots[0] - 1e-9 || hi > knots[knots.len() - 1] + 1e-9 {
            return Err(bad(format!(
                "the stations [{}, {}] mm must span the travel of axis {letter} [{lo}, {hi}] mm",
                knots[0],
                knots[knots.len() - 1]
            )));
        }
        let n_int = knots.len() - 1;
        let ns = sensors.len();
        // a, c, d per interval: linear in t, per sensor
        let field = |k: usize| -> Piecewise {
            (0..n_int)
                .map(|i| {
                    let h = knots[i + 1] - knots[i];
                    (0..ns).map(|s| vec![station_maps[i][k][s], (station_maps[i + 1][k][s] - station_maps[i][k][s]) / h]).collect()
                })
                .collect()
        };
        let alpha = file.alpha_um_per_m_k; // 1e-6 / K
        let fixed = file.fixed_at_mm.unwrap_or(knots[0]);
        if !(knots[0]..=knots[n_int]).contains(&fixed) {
            return Err(bad(format!("`fixed_at_mm` = {fixed} lies outside the stations [{}, {}] mm", knots[0], knots[n_int])));
        }
        // integral from the fixed point of a piecewise polynomial, continuous
        let integrate = |g: &Piecewise, scale: f64| -> Piecewise {
            let mut out: Piecewise =
                g.iter().map(|per| per.iter().map(|p| poly_integral(p).iter().map(|c| c * scale).collect()).collect()).collect();
            for s in 0..ns {
                let mut value = 0.0;
                for (i, per) in out.iter_mut().enumerate() {
                    per[s][0] += value;
                    value = poly_eval(&per[s], knots[i + 1] - knots[i]);
                }
                // zero at the fixed point
                let i = knots.windows(2).position(|w| fixed < w[1]).unwrap_or(n_int - 1);
                let at = poly_eval(&out[i][s], fixed - knots[i]);
                for per in out.iter_mut() {
                    per[s][0] -= at;
                }
            }
            out
        };
        // e_x (um) = alpha [um/m/K] 1e-3 int a dx[mm]; eps (urad) = alpha int d dx; e_y (um) = 1e-3 int eps_z dx
        let e_x = integrate(&field(0), alpha * 1e-3);
        let eps_y = integrate(&field(2), alpha);
        let eps_z = integrate(&field(1), -alpha);
        let e_y = integrate(&eps_z, 1e-3);
        let e_z = integrate(&eps_y, -1e-3);
        Ok(Beam { sensors, knots, e: [e_x, e_y, e_z], eps: [eps_y, eps_z], axis: letter, frame: [d, y, z], structural_loop })
    }

    /// `(e_x, e_y, e_z)` (um) and `(eps_y, eps_z)` (urad) in the beam's frame at axis position `x`
    /// (mm) for sensor readings `t` (degC, in the order of [`Beam::sensors`]).
    pub fn errors_at(&self, x: f64, t: &[f64]) -> ([f64; 3], [f64; 2]) {
        let n = self.knots.len() - 1;
        let i = self.knots.windows(2).position(|w| x < w[1]).unwrap_or(n - 1);
        let local = x - self.knots[i];
        let sum = |p: &Piecewise| self.sensors.iter().enumerate().map(|(s, _)| (t[s] - 20.0) * poly_eval(&p[i][s], local)).sum::<f64>();
        ([sum(&self.e[0]), sum(&self.e[1]), sum(&self.e[2])], [sum(&self.eps[0]), sum(&self.eps[1])])
    }

    /// The beam as error terms of the axis's motion errors (module documentation).
    pub fn terms(&self) -> Vec<ErrorTerm> {
        let a = self.axis;
        let [d, y, z] = self.frame;
        let translations = ["X", "Y", "Z"].map(|c| format!("E{c}{a}"));
        let rot_names = ["A", "B", "C"].map(|c| format!("E{c}{a}"));
        // (piecewise, direction in M, names): e_x along d, e_y along y, e_z along z; eps_y about y, eps_z about z
        let mut parts: Vec<(&Piecewise, [f64; 3], &[String; 3])> = Vec::new();
        if self.structural_loop != "guideway" {
            parts.push((&self.e[0], d, &translations));
        }
        if self.structural_loop != "scale" {
            parts.push((&self.e[1], y, &translations));
            parts.push((&self.e[2], z, &translations));
            parts.push((&self.eps[0], y, &rot_names));
            parts.push((&self.eps[1], z, &rot_names));
        }
        let n = self.knots.len() - 1;
        let mut out = Vec::new();
        for (p, dir, targets) in parts {
            for (i, per_sensor) in p.iter().enumerate() {
                let lo = if i == 0 { f64::NEG_INFINITY } else { self.knots[i] };
                let hi = if i == n - 1 { f64::INFINITY } else { self.knots[i + 1] };
                for (local, sensor) in per_sensor.iter().zip(&self.sensors) {
                    // sum_k c_k (x - x_i)^k into powers of x: C(k, j) x^j (-x_i)^(k-j)
                    let mut global = vec![0.0; local.len()];
                    for (k, c) in local.iter().enumerate() {
                        let mut binom = 1.0;
                        for (j, g) in global.iter_mut().enumerate().take(k + 1) {
                            *g += c * binom * (-self.knots[i]).powi((k - j) as i32);
                            binom = binom * (k - j) as f64 / (j + 1) as f64;
                        }
                    }
                    for (target, component) in targets.iter().zip(dir) {
                        if component.abs() < 1e-12 {
                            continue;
                        }
                        for (k, c) in global.iter().enumerate() {
                            if c.abs() > 0.0 {
                                out.push(ErrorTerm {
                                    parameter: target.clone(),
                                    coefficient: c * component,
                                    axes: if k > 0 { vec![(a, k as i32)] } else { Vec::new() },
                                    sensors: vec![(sensor.clone(), 1)],
                                    direction: None,
                                    range: Some([lo, hi]),
                                });
                            }
                        }
                    }
                }
            }
        }
        out
    }
}

/// Reads a beam file's text.
pub fn read_beam(text: &str, origin: &str) -> Result<BeamFile, Error> {
    crate::io::toml_numbers::refuse_underflow(text).map_err(|e| e.in_file(origin))?;
    toml::from_str(text).map_err(|e| Error::input(format!("{origin}: {}", e.to_string().split_whitespace().collect::<Vec<_>>().join(" "))))
}
