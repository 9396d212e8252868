//! `trueaxis predict` over a pose file of any length: the poses read chunk by chunk
//! ([`PoseStream`]), each chunk predicted on the exact chain by the batch kernel (in parallel,
//! `model::Predictor::predict_states`) and written as rows of the prediction table
//! ([`PredictionWriter`]), so that memory does not grow with the number of poses (10^7 poses in a
//! few tens of MB, BENCHMARKS.md). The table equals the one written whole.

use super::{PoseStream, PredictionFormat, PredictionWriter};
use crate::data::DataError;
use crate::model::Predictor;
use std::io::{BufRead, Write};

/// Poses predicted at a time.
pub const CHUNK: usize = 1 << 16;

/// Predicts every pose of `poses` with `predictor` and writes the table to `out` (named `name` in
/// messages); returns the number of poses. A bad row is refused with its line, a prediction that
/// is not finite with the line of its pose; what was written before stays (the output layer
/// discards it for a file, [`crate::data::OutputSet`]).
pub fn predict_poses<R: BufRead>(
    predictor: &Predictor,
    mut poses: PoseStream<R>,
    origin: &str,
    format: PredictionFormat,
    out: &mut dyn Write,
    name: &str,
) -> Result<usize, DataError> {
    let machine = predictor.machine;
    let mut writer = PredictionWriter::begin(machine, format, out, name)?;
    while let Some(chunk) = poses.next_chunk(CHUNK)? {
        let internal = chunk.poses.internal(machine);
        let predictions = predictor.predict_states(&internal, chunk.poses.directions.as_deref(), &chunk.inputs);
        writer.write(&chunk.poses.user, &predictions, &|i| format!("the pose of line {} of {origin}", chunk.poses.lines[i]))?;
    }
    writer.finish()
}
