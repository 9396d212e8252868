//! The poses of a volumetric error map: grids over the mid-planes of the linear-axis travel (rotary
//! axes at 0), and their heat maps (SVG) and tables (the `predict` CSV).

use super::CalibrationError;
use crate::{heatmap_svg_scaled, MapSlice};
use trueaxis::data::predictions_csv;
use trueaxis::machine::{AxisKind, Machine};
use trueaxis::model::VolumetricError;

/// Nodes per axis of each plane.
pub const GRID: usize = 21;

/// The poses of the map (user and internal units) and the planes they form.
pub struct VolumeMap {
    planes: Vec<Grid>,
    pub poses_user: Vec<f64>,
    pub poses_internal: Vec<f64>,
}

impl VolumeMap {
    /// The map of a machine with at least two linear axes with a travel; `None` otherwise.
    pub fn new(machine: &Machine) -> Option<VolumeMap> {
        let planes = mid_plane_grids(machine, GRID);
        if planes.is_empty() {
            return None;
        }
        let poses_user: Vec<f64> = planes.iter().flat_map(|(_, _, _, p)| p.iter().copied()).collect();
        let mut poses_internal = poses_user.clone();
        let n = machine.axis_count();
        for (u, q) in poses_user.chunks(n).zip(poses_internal.chunks_mut(n)) {
            machine.pose_to_internal(u, q);
        }
        Some(VolumeMap { planes, poses_user, poses_internal })
    }

    pub fn len(&self, machine: &Machine) -> usize {
        self.poses_user.len() / machine.axis_count()
    }

    /// CSV of the poses and predictions (the `predict` output format).
    pub fn csv(&self, machine: &Machine, predictions: &[VolumetricError]) -> Result<String, CalibrationError> {
        Ok(predictions_csv(machine, &self.poses_user, predictions)?)
    }

    /// Heat maps of `|d|` (um) over the planes, one colour scale (over `range` when given).
    pub fn heatmap(&self, title: &str, magnitudes_um: &[f64], range: Option<(f64, f64)>) -> Result<String, CalibrationError> {
        let mut maps = Vec::new();
        let mut offset = 0;
        for (plane, (xa, xs), (ya, ys), _) in &self.planes {
            let count = xs.len() * ys.len();
            maps.push(MapSlice {
                title: plane.clone(),
                x_label: format!("{xa} (mm)"),
                y_label: format!("{ya} (mm)"),
                xs: xs.clone(),
                ys: ys.clone(),
                values: magnitudes_um[offset..offset + count].to_vec(),
            });
            offset += count;
        }
        Ok(heatmap_svg_scaled(title, &maps, "|d| (um)", range)?)
    }
}

/// `|d|` (um) of each prediction.
pub fn magnitudes_um(predictions: &[VolumetricError]) -> Vec<f64> {
    predictions.iter().map(|p| p.position.norm() * 1e3).collect()
}

/// `(largest, index of the largest, RMS)` of magnitudes.
pub fn statistics(values: &[f64]) -> (f64, usize, f64) {
    let (imax, max) = values.iter().copied().enumerate().fold((0, f64::NEG_INFINITY), |a, (i, v)| if v > a.1 { (i, v) } else { a });
    let rms = (values.iter().map(|v| v * v).sum::<f64>() / values.len().max(1) as f64).sqrt();
    (max, imax, rms)
}

type Grid = (String, (char, Vec<f64>), (char, Vec<f64>), Vec<f64>);

/// Grids over the three mid-planes of the linear-axis travel (XY at mid Z, XZ at mid Y, YZ at mid
/// X), rotary axes at 0: title, the two varied axes with their nodes, and the poses (user units).
fn mid_plane_grids(machine: &Machine, nodes: usize) -> Vec<Grid> {
    let linear: Vec<usize> = (0..machine.axis_count())
        .filter(|&i| machine.axes()[i].kind == AxisKind::Linear && machine.axes()[i].range.is_some())
        .take(3)
        .collect();
    let range = |i: usize| machine.axes()[i].range.unwrap_or([0.0, 0.0]);
    let mid = |i: usize| 0.5 * (range(i)[0] + range(i)[1]);
    let nodes_of = |i: usize| -> Vec<f64> {
        let [lo, hi] = range(i);
        (0..nodes).map(|k| lo + (hi - lo) * k as f64 / (nodes - 1) as f64).collect()
    };
    let mut grids = Vec::new();
    for a in 0..linear.len() {
        for b in a + 1..linear.len() {
            let (ia, ib) = (linear[a], linear[b]);
            let fixed: Vec<usize> = linear.iter().copied().filter(|&i| i != ia && i != ib).collect();
            let (xs, ys) = (nodes_of(ia), nodes_of(ib));
            let mut poses = Vec::new();
            for &y in &ys {
                for &x in &xs {
                    let mut pose = vec![0.0; machine.axis_count()];
                    for &f in &fixed {
                        pose[f] = mid(f);
                    }
                    pose[ia] = x;
                    pose[ib] = y;
                    poses.extend(pose);
                }
            }
            let (la, lb) = (machine.axes()[ia].letter, machine.axes()[ib].letter);
            let title = match fixed.first() {
                Some(&f) => format!("{la}{lb} plane, {} = {} mm", machine.axes()[f].letter, mid(f)),
                None => format!("{la}{lb} plane"),
            };
            grids.push((title, (la, xs), (lb, ys), poses));
        }
    }
    grids
}
