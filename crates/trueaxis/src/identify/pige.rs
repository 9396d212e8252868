//! The 8 position-independent geometric errors (PIGEs, location errors) of the two rotary axes of a
//! table-tilting machine from double-ballbar traces (Jiang 2014, ch. 4-6; digest
//! `specs/jiang.md` 2.6).
//!
//! Procedure (thesis §4.2, §5.2):
//! 1. points from each trace: `r_i = L + dL_i` for a radial bar, `r_i = sqrt((L + dL_i)^2 - D^2)`
//!    for the extended bar (the spindle ball `D` off the pivot plane, Figs. 4.5 / 5.2), at the angle
//!    `theta_i + delta_e` with the start-angle correction of Eq. 4.1;
//! 2. the algebraic (Kåsa) circle fit gives the local centre of the actual axis seen from the
//!    spindle ball, in the plane of the pivot circle;
//! 3. centres at two (or more) spindle positions `s` along the axis lie on the actual axis line
//!    `c(s) = e + s t`: the offset `e` is the position PIGE pair, the slope `t = omega x d` the
//!    orientation pair (`theta = atan(slope)`, the thesis's `atan(O'E / |S'O'|)`). Ch. 5 uses the
//!    normal bar at `s = 0` and the extended bar at `s = -D` (A) or `+D` (C); ch. 4 the same with the
//!    pivot offset along A; ch. 6 (Lee & Yang) two normal-bar setups at two positions along each axis.
//! 4. the inner axis (C) rides on the outer (A): its apparent line contains the outer's offset and
//!    tilt, which are subtracted (Table 5.1: `e_y0c = fit_y(C1) - e_y0a`; `theta_y0c = ... - theta_y0a`).
//!
//! Sign conventions follow the HTM of thesis Eq. 3.2-3.3 (= the library's chain): the thesis's
//! ch. 5 prints the Y and Z components of the orientation formulas swapped, and ch. 6 prints the
//! `theta_y0a` and `theta_x0c` differences with the opposite sign; both are errata (digest 2.6(d),
//! (e)) and the consistent forms are used here.

use super::IdentifyError;
use crate::geometry::Vec3;
use crate::instruments::ballbar::{BallbarTest, RotaryGeometry, RotaryPair};
use crate::machine::{Component, Machine, ParameterId};
use nalgebra::{Matrix3, Vector3};

/// A circle from the algebraic fit (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CircleFit {
    pub centre: [f64; 2],
    pub radius: f64,
    /// RMS of the geometric residuals `|p_i - c| - radius` (mm).
    pub residual_rms: f64,
    /// Largest minus smallest geometric residual (mm).
    pub residual_range: f64,
    /// Covariance of the centre (mm^2) from the scatter of the points about the circle: the
    /// geometric fit linearised at the solution, `s^2 (A^T A)^-1` with rows
    /// `A_i = -[(p_i - c) / |p_i - c|, 1]` and `s^2 = sum r_i^2 / (n - 3)`. `None` with three points
    /// (no scatter to judge by).
    pub centre_covariance: Option<[[f64; 2]; 2]>,
}

