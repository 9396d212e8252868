//! The load of one machine's live compensation (BENCHMARKS.md, docs/live.md): model updates per
//! second on one core with the shipped drift model (examples/live/dz_drift.toml) on vmc3, the
//! samples of examples/thermal/campaign.csv replayed back to back as one long run, for
//!
//! - the update step alone (screening, the model step, offsets, the limit),
//! - plus the state file written each step without fsync (whole after a crash of the process),
//! - plus the state file with fsync (whole after a power loss: what `trueaxis live` does),
//! - plus a line of the CSV log.
//!
//! and the peak resident memory of this process (VmHWM). Run:
//! `cargo run --release -p trueaxis-live --example live_cost [UPDATES]`.

use std::path::PathBuf;
use std::time::{Duration, Instant};
use trueaxis::machine::Machine;
use trueaxis::thermal::campaign_predict::read_model_file;
use trueaxis_live::engine::{Engine, Sample, Step};
use trueaxis_live::log::CsvLog;
use trueaxis_live::mapping::Mapping;
use trueaxis_live::source::{CsvReplay, Event, Sink, Source};

fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// The campaign's readings (964 rows).
fn rows() -> Vec<Vec<f64>> {
    let inputs = vec!["T:p1".to_string(), "T:p5".to_string()];
    let path = root().join("examples/thermal/campaign.csv");
    let mut src = CsvReplay::open(&path, &inputs, &Mapping::default(), f64::INFINITY, None).expect("the shipped campaign");
    let mut rows = Vec::new();
    while let Ok(Some(Event::Sample(s))) = src.next(Duration::ZERO) {
        rows.push(s.readings);
    }
    rows
}

/// Sample k of one long run of the campaign's readings, each 120 s after the one before.
fn sample(rows: &[Vec<f64>], k: usize) -> Sample {
    Sample { time_s: 120.0 * k as f64, run: None, readings: rows[k % rows.len()].clone() }
}

fn engine() -> Engine {
    let machine = Machine::load(root().join("examples/machines/vmc3.toml")).expect("vmc3");
    let model = read_model_file(&root().join("examples/live/dz_drift.toml")).expect("the shipped model");
    // a wide rate limit: the replayed rows jump at the seams of the runs
    let mapping = Mapping::parse("[input.\"T:p1\"]\nrate_limit = 1\n[input.\"T:p5\"]\nrate_limit = 1\n", "bench").expect("mapping");
    Engine::new(&machine, vec![model], &mapping, 600.0, 600.0).expect("engine")
}

/// CPU time of this process (user + system, s), from /proc/self/stat (clock ticks of 10 ms).
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat.rsplit(')').next().unwrap_or("").split_whitespace().collect();
    let ticks = |k: usize| fields.get(k).and_then(|v| v.parse::<f64>().ok()).unwrap_or(0.0);
    // fields after the command name: state is 0, utime 11, stime 12
    (ticks(11) + ticks(12)) / 100.0
}

/// Wall and CPU time per update (one thread) of `n` samples through `each`.
fn measure(name: &str, n: usize, mut each: impl FnMut(&mut Engine, &Step)) {
    let rows = rows();
    let mut e = engine();
    let (start, cpu0) = (Instant::now(), cpu_s());
    for k in 0..n {
        let step = e.update(&sample(&rows, k)).expect("a new sample");
        assert!(step.write, "{:?}", step.message);
        each(&mut e, &step);
    }
    let per = start.elapsed().as_secs_f64() / n as f64;
    let cpu = (cpu_s() - cpu0) / n as f64;
    println!(
        "{name:<44} {n:>8} updates  wall {:>9.2} us/update ({:>8.0} updates/s)  CPU {:>9.2} us/update ({:>8.0} updates/s)",
        per * 1e6,
        1.0 / per,
        cpu * 1e6,
        1.0 / cpu
    );
}

fn peak_rss_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

fn main() {
    let n: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(200_000);
    let dir = tempfile::tempdir().expect("a temporary directory");
    let state = dir.path().join("state.json");
    measure("update step", n, |_, _| {});
    measure("update + state file (no fsync)", n / 10, |e, _| e.state.save(&state, false).expect("state"));
    measure("update + state file (fsync)", (n / 200).max(100), |e, _| e.state.save(&state, true).expect("state"));
    let log_path = dir.path().join("live.csv");
    let mut log = CsvLog::open(&log_path, &engine()).expect("log");
    measure("update + state (no fsync) + CSV log line", n / 10, |e, step| {
        e.state.save(&state, false).expect("state");
        log.write(step).expect("log");
    });
    println!("peak resident memory of this process: {} KiB", peak_rss_kib().map_or("?".into(), |k| k.to_string()));
}
