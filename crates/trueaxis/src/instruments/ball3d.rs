//! 3D ball instruments (R-test, CapBall): the three components of the position of a tool-side
//! point (sensing-head centre `P_t`) relative to a workpiece-side point (master-ball centre `P_w`),
//! actual minus nominal (Andolfatto et al. 2011 §3.1, eq. 2), and the sensor-frame calibration of a 3D head from a
//! programmed cube (Andolfatto et al. 2011 §3.3, eqs. 6-10), given as a matrix or fitted from a cube data file.

use crate::bail;
use crate::data::CsvTable;
use crate::error::{Error, Result};
use crate::geometry::Vec3;
use crate::machine::Machine;
use crate::model::{volumetric_error, Frame, Setup};
use nalgebra::{DMatrix, Matrix3, Matrix4};
use std::path::Path;

/// A 3D ball measurement setup.
///
/// - `frame = Machine`: CapBall, the sensing head in the spindle keeps its orientation relative to
///   M, the readings are in M (after the sensor-frame calibration).
/// - `frame = Workpiece`: R-test, the sensors sit on the table and turn with the workpiece.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball3d {
    pub setup: Setup,
    pub frame: Frame,
}

impl Ball3d {
    /// Exact reading `dx dy dz` (mm) at pose `q` (mm, rad) with the parameter vector `params`
    /// (mm, rad): the volumetric error of `P_t` relative to `P_w` in the instrument's frame. The
    /// sensing frame is taken as the nominal one; its own rotation by the machine's angular errors
    /// changes a reading by (angular error) x (reading), below 1e-8 mm for 100 urad and 100 um.
    pub fn exact(&self, machine: &Machine, q: &[f64], params: &[f64]) -> [f64; 3] {
        let p = volumetric_error(machine, q, params, &self.setup, self.frame).position;
        [p.x, p.y, p.z]
    }
}

/// Bad input to the sensor-frame calibration: `sensor calibration: {message}`.
fn refused(message: impl std::fmt::Display) -> Error {
    Error::input(format!("sensor calibration: {message}"))
}

/// The affine map from sensor readings to machine-frame displacements of a 3D head:
/// `M_s->t = [e1 e2 e3 d; 0 0 0 1]` (Andolfatto et al. 2011 eq. 10), fitted as `M = Delta_t Delta_s^+`
/// (eq. 9) from programmed displacements `Delta_t` and readings `Delta_s` in homogeneous form
/// (eqs. 6-7). Readings and displacements share one unit (um in the seed); `d` is in that unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorCalibration {
    pub matrix: Matrix4<f64>,
}

impl SensorCalibration {
    /// The programmed points of the calibration cube: `per_edge^3` points on a regular mesh of a
    /// cube of edge `side` centred on `centre`, x fastest (Andolfatto et al. 2011: 0.2 mm, 5 per edge, 125 points).
    pub fn cube(centre: Vec3, side: f64, per_edge: usize) -> Vec<Vec3> {
        let step = if per_edge > 1 { side / (per_edge - 1) as f64 } else { 0.0 };
        let offset = |i: usize| -0.5 * side + step * i as f64;
        let mut points = Vec::with_capacity(per_edge.pow(3));
        for k in 0..per_edge {
            for j in 0..per_edge {
                for i in 0..per_edge {
                    points.push(centre + Vec3::new(offset(i), offset(j), offset(k)));
                }
            }
        }
        points
    }

    /// `M_s->t = Delta_t Delta_s^+` (Andolfatto et al. 2011 eqs. 6-9). `programmed[i]` is the displacement
    /// commanded in M, `readings[i]` what the sensors read. Needs at least 4 points not in a plane.
    pub fn fit(programmed: &[Vec3], readings: &[Vec3]) -> Result<SensorCalibration> {
        Self::fit_points(programmed, readings).map_err(|e| refused(e.message()))
    }