/// Algebraic (Kåsa) least-squares circle: minimises `sum (Y^2 + Z^2 + a Y + b Z + c)^2` (Jiang 2014
/// §4.2), solving the normal equations
/// `[SYY SYZ SY; SYZ SZZ SZ; SY SZ N] [a b c]^T = -[S(Y^3+YZ^2); S(Y^2Z+Z^3); S(Y^2+Z^2)]`
/// with the minus sign that the thesis omits (erratum 2 of the digest) and `N` the actual number of
/// points. Centre `(-a/2, -b/2)`, radius `sqrt(a^2 + b^2 - 4c) / 2`. Works on partial arcs.
/// Points in mm; at least three, not on one line.
pub fn kasa_fit(points: &[[f64; 2]]) -> Result<CircleFit, IdentifyError> {
    if points.len() < 3 {
        return Err(IdentifyError::Input(format!("a circle fit needs at least 3 points, got {}", points.len())));
    }
    if points.iter().flatten().any(|v| !v.is_finite()) {
        return Err(IdentifyError::Input("a circle fit point is not a finite number".into()));
    }
    // Centre the data on its mean for conditioning; shift back at the end.
    let n = points.len() as f64;
    let my = points.iter().map(|p| p[0]).sum::<f64>() / n;
    let mz = points.iter().map(|p| p[1]).sum::<f64>() / n;
    let mut m = Matrix3::<f64>::zeros();
    let mut rhs = Vector3::<f64>::zeros();
    for p in points {
        let (y, z) = (p[0] - my, p[1] - mz);
        let r2 = y * y + z * z;
        let row = Vector3::new(y, z, 1.0);
        m += row * row.transpose();
        rhs -= row * r2;
    }
    let solution = m.lu().solve(&rhs).filter(|s| s.iter().all(|v| v.is_finite()));
    let Some(abc) = solution else {
        return Err(IdentifyError::RankDeficient { message: "the circle-fit points lie on a line".into() });
    };
    let (a, b, c) = (abc[0], abc[1], abc[2]);
    let r2 = a * a + b * b - 4.0 * c;
    if r2.is_nan() || r2 <= 0.0 {
        return Err(IdentifyError::RankDeficient { message: "the circle-fit points do not determine a circle".into() });
    }
    let centre = [my - a / 2.0, mz - b / 2.0];
    let radius = r2.sqrt() / 2.0;
    let residuals: Vec<f64> = points.iter().map(|p| (p[0] - centre[0]).hypot(p[1] - centre[1]) - radius).collect();
    let rms = (residuals.iter().map(|r| r * r).sum::<f64>() / n).sqrt();
    let (lo, hi) = residuals.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &r| (a.min(r), b.max(r)));
    Ok(CircleFit {
        centre,
        radius,
        residual_rms: rms,
        residual_range: hi - lo,
        centre_covariance: centre_covariance(points, centre, &residuals),
    })
}

/// The covariance of a fitted circle's centre (see [`CircleFit::centre_covariance`]).
fn centre_covariance(points: &[[f64; 2]], centre: [f64; 2], residuals: &[f64]) -> Option<[[f64; 2]; 2]> {
    let n = points.len();
    if n <= 3 {
        return None;
    }
    let s2 = residuals.iter().map(|r| r * r).sum::<f64>() / (n - 3) as f64;
    centre_covariance_per_unit_variance(points, centre).map(|c| c.map(|row| row.map(|v| s2 * v)))
}

/// The centre block of `(A^T A)^-1` of the linearised geometric circle fit (rows
/// `A_i = -[(p_i - c) / |p_i - c|, 1]`): the centre covariance for points of unit radial variance.
pub(crate) fn centre_covariance_per_unit_variance(points: &[[f64; 2]], centre: [f64; 2]) -> Option<[[f64; 2]; 2]> {
    let mut ata = Matrix3::<f64>::zeros();
    for p in points {
        let (dy, dz) = (p[0] - centre[0], p[1] - centre[1]);
        let r = dy.hypot(dz);
        let row = Vector3::new(dy / r, dz / r, 1.0);
        ata += row * row.transpose();
    }
    let inverse = ata.try_inverse().filter(|m| m.iter().all(|v| v.is_finite()))?;
    Some([[inverse[(0, 0)], inverse[(0, 1)]], [inverse[(1, 0)], inverse[(1, 1)]]])
}

/// Fewest readings of one step accepted for identification.
pub const MIN_READINGS: usize = 8;
/// Smallest rotation (deg) of one step accepted for identification. The Kåsa centre's noise grows
/// fast as the arc shrinks: relative to a full circle with as many points, its worst component's
/// standard deviation is 2.3 x on 180 deg, 5.7 x on the thesis's 90 deg A arc, 28 x on 45 deg and
/// 150 x on 20 deg (first-order least squares of `dL = c1 cos t + c2 sin t + dr`).
pub const MIN_SPAN_DEG: f64 = 45.0;

