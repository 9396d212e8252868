//! From a thermal drift to axis offsets. Each model predicts one component of the drift of the
//! tool point relative to the workpiece, in the machine frame M (`dx`, `dy`, `dz`, um: actual minus
//! nominal, the error columns of a thermal campaign, docs/thermal.md §4). Moving linear axis k by
//! `q_k` moves the tool relative to the workpiece by `s_k q_k d_k` (d_k the axis direction in M,
//! s_k = +1 on the tool side, -1 on the workpiece side of the structure code), so the offsets that
//! cancel a drift `e` solve
//!
//! `sum_k s_k d_k q_k = -e`
//!
//! by least squares over the machine's linear axes (exact when they span the drift). A drift
//! direction no linear axis can move (a lathe has no Y) is refused when the compensation starts.
//! Offsets beyond the machine file's `[limits] correction_um` are refused, never clipped
//! (docs/limits.md).

use crate::{input, LiveError};
use nalgebra::{DMatrix, DVector};
use trueaxis::machine::{AxisKind, Machine, Side};

/// The linear axes that carry offsets and the map from drift to offsets.
#[derive(Clone, Debug)]
pub struct OffsetMap {
    /// Letters of the axes that get offsets, in machine order.
    pub letters: Vec<char>,
    /// `offsets = solve * drift` (axes x 3, um per um).
    solve: DMatrix<f64>,
    /// The largest offset of a linear axis (um).
    pub limit_um: f64,
}

/// The drift component a model's error column names: 0, 1, 2 for `dx`, `dy`, `dz`.
pub fn drift_component(error: &str) -> Result<usize, LiveError> {
    match error {
        "dx" => Ok(0),
        "dy" => Ok(1),
        "dz" => Ok(2),
        other => Err(input(format!(
            "model error `{other}`: a live offset needs a drift of the tool relative to the workpiece along x, y or z of the machine frame (error column dx, dy or dz)"
        ))),
    }
}

impl OffsetMap {
    /// The offset map of `machine` for the drift components `used` (0..3).
    pub fn new(machine: &Machine, used: &[usize]) -> Result<OffsetMap, LiveError> {
        let linear: Vec<usize> = (0..machine.axis_count()).filter(|&k| machine.axes()[k].kind == AxisKind::Linear).collect();
        let a = DMatrix::from_fn(3, linear.len(), |r, c| {
            let axis = &machine.axes()[linear[c]];
            let s = if axis.side == Side::Tool { 1.0 } else { -1.0 };
            s * axis.direction[r]
        });
        // least squares: q = -(A^T A)^-1 A^T e
        let gram = a.transpose() * &a;
        let inverse = gram.try_inverse().ok_or_else(|| input(format!("{}: its linear axes are not independent", machine.name)))?;
        let solve = -(inverse * a.transpose());
        // each used drift direction must be reproduced by the axes
        for &c in used {
            let e = DVector::from_fn(3, |r, _| if r == c { 1.0 } else { 0.0 });
            let q = &solve * &e;
            let reached = &a * q + &e;
            if reached.norm() > 1e-9 {
                return Err(input(format!(
                    "{}: no linear axis moves the tool along {} of the machine frame: the drift d{} cannot be compensated",
                    machine.name,
                    ['x', 'y', 'z'][c],
                    ['x', 'y', 'z'][c]
                )));
            }
        }
        Ok(OffsetMap {
            letters: linear.iter().map(|&k| machine.axes()[k].letter).collect(),
            solve,
            limit_um: machine.correction_limits.linear_um(),
        })
    }

    /// The offsets (um) that cancel the drift `e` (um, dx dy dz in M).
    pub fn offsets(&self, e: [f64; 3]) -> Vec<f64> {
        // + 0.0: no negative zero in logs and writes
        (&self.solve * DVector::from_column_slice(&e)).iter().map(|q| q + 0.0).collect()
    }

    /// Why `offsets` (um) cannot be written: the first beyond the limit.
    pub fn beyond_limit(&self, offsets: &[f64]) -> Option<String> {
        let (k, v) = offsets.iter().enumerate().find(|(_, v)| v.is_nan() || v.abs() > self.limit_um)?;
        Some(format!(
            "the offset of {} ({v:.1} um) is beyond the correction limit of {} um ([limits] correction_um of the machine file)",
            self.letters[k], self.limit_um
        ))
    }
}
