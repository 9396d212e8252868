//! `trueaxis design trajectory|simulate|steady|optimal`: planning indirect measurements.

mod steady;

use crate::output::{json, print, text_or_file};
use crate::{parse, Failure};
use std::path::PathBuf;
use trueaxis::data::{write_atomically, OutputSet};
use trueaxis::error_model::ErrorModel;
use trueaxis::geometry::Vec3;
use trueaxis::identify::{criteria_units, CriteriaUnits};
use trueaxis::identify::{measurement_csv, optimal_design_json, simulate_campaign, Campaign, CampaignCandidates, Criterion, IdentifyError};
use trueaxis::instruments::{ball_trajectory, Sweep};
use trueaxis::machine::Machine;
use trueaxis::model::Setup;

/// Plan indirect measurements: 3D-ball trajectories, simulated campaign data, steady readings from a
/// recording, optimal designs.
#[derive(clap::Args)]
#[command(after_help = "Examples (see `trueaxis design <command> --help`):\n  \
trueaxis design trajectory --machine examples/machines/kx8five.toml --work-point 150,0,100 --sweep A=0:120 --sweep C=0:1440 --count 807\n  \
trueaxis design optimal --machine examples/machines/kx8five.toml --campaign examples/campaigns/kx8five/campaign.toml --count 20 --starts 1")]
pub struct DesignArgs {
    #[command(subcommand)]
    command: DesignCommand,
}

#[derive(clap::Subcommand)]
enum DesignCommand {
    Trajectory(TrajectoryArgs),
    Simulate(SimulateArgs),
    Steady(steady::SteadyArgs),
    Optimal(OptimalArgs),
}

/// Poses of a 3D-ball test: the rotary axes sweep, the linear axes keep the tool point on the ball
/// (Andolfatto et al. (2011)). Writes a pose CSV (axis columns, mm and deg).
#[derive(clap::Args)]
#[command(after_help = "Example (the identification trajectory of Andolfatto et al. (2011), of the shipped campaign):\n  \
trueaxis design trajectory --machine examples/machines/kx8five.toml --work-point 150,0,100 \\\n      \
--sweep A=0:120 --sweep C=0:1440 --count 807 --out capball.csv\n\n\
Every swept axis moves linearly from FROM to TO (deg) over the COUNT poses, simultaneously; axes not\n\
swept stay at 0. Poses outside an axis range are refused (exit 2).")]
struct TrajectoryArgs {
    #[arg(long)]
    machine: PathBuf,
    /// Ball centre at home, x,y,z in mm in M.
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true)]
    work_point: Vec3,
    /// Sensing-head centre at home, x,y,z in mm in M (default: the machine's tool point).
    #[arg(long, value_parser = parse::point, allow_hyphen_values = true)]
    tool_point: Option<Vec3>,
    /// A rotary sweep AXIS=FROM:TO in deg (repeat for several axes).
    #[arg(long = "sweep", value_parser = Sweep::parse, required = true, allow_hyphen_values = true)]
    sweeps: Vec<Sweep>,
    /// Number of poses (at most 1000000).
    #[arg(long, value_parser = crate::bounds::count::<1, { crate::bounds::MAX_POSES }>)]
    count: usize,
    /// Output CSV (written atomically); stdout if absent.
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
}

/// Simulated readings of every measurement of a campaign: the exact chain with known errors plus
/// Gaussian noise of each channel's sigma_um. Rewrites each data file with its reading columns.
#[derive(clap::Args)]
#[command(after_help = "Example:\n  \
trueaxis design simulate --machine examples/machines/kx8five.toml \\\n      \
--campaign examples/campaigns/kx8five/campaign.toml --errors examples/errors/kx8five_table1.toml --seed 4\n\n\
The data files must exist and hold the poses (axis columns); reading columns are added or replaced.\n\
With --noise-free no noise is added.")]
struct SimulateArgs {
    #[arg(long)]
    machine: PathBuf,
    #[arg(long)]
    campaign: PathBuf,
    /// The true errors (error-values TOML).
    #[arg(long)]
    errors: PathBuf,
    /// Seed of the noise generator (ChaCha8).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Do not add noise.
    #[arg(long)]
    noise_free: bool,
    /// Print one JSON document: {"files": [{"path", "records", "channels"}]}.
    #[arg(long)]
    json: bool,
}

