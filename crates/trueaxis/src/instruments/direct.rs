//! Direct instruments: one reading per pose of one error motion of one axis (NISTIR 5236 §3.2-3.3,
//! Soons 1993 §3.2): laser interferometer optics ([`Laser`]) and electronic levels ([`Level`]), their
//! choice for an ISO parameter, and their simulation on the exact chain.

use super::laser::{Laser, LaserError, LaserOptics};
use super::level::{Level, LevelBody, LevelError};
use crate::error_model::{Direction, ErrorModel, MachineState};
use crate::geometry::Vec3;
use crate::machine::{AxisKind, Machine, ParameterId, Side};
use crate::model::{nominal_chain, Setup};

/// The kind of direct instrument, by its command-line name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectKind {
    /// `laser-linear`: positioning error along the axis (`EXX`).
    LaserLinear,
    /// `laser-straightness`: displacement perpendicular to the axis (`EYX`, `EZX`).
    LaserStraightness,
    /// `laser-angular`: rotation (`EAX`, `EBX`, `ECX`).
    LaserAngular,
    /// `level`: rotation about a horizontal axis, pitch or roll (`EAX`, `EBX` when z is up).
    Level,
}

impl DirectKind {
    pub const NAMES: [&'static str; 4] = ["laser-linear", "laser-straightness", "laser-angular", "level"];

    /// Parses a command-line name (see [`DirectKind::NAMES`]).
    pub fn parse(name: &str) -> crate::error::Result<DirectKind> {
        match name {
            "laser-linear" => Ok(DirectKind::LaserLinear),
            "laser-straightness" => Ok(DirectKind::LaserStraightness),
            "laser-angular" => Ok(DirectKind::LaserAngular),
            "level" => Ok(DirectKind::Level),
            other => Err(crate::Error::input(format!("unknown instrument `{other}` (expected one of: {})", Self::NAMES.join(", ")))),
        }
    }

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// Where a direct instrument stands, besides what the parameter fixes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectSetup {
    /// Laser: the tool-side and workpiece-side optics (mm, in M at home).
    pub setup: Setup,
    /// Laser: the body that carries the interferometer; `None`: the side that does not carry the
    /// measured axis (the interferometer on the stationary part).
    pub beam_on: Option<Side>,
    /// Level: the body of the reference level (the base for a single level).
    pub level_reference: LevelBody,
    /// Level: the vertical, up (in M).
    pub up: Vec3,
}

impl DirectSetup {
    /// The optics at the machine's tool point and the workpiece origin, the interferometer on the
    /// stationary side, a single level, z up.
    pub fn of_machine(machine: &Machine) -> DirectSetup {
        DirectSetup { setup: Setup::of_machine(machine), beam_on: None, level_reference: LevelBody::Base, up: Vec3::z() }
    }
}

/// Why a direct instrument cannot measure a parameter.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DirectError {
    #[error(
        "{0} is not a motion error: a direct measurement along an axis gives a function of the axis position, \
         which only motion errors (E<direction><axis>, e.g. EXX, EBX, ECC) are; constants (location and setup errors such as \
         EC0Y, TX) come from `trueaxis identify` or a reversal"
    )]
    NotMotion(ParameterId),
    /// The parameter does not exist on the machine (the message names it and the axes).
    #[error("{message}")]
    Machine { parameter: ParameterId, message: String },
    #[error("{parameter} with {instrument}: {message}")]
    Mismatch { parameter: ParameterId, instrument: &'static str, message: String },
    #[error(transparent)]
    Laser(#[from] LaserError),
    #[error(transparent)]
    Level(#[from] LevelError),
}

crate::error::error_of_kind!(DirectError, Input);

/// A direct instrument set up on a machine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DirectInstrument {
    Laser(Laser),
    Level(Level),
}

/// Checks that `parameter` is a motion error of an axis of `machine` (what `trueaxis fit` can fit),
/// and returns the axis index.
pub fn motion_error_axis(machine: &Machine, parameter: &ParameterId) -> Result<usize, DirectError> {
    let ParameterId::Motion { axis, .. } = *parameter else { return Err(DirectError::NotMotion(*parameter)) };
    machine.parameter_index(parameter).map_err(|e| DirectError::Machine { parameter: *parameter, message: e.to_string() })?;
    Ok(machine.axis_index(axis).expect("checked by parameter_index"))
}

impl DirectInstrument {
    /// The instrument of `kind` that measures `parameter` (a motion error of an axis of `machine`):
    /// laser optics along / perpendicular to the axis or about the parameter's direction, a level
    /// on the body the axis carries, sensitive about the parameter's (horizontal) direction. `None`
    /// picks the usual instrument: linear optics for the translation along a linear axis,
    /// straightness optics for the other translations, angular optics for rotations.
    pub fn for_parameter(
        machine: &Machine,
        parameter: &ParameterId,
        kind: Option<DirectKind>,
        setup: &DirectSetup,
    ) -> Result<DirectInstrument, DirectError> {
        let k = motion_error_axis(machine, parameter)?;
        let axis = &machine.axes()[k];
        let component = parameter.component();
        let mut direction = Vec3::zeros();
        direction[component.direction()] = 1.0;
        let along_axis = axis.kind == AxisKind::Linear && direction.cross(&axis.direction).norm() < 1e-9;
        let kind = kind.unwrap_or(match (component.is_rotation(), along_axis) {
            (true, _) => DirectKind::LaserAngular,
            (false, true) => DirectKind::LaserLinear,
            (false, false) => DirectKind::LaserStraightness,
        });
        let mismatch = |message: String| DirectError::Mismatch { parameter: *parameter, instrument: kind.name(), message };
        let translation = !component.is_rotation();
        let laser = |optics| {
            let beam_on = setup.beam_on.unwrap_or(match axis.side {
                Side::Workpiece => Side::Tool,
                Side::Tool => Side::Workpiece,
            });
            DirectInstrument::Laser(Laser { optics, setup: setup.setup, beam_on })
        };
        match kind {
            DirectKind::LaserLinear if !translation => {
                Err(mismatch("linear optics read a displacement; use laser-angular or level".into()))
            }
            DirectKind::LaserLinear if !along_axis => Err(mismatch(format!(
                "linear optics read the displacement along the beam, which lies along the motion of {}; {parameter} is perpendicular \
                 to it: use laser-straightness",
                axis.letter
            ))),
            DirectKind::LaserLinear => Ok(laser(LaserOptics::linear(direction)?)),
            DirectKind::LaserStraightness if !translation => {
                Err(mismatch("straightness optics read a displacement; use laser-angular or level".into()))
            }
            DirectKind::LaserStraightness if along_axis => Err(mismatch(format!(
                "straightness optics read a displacement perpendicular to the beam (the motion of {}); {parameter} is along it: \
                 use laser-linear",
                axis.letter
            ))),
            DirectKind::LaserStraightness => {
                let beam = if axis.kind == AxisKind::Linear { axis.direction } else { perpendicular_to(&direction) };
                Ok(laser(LaserOptics::straightness(beam, direction)?))
            }
            DirectKind::LaserAngular if translation => {
                Err(mismatch("angular optics read a rotation; use laser-linear or laser-straightness".into()))
            }
            DirectKind::LaserAngular => Ok(laser(LaserOptics::angular(direction)?)),
            DirectKind::Level if translation => Err(mismatch("a level reads a rotation (pitch or roll), not a displacement".into())),
            DirectKind::Level => {
                let level = Level::new(machine, LevelBody::CarriedBy(axis.letter), setup.level_reference, direction, setup.up).map_err(
                    |e| match e {
                        LevelError::NotHorizontal { .. } => mismatch(format!(
                            "a level reads pitch or roll (a rotation about a horizontal axis), never yaw: {parameter} is a rotation about \
                             {}, the vertical; use laser-angular",
                            ['x', 'y', 'z'][component.direction()]
                        )),
                        other => DirectError::Level(other),
                    },
                )?;
                Ok(DirectInstrument::Level(level))
            }
        }
    }

    /// The laser with its optics on the beam line offset from the tool point by `offset` (mm, the
    /// two coordinates perpendicular to the beam in x, y, z order: y, z for a beam along x), both
    /// optics at that point at the nominal pose `q` (mm, rad), taken into the body coordinates of
    /// their bodies (M at home). The offsets are the Abbe offsets of the reading: the angular
    /// errors move the optics through the chain. Angular optics and levels read rotations, which do
    /// not depend on position: refused.
    pub fn with_optics_offset(self, machine: &Machine, q: &[f64], offset: [f64; 2]) -> crate::error::Result<DirectInstrument> {
        let DirectInstrument::Laser(mut laser) = self else {
            return Err(crate::Error::input("an optics offset applies to laser linear and straightness optics; a level reads a rotation, the same everywhere on its body"));
        };
        let beam =
            match laser.optics {
                LaserOptics::Linear { beam } | LaserOptics::Straightness { beam, .. } => beam,
                LaserOptics::Angular { .. } => return Err(crate::Error::input(
                    "an optics offset applies to laser linear and straightness optics; angular optics read a rotation, the same everywhere",
                )),
            };
        let tool = nominal_chain(machine, machine.tool_chain(), q, None);
        let work = nominal_chain(machine, machine.work_chain(), q, None);
        let along = beam.iamax();
        let mut point = tool.transform_point(&laser.setup.tool_point);
        for (c, o) in (0..3).filter(|c| *c != along).zip(offset) {
            point[c] += o;
        }
        laser.setup = Setup { tool_point: tool.inverse().transform_point(&point), work_point: work.inverse().transform_point(&point) };
        Ok(DirectInstrument::Laser(laser))
    }

    /// The reading in user units (um for displacements, urad for rotations) at pose `q` (mm, rad)
    /// with the parameter vector `params` (mm, rad), on the exact chain.
    pub fn reading_user(&self, machine: &Machine, q: &[f64], params: &[f64]) -> f64 {
        match self {
            DirectInstrument::Laser(l) => l.reading_user(machine, q, params),
            DirectInstrument::Level(l) => l.reading_user(machine, q, params),
        }
    }

    /// Whether the reading is a displacement (laser linear and straightness optics), which depends
    /// on where the optics are, rather than a rotation.
    pub fn reads_a_displacement(&self) -> bool {
        matches!(self, DirectInstrument::Laser(l) if !l.optics.is_angular())
    }

    /// `um` or `urad`.
    pub fn unit(&self) -> &'static str {
        match self {
            DirectInstrument::Laser(l) if !l.optics.is_angular() => "um",
            _ => "urad",
        }
    }

    /// Simulated readings (um or urad) of the machine with `errors` at `poses` (user units, mm
    /// and deg, `axis_count` per pose) with the directions of motion `directions` (one per axis
    /// per pose, or `None`), on the exact chain.
    pub fn simulate(&self, machine: &Machine, errors: &ErrorModel, poses: &[f64], directions: Option<&[Option<Direction>]>) -> Vec<f64> {
        let n = machine.axis_count();
        let mut q = vec![0.0; n];
        let mut values = vec![0.0; machine.parameter_count()];
        poses
            .chunks(n)
            .enumerate()
            .map(|(i, user)| {
                machine.pose_to_internal(user, &mut q);
                let state = MachineState { directions: directions.map(|d| &d[i * n..(i + 1) * n]), temperatures: &[] };
                errors.values_at_state(machine, &q, &state, &mut values);
                self.reading_user(machine, &q, &values)
            })
            .collect()
    }
}

/// A unit vector perpendicular to `v`.
fn perpendicular_to(v: &Vec3) -> Vec3 {
    let other = if v.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
    v.cross(&other).normalize()
}