    /// [`SensorCalibration::fit`], its message not yet prefixed.
    fn fit_points(programmed: &[Vec3], readings: &[Vec3]) -> Result<SensorCalibration> {
        let n = programmed.len();
        if readings.len() != n {
            bail!(input, "{n} programmed points but {} readings", readings.len());
        }
        if programmed.iter().chain(readings).any(|v| !v.iter().all(|x| x.is_finite())) {
            bail!(input, "points and readings must be finite numbers");
        }
        let homogeneous = |v: &[Vec3]| DMatrix::from_fn(4, n, |r, c| if r < 3 { v[c][r] } else { 1.0 });
        let delta_t = homogeneous(programmed);
        let delta_s = homogeneous(readings);
        let svd = delta_s.clone().svd(true, true);
        let largest = svd.singular_values.max();
        if n < 4 || svd.singular_values.min() <= 1e-12 * largest {
            bail!(input, "the {n} readings do not span three dimensions (a cube of at least 2 x 2 x 2 points is needed)");
        }
        let pinv = svd.pseudo_inverse(1e-12 * largest).map_err(Error::input)?;
        let m = delta_t * pinv;
        SensorCalibration { matrix: Matrix4::from_fn(|r, c| m[(r, c)]) }.checked()
    }

    /// From a given sensor map: the columns `e1 e2 e3` of `a` (machine-frame displacement per unit
    /// of each sensor reading) and the offset `d` (um): `M = [a d; 0 1]` (Andolfatto et al. 2011 eq. 10).
    pub fn from_matrix(a: Matrix3<f64>, d: Vec3) -> Result<SensorCalibration> {
        let mut matrix = Matrix4::identity();
        matrix.fixed_view_mut::<3, 3>(0, 0).copy_from(&a);
        matrix.fixed_view_mut::<3, 1>(0, 3).copy_from(&d);
        SensorCalibration { matrix }.checked().map_err(|e| refused(e.message()))
    }

    /// Fitted from a cube data file (CSV, `#` comments): one row per programmed point with the
    /// programmed displacement `tx,ty,tz` and the sensor readings `sx,sy,sz`, all in um (Andolfatto et al. 2011:
    /// 125 points on a 0.2 mm cube). Errors name the file.
    pub fn from_cube_file(path: &Path) -> Result<SensorCalibration> {
        let origin = path.display().to_string();
        let table = CsvTable::read(path).map_err(refused)?;
        let column =
            |name: &str| table.numbers(name).map_err(|e| refused(format!("{e} (a cube file has columns tx,ty,tz,sx,sy,sz in um)")));
        let points = |x: &str, y: &str, z: &str| -> Result<Vec<Vec3>> {
            let (x, y, z) = (column(x)?, column(y)?, column(z)?);
            Ok((0..x.len()).map(|i| Vec3::new(x[i], y[i], z[i])).collect())
        };
        let programmed = points("tx", "ty", "tz")?;
        let readings = points("sx", "sy", "sz")?;
        SensorCalibration::fit_points(&programmed, &readings).map_err(|e| refused(format!("{origin}: {}", e.message())))
    }

    /// Refuses a map that is not finite or whose sensor axes are (nearly) dependent, so that
    /// [`SensorCalibration::reading_of`] exists.
    fn checked(self) -> Result<SensorCalibration> {
        if self.matrix.iter().any(|v| !v.is_finite()) {
            bail!(input, "the sensor map must be finite numbers");
        }
        let singular = self.linear().singular_values();
        if singular.min() <= 1e-6 * singular.max() {
            bail!(
                input,
                "the sensor axes e1 e2 e3 are (nearly) dependent (singular values {:.3e} .. {:.3e})",
                singular.min(),
                singular.max()
            );
        }
        Ok(self)
    }

    /// The 3x3 part `[e1 e2 e3]`.
    pub fn linear(&self) -> Matrix3<f64> {
        self.matrix.fixed_view::<3, 3>(0, 0).into_owned()
    }

    /// The sensor reading that [`SensorCalibration::apply`] maps to `displacement`:
    /// `[e1 e2 e3]^-1 (displacement - d)` (for simulating raw sensor readings).
    pub fn reading_of(&self, displacement: &Vec3) -> Vec3 {
        let inverse = self.linear().try_inverse().expect("checked on construction: the sensor axes are independent");
        inverse * (displacement - self.offset())
    }

    /// Machine-frame displacement of a sensor reading: `M [s; 1]`.
    pub fn apply(&self, reading: &Vec3) -> Vec3 {
        let h = self.matrix * nalgebra::Vector4::new(reading.x, reading.y, reading.z, 1.0);
        Vec3::new(h.x, h.y, h.z)
    }

    /// The columns `e1 e2 e3`.
    pub fn axis(&self, i: usize) -> Vec3 {
        Vec3::new(self.matrix[(0, i)], self.matrix[(1, i)], self.matrix[(2, i)])
    }

