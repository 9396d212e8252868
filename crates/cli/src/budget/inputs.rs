//! The inputs shared by `budget analyse` and `budget allocate`: machine, budget file or tolerances by
//! kind, and the poses (a file, part sizes or a grid over the work volume).

use super::failure;
use crate::predict::parse_point;
use crate::Failure;
use std::path::PathBuf;
use trueaxis::budget::poses::{part_grid, volume_grid};
use trueaxis::budget::spec::{BudgetSpec, KindValues};
use trueaxis::data::read_poses;
use trueaxis::geometry::Vec3;
use trueaxis::machine::{AxisKind, Machine};
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
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
    pub tool_point: Option<Vec3>,
    /// Workpiece-side point x,y,z in mm, in M at home (default: 0,0,0).
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
    pub work_point: Option<Vec3>,
    /// Frame of the volumetric error components.
    #[arg(long, value_enum, default_value = "workpiece")]
    pub frame: FrameArg,
}

/// One pose set: a label (the part size or the source) and its poses in user and internal units.
pub struct PoseSet {
    pub label: String,
    pub part: Option<[f64; 3]>,
    pub user: Vec<f64>,
    pub internal: Vec<f64>,
}

pub struct Loaded {
    pub machine: Machine,
    pub spec: BudgetSpec,
    pub setup: Setup,
    pub frame: Frame,
    pub sets: Vec<PoseSet>,
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
    pub fn load(&self) -> Result<Loaded, Failure> {
        let machine = Machine::load(&self.machine).map_err(Failure::input)?;
        let kinds = [("--linear-um", self.linear_um), ("--angular-urad", self.angular_urad), ("--squareness-urad", self.squareness_urad)];
        for (name, v) in kinds {
            if !(v.is_finite() && v > 0.0) {
                return Err(Failure::input(anyhow::anyhow!("{name} {v}: a tolerance must be a positive number")));
            }
        }
        let defaults = KindValues([self.linear_um, self.angular_urad, self.squareness_urad]);
        let spec = match &self.budget {
            Some(path) => BudgetSpec::load(path, &machine, defaults).map_err(failure)?,
            None => BudgetSpec::standard(&machine, defaults),
        };
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
        let mut rotary = Vec::new();
        for axis in machine.axes().iter().filter(|a| a.kind == AxisKind::Rotary) {
            rotary.push(given.iter().find(|(c, _)| *c == axis.letter).map_or(0.0, |r| r.1));
        }
        for (c, _) in &given {
            if !machine.axes().iter().any(|a| a.letter == *c && a.kind == AxisKind::Rotary) {
                return Err(Failure::input(anyhow::anyhow!(
                    "--rotary {c}=...: machine `{}` has no rotary axis {c} (axes: {})",
                    machine.name,
                    machine.axis_letters()
                )));
            }
        }
        let mut sets = Vec::new();
        if let Some(path) = &self.poses {
            let table = read_poses(path, &machine).map_err(Failure::input)?;
            if table.is_empty() {
                return Err(Failure::input(anyhow::anyhow!("{}: no poses", path.display())));
            }
            for (i, pose) in table.user.chunks(machine.axis_count()).enumerate() {
                machine
                    .check_range(pose)
                    .map_err(|m| Failure::input(anyhow::anyhow!("{}: line {}: {m}", path.display(), table.lines[i])))?;
            }
            sets.push(PoseSet { label: path.display().to_string(), part: None, internal: table.internal(&machine), user: table.user });
        } else if !parts.is_empty() {
            if self.part_nodes < 2 {
                return Err(Failure::input(anyhow::anyhow!("--part-nodes {}: at least 2 points per edge", self.part_nodes)));
            }
            for size in &parts {
                let user = part_grid(&machine, &setup, *size, self.part_nodes, &rotary).map_err(failure)?;
                sets.push(PoseSet {
                    label: format!("{}x{}x{}", size[0], size[1], size[2]),
                    part: Some(*size),
                    internal: internal(&machine, &user),
                    user,
                });
            }
        } else {
            let nodes = self.grid.unwrap_or(5);
            if nodes < 2 {
                return Err(Failure::input(anyhow::anyhow!("--grid {nodes}: at least 2 points per axis")));
            }
            let user = volume_grid(&machine, nodes, &rotary).map_err(failure)?;
            sets.push(PoseSet { label: "work volume".into(), part: None, internal: internal(&machine, &user), user });
        }
        Ok(Loaded { machine, spec, setup, frame, sets })
    }
}

pub fn internal(machine: &Machine, user: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; user.len()];
    for (u, q) in user.chunks(machine.axis_count()).zip(out.chunks_mut(machine.axis_count())) {
        machine.pose_to_internal(u, q);
    }
    out
}

pub fn frame_name(frame: Frame) -> &'static str {
    match frame {
        Frame::Workpiece => "workpiece",
        Frame::Machine => "machine",
    }
}