/// The rotation covered by axis positions `angles` (rad), in deg, at most 360.
pub fn angle_span_deg(angles: &[f64]) -> f64 {
    let (lo, hi) = angles.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &a| (lo.min(a), hi.max(a)));
    if angles.is_empty() {
        0.0
    } else {
        (hi - lo).to_degrees().min(360.0)
    }
}

/// Start-angle error of Jiang 2014 Eq. 4.1: `delta_e = atan((P0P0'.j) / (P0P0'.i + R))` (rad), where
/// `P0P0'` is the displacement (mm) of the actual start point of the pivot from the ideal one, `i`
/// along the bar (radial) and `j` along the path (tangential), from a conventional centring test; the
/// thesis writes `R` = 100 mm and once `theta_e` for `delta_e` (errata 9).
pub fn start_angle_error(radial_mm: f64, tangential_mm: f64, radius_mm: f64) -> f64 {
    tangential_mm.atan2(radial_mm + radius_mm)
}

/// One bar trace of a rotary-axis test, ready for the circle fit.
#[derive(Clone, Debug)]
pub struct DbbTrace {
    pub geometry: RotaryGeometry,
    /// Axis positions (rad) of the samples: the pivot's angle in the plane basis, before correction.
    pub angles: Vec<f64>,
    /// Bar readings relative to `bar_length` (mm).
    pub dl: Vec<f64>,
    /// The length the readings are relative to (mm): nominal or calibrated (thesis `R_c`, `R_e`).
    pub bar_length: f64,
    /// Start-angle correction `delta_e` (rad), Eq. 4.1; 0 if the pivot was placed exactly.
    pub start_angle: f64,
}

impl DbbTrace {
    /// The trace of a simulated or measured test with readings `dl` (mm) relative to its nominal
    /// length.
    pub fn of_test(test: &BallbarTest, dl: Vec<f64>) -> Result<DbbTrace, IdentifyError> {
        let geometry = test.rotary.ok_or_else(|| IdentifyError::Input(format!("`{}` is not a rotary-axis test", test.name)))?;
        Ok(DbbTrace { geometry, angles: test.angles.clone(), dl, bar_length: test.nominal_length, start_angle: 0.0 })
    }

    /// Points in the plane of the pivot circle (mm, basis `u1 u2`): Jiang 2014 §4.2 (b) and, for the
    /// extended bar, `EP_i = sqrt(L_i^2 - D^2)` (§4.2 (d)).
    pub fn points(&self) -> Result<Vec<[f64; 2]>, IdentifyError> {
        if self.angles.len() != self.dl.len() {
            return Err(IdentifyError::Input(format!("{} angles but {} bar readings", self.angles.len(), self.dl.len())));
        }
        let d2 = self.geometry.axial_separation.powi(2);
        self.angles
            .iter()
            .zip(&self.dl)
            .map(|(&t, &dl)| {
                let l = self.bar_length + dl;
                let r2 = l * l - d2;
                if r2.is_nan() || r2 <= 0.0 {
                    return Err(IdentifyError::Input(format!(
                        "bar length {l} mm is not longer than the axial offset {} mm of the spindle ball",
                        self.geometry.axial_separation.abs()
                    )));
                }
                let r = r2.sqrt();
                let a = t + self.start_angle;
                Ok([r * a.cos(), r * a.sin()])
            })
            .collect()
    }

    /// The local centre of the actual axis seen from the spindle ball (mm, basis `u1 u2`).
    pub fn fit(&self) -> Result<CircleFit, IdentifyError> {
        kasa_fit(&self.points()?)
    }
}

/// The actual line of one rotary axis from the local centres at several spindle positions.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisLine {
    pub axis: char,
    /// Offset of the actual axis from the nominal one at the axis point, perpendicular to it (mm, M).
    pub offset: Vec3,
    /// Rotation vector of the actual axis direction, perpendicular to it (rad, M); `None` when all
    /// traces had the same spindle position (position step only).
    pub tilt: Option<Vec3>,
    /// (spindle position along the axis (mm), local centre (mm, basis u1 u2), fit) of each trace.
    pub stations: Vec<Station>,
}

