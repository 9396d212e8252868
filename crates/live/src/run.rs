//! The live compensation process: reads the machine, the models and the mapping, reloads the
//! state, opens the source and the sinks, then loops: the next event of the source (a sample, a
//! note, the end of a replay), the engine's step, and after every step: the state saved (fsync,
//! rename), the offsets written to the controller, the logs appended, the status updated. Between
//! samples the engine is ticked on the source's clock ([`crate::clock`]) for holds and ramps.

use crate::clock::Clock;
use crate::engine::{Engine, Step};
use crate::hal::{HalSink, HalSource};
use crate::log::{CsvLog, JsonLog, Names};
use crate::mapping::Mapping;
use crate::source::{CsvReplay, Event, Sink, Source};
use crate::state::EngineState;
use crate::status::Status;
use crate::{input, LiveError};
use std::path::{Path, PathBuf};
use std::time::Duration;
use trueaxis::machine::Machine;
use trueaxis::thermal::campaign_predict::read_model_file;

/// Everything `trueaxis live` is given.
#[derive(Clone, Debug)]
pub struct Options {
    pub machine: PathBuf,
    pub models: Vec<PathBuf>,
    /// `csv:FILE`, `opcua:URL` or `hal`.
    pub source: String,
    /// Each `opcua`, `opcua:URL` or `hal`.
    pub sinks: Vec<String>,
    pub map: Option<PathBuf>,
    /// Update period (s): OPC UA sampling and publishing interval, HAL polling period.
    pub period_s: f64,
    /// Source time per wall time (1 for a machine; a replay or a test may run faster).
    pub speed: f64,
    pub hold_s: f64,
    pub ramp_s: f64,
    pub state: PathBuf,
    /// Start a new run: ignore (and replace) the state file.
    pub reset: bool,
    /// Logs (`.csv` or `.jsonl`).
    pub logs: Vec<PathBuf>,
    pub status: Option<PathBuf>,
    /// Skip the fsync of the state file (whole after a crash of the process, not a power loss).
    pub no_sync: bool,
    /// Seconds without an OPC UA connection after which the run ends (exit 3); infinite: never.
    pub give_up_after_s: f64,
}

/// How a run ended.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Summary {
    pub samples: u64,
    pub refused: u64,
}

/// The source named by `--source`.
enum SourceSpec {
    Csv(PathBuf),
    OpcUa(String),
    Hal,
}

fn source_spec(text: &str) -> Result<SourceSpec, LiveError> {
    match text.split_once(':') {
        Some(("csv", path)) => Ok(SourceSpec::Csv(path.into())),
        Some(("opcua", url)) if url.starts_with("opc.tcp://") => Ok(SourceSpec::OpcUa(url.into())),
        None if text == "hal" => Ok(SourceSpec::Hal),
        _ => Err(input(format!("--source `{text}`: use csv:FILE, opcua:opc.tcp://HOST:PORT[/PATH] or hal"))),
    }
}

/// Builds the engine from the files and the saved state.
pub fn engine(o: &Options, mapping: &Mapping) -> Result<(Engine, String, String), LiveError> {
    let machine = Machine::load(&o.machine).map_err(|e| input(e.to_string()))?;
    let models = o.models.iter().map(|p| read_model_file(p)).collect::<Result<Vec<_>, _>>()?;
    let mut engine = Engine::new(&machine, models, mapping, o.hold_s, o.ramp_s)?;
    let note = match (o.reset, EngineState::load(&o.state)?) {
        (false, Some(saved)) => {
            engine.resume(saved, &o.state.display().to_string())?;
            let s = &engine.state;
            format!(
                "continuing from {} ({} samples, run `{}`, phase {:?})",
                o.state.display(),
                s.samples,
                s.run.clone().unwrap_or_default(),
                s.phase
            )
        }
        _ => format!(
            "new state {}: the first sample is the reference state of the drift models (start on a machine at its reference temperature)",
            o.state.display()
        ),
    };
    Ok((engine, machine.name, note))
}

