//! The inputs shared by `budget analyse` and `budget allocate`: machine, budget file or tolerances by
//! kind, and the poses (a file, part sizes or a grid over the work volume), parsed into the
//! library's budget problem.

use crate::{parse, Failure};
use std::path::PathBuf;
use trueaxis::budget::problem::{budget_spec, pose_sets, rotary_positions, BudgetProblem, PoseSource};
use trueaxis::budget::spec::KindValues;
use trueaxis::geometry::Vec3;
use trueaxis::machine::Machine;
use trueaxis::model::{Frame, Setup};

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum FrameArg {
    Workpiece,
    Machine,
}

#[derive(clap::Args)]
pub struct BudgetInputs {
    /// Machine description (TOML).
    #[arg(long)]
    pub machine: PathBuf,
    /// Budget file (TOML): components, tolerances, homogenisation lengths, costs (docs/budget.md).
    #[arg(long)]
    pub budget: Option<PathBuf>,
    /// Tolerance of every linear error the budget file does not name (um).
    #[arg(long, default_value_t = 5.0)]
    pub linear_um: f64,
    /// Tolerance of every angular error the budget file does not name (urad).
    #[arg(long, default_value_t = 10.0)]
    pub angular_urad: f64,
    /// Tolerance of every squareness or parallelism error the budget file does not name (urad).
    #[arg(long, default_value_t = 10.0)]
    pub squareness_urad: f64,
    /// Poses (CSV) with one column per axis; instead of --part or --grid.
    #[arg(long, conflicts_with_all = ["part", "grid"])]
    pub poses: Option<PathBuf>,
    /// Part size LxMxN (mm) or L for a cube: the tool point on a grid over the part, centred on the
    /// workpiece point and standing on it; repeat for several sizes.
    #[arg(long)]
    pub part: Vec<String>,
    /// Grid points per linear axis over the travel (the work volume; the default, with 5).
    #[arg(long)]
    pub grid: Option<usize>,
    /// Grid points per edge of a part.
    #[arg(long, default_value_t = 5)]
    pub part_nodes: usize,
    /// Position of a rotary axis for --part and --grid, e.g. A=30 (deg; default 0); repeatable.
    #[arg(long)]
    pub rotary: Vec<String>,
    /// Tool-side point x,y,z in mm, in M at home (default: the machine's tool point).
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true)]
    pub tool_point: Option<Vec3>,
    /// Workpiece-side point x,y,z in mm, in M at home (default: 0,0,0).
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true)]
    pub work_point: Option<Vec3>,
    /// Frame of the volumetric error components.
    #[arg(long, value_enum, default_value = "workpiece")]
    pub frame: FrameArg,
}

pub fn parse_part(text: &str) -> Result<[f64; 3], String> {
    let values: Result<Vec<f64>, _> = text.split(['x', 'X']).map(|p| p.trim().parse::<f64>()).collect();
    match values {
        Ok(v) if v.iter().all(|x| x.is_finite() && *x > 0.0) && v.len() == 1 => Ok([v[0]; 3]),
        Ok(v) if v.iter().all(|x| x.is_finite() && *x > 0.0) && v.len() == 3 => Ok([v[0], v[1], v[2]]),
        _ => Err(format!("`{text}` is not a part size: give LxMxN in mm (e.g. 200x150x100) or L for a cube")),
    }
}

fn parse_rotary(text: &str) -> Result<(char, f64), String> {
    let bad = || format!("`{text}` is not a rotary position: give LETTER=DEG, e.g. A=30");
    let (letter, value) = text.split_once('=').ok_or_else(bad)?;
    let mut chars = letter.trim().chars();
    let (Some(c), None) = (chars.next(), chars.next()) else { return Err(bad()) };
    let v: f64 = value.trim().parse().map_err(|_| bad())?;
    v.is_finite().then_some((c.to_ascii_uppercase(), v)).ok_or_else(bad)
}

impl BudgetInputs {
    /// The budget problem of the options: the machine, the budget, the points, the frame and the
    /// pose sets (trueaxis::budget::problem).
    pub fn load(&self) -> Result<BudgetProblem, Failure> {
        let machine = Machine::load(&self.machine).map_err(Failure::input)?;
        let defaults = KindValues([self.linear_um, self.angular_urad, self.squareness_urad]);
        let spec = budget_spec(&machine, self.budget.as_deref(), defaults).map_err(Failure::of)?;
        let setup =
            Setup { tool_point: self.tool_point.unwrap_or(machine.tool_point), work_point: self.work_point.unwrap_or_else(Vec3::zeros) };
        let frame = match self.frame {
            FrameArg::Workpiece => Frame::Workpiece,
            FrameArg::Machine => Frame::Machine,
        };
        let given: Vec<(char, f64)> = self
            .rotary
            .iter()
            .map(|r| parse_rotary(r).map_err(|m| Failure::input(anyhow::anyhow!("--rotary: {m}"))))
            .collect::<Result<_, _>>()?;
        let parts: Vec<[f64; 3]> = self
            .part
            .iter()
            .map(|p| parse_part(p).map_err(|m| Failure::input(anyhow::anyhow!("--part: {m}"))))
            .collect::<Result<_, _>>()?;
        let rotary = rotary_positions(&machine, &given).map_err(Failure::of)?;
        let source = match (&self.poses, parts.is_empty()) {
            (Some(path), _) => PoseSource::File(path),
            (None, false) => PoseSource::Parts { sizes: &parts, nodes: self.part_nodes },
            (None, true) => PoseSource::Grid(self.grid.unwrap_or(5)),
        };
        let sets = pose_sets(&machine, &setup, &source, &rotary).map_err(Failure::of)?;
        Ok(BudgetProblem { machine, spec, setup, frame, sets })
    }
}
