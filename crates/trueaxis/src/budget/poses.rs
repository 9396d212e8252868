//! Pose sets of a budget: a grid over the travel of the linear axes (the work volume), or the poses
//! that put the tool point on a grid over a part (the part size of Zhu 2008 B.2).

use crate::error::Error;
use crate::geometry::Vec3;
use crate::machine::{AxisKind, Machine};
use crate::model::{nominal_chain, Setup};
use nalgebra::{Matrix3, Vector3};

/// The nodes `lo, ..., hi` of a regular grid with `nodes` points (the midpoint for one node).
pub fn linspace(lo: f64, hi: f64, nodes: usize) -> Vec<f64> {
    match nodes {
        0 => Vec::new(),
        1 => vec![0.5 * (lo + hi)],
        _ => (0..nodes).map(|i| lo + (hi - lo) * i as f64 / (nodes - 1) as f64).collect(),
    }
}

/// Poses (user units, canonical axis order) of a grid with `nodes` points along the travel of every
/// linear axis; rotary axes at `rotary` (deg, one per rotary axis in canonical order; zero if empty).
pub fn volume_grid(machine: &Machine, nodes: usize, rotary: &[f64]) -> Result<Vec<f64>, Error> {
    let rotary_axes: Vec<usize> = (0..machine.axis_count()).filter(|&k| machine.axes()[k].kind == AxisKind::Rotary).collect();
    if !rotary.is_empty() && rotary.len() != rotary_axes.len() {
        return Err(Error::input(format!(
            "{} rotary positions given, machine `{}` has {} rotary axes",
            rotary.len(),
            machine.name,
            rotary_axes.len()
        )));
    }
    let mut base = vec![0.0; machine.axis_count()];
    for (i, &k) in rotary_axes.iter().enumerate() {
        base[k] = rotary.get(i).copied().unwrap_or(0.0);
    }
    let mut poses = base.clone();
    for (k, axis) in machine.axes().iter().enumerate() {
        if axis.kind != AxisKind::Linear {
            continue;
        }
        let [lo, hi] = axis.range.expect("a linear axis has a range");
        let previous = std::mem::take(&mut poses);
        for pose in previous.chunks(machine.axis_count()) {
            for v in linspace(lo, hi, nodes) {
                poses.extend_from_slice(pose);
                let last = poses.len() - machine.axis_count();
                poses[last + k] = v;
            }
        }
    }
    Ok(poses)
}

/// Nominal vector (mm) from the workpiece point to the tool point, in the workpiece frame, at pose
/// `q` (internal units).
pub fn nominal_relative(machine: &Machine, q: &[f64], setup: &Setup) -> Vec3 {
    let tool = nominal_chain(machine, machine.tool_chain(), q, None);
    let work = nominal_chain(machine, machine.work_chain(), q, None);
    work.rotation.transpose() * (tool.transform_point(&setup.tool_point) - work.transform_point(&setup.work_point))
}

/// Poses (user units) that put the tool point at the nodes of a grid over a part of `size` (mm, x y
/// z), centred on the workpiece point in x and y and standing on it in z, `nodes` points per edge; the
/// rotary axes at `rotary` (deg, canonical order of the rotary axes; zero if empty). The linear
/// axes follow by the inverse of the nominal chain, which is affine in them once the rotary axes are
/// fixed; it needs exactly three linear axes. A node outside the travel is an error naming the axis.
pub fn part_grid(machine: &Machine, setup: &Setup, size: [f64; 3], nodes: usize, rotary: &[f64]) -> Result<Vec<f64>, Error> {
    let linear: Vec<usize> = (0..machine.axis_count()).filter(|&k| machine.axes()[k].kind == AxisKind::Linear).collect();
    if linear.len() != 3 {
        return Err(Error::input(format!(
            "a part size needs a machine with three linear axes; `{}` has {} (give poses instead)",
            machine.name,
            linear.len()
        )));
    }
    if size.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return Err(Error::input(format!("part size {:?} mm: every edge must be a positive length", size)));
    }
    let base_user = volume_grid(machine, 1, rotary)?;
    let mut base_user: Vec<f64> = base_user[..machine.axis_count()].to_vec();
    for &k in &linear {
        base_user[k] = 0.0;
    }
    let mut q0 = vec![0.0; machine.axis_count()];
    machine.pose_to_internal(&base_user, &mut q0);
    let r0 = nominal_relative(machine, &q0, setup);
    let mut m = Matrix3::zeros();
    for (i, &k) in linear.iter().enumerate() {
        let mut q = q0.clone();
        q[k] += 1.0;
        m.set_column(i, &(nominal_relative(machine, &q, setup) - r0));
    }
    let inverse = m.try_inverse().ok_or_else(|| Error::input("the linear axes do not span three directions"))?;
    let mut poses = Vec::new();
    for z in linspace(0.0, size[2], nodes) {
        for y in linspace(-0.5 * size[1], 0.5 * size[1], nodes) {
            for x in linspace(-0.5 * size[0], 0.5 * size[0], nodes) {
                let lin: Vector3<f64> = inverse * (Vec3::new(x, y, z) - r0);
                let mut pose = base_user.clone();
                for (i, &k) in linear.iter().enumerate() {
                    pose[k] = lin[i];
                }
                machine.check_range(&pose).map_err(|m| {
                    Error::input(format!(
                        "a part of {} x {} x {} mm does not fit machine `{}`: the tool point at ({x:.1}, {y:.1}, {z:.1}) mm of the part puts {m}",
                        size[0], size[1], size[2], machine.name
                    ))
                })?;
                poses.extend(pose);
            }
        }
    }
    Ok(poses)
}

/// Poses in internal units (mm, rad) of poses in user units (mm, deg), `machine.axis_count()`
/// values per pose.
pub fn to_internal(machine: &Machine, user: &[f64]) -> Vec<f64> {
    let n = machine.axis_count().max(1);
    let mut out = vec![0.0; user.len()];
    for (u, q) in user.chunks(n).zip(out.chunks_mut(n)) {
        machine.pose_to_internal(u, q);
    }
    out
}