/// Fits the line `c(s) = e + s t` through the local centres of `traces` (all of the same axis) and
/// turns it into an offset and a tilt in M: `omega = d x t3` with `t3 = t1 u1 + t2 u2`, each
/// component `atan` of the slope (thesis §4.2 (d)).
pub fn axis_line(machine: &Machine, traces: &[DbbTrace]) -> Result<AxisLine, IdentifyError> {
    let (geometry, stations) = fitted_stations(traces)?;
    Ok(line_through(machine, &geometry, stations))
}

/// A trace's station on its axis line: spindle position along the axis (mm), local centre (mm,
/// basis u1 u2) and the circle fit.
pub type Station = (f64, [f64; 2], CircleFit);

/// The circle fit of every trace of one axis, with the geometry they share.
fn fitted_stations(traces: &[DbbTrace]) -> Result<(RotaryGeometry, Vec<Station>), IdentifyError> {
    let Some(first) = traces.first() else {
        return Err(IdentifyError::Input("no trace for the axis".into()));
    };
    let g0 = first.geometry;
    if traces.iter().any(|t| t.geometry.axis != g0.axis || (t.geometry.u1 - g0.u1).norm() > 1e-9) {
        return Err(IdentifyError::Input("the traces of one axis must share the axis and the pivot direction".into()));
    }
    let stations = traces
        .iter()
        .map(|t| {
            let fit = t.fit()?;
            Ok((t.geometry.spindle_position, fit.centre, fit))
        })
        .collect::<Result<Vec<_>, IdentifyError>>()?;
    Ok((g0, stations))
}

/// The axis line through the local centres of `stations` (spindle position, centre, fit).
fn line_through(machine: &Machine, g0: &RotaryGeometry, stations: Vec<Station>) -> AxisLine {
    let axis = &machine.axes()[g0.axis];
    let n = stations.len() as f64;
    let s_mean = stations.iter().map(|s| s.0).sum::<f64>() / n;
    let c_mean = [0, 1].map(|k| stations.iter().map(|s| s.1[k]).sum::<f64>() / n);
    let sss: f64 = stations.iter().map(|s| (s.0 - s_mean).powi(2)).sum();
    let (slope, tilt) = if sss > 1e-6 {
        let slope = [0, 1].map(|k| stations.iter().map(|s| (s.0 - s_mean) * (s.1[k] - c_mean[k])).sum::<f64>() / sss);
        let t3 = g0.u1 * slope[0].atan() + g0.u2 * slope[1].atan();
        (slope, Some(axis.direction.cross(&t3)))
    } else {
        ([0.0, 0.0], None)
    };
    let e = [0, 1].map(|k| c_mean[k] - slope[k] * s_mean);
    AxisLine { axis: axis.letter, offset: g0.u1 * e[0] + g0.u2 * e[1], tilt, stations }
}

/// The PIGEs of a rotary pair.
#[derive(Clone, Debug, PartialEq)]
pub struct Piges {
    /// ISO names and values (mm, rad), in the thesis order: outer translations, outer rotations,
    /// inner translations, inner rotations (C600U: EY0A EZ0A EB0A EC0A EX0C EY0C EA0C EB0C); six
    /// per axis for an axis not along X, Y or Z (see `named`).
    pub values: Vec<(ParameterId, f64)>,
    pub outer: AxisLine,
    pub inner: AxisLine,
}

impl Piges {
    /// The value of parameter `name` (mm or rad).
    pub fn get(&self, name: &str) -> Option<f64> {
        self.values.iter().find(|(id, _)| id.to_string() == name).map(|(_, v)| *v)
    }

