//! Trajectories for 3D-ball tests on multi-axis machines (Andolfatto et al. 2011 §3.2, Fig. 2): the rotary axes
//! sweep, and the linear axes follow so that the tool point stays nominally on the ball centre.
//!
//! With the rotary axes fixed, the nominal position of the tool point relative to the workpiece
//! point is an affine function of the linear axis positions (translations do not rotate), so the
//! linear axes are found exactly by one small linear solve per pose.

use super::measurement::nominal_vector;
use crate::error::{Error, Result};
use crate::geometry::Vec3;
use crate::machine::{AxisKind, Machine};
use crate::model::Setup;
use nalgebra::DMatrix;

/// Bad input to a trajectory (a sweep, a count, a pose out of range): `trajectory: {message}`.
fn refused(message: impl std::fmt::Display) -> Error {
    Error::input(format!("trajectory: {message}"))
}

/// One axis moving linearly from `from` to `to` (mm or deg) over the trajectory.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sweep {
    pub axis: char,
    pub from: f64,
    pub to: f64,
}

impl Sweep {
    /// Parses `A=0:90` (axis letter, start and end in mm or deg).
    pub fn parse(text: &str) -> Result<Sweep> {
        let bad = || Error::input(format!("`{text}` is not a sweep AXIS=FROM:TO, e.g. C=0:720 (deg for rotary axes)"));
        let (axis, range) = text.split_once('=').ok_or_else(bad)?;
        let mut letters = axis.trim().chars();
        let (Some(letter), None) = (letters.next(), letters.next()) else { return Err(bad()) };
        let (from, to) = range.split_once(':').ok_or_else(bad)?;
        let (from, to): (f64, f64) = (from.trim().parse().map_err(|_| bad())?, to.trim().parse().map_err(|_| bad())?);
        if !from.is_finite() || !to.is_finite() {
            return Err(bad());
        }
        Ok(Sweep { axis: letter.to_ascii_uppercase(), from, to })
    }
}

/// Poses (user units, `machine.axis_count()` per pose, canonical axis order) of a 3D-ball test:
/// `count` poses; every swept axis moves linearly from its start to its end, the other non-linear
/// axes stay at 0, and the linear axes keep the nominal vector from `setup.work_point` to
/// `setup.tool_point` equal to `offset` (mm, workpiece frame; zero for a ball test). Every pose is
/// checked against the axis ranges.
pub fn ball_trajectory(machine: &Machine, setup: &Setup, sweeps: &[Sweep], count: usize, offset: Vec3) -> Result<Vec<f64>> {
    let n = machine.axis_count();
    let linear: Vec<usize> = (0..n).filter(|&k| machine.axes()[k].kind == AxisKind::Linear).collect();
    if count == 0 {
        return Err(refused("the number of poses must be at least 1"));
    }
    for s in sweeps {
        let k = machine.axis_index(s.axis).ok_or_else(|| {
            refused(format!("sweep of axis {}: machine `{}` has no such axis (axes: {})", s.axis, machine.name, machine.axis_letters()))
        })?;
        if machine.axes()[k].kind == AxisKind::Linear {
            return Err(refused(format!("sweep of axis {}: linear axes follow the ball; sweep rotary axes only", s.axis)));
        }
    }
    let mut user = vec![0.0; n * count];
    let mut q = vec![0.0; n];
    for (i, pose) in user.chunks_mut(n).enumerate() {
        let t = if count > 1 { i as f64 / (count - 1) as f64 } else { 0.0 };
        for s in sweeps {
            let k = machine.axis_index(s.axis).expect("checked");
            pose[k] = s.from + (s.to - s.from) * t;
        }
        for &k in &linear {
            pose[k] = 0.0;
        }
        machine.pose_to_internal(pose, &mut q);
        let base = nominal_vector(machine, &q, setup);
        let mut columns = DMatrix::zeros(3, linear.len());
        for (c, &k) in linear.iter().enumerate() {
            q[k] = 1.0;
            let moved = nominal_vector(machine, &q, setup) - base;
            q[k] = 0.0;
            columns.set_column(c, &moved);
        }
        let svd = columns.svd(true, true);
        if linear.len() < 3 || svd.singular_values.iter().filter(|s| **s > 1e-9).count() < 3 {
            return Err(refused("the linear axes of this machine cannot move the tool point in three directions"));
        }
        let target = offset - base;
        let solution = svd.solve(&DMatrix::from_column_slice(3, 1, target.as_slice()), 1e-9).map_err(refused)?;
        for (c, &k) in linear.iter().enumerate() {
            pose[k] = solution[(c, 0)];
        }
        machine.check_range(pose).map_err(|m| refused(format!("pose {} of {count}: {m}", i + 1)))?;
    }
    Ok(user)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tool_point_stays_on_the_ball() {
        let machine = Machine::from_toml_str(include_str!("../../../../examples/machines/kx8five.toml"), "kx8five").unwrap();
        let setup = Setup { tool_point: machine.tool_point, work_point: Vec3::new(150.0, 0.0, 100.0) };
        let sweeps = [Sweep::parse("A=0:90").unwrap(), Sweep::parse("C=0:720").unwrap()];
        let poses = ball_trajectory(&machine, &setup, &sweeps, 50, Vec3::zeros()).unwrap();
        let mut q = vec![0.0; 5];
        for pose in poses.chunks(5) {
            machine.pose_to_internal(pose, &mut q);
            assert!(nominal_vector(&machine, &q, &setup).norm() < 1e-9);
        }
        // last pose: A = 90, C = 720 deg
        assert!((poses[5 * 49 + 3] - 90.0).abs() < 1e-12 && (poses[5 * 49 + 4] - 720.0).abs() < 1e-12);
        assert!(Sweep::parse("X=0:10").map(|s| ball_trajectory(&machine, &setup, &[s], 3, Vec3::zeros())).unwrap().is_err());
        let far = Setup { tool_point: machine.tool_point, work_point: Vec3::new(900.0, 0.0, 0.0) };
        let e = ball_trajectory(&machine, &far, &sweeps, 5, Vec3::zeros()).unwrap_err().to_string();
        assert!(e.contains("outside its range"), "{e}");
    }
}