    /// Norms of `e1 e2 e3` (Andolfatto et al. 2011 Table 2: 0.998 / 0.996 / 0.996): sensor gain errors.
    pub fn column_norms(&self) -> [f64; 3] {
        [self.axis(0).norm(), self.axis(1).norm(), self.axis(2).norm()]
    }

    /// Projections `e1.e2, e1.e3, e2.e3` (Andolfatto et al. 2011 Table 2: -0.030 / -0.029 / -0.021): lack of
    /// orthogonality of the sensor axes and the local squareness of the machine.
    pub fn projections(&self) -> [f64; 3] {
        [self.axis(0).dot(&self.axis(1)), self.axis(0).dot(&self.axis(2)), self.axis(1).dot(&self.axis(2))]
    }

    /// The offset `d` (reading offsets of the sensors).
    pub fn offset(&self) -> Vec3 {
        Vec3::new(self.matrix[(0, 3)], self.matrix[(1, 3)], self.matrix[(2, 3)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cube_recovers_a_known_sensor_map_exactly() {
        // sensors with gains 0.998 / 0.996 / 0.996, skewed axes and offsets (um): readings
        // s = A^-1 (t - d); the fit must return [A d] to rounding
        let a = Matrix3::new(0.998, -0.030, -0.029, 0.0, 0.996, -0.021, 0.0, 0.0, 0.996);
        let d = Vec3::new(4.0, -7.5, 9.0);
        let programmed = SensorCalibration::cube(Vec3::zeros(), 200.0, 5);
        assert_eq!(programmed.len(), 125);
        let inverse = a.try_inverse().unwrap();
        let readings: Vec<Vec3> = programmed.iter().map(|t| inverse * (t - d)).collect();
        let cal = SensorCalibration::fit(&programmed, &readings).unwrap();
        for r in 0..3 {
            for c in 0..3 {
                assert!((cal.matrix[(r, c)] - a[(r, c)]).abs() < 1e-12);
            }
        }
        assert!((cal.offset() - d).norm() < 1e-10);
        assert!((cal.matrix[(3, 3)] - 1.0).abs() < 1e-12 && cal.matrix[(3, 0)].abs() < 1e-12);
        assert!((cal.column_norms()[0] - 0.998).abs() < 1e-12);
        assert!((cal.projections()[0] - 0.998 * -0.030).abs() < 1e-12);
        let s = readings[17];
        assert!((cal.apply(&s) - programmed[17]).norm() < 1e-10);
    }

    #[test]
    fn a_given_matrix_and_a_cube_file_give_the_same_map() {
        let a = Matrix3::new(0.998, -0.030, -0.029, 0.004, 0.996, -0.021, -0.002, 0.003, 0.996);
        let d = Vec3::new(4.0, -7.5, 9.0);
        let given = SensorCalibration::from_matrix(a, d).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let mut csv = String::from("# programmed (um), readings (um)\ntx,ty,tz,sx,sy,sz\n");
        for t in SensorCalibration::cube(Vec3::zeros(), 200.0, 3) {
            let s = given.reading_of(&t);
            csv += &format!("{},{},{},{},{},{}\n", t.x, t.y, t.z, s.x, s.y, s.z);
        }
        let path = dir.path().join("cube.csv");
        std::fs::write(&path, csv).unwrap();
        let fitted = SensorCalibration::from_cube_file(&path).unwrap();
        assert!((fitted.matrix - given.matrix).amax() < 1e-9, "{}", fitted.matrix - given.matrix);
        let t = Vec3::new(12.0, -30.0, 7.0);
        assert!((given.apply(&given.reading_of(&t)) - t).norm() < 1e-12);
        std::fs::write(&path, "tx,ty,tz,sx,sy\n0,0,0,0,0\n").unwrap();
        let e = SensorCalibration::from_cube_file(&path).unwrap_err().to_string();
        assert!(e.contains("cube.csv") && e.contains("sz"), "{e}");
        let flat = Matrix3::new(1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0);
        assert!(SensorCalibration::from_matrix(flat, d).unwrap_err().to_string().contains("dependent"));
    }

    #[test]
    fn flat_readings_are_refused() {
        let programmed = SensorCalibration::cube(Vec3::zeros(), 0.2, 2);
        let flat: Vec<Vec3> = programmed.iter().map(|p| Vec3::new(p.x, p.y, 0.0)).collect();
        assert!(SensorCalibration::fit(&programmed, &flat).unwrap_err().to_string().contains("three dimensions"));
    }
}