    /// The machine's parameter vector holding these PIGEs (zero elsewhere).
    pub fn parameters(&self, machine: &Machine) -> Vec<f64> {
        let mut p = vec![0.0; machine.parameter_count()];
        for (id, v) in &self.values {
            if let Ok(i) = machine.parameter_index(id) {
                p[i] = *v;
            }
        }
        p
    }
}

/// Index (0, 1, 2) of the coordinate axis `d` lies along, if it lies along one.
fn coordinate_axis(d: &Vec3) -> Option<usize> {
    (0..3).find(|&j| (d[j].abs() - 1.0).abs() < 1e-9)
}

/// The offset `offset` and tilt `tilt` (both perpendicular to the axis, M) as ISO location errors
/// of `letter`. An axis along coordinate `j` (X, Y or Z) has the four PIGEs of the thesis: the two
/// translation and two rotation components perpendicular to it (A: EY0A EZ0A EB0A EC0A). An axis
/// in any other direction (the KX8-Five's A, tilted 45 deg) has no such pair of names: it gets all
/// three translation and three rotation components in M (EX0A ... EC0A); their components along
/// the axis are zero, which is the axis line's own convention (a shift along the axis or a turn
/// about it does not move the line), so the chain reproduces the identified line with them.
fn named(letter: char, direction: &Vec3, offset: &Vec3, tilt: &Vec3) -> Vec<(ParameterId, f64)> {
    let others: Vec<usize> = match coordinate_axis(direction) {
        Some(j) => (0..3).filter(|&k| k != j).collect(),
        None => (0..3).collect(),
    };
    let mut out = Vec::with_capacity(4);
    for &k in &others {
        out.push((ParameterId::Location { axis: letter, component: Component::from_index(k) }, offset[k]));
    }
    for &k in &others {
        out.push((ParameterId::Location { axis: letter, component: Component::from_index(3 + k) }, tilt[k]));
    }
    out
}

fn perpendicular(v: &Vec3, d: &Vec3) -> Vec3 {
    v - d * v.dot(d)
}

/// Identifies the 8 PIGEs of `pair` from traces of both axes (Jiang 2014 ch. 4, 5 or 6): `outer`
/// traces sweep the outer axis, `inner` traces the inner one (with the outer axis at 0). Both axes
/// must be on the same side of the chain (the outer carrying the inner): with one on each side a
/// common shift of both lines changes no bar length, and the error says so. Each axis
/// needs traces at two different spindle positions for its orientation PIGEs; with one position
/// the orientation is reported as 0 and not corrected for.
pub fn identify_piges(machine: &Machine, pair: RotaryPair, outer: &[DbbTrace], inner: &[DbbTrace]) -> Result<Piges, IdentifyError> {
    let o = machine.axis_index(pair.outer).ok_or_else(|| IdentifyError::Input(format!("no axis {}", pair.outer)))?;
    let i = machine.axis_index(pair.inner).ok_or_else(|| IdentifyError::Input(format!("no axis {}", pair.inner)))?;
    for (traces, k, letter) in [(outer, o, pair.outer), (inner, i, pair.inner)] {
        if traces.iter().any(|t| t.geometry.axis != k) {
            return Err(IdentifyError::Input(format!("a trace given for axis {letter} sweeps another axis")));
        }
    }
    if !pair.inner_carried_by_outer(machine) {
        return Err(IdentifyError::Input(format!(
            "machine `{}`: the rotary axes {} and {} are on different sides of the chain (one carries the tool, the other the workpiece); \
             a shift of both axis lines by one displacement moves the tool and the workpiece together and changes no bar length, so their \
             PIGEs cannot be separated by these tests. Identification supports two rotary axes on the same side (a tilting table such as \
             wCAbYXZt, a tilting head such as wXYbZCBt), in any direction; `simulate` works on any machine",
            machine.name, pair.outer, pair.inner
        )));
    }
    let outer_line = axis_line(machine, outer)?;
    let inner_line = axis_line(machine, inner)?;
    Ok(combine_lines(machine, pair, outer_line, inner_line))
}

