//! The poses of a volumetric error map: grids over the mid-planes of the linear-axis travel, with
//! the rotary axes at 0 ([`VolumeMap::new`]) or at each of a set of rotary states spanning their
//! travel ([`VolumeMap::over_rotary_states`]: a five-axis machine's location errors show only where
//! its rotary axes turn), and their heat maps (SVG: at each node the largest value over the rotary
//! states) and tables (the `predict` CSV, every pose).

use super::CalibrationError;
use crate::{heatmap_svg_scaled, MapSlice};
use trueaxis::machine::{AxisKind, Machine};
use trueaxis::model::VolumetricError;
use trueaxis::poses::predictions_csv;

/// Nodes per axis of each plane.
pub const GRID: usize = 21;

/// The poses of the map (user and internal units) and the planes they form.
pub struct VolumeMap {
    planes: Vec<Grid>,
    /// The rotary states: `(axis letter, position in deg)` of every rotary axis; one empty state
    /// for a machine without rotary axes or a map with them at 0.
    pub states: Vec<Vec<(char, f64)>>,
    /// Every pose (user units): the grids of all planes for the first state, then for the next.
    pub poses_user: Vec<f64>,
    pub poses_internal: Vec<f64>,
}

impl VolumeMap {
    /// The map of a machine with at least two linear axes with a travel, rotary axes at 0; `None`
    /// otherwise.
    pub fn new(machine: &Machine) -> Option<VolumeMap> {
        Self::with_states(machine, vec![Vec::new()])
    }

    /// The map at each rotary state of [`rotary_states`] (for a machine without rotary axes the
    /// same as [`VolumeMap::new`]).
    pub fn over_rotary_states(machine: &Machine) -> Option<VolumeMap> {
        Self::with_states(machine, rotary_states(machine))
    }

    fn with_states(machine: &Machine, states: Vec<Vec<(char, f64)>>) -> Option<VolumeMap> {
        let planes = mid_plane_grids(machine, GRID);
        if planes.is_empty() {
            return None;
        }
        let n = machine.axis_count();
        let mut poses_user = Vec::new();
        for state in &states {
            for pose in planes.iter().flat_map(|(_, _, _, p)| p.chunks(n)) {
                let start = poses_user.len();
                poses_user.extend_from_slice(pose);
                for &(letter, value) in state {
                    let k = machine.axes().iter().position(|a| a.letter == letter).expect("a rotary axis of the machine");
                    poses_user[start + k] = value;
                }
            }
        }
        let mut poses_internal = poses_user.clone();
        for (u, q) in poses_user.chunks(n).zip(poses_internal.chunks_mut(n)) {
            machine.pose_to_internal(u, q);
        }
        Some(VolumeMap { planes, states, poses_user, poses_internal })
    }

    pub fn len(&self, machine: &Machine) -> usize {
        self.poses_user.len() / machine.axis_count()
    }

    /// The rotary states in words: `A 0, 90, 180 deg x C 0, 90, 180, 270 deg (12 states)`; empty
    /// for one state.
    pub fn states_text(&self) -> String {
        if self.states.len() < 2 {
            return String::new();
        }
        let axes: Vec<String> = self.states[0]
            .iter()
            .enumerate()
            .map(|(j, (letter, _))| {
                let mut values: Vec<f64> = self.states.iter().map(|s| s[j].1).collect();
                values.sort_by(f64::total_cmp);
                values.dedup();
                let values: Vec<String> = values.iter().map(|v| format!("{v}")).collect();
                format!("{letter} {} deg", values.join(", "))
            })
            .collect();
        format!("{} ({} states)", axes.join(" x "), self.states.len())
    }

    /// CSV of the poses and predictions (the `predict` output format).
    pub fn csv(&self, machine: &Machine, predictions: &[VolumetricError]) -> Result<String, CalibrationError> {
        Ok(predictions_csv(machine, &self.poses_user, predictions)?)
    }

    /// At each node of the planes, the largest of `values` (one per pose) over the rotary states.
    pub fn worst_over_states(&self, values: &[f64]) -> Vec<f64> {
        let per_state = values.len() / self.states.len().max(1);
        (0..per_state).map(|i| values.iter().skip(i).step_by(per_state).fold(f64::NEG_INFINITY, |a, &b| a.max(b))).collect()
    }

