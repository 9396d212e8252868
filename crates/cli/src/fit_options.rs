//! The options of a direct fit (`trueaxis::identify::direct_job`), shared by `trueaxis fit` and the
//! `[[fit]]` tables of `trueaxis report` (which hold these options by name): one definition, so
//! that both parse them alike and hand the library the same job. Positions in mm (deg for rotary
//! axes), values in um (urad for angular errors), points in mm in the machine frame at home.

use crate::parse;
use std::path::PathBuf;
use trueaxis::geometry::Vec3;
use trueaxis::identify::{DirectFitJob, Given};
use trueaxis::instruments::DirectKind;

/// What to fit and how: the measured data, the parameter, the machine and instrument, the basis.
#[derive(clap::Args)]
pub struct FitOptions {
    /// Measured data: a table (read forgivingly: `;` or tab, decimal commas, units in the headers,
    /// one column per run and direction) or a Renishaw .rtl laser file.
    #[arg(long)]
    pub data: PathBuf,
    /// ISO 230 name of the measured error, e.g. EXX, EBX, EYZ.
    #[arg(long)]
    parameter: String,
    /// Machine description: checks the parameter, gives the axis range as the default domain and
    /// relates the readings to the parameter through the exact kinematic chain.
    #[arg(long)]
    machine: Option<PathBuf>,
    /// The instrument (needs --machine): laser-linear, laser-straightness, laser-angular or level.
    /// Default: linear optics for the positioning error, straightness optics for the other
    /// translations, angular optics for rotations.
    #[arg(long, value_parser = DirectKind::NAMES)]
    instrument: Option<String>,
    /// Laser linear / straightness optics: offsets A,B (mm) of the beam line from the tool point,
    /// in the two coordinates perpendicular to the beam (y,z for a beam along x; x,z along y; x,y
    /// along z), at the measurement pose (default 0,0: both optics at the tool point). The Abbe
    /// terms of known angular errors (--errors-in) then come from the chain.
    #[arg(long, value_parser = parse::offsets, allow_hyphen_values = true, value_name = "A,B")]
    optics_offset: Option<[f64; 2]>,
    /// The body that carries the interferometer (fixes the beam): tool or workpiece. Default: the
    /// side that does not carry the measured axis.
    #[arg(long, value_parser = ["tool", "workpiece"])]
    beam_on: Option<String>,
    /// Level: the body of the reference level of a differential pair: base (a single level) or the
    /// letter of the axis whose body carries it.
    #[arg(long, default_value = "base")]
    level_reference: String,
    #[command(flatten)]
    temperature: crate::temperature::TemperatureArgs,
    /// Errors already known (e.g. the angular errors fitted first): their Abbe contributions are
    /// removed from the readings (needs --machine).
    #[arg(long)]
    errors_in: Option<PathBuf>,
    /// Tool point x,y,z in mm, in M at home, that the optics are placed from (default: the machine's
    /// tool point); with --work-point, the tool-side optic itself.
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true)]
    tool_point: Option<Vec3>,
    /// The workpiece-side optic x,y,z in mm, in M at home: with --tool-point, places the two optics
    /// explicitly (instead of --optics-offset).
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true)]
    work_point: Option<Vec3>,
    /// Positions of the other axes during the measurement, e.g. `Y=0,Z=-200` (default 0).
    #[arg(long, allow_hyphen_values = true)]
    at: Option<String>,
    /// Position column (default: `target` if present, else the letter of the parameter's axis).
    #[arg(long)]
    position: Option<String>,
    /// Value column (um or urad).
    #[arg(long, default_value = "dev")]
    value: String,
    /// Basis domain MIN,MAX (default: the axis range, else the data range).
    #[arg(long, value_parser = parse::interval, allow_hyphen_values = true)]
    domain: Option<[f64; 2]>,
    /// Basis family: piecewise (truncated powers), bspline (the same splines of continuity degree - 1,
    /// well conditioned with many knots), legendre, none.
    #[arg(long, default_value = "piecewise")]
    family: String,
    /// Polynomial degree.
    #[arg(long, default_value_t = 2)]
    degree: usize,
    /// Interior knots, comma separated (mm or deg).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    knots: Vec<f64>,
    /// Equally spaced knots at this spacing across the domain (instead of --knots).
    #[arg(long)]
    knot_spacing: Option<f64>,
    /// Continuity order at the knots (1 = continuous slope).
    #[arg(long, default_value_t = 1)]
    continuity: usize,
    /// Leave out the constant term (by default it is fitted: a laser reading has an arbitrary zero,
    /// and the constants of the + and - fits carry the backlash).
    #[arg(long)]
    no_constant: bool,
    /// none, straightness (no linear trend over the domain) or revolution (no once-per-turn term).
    #[arg(long, default_value = "none")]
    constraint: String,
    /// A periodic term: WAVELENGTH[:DEGREE[:KNOT;KNOT...]] (knots as fractions of the wavelength). Repeatable.
    #[arg(long)]
    periodic: Vec<String>,
    /// Refine the periodic wavelengths within this relative bracket (e.g. 0.002).
    #[arg(long)]
    refine_wavelength: Option<f64>,
    /// Stepwise selection at this confidence (e.g. 0.9999); default keeps every function.
    #[arg(long)]
    stepwise: Option<f64>,
    /// Bidirectional model (needs a `dir` column): `both` fits the `+` and the `-` rows separately and
    /// writes `EXX+` and `EXX-`; `+` or `-` fits and writes one direction, keeping the other's.
    #[arg(long, allow_hyphen_values = true, value_parser = ["+", "-", "both"])]
    direction: Option<String>,
    /// Remove per-cycle linear drift (needs `run` and `t` columns).
    #[arg(long)]
    drift: bool,
}

impl FitOptions {
    /// The job of these options; `errors_out` is the error-values file the fit will be written
    /// into, if any (the job checks that it has a machine).
    pub fn job(&self, errors_out: Option<PathBuf>) -> DirectFitJob {
        DirectFitJob {
            data: self.data.clone(),
            parameter: self.parameter.clone(),
            machine: self.machine.clone().map(Given::File),
            instrument: self.instrument.clone(),
            optics_offset: self.optics_offset,
            beam_on: self.beam_on.clone(),
            level_reference: self.level_reference.clone(),
            temperature: self.temperature.options(),
            errors_in: self.errors_in.clone().map(Given::File),
            errors_out,
            tool_point: self.tool_point,
            work_point: self.work_point,
            at: self.at.clone(),
            position: self.position.clone(),
            value: self.value.clone(),
            domain: self.domain,
            family: self.family.clone(),
            degree: self.degree,
            knots: self.knots.clone(),
            knot_spacing: self.knot_spacing,
            continuity: self.continuity,
            constant: !self.no_constant,
            constraint: self.constraint.clone(),
            periodic: self.periodic.clone(),
            refine_wavelength: self.refine_wavelength,
            stepwise: self.stepwise,
            direction: self.direction.clone(),
            drift: self.drift,
        }
    }
}