/// The PIGEs of both axes from their lines (the checks of [`identify_piges`] done): the inner axis
/// is carried by the outer, so the outer's offset and tilt are removed from the inner's line.
fn combine_lines(machine: &Machine, pair: RotaryPair, outer_line: AxisLine, inner_line: AxisLine) -> Piges {
    let ax_o = &machine.axes()[machine.axis_index(pair.outer).expect("checked")];
    let ax_i = &machine.axes()[machine.axis_index(pair.inner).expect("checked")];
    let tilt_o = outer_line.tilt.unwrap_or_else(Vec3::zeros);
    let di = ax_i.direction;
    // Table 5.1: the inner axis is carried by the outer; remove the outer's offset and tilt.
    let carried = outer_line.offset + tilt_o.cross(&(ax_i.point - ax_o.point));
    let offset_i = inner_line.offset - perpendicular(&carried, &di);
    let tilt_i = inner_line.tilt.map(|t| t - perpendicular(&tilt_o, &di)).unwrap_or_else(Vec3::zeros);
    let mut values = named(pair.outer, &ax_o.direction, &outer_line.offset, &tilt_o);
    values.extend(named(pair.inner, &di, &offset_i, &tilt_i));
    Piges { values, outer: outer_line, inner: inner_line }
}

/// Standard uncertainty of each PIGE of one set of traces (mm, rad; the order of
/// [`Piges::values`]), from the scatter of every trace about its fitted circle: the covariance of
/// each circle centre ([`CircleFit::centre_covariance`]) propagated through the axis lines and the
/// removal of the outer axis (GUM law of propagation; the map from centres to PIGEs is linear but
/// for the `atan` of the slopes, differentiated numerically). The scatter includes whatever the
/// circle does not explain (noise, motion errors), so the uncertainty is that of the method on
/// this machine, not of the bar alone. `None` when a trace has three points or fewer.
pub fn pige_uncertainty(
    machine: &Machine,
    pair: RotaryPair,
    outer: &[DbbTrace],
    inner: &[DbbTrace],
) -> Result<Option<Vec<f64>>, IdentifyError> {
    identify_piges(machine, pair, outer, inner)?;
    let covariances: Option<Vec<[[f64; 2]; 2]>> =
        outer.iter().chain(inner).map(|t| t.fit().map(|f| f.centre_covariance)).collect::<Result<Vec<_>, _>>()?.into_iter().collect();
    let Some(covariances) = covariances else { return Ok(None) };
    propagate_centre_covariances(machine, pair, outer, inner, &covariances).map(Some)
}

/// Standard uncertainty of each PIGE (mm, rad; the order of [`Piges::values`]) when the centre of
/// trace `k` (outer traces first, then inner) has the covariance `covariances[k]` (mm^2) and the
/// traces are independent: `u_p^2 = sum_k J_pk C_k J_pk^T`, the Jacobian `J` of the PIGEs with
/// respect to the centres by differences (the map is linear but for the `atan` of the slopes).
pub(crate) fn propagate_centre_covariances(
    machine: &Machine,
    pair: RotaryPair,
    outer: &[DbbTrace],
    inner: &[DbbTrace],
    covariances: &[[[f64; 2]; 2]],
) -> Result<Vec<f64>, IdentifyError> {
    let (go, so) = fitted_stations(outer)?;
    let (gi, si) = fitted_stations(inner)?;
    let values = |so: Vec<_>, si: Vec<_>| -> Vec<f64> {
        combine_lines(machine, pair, line_through(machine, &go, so), line_through(machine, &gi, si)).values.iter().map(|v| v.1).collect()
    };
    let reference = values(so.clone(), si.clone());
    let h = 1e-6; // mm
    let mut variance = vec![0.0; reference.len()];
    let stations = (0..so.len()).map(|k| (0, k)).chain((0..si.len()).map(|k| (1, k)));
    for ((side, k), cov) in stations.zip(covariances) {
        let column = |c: usize| -> Vec<f64> {
            let (mut o, mut i) = (so.clone(), si.clone());
            let target = if side == 0 { &mut o[k] } else { &mut i[k] };
            target.1[c] += h;
            values(o, i).iter().zip(&reference).map(|(v, r)| (v - r) / h).collect()
        };
        let (j0, j1) = (column(0), column(1));
        for (p, var) in variance.iter_mut().enumerate() {
            *var += j0[p] * j0[p] * cov[0][0] + 2.0 * j0[p] * j1[p] * cov[0][1] + j1[p] * j1[p] * cov[1][1];
        }
    }
    Ok(variance.iter().map(|v| v.max(0.0).sqrt()).collect())
}