/// Runs until the source ends (a replay) or fails.
pub fn run(o: &Options) -> Result<Summary, LiveError> {
    if !(o.period_s.is_finite() && o.period_s > 0.0) {
        return Err(input(format!("--period {} must be a positive number of seconds", o.period_s)));
    }
    if o.give_up_after_s.is_nan() || o.give_up_after_s <= 0.0 {
        return Err(input(format!("--give-up-after {} must be a positive number of seconds (inf: never)", o.give_up_after_s)));
    }
    let mapping = match &o.map {
        Some(p) => Mapping::read(p)?,
        None => Mapping::default(),
    };
    let (mut engine, machine, note) = engine(o, &mapping)?;
    let period = Duration::from_secs_f64(o.period_s);
    let resume = (!o.reset).then_some(&engine.state);
    let (mut source, mut sinks) = open(o, &engine, &mapping, period, resume)?;
    for log in &o.logs {
        sinks.push(open_log(log, &engine)?);
    }
    let mut status = Status::new(&machine, Names::of(&engine), o.status.clone());
    let mut clock = Clock::new(o.speed);
    // a machine's source time is the Unix time: a restart during an outage still holds and ramps
    if !o.source.starts_with("csv:") {
        let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0.0, |d| d.as_secs_f64());
        match (o.speed == 1.0, engine.state.accepted.as_ref()) {
            (true, _) => clock.anchor(now),
            (false, Some(a)) => clock.anchor(a.time_s),
            (false, None) => {}
        }
    }
    let mut summary = Summary::default();
    status.note(&note);
    status.note(&format!(
        "trueaxis live on {machine}: inputs {}; offsets of {}",
        engine.inputs.join(", "),
        engine.offsets.letters.iter().collect::<String>()
    ));
    if let Some(mut step) = engine.last_step().filter(|_| engine.state.samples > 0) {
        step.offsets_um = engine.state.written_um.clone();
        step.write = true;
        step.readings = None;
        step.drift_um = None;
        step.message = Some("restarted: the offsets of the state file are written again".into());
        deliver(&step, &mut sinks, &mut status, engine.state.samples);
    }
    loop {
        match source.next(period)? {
            Some(Event::Sample(sample)) => {
                clock.anchor(sample.time_s);
                if let Some(step) = engine.update(&sample) {
                    summary.refused += u64::from(step.readings.is_none() || step.drift_um.is_none());
                    commit(&engine, &step, o, &mut sinks, &mut status)?;
                }
            }
            Some(Event::Note(n)) => broadcast(&n, &mut sinks, &mut status),
            Some(Event::End) => break,
            None => {}
        }
        for n in sinks.iter_mut().map(|s| s.notes()).collect::<Result<Vec<_>, _>>()?.concat() {
            broadcast(&n, &mut sinks, &mut status);
        }
        if let Some(now) = clock.now().filter(|t| t.is_finite()) {
            if let Some(step) = engine.tick(now) {
                commit(&engine, &step, o, &mut sinks, &mut status)?;
            }
        }
    }
    summary.samples = engine.state.samples;
    status.note(&format!("end of the source: {} samples accepted, {} refused", summary.samples, summary.refused));
    Ok(summary)
}

/// After a step: the state first (what a restart continues from), then the controller and logs.
fn commit(engine: &Engine, step: &Step, o: &Options, sinks: &mut [Box<dyn Sink>], status: &mut Status) -> Result<(), LiveError> {
    engine.state.save(&o.state, !o.no_sync)?;
    deliver(step, sinks, status, engine.state.samples);
    Ok(())
}

/// A message on the status line and in every log.
fn broadcast(message: &str, sinks: &mut [Box<dyn Sink>], status: &mut Status) {
    status.note(message);
    sinks.iter_mut().for_each(|s| s.note(message));
}

/// Writes a step to every sink; a failing sink is reported and the others still written.
fn deliver(step: &Step, sinks: &mut [Box<dyn Sink>], status: &mut Status, samples: u64) {
    for sink in sinks.iter_mut() {
        if let Err(e) = sink.write(step) {
            status.note(&format!("warning: {e}"));
        }
    }
    status.step(step, samples);
}

fn open_log(path: &Path, engine: &Engine) -> Result<Box<dyn Sink>, LiveError> {
    match path.extension().and_then(|e| e.to_str()) {
        Some("csv") => Ok(Box::new(CsvLog::open(path, engine)?)),
        Some("jsonl") => Ok(Box::new(JsonLog::open(path, engine)?)),
        _ => {
            Err(input(format!("--log {}: a log is FILE.csv (a campaign thermal predict reads) or FILE.jsonl (JSON lines)", path.display())))
        }
    }
}

type Opened = (Box<dyn Source>, Vec<Box<dyn Sink>>);

