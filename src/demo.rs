//! `trueaxis demo`: the built-in machine (seed 004 KX8-Five) with known errors; a volumetric error
//! map over the work volume written as CSV and SVG.

use crate::data::{predictions_csv, write_atomically, DataError};
use crate::errors::{ErrorModel, ErrorsError};
use crate::machine::{AxisKind, Machine, MachineError};
use crate::model::{Frame, Predictor};
use crate::report::{heatmap_svg, MapSlice, ReportError};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The built-in machine: examples/machines/kx8five.toml.
pub const MACHINE_TOML: &str = include_str!("../examples/machines/kx8five.toml");
/// The built-in errors: examples/errors/kx8five.toml (seed 004 Table 1 plus motion errors).
pub const ERRORS_TOML: &str = include_str!("../examples/errors/kx8five.toml");
/// Grid nodes per side of each map slice.
pub const GRID: usize = 21;

#[derive(Debug, Error)]
pub enum DemoError {
    #[error(transparent)]
    Machine(#[from] MachineError),
    #[error(transparent)]
    Errors(#[from] ErrorsError),
    #[error(transparent)]
    Data(#[from] DataError),
    #[error(transparent)]
    Report(#[from] ReportError),
    #[error("{path}: cannot create output directory: {source}")]
    CreateDir { path: String, source: std::io::Error },
}

/// What the demo computed and wrote.
#[derive(Clone, Debug)]
pub struct DemoSummary {
    pub machine: String,
    pub poses: usize,
    /// Largest position error magnitude over the map (um) and the pose (mm, deg) where it occurs.
    pub max_um: f64,
    pub max_pose: Vec<(char, f64)>,
    /// Root mean square of the position error magnitude over the map (um).
    pub rms_um: f64,
    pub files: Vec<PathBuf>,
}

/// The built-in machine and its error model.
pub fn builtin() -> Result<(Machine, ErrorModel), DemoError> {
    let machine = Machine::from_toml_str(MACHINE_TOML, "built-in kx8five.toml")?;
    let errors = ErrorModel::from_toml_str(ERRORS_TOML, "built-in kx8five errors", &machine)?;
    Ok((machine, errors))
}

/// Runs the demo and writes `machine.toml`, `errors.toml`, `volumetric_map.csv` and
/// `volumetric_map.svg` into `out_dir` (created if missing).
pub fn run(out_dir: &Path) -> Result<DemoSummary, DemoError> {
    let (machine, errors) = builtin()?;
    std::fs::create_dir_all(out_dir).map_err(|source| DemoError::CreateDir { path: out_dir.display().to_string(), source })?;
    let mut predictor = Predictor::new(&machine, &errors);
    predictor.frame = Frame::Machine;

    let slices = mid_plane_grids(&machine, GRID);
    let mut poses_user = Vec::new();
    for (_, _, _, poses) in &slices {
        poses_user.extend_from_slice(poses);
    }
    let mut poses_internal = poses_user.clone();
    let n = machine.axis_count();
    for (u, q) in poses_user.chunks(n).zip(poses_internal.chunks_mut(n)) {
        machine.pose_to_internal(u, q);
    }
    let predictions = predictor.predict_batch(&poses_internal);
    let magnitudes: Vec<f64> = predictions.iter().map(|p| p.position.norm() * 1e3).collect();

    let mut maps = Vec::new();
    let mut offset = 0;
    for (title, (xa, xs), (ya, ys), _) in &slices {
        let count = xs.len() * ys.len();
        maps.push(MapSlice {
            title: title.clone(),
            x_label: format!("{} (mm)", xa),
            y_label: format!("{} (mm)", ya),
            xs: xs.clone(),
            ys: ys.clone(),
            values: magnitudes[offset..offset + count].to_vec(),
        });
        offset += count;
    }
    let svg = heatmap_svg(&format!("Volumetric error |d| (machine frame), {}", machine.name), &maps, "|d| (um)")?;
    let csv = predictions_csv(&machine, &poses_user, &predictions)?;

    let files = [
        ("machine.toml", MACHINE_TOML.as_bytes().to_vec()),
        ("errors.toml", ERRORS_TOML.as_bytes().to_vec()),
        ("volumetric_map.csv", csv.into_bytes()),
        ("volumetric_map.svg", svg.into_bytes()),
    ];
    let mut written = Vec::new();
    for (name, bytes) in files {
        let path = out_dir.join(name);
        write_atomically(&path, &bytes)?;
        written.push(path);
    }
    let (imax, max_um) = magnitudes.iter().copied().enumerate().fold((0, f64::NEG_INFINITY), |a, (i, v)| if v > a.1 { (i, v) } else { a });
    let rms_um = (magnitudes.iter().map(|v| v * v).sum::<f64>() / magnitudes.len() as f64).sqrt();
    let max_pose = machine.axes().iter().map(|a| a.letter).zip(poses_user[imax * n..(imax + 1) * n].iter().copied()).collect();
    Ok(DemoSummary { machine: machine.name.clone(), poses: magnitudes.len(), max_um, max_pose, rms_um, files: written })
}

type Grid = (String, (char, Vec<f64>), (char, Vec<f64>), Vec<f64>);

/// Grids over the three mid-planes of the linear-axis travel (XY at mid Z, XZ at mid Y, YZ at mid
/// X), rotary axes at 0: title, the two varied axes with their nodes, and the poses (user units).
fn mid_plane_grids(machine: &Machine, nodes: usize) -> Vec<Grid> {
    let linear: Vec<usize> = (0..machine.axis_count()).filter(|&i| machine.axes()[i].kind == AxisKind::Linear).take(3).collect();
    let range = |i: usize| machine.axes()[i].range.expect("linear axes have a range");
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