/// Simulated compensation (Jiang 2014 §4.3, Fig. 4.8): the readings minus the exact-chain readings of
/// the identified PIGEs, `dL_comp = dL_meas - dL_model(PIGE_hat)` (mm), per sample.
pub fn compensation_residual(machine: &Machine, test: &BallbarTest, measured: &[f64], piges: &Piges) -> Vec<f64> {
    let model = test.simulate_params(machine, &piges.parameters(machine));
    measured.iter().zip(model).map(|(m, p)| m - p).collect()
}

/// Mean and sample standard deviation of each PIGE over repeated identifications (thesis Tables
/// 4.2-6.4), with the thesis's stopping rule: position PIGEs within `position_tol` (mm) and
/// orientation PIGEs within `orientation_tol` (rad) (1 um and 1 arcsec in §4.2).
#[derive(Clone, Debug, PartialEq)]
pub struct Repeatability {
    /// (name, mean, standard deviation), mm or rad.
    pub parameters: Vec<(ParameterId, f64, f64)>,
    pub runs: usize,
    /// Every standard deviation within its tolerance.
    pub within_tolerance: bool,
}

pub fn repeatability(runs: &[Piges], position_tol: f64, orientation_tol: f64) -> Result<Repeatability, IdentifyError> {
    let Some(first) = runs.first() else {
        return Err(IdentifyError::Input("no runs".into()));
    };
    let n = runs.len() as f64;
    let mut parameters = Vec::with_capacity(first.values.len());
    let mut ok = runs.len() >= 2;
    for (k, (id, _)) in first.values.iter().enumerate() {
        let values: Vec<f64> = runs.iter().map(|r| r.values[k].1).collect();
        let mean = values.iter().sum::<f64>() / n;
        let sd = if runs.len() > 1 { (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt() } else { 0.0 };
        let tol =
            if matches!(id, ParameterId::Location { component, .. } if component.is_rotation()) { orientation_tol } else { position_tol };
        ok &= sd <= tol;
        parameters.push((*id, mean, sd));
    }
    Ok(Repeatability { parameters, runs: runs.len(), within_tolerance: ok })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kasa_fit_recovers_a_circle_on_a_partial_arc() {
        // a 90 deg arc of radius 100 mm about (0.01, -0.02) mm
        let points: Vec<[f64; 2]> = (0..=90)
            .map(|i| {
                let t = (f64::from(i) - 20.0).to_radians();
                [0.01 + 100.0 * t.cos(), -0.02 + 100.0 * t.sin()]
            })
            .collect();
        let fit = kasa_fit(&points).unwrap();
        assert!((fit.centre[0] - 0.01).abs() < 1e-10 && (fit.centre[1] + 0.02).abs() < 1e-10, "{fit:?}");
        assert!((fit.radius - 100.0).abs() < 1e-10);
        assert!(fit.residual_rms < 1e-10);
        assert!(kasa_fit(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]).is_err());
    }

    #[test]
    fn start_angle_is_eq_4_1() {
        // P0P0' = (0, 5) mm on R = 100 mm: atan(5/100) = 2.862 deg
        assert!((start_angle_error(0.0, 5.0, 100.0).to_degrees() - 2.862_405_226).abs() < 1e-8);
        assert!((start_angle_error(-100.0, 1.0, 100.0).to_degrees() - 90.0).abs() < 1e-12);
    }
}