/// The source and the controller sinks.
fn open(o: &Options, engine: &Engine, mapping: &Mapping, period: Duration, resume: Option<&EngineState>) -> Result<Opened, LiveError> {
    let spec = source_spec(&o.source)?;
    let mut sinks: Vec<Box<dyn Sink>> = Vec::new();
    let mut source: Option<Box<dyn Source>> = match &spec {
        SourceSpec::Csv(path) => Some(Box::new(CsvReplay::open(path, &engine.inputs, mapping, o.speed, resume)?)),
        SourceSpec::Hal => Some(Box::new(HalSource::open(&engine.inputs, mapping, period)?)),
        SourceSpec::OpcUa(_) => None,
    };
    let source_url = match &spec {
        SourceSpec::OpcUa(url) => Some(url.clone()),
        _ => None,
    };
    let mut opcua_sink_url = None;
    for sink in &o.sinks {
        match sink.split_once(':') {
            None if sink == "hal" => sinks.push(Box::new(HalSink::open(&engine.offsets.letters, mapping)?)),
            None if sink == "opcua" => {
                opcua_sink_url = Some(
                    source_url
                        .clone()
                        .ok_or_else(|| input("--sink opcua without an OPC UA source: name the server, --sink opcua:opc.tcp://HOST:PORT"))?,
                )
            }
            Some(("opcua", url)) if url.starts_with("opc.tcp://") => opcua_sink_url = Some(url.to_string()),
            _ => return Err(input(format!("--sink `{sink}`: use opcua, opcua:opc.tcp://HOST:PORT or hal"))),
        }
    }
    if source_url.is_some() || opcua_sink_url.is_some() {
        opcua_open(o, engine, mapping, period, source_url, opcua_sink_url, &mut source, &mut sinks)?;
    }
    Ok((source.expect("every source kind is opened"), sinks))
}

#[cfg(feature = "opcua")]
#[allow(clippy::too_many_arguments)]
fn opcua_open(
    o: &Options,
    engine: &Engine,
    mapping: &Mapping,
    period: Duration,
    source_url: Option<String>,
    sink_url: Option<String>,
    source: &mut Option<Box<dyn Source>>,
    sinks: &mut Vec<Box<dyn Sink>>,
) -> Result<(), LiveError> {
    use crate::mapping::AddressKind;
    use crate::opcua::{connect, Nodes};
    let give_up = o.give_up_after_s.is_finite().then(|| Duration::from_secs_f64(o.give_up_after_s));
    let outputs = || -> Result<Vec<(usize, String, f64)>, LiveError> {
        let mut out = Vec::new();
        for (k, l) in engine.offsets.letters.iter().enumerate() {
            if let Some(o) = mapping.output.get(&l.to_string()) {
                if let Some(node) = &o.node {
                    out.push((k, node.clone(), if o.unit == "um" { 1.0 } else { 1e-3 }));
                }
            }
        }
        if out.is_empty() {
            return Err(input(format!(
                "{}: the OPC UA sink needs a node per axis, e.g. [output.Z] node = \"ns=2;s=ThermalOffsetZ\"",
                mapping.origin
            )));
        }
        Ok(out)
    };
    if let Some(url) = &source_url {
        let names = mapping.addresses(&engine.inputs, AddressKind::Node)?;
        let nodes = Nodes {
            inputs: engine.inputs.iter().cloned().zip(names).collect(),
            run: mapping.run_address(AddressKind::Node),
            outputs: if sink_url.as_ref() == Some(url) { outputs()? } else { Vec::new() },
        };
        let (src, sink) = connect(url, nodes, period, give_up)?;
        *source = Some(Box::new(src));
        if sink_url.as_ref() == Some(url) {
            sinks.push(Box::new(sink));
        }
    }
    if let Some(url) = sink_url.filter(|u| Some(u) != source_url.as_ref()) {
        let (source, sink) = connect(&url, Nodes { outputs: outputs()?, ..Nodes::default() }, period, give_up)?;
        sinks.push(Box::new(sink.reporting(source)));
    }
    Ok(())
}

#[cfg(not(feature = "opcua"))]
#[allow(clippy::too_many_arguments)]
fn opcua_open(
    _o: &Options,
    _engine: &Engine,
    _mapping: &Mapping,
    _period: Duration,
    _source_url: Option<String>,
    _sink_url: Option<String>,
    _source: &mut Option<Box<dyn Source>>,
    _sinks: &mut Vec<Box<dyn Sink>>,
) -> Result<(), LiveError> {
    Err(input("this trueaxis was built without OPC UA (cargo feature `opcua` of trueaxis-live)"))
}
