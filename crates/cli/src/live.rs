//! `trueaxis live`: live thermal compensation of one machine (`trueaxis_live::run`): temperatures
//! in from OPC UA, LinuxCNC HAL or a CSV replay, the fitted thermal model one sample at a time,
//! offsets out to the controller, state saved after every step (docs/live.md).

use crate::Failure;
use std::path::PathBuf;
use trueaxis_live::run::{run as run_live, Options};

/// Live thermal compensation: reads the machine's temperature sensors as they change, predicts
/// the drift with a model of `thermal fit`, writes the offsets that cancel it to the controller.
#[derive(clap::Args)]
#[command(after_help = "Examples (docs/live.md):\n  \
trueaxis live --machine examples/machines/vmc3.toml --thermal-model examples/live/dz_drift.toml \\\n      \
--source csv:examples/thermal/campaign.csv --speed inf --state vmc3.state.json --log vmc3.csv\n  \
trueaxis live --machine vmc3.toml --thermal-model dz_drift.toml --map examples/live/vmc3_opcua.toml \\\n      \
--source opcua:opc.tcp://controller:4840 --sink opcua --state /var/lib/trueaxis/vmc3.json --log vmc3.jsonl\n  \
trueaxis live --machine vmc3.toml --thermal-model dz_drift.toml --map examples/live/vmc3_hal.toml \\\n      \
--source hal --sink hal --period 1 --state vmc3.json --status /run/trueaxis/vmc3.status.json\n\n\
Exit status: 2 bad input (a file, a node id, a pin), 1 a failed computation, 3 the environment\n\
(a server that cannot be reached, halcmd missing, a state file that cannot be written).")]
pub struct LiveArgs {
    /// Machine description (TOML): its linear axes take the offsets, `[limits] correction_um`
    /// bounds them.
    #[arg(long)]
    machine: PathBuf,
    /// Fitted thermal model (TOML of `thermal fit --out`, a regression or a state-space drift
    /// model of `dx`, `dy` or `dz`); repeat for several drift components.
    #[arg(long = "thermal-model", required = true)]
    thermal_model: Vec<PathBuf>,
    /// Where samples come from: `csv:FILE` (a campaign replayed), `opcua:opc.tcp://HOST:PORT`
    /// (subscriptions to the nodes of --map) or `hal` (the pins of --map, through halcmd).
    #[arg(long)]
    source: String,
    /// Where offsets go: `opcua` (the source's server), `opcua:opc.tcp://HOST:PORT` or `hal` (the
    /// thermal-offset pins of the HAL component of `compensate --format linuxcnc-hal`); repeat
    /// for several; none: logs only.
    #[arg(long)]
    sink: Vec<String>,
    /// Mapping file (TOML): per input its node id, pin or column, unit, physical range and rate
    /// limit; the run signal; per axis its output node or pin.
    #[arg(long)]
    map: Option<PathBuf>,
    /// Update period (s): OPC UA sampling and publishing interval, HAL polling period.
    #[arg(long, default_value_t = 1.0)]
    period: f64,
    /// State file (JSON), saved atomically after every step and continued after a restart.
    #[arg(long)]
    state: PathBuf,
    /// Start a new run: the next sample is the reference state (the saved state is replaced).
    #[arg(long)]
    reset: bool,
    /// Seconds the last offsets are held without an accepted sample, before the ramp.
    #[arg(long, default_value_t = 600.0)]
    hold: f64,
    /// Seconds of the linear ramp of the offsets to zero after the hold.
    #[arg(long, default_value_t = 600.0)]
    ramp: f64,
    /// Source time per wall time: 1 for a machine; a replay (`inf`: as fast as possible) or a
    /// test server faster than real time (holds and ramps are timed on the source's clock).
    #[arg(long, default_value_t = 1.0)]
    speed: f64,
    /// Log (FILE.csv: a campaign that `thermal predict` reads; FILE.jsonl: every step as JSON);
    /// appended to; repeat for both.
    #[arg(long)]
    log: Vec<PathBuf>,
    /// Status file (JSON, replaced atomically after every step): last update, inputs, drift,
    /// offsets, warnings.
    #[arg(long)]
    status: Option<PathBuf>,
    /// Do not fsync the state file (it stays whole when the process is killed, not after a power
    /// loss).
    #[arg(long)]
    no_sync: bool,
    /// Seconds without an OPC UA connection after which the process ends with exit status 3 (for a
    /// supervisor to act on); default: never. A lost connection is tried again after 0.5 s, the
    /// wait doubling to 5 s between attempts; the offsets are held, then ramped to zero meanwhile.
    #[arg(long, default_value_t = f64::INFINITY, value_name = "S")]
    give_up_after: f64,
}

pub fn run(a: LiveArgs) -> Result<(), Failure> {
    let options = Options {
        machine: a.machine,
        models: a.thermal_model,
        source: a.source,
        sinks: a.sink,
        map: a.map,
        period_s: a.period,
        speed: a.speed,
        hold_s: a.hold,
        ramp_s: a.ramp,
        state: a.state,
        reset: a.reset,
        logs: a.log,
        status: a.status,
        no_sync: a.no_sync,
        give_up_after_s: a.give_up_after,
    };
    run_live(&options).map(|_| ()).map_err(Failure::of)
}
