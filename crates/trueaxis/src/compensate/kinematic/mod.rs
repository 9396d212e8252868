//! Kinematic corrections: the location errors of a machine written into the controller's own
//! kinematic description, as the controllers' calibration cycles do (Heidenhain KinematicsOpt,
//! cycles 451/452; Siemens CYCLE996 writing the swivel data of CYCLE800 / TRAORI; a LinuxCNC
//! kinematics module), with axis tables for the motion errors that remain (docs/compensation.md,
//! "Five-axis machines").
//!
//! An axis-indexed table holds a correction as a function of one axis; the effect of a rotary axis
//! that is tilted or shifted depends on where the other rotary axis stands, so tables leave it. The
//! controller's kinematics (what its tool-centre-point and swivel functions compute joint positions
//! with) carries it exactly once it describes the actual axis lines.

pub mod description;
pub mod layout;
pub mod plan;

pub use description::{smallest_rotation, AxisLine, KinematicDescription};
pub use layout::{RotaryKind, RotaryLayout};
pub use plan::{plan_tables, Carried, KinematicCorrection, PlanApplied};
