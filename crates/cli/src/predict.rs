//! `trueaxis predict`.

use crate::{parse, Failure};
use std::path::{Path, PathBuf};
use trueaxis::data::{output_name, write_streamed};
use trueaxis::error_model::ErrorModel;
use trueaxis::geometry::Vec3;
use trueaxis::machine::Machine;
use trueaxis::model::{Frame, Predictor, Setup};
use trueaxis::poses::{predict_poses, PoseStream, PredictionFormat};

#[derive(Clone, Copy, clap::ValueEnum)]
enum FrameArg {
    Workpiece,
    Machine,
}

/// Volumetric error per pose: dx dy dz (um), drx dry drz (urad), dL (um) of the tool point relative
/// to the workpiece point, actual minus nominal (exact kinematic chain).
#[derive(clap::Args)]
#[command(
    after_help = "Example:\n  trueaxis predict --machine examples/machines/kx8five.toml --errors examples/errors/kx8five.toml \\\n      --poses examples/poses/kx8five.csv --frame machine --json\n\nThe poses CSV has one column per axis, named by letter (X Y Z in mm, A B C in deg), and one per\ninput of the error model (T:<sensor> degC, S:<spindle> rpm, F:<load> N, P:<name> mm), unless given by\n--input; a model with drift terms also needs the time column t (s) and, for several runs, run."
)]
pub struct PredictArgs {
    /// Machine description (TOML).
    #[arg(long)]
    machine: PathBuf,
    /// Error values (TOML): [constant], [table.NAME], [polynomial.NAME].
    #[arg(long)]
    errors: PathBuf,
    /// Poses (CSV) with one column per axis.
    #[arg(long)]
    poses: PathBuf,
    /// Tool-side point x,y,z in mm, in M at home (default: the machine's tool point).
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true)]
    tool_point: Option<Vec3>,
    /// Workpiece-side point x,y,z in mm, in M at home (default: 0,0,0).
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true)]
    work_point: Option<Vec3>,
    /// Frame of the error components.
    #[arg(long, value_enum, default_value = "workpiece")]
    frame: FrameArg,
    /// Print one JSON document instead of CSV.
    #[arg(long)]
    json: bool,
    /// Write the result to this file (atomically; a device or FIFO in place, `-` standard output)
    /// instead of stdout. Any number of poses: they are read, predicted and written in chunks.
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
    /// Value of an input of the error model for every pose, `NAME=VALUE` (repeatable): a
    /// temperature `T:<sensor>=degC`, a spindle speed `S:<name>=rpm`, a load `F:<name>=N`, a
    /// position `P:<name>=mm`. A column of the poses file with that name takes precedence.
    #[arg(long = "input", visible_alias = "temperature", value_name = "NAME=VALUE", allow_hyphen_values = true)]
    inputs: Vec<String>,
}

pub fn run(args: PredictArgs) -> Result<(), Failure> {
    let machine = Machine::load(&args.machine).map_err(Failure::input)?;
    let errors = ErrorModel::load(&args.errors, &machine).map_err(Failure::input)?;
    let mut predictor = Predictor::new(&machine, &errors);
    predictor.setup =
        Setup { tool_point: args.tool_point.unwrap_or(machine.tool_point), work_point: args.work_point.unwrap_or_else(Vec3::zeros) };
    let (frame, frame_name) = match args.frame {
        FrameArg::Workpiece => (Frame::Workpiece, "workpiece"),
        FrameArg::Machine => (Frame::Machine, "machine"),
    };
    predictor.frame = frame;
    let given = crate::inputs::parse_given(&args.inputs, "--input")?;
    crate::inputs::state_inputs(&errors, &given, "--input")?;
    let poses = PoseStream::open(&args.poses, &machine).and_then(|p| p.with_inputs(&errors, &given)).map_err(Failure::input)?;
    let format = if args.json { PredictionFormat::Json { frame: frame_name.into() } } else { PredictionFormat::Csv };
    let out = args.out.as_deref().unwrap_or(Path::new(trueaxis::data::STANDARD_OUTPUT));
    let origin = args.poses.display().to_string();
    write_streamed(out, |w| predict_poses(&predictor, poses, &origin, format, w, &output_name(out)).map(drop)).map_err(Failure::of)
}