/// Choose N records of a campaign (the candidate set) that minimise a design criterion, by an
/// exchange algorithm (Soons (1993)).
#[derive(clap::Args)]
#[command(after_help = "Example:\n  \
trueaxis design optimal --machine examples/machines/kx8five.toml \\\n      \
--campaign examples/campaigns/kx8five/campaign.toml --count 40 --criterion d --json\n\n\
Criteria (all minimised, sigma-weighted rows, n = count): d = det(n M^-1)^(1/p), a = trace(n M^-1)/p,\n\
e = largest eigenvalue of n M^-1, g = largest n trace(X_r M^-1 X_r^T) over the candidate records r\n\
(the summed prediction variance of a record's readings; p at a D-optimal approximate design).\n\
Units: rows weighted by 1/sigma (sigma in um), unknowns in their own units (um, urad, um/mm^k):\n\
d in (u_1^2 ... u_p^2)^(1/p), a and e in u^2 when all units agree, g dimensionless; the output\n\
also gives the values in the units of Soons (1993) (mm, rad, sigma = 1 mm), see docs/identification.md.\n\
A candidate set or a design that cannot determine every unknown is an error naming the unseen\n\
combinations (exit 1); --count too small to hold p readings is bad input (exit 2).")]
struct OptimalArgs {
    #[arg(long)]
    machine: PathBuf,
    #[arg(long)]
    campaign: PathBuf,
    /// Number of records to choose (repetitions allowed), 1 to 1000000.
    #[arg(long, value_parser = crate::bounds::count::<1, { crate::bounds::MAX_POSES }>)]
    count: usize,
    /// d, a, e or g.
    #[arg(long, default_value = "d", value_parser = Criterion::parse)]
    criterion: Criterion,
    /// Random starts of the exchange algorithm, 1 to 100000.
    #[arg(long, default_value_t = 5, value_parser = crate::bounds::count::<1, { crate::bounds::MAX_ITERATIONS }>)]
    starts: usize,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Write the chosen records (poses, with a `measurement` column) to this CSV.
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
    #[arg(long)]
    json: bool,
}

pub fn run(args: DesignArgs) -> Result<(), Failure> {
    match args.command {
        DesignCommand::Trajectory(a) => trajectory(a),
        DesignCommand::Simulate(a) => simulate(a),
        DesignCommand::Steady(a) => steady::run(a),
        DesignCommand::Optimal(a) => optimal(a),
    }
}

fn trajectory(args: TrajectoryArgs) -> Result<(), Failure> {
    let machine = Machine::load(&args.machine).map_err(Failure::input)?;
    let setup = Setup { tool_point: args.tool_point.unwrap_or(machine.tool_point), work_point: args.work_point };
    let poses = ball_trajectory(&machine, &setup, &args.sweeps, args.count, Vec3::zeros()).map_err(Failure::of)?;
    let mut text = format!(
        "# 3D-ball trajectory on `{}`: ball at {:?} mm, head at {:?} mm (in M at home), sweeps {}\n{}\n",
        machine.name,
        setup.work_point.as_slice(),
        setup.tool_point.as_slice(),
        args.sweeps.iter().map(|s| format!("{}={}:{}", s.axis, s.from, s.to)).collect::<Vec<_>>().join(" "),
        machine.axis_letters().chars().map(String::from).collect::<Vec<_>>().join(",")
    );
    for pose in poses.chunks(machine.axis_count()) {
        text += &pose.iter().map(|v| format!("{}", (v * 1e9).round() / 1e9 + 0.0)).collect::<Vec<_>>().join(",");
        text.push('\n');
    }
    text_or_file(args.out.as_deref(), &text)
}

fn simulate(args: SimulateArgs) -> Result<(), Failure> {
    let machine = Machine::load(&args.machine).map_err(Failure::input)?;
    let truth = ErrorModel::load(&args.errors, &machine).map_err(Failure::input)?;
    let campaign = Campaign::load(&args.campaign, &machine).map_err(Failure::of)?;
    let readings = simulate_campaign(&campaign, &machine, &truth, (!args.noise_free).then_some(args.seed)).map_err(Failure::of)?;
    let mut text = String::new();
    let mut files = Vec::new();
    // every data file of the campaign, or none (docs/reliability.md)
    let mut outputs = OutputSet::new();
    // the job is to write the readings into the data files it read the poses from
    outputs.updating_inputs();
    for (m, r) in campaign.measurements.iter().zip(&readings) {
        outputs.file(&m.data, measurement_csv(&machine, m, r));
        text += &format!("wrote {} ({} records, {})\n", m.data.display(), m.records(), m.instrument.channels().join(" "));
        files.push(serde_json::json!({"path": m.data.display().to_string(), "records": m.records(), "channels": m.instrument.channels()}));
    }
    outputs.commit().map_err(Failure::input)?;
    if args.json {
        text = format!("{}\n", serde_json::json!({ "files": files }));
    }
    print(&text)
}

fn optimal(args: OptimalArgs) -> Result<(), Failure> {
    let machine = Machine::load(&args.machine).map_err(Failure::input)?;
    let campaign = Campaign::load(&args.campaign, &machine).map_err(Failure::of)?;
    let nominal = campaign.nominal_errors(&machine).map_err(Failure::of)?;
    let candidates = CampaignCandidates::new(&campaign, &machine, &nominal).map_err(Failure::of)?;
    let set = &candidates.set;
    // a design that cannot determine every unknown is a failed computation (exit 1), named like
    // `identify` names it; a --count too small for the unknowns is bad input (exit 2)
    let in_campaign = |e: IdentifyError| match e {
        IdentifyError::RankDeficient { message } => {
            Failure::computation(anyhow::anyhow!("{}: rank deficient: {message}", args.campaign.display()))
        }
        IdentifyError::Input(message) => Failure::input(anyhow::anyhow!("--count {}: {message}", args.count)),
        other => Failure::of(other),
    };
    let (chosen, criteria) = set.exchange(args.count, args.criterion, args.starts, args.seed).map_err(in_campaign)?;
    let all: Vec<usize> = (0..set.len()).collect();
    let full = set.criteria(&all).map_err(in_campaign)?;
    if let Some(path) = &args.out {
        write_atomically(path, candidates.chosen_csv(&campaign, &machine, &chosen).as_bytes()).map_err(Failure::input)?;
    }
    let doc = optimal_design_json(&campaign, &candidates, args.criterion, args.count, &chosen, &criteria, &full);
    if args.json {
        return json(&doc);
    }
    let mut text = format!(
        "{:?}-optimal design of {} records out of {} candidates, {} unknowns\n",
        args.criterion,
        args.count,
        set.len(),
        candidates.parameters.len()
    );
    let line = |c: &trueaxis::identify::DesignCriteria| {
        format!("D {:.4e}  A {:.4e}  E {:.4e}  G {:.4}  (max reading variance {:.4})", c.d, c.a, c.e, c.g, c.max_reading_variance)
    };
    text += &format!("  chosen:     {}\n", line(&criteria));
    text += &format!("  all {:>5}:  {}  (n = {})\n", set.len(), line(&full), set.len());
    text += &format!(
        "  (G: largest summed prediction variance of one record's readings over the candidates; p = {} at a D-optimal design)\n",
        candidates.parameters.len()
    );
    text += &units_text(&candidates.parameters, &candidates.units, &criteria_units(&candidates.units), &criteria);
    text += "records (measurement:line):";
    for r in doc["chosen"].as_array().into_iter().flatten() {
        text += &format!(" {}:{}", r["measurement"].as_str().unwrap_or(""), r["line"]);
    }
    text.push('\n');
    print(&text)
}

/// The units the criteria are computed in, and their values in the units of Soons (1993) (`design_units`).
fn units_text(names: &[String], units: &[String], u: &CriteriaUnits, chosen: &trueaxis::identify::DesignCriteria) -> String {
    let list: Vec<String> = names.iter().zip(units).map(|(n, u)| format!("{n} {u}")).collect();
    let mut text = format!(
        "  units: rows weighted by 1/sigma (sigma in um), unknowns in {}: D in {}; A, E in {}; G dimensionless (over sigma^2)\n",
        list.join(", "),
        u.d,
        u.a_e.as_deref().unwrap_or("mixed units (the unknowns' units differ)")
    );
    if let Some(f) = u.d_to_seed000 {
        text += &format!(
            "  in the units of Soons (1993) (mm, rad, sigma = 1 in mm): D x {f:.4e} = {:.4e}{}\n",
            f * chosen.d,
            u.a_e_to_seed000.map_or(String::new(), |g| format!(", A x {g:.4e} = {:.4e}, E x {g:.4e} = {:.4e}", g * chosen.a, g * chosen.e))
        );
    }
    text
}
