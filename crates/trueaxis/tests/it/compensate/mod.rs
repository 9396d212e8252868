//! Compensation (`trueaxis::compensate`): the pose correction, corrections in batches, the export formats and NC programs.

mod batch_correction;
mod correction;
mod export;
mod nc;