    /// Heat maps of `|d|` (um) over the planes, one colour scale (over `range` when given); with
    /// several rotary states, the largest value over them at each node.
    pub fn heatmap(&self, title: &str, magnitudes_um: &[f64], range: Option<(f64, f64)>) -> Result<String, CalibrationError> {
        let worst = self.worst_over_states(magnitudes_um);
        let magnitudes_um = &worst;
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

/// Positions of each rotary axis at which the map is evaluated (deg): an axis with a travel of
/// less than a turn at both ends of it, at 0 when 0 is inside, and at its middle when that leaves
/// fewer than three; an axis without a travel or with a turn or more at 0, 90, 180 and 270. The
/// states are every combination (a table-tilting machine's A and C: 3 x 4 = 12).
pub fn rotary_states(machine: &Machine) -> Vec<Vec<(char, f64)>> {
    let mut states: Vec<Vec<(char, f64)>> = vec![Vec::new()];
    for axis in machine.axes().iter().filter(|a| a.kind == AxisKind::Rotary) {
        let positions: Vec<f64> = match axis.range {
            Some([lo, hi]) if hi - lo < 360.0 => {
                let mut p = vec![lo, hi];
                if lo < 0.0 && hi > 0.0 {
                    p.push(0.0);
                } else {
                    p.push(0.5 * (lo + hi));
                }
                p.sort_by(f64::total_cmp);
                p.dedup();
                p
            }
            _ => vec![0.0, 90.0, 180.0, 270.0],
        };
        states = states.iter().flat_map(|s| positions.iter().map(move |&v| [s.clone(), vec![(axis.letter, v)]].concat())).collect();
    }
    states
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

#[cfg(test)]
mod tests {
    use super::*;

    fn machine(toml: &str) -> Machine {
        Machine::from_toml_str(toml, "m").unwrap()
    }

    #[test]
    fn rotary_states_span_each_rotary_axis_travel() {
        let kx8five = machine(include_str!("../../../../examples/machines/kx8five.toml"));
        let states = rotary_states(&kx8five);
        assert_eq!(states.len(), 12);
        assert_eq!(states[0], vec![('A', 0.0), ('C', 0.0)]);
        assert_eq!(states[11], vec![('A', 180.0), ('C', 270.0)]);
        let c600u = machine(include_str!("../../../../examples/machines/c600u.toml"));
        let a: Vec<f64> = rotary_states(&c600u).iter().map(|s| s[0].1).collect();
        assert_eq!(&a[..], &[-20.0, -20.0, -20.0, -20.0, 0.0, 0.0, 0.0, 0.0, 70.0, 70.0, 70.0, 70.0]);
        let vmc3 = machine(include_str!("../../../../examples/machines/vmc3.toml"));
        assert_eq!(rotary_states(&vmc3), vec![Vec::<(char, f64)>::new()]);
        assert_eq!(VolumeMap::over_rotary_states(&vmc3).unwrap().poses_user, VolumeMap::new(&vmc3).unwrap().poses_user);
    }

    #[test]
    fn the_map_repeats_the_mid_planes_at_every_state_and_shows_the_worst() {
        let kx8five = machine(include_str!("../../../../examples/machines/kx8five.toml"));
        let (flat, map) = (VolumeMap::new(&kx8five).unwrap(), VolumeMap::over_rotary_states(&kx8five).unwrap());
        let per_state = 3 * GRID * GRID;
        assert_eq!((flat.len(&kx8five), map.len(&kx8five)), (per_state, 12 * per_state));
        // state 7 (A 90, C 270): the linear axes as at A = C = 0, the rotary axes at the state
        let state7 = &map.poses_user[7 * per_state * 5..8 * per_state * 5];
        for (p, f) in state7.chunks(5).zip(flat.poses_user.chunks(5)) {
            assert_eq!((&p[..3], p[3], p[4]), (&f[..3], 90.0, 270.0));
        }
        let mut values = vec![1.0; 12 * per_state];
        values[5 * per_state + 17] = 9.0;
        let worst = map.worst_over_states(&values);
        assert_eq!(worst.len(), per_state);
        assert_eq!((worst[17], worst[16], worst.iter().sum::<f64>()), (9.0, 1.0, per_state as f64 + 8.0));
        assert_eq!(map.states_text(), "A 0, 90, 180 deg x C 0, 90, 180, 270 deg (12 states)");
    }
}
