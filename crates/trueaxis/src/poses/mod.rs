//! Pose files and what is predicted at them (docs/design.md, Files): pose CSVs read whole
//! ([`pose_table`]) or as a stream in bounded memory ([`pose_stream`]) through the same columns
//! ([`pose_columns`]: one per axis of the machine, directions of motion, temperatures), the
//! volumetric error predicted chunk by chunk ([`prediction`]) and written as prediction tables
//! ([`prediction_table`]). Above `model` (it predicts) and below the stages that read poses.

mod pose_columns;
mod pose_stream;
mod pose_table;
mod prediction;
mod prediction_table;

pub use pose_stream::{PoseChunk, PoseStream, MAX_PREAMBLE};
pub use pose_table::{poses_of, read_poses, read_poses_from, PoseTable};
pub use prediction::{predict_poses, CHUNK};
pub use prediction_table::{predictions_csv, predictions_json, PredictionFormat, PredictionWriter, PREDICTION_COLUMNS};
