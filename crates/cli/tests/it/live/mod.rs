//! `trueaxis live` end to end, against real consumers: an OPC UA server of asyncua (PyPI) that plays
//! the shipped campaign (examples/thermal/campaign.csv) into its nodes and records the offsets
//! written back (tests/live/opcua_server.py), and LinuxCNC 2.9 (halcompile, halrun, halcmd) with
//! the HAL component of `compensate --format linuxcnc-hal` driving motion's external offsets.
//! Checked: the offsets equal `trueaxis thermal predict` on the same samples to its printed
//! precision over the whole campaign; a server outage is held, ramped and resumed, and logged; a
//! server restarted twice, each time down for longer than the hold and the ramp: zero offsets,
//! reconnected, zero written first, then the predictions again; a server that never comes back:
//! attempts logged without a flood, SIGTERM ends the process at once, `--give-up-after` ends it with
//! exit 3; a 200 degC jump is refused and logged; `kill -9` and a restart continue from a whole
//! state file; a node id that does not exist ends with exit status 2 naming it.
//!
//! The server plays the campaign faster than real time (`--speed`), and trueaxis live times its
//! holds and ramps on the source's clock at the same speed: the outage test stops the server for
//! 3 s of wall time, which is 30 min of machine time at 600 times real time.

use crate::support::{alone, arg, root, trueaxis, Alone, Run};
use serde_json::Value;
use std::net::TcpListener;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn example(path: &str) -> String {
    root().join(path).display().to_string()
}

#[path = "../../../../trueaxis/tests/it/support/tools.rs"]
mod tools;

use tools::required;

/// Whether asyncua is importable; without it the OPC UA tests are skipped unless required.
fn asyncua() -> bool {
    let ok = Command::new("python3").args(["-c", "import asyncua"]).output().is_ok_and(|o| o.status.success());
    if !ok {
        assert!(!required("TRUEAXIS_REQUIRE_ASYNCUA"), "asyncua (pip install asyncua) is required but not importable");
        eprintln!("SKIPPED: python3 -c 'import asyncua' failed (pip install asyncua)");
    }
    ok
}

/// One real-time test at a time, with no other test's run beside it: each plays a campaign in
/// real time against a running `trueaxis live`, and two at once on a 2-core machine starve each
/// other of the periods they time (a test that failed while holding it does not fail the others).
fn real_time() -> Alone {
    alone()
}

/// What an OPC UA test holds for its whole length: the machine to itself, a free port and the URL
/// of its test server there.
struct Opcua {
    _real_time: Alone,
    port: u16,
    url: String,
}

/// An OPC UA test's setup, or `None` (the test skipped) without asyncua.
fn opcua() -> Option<Opcua> {
    if !asyncua() {
        return None;
    }
    let _real_time = real_time();
    let port = free_port();
    Some(Opcua { _real_time, port, url: format!("opc.tcp://127.0.0.1:{port}/trueaxis/") })
}

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

/// Starts the test server and waits until it listens.
fn server(port: u16, args: &[&str]) -> Child {
    let script = root().join("crates/cli/tests/it/live/opcua_server.py");
    let child = Command::new("python3")
        .arg(script)
        .args(["--port", &port.to_string(), "--campaign", &example("examples/thermal/campaign.csv")])
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(start.elapsed() < Duration::from_secs(30), "the asyncua server did not start");
        std::thread::sleep(Duration::from_millis(100));
    }
    child
}

/// The stderr of each `trueaxis live` started, drained as it comes: a pipe left full (64 KiB of
/// messages on a loaded machine) would block the process on its next message.
static DRAINS: std::sync::Mutex<Vec<(u32, std::thread::JoinHandle<String>)>> = std::sync::Mutex::new(Vec::new());

fn live<S: AsRef<str>>(args: &[S]) -> Child {
    let mut child = Run::new(live_args(args)).command().stdout(Stdio::null()).stderr(Stdio::piped()).spawn().unwrap();
    let mut pipe = child.stderr.take().unwrap();
    let drain = std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = std::io::Read::read_to_end(&mut pipe, &mut bytes);
        String::from_utf8_lossy(&bytes).into_owned()
    });
    DRAINS.lock().unwrap_or_else(|e| e.into_inner()).push((child.id(), drain));
    child
}

/// `live ARGS`.
fn live_args<S: AsRef<str>>(args: &[S]) -> Vec<&str> {
    ["live"].into_iter().chain(args.iter().map(AsRef::as_ref)).collect()
}

/// `--machine examples/machines/vmc3.toml --thermal-model MODEL REST...`: how every `trueaxis live`
/// here begins.
fn on_vmc3(model: &str, rest: &[&str]) -> Vec<String> {
    let head = ["--machine".to_string(), example("examples/machines/vmc3.toml"), "--thermal-model".into(), model.into()];
    head.into_iter().chain(rest.iter().map(|a| a.to_string())).collect()
}

/// What the `trueaxis live` of `pid` wrote on stderr, once it has ended.
fn stderr_of(pid: u32) -> String {
    let mut drains = DRAINS.lock().unwrap_or_else(|e| e.into_inner());
    match drains.iter().position(|(p, _)| *p == pid) {
        Some(i) => drains.remove(i).1.join().unwrap_or_default(),
        None => String::new(),
    }
}

/// The server's JSON report once it has played its rows.
/// The longest a test server may run (s): the longest campaign plays in under a minute.
const SERVER_LIMIT_S: u64 = 240;

fn report(server: Child) -> Value {
    // bounded: a server that hangs fails this test instead of holding the whole run
    let pid = server.id();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || tx.send(server.wait_with_output()));
    let out = match rx.recv_timeout(std::time::Duration::from_secs(SERVER_LIMIT_S)) {
        Ok(out) => out.unwrap(),
        Err(_) => {
            Command::new("kill").arg("-9").arg(pid.to_string()).status().ok();
            panic!("the OPC UA test server did not finish within {SERVER_LIMIT_S} s");
        }
    };
    assert!(out.status.success(), "server: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// CPU time (s, user + system) and peak resident memory (KiB) of a running process.
fn load(pid: u32) -> (f64, u64) {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
    let fields: Vec<&str> = stat.rsplit(')').next().unwrap_or("").split_whitespace().collect();
    let ticks = |k: usize| fields.get(k).and_then(|v| v.parse::<f64>().ok()).unwrap_or(0.0);
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    let peak = status.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| l.split_whitespace().nth(1)?.parse().ok()).unwrap_or(0);
    ((ticks(11) + ticks(12)) / 100.0, peak)
}

fn stop(mut child: Child) -> String {
    child.kill().ok();
    child.wait().unwrap();
    stderr_of(child.id())
}

/// `thermal predict --json` of a model on a campaign: (run, t, predicted um).
fn predict(model: &str, data: &Path) -> Vec<(String, f64, f64)> {
    let out = trueaxis(&["thermal", "predict", "--model", model, "--data", &data.display().to_string(), "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    doc["samples"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| (s["run"].as_str().unwrap().to_string(), s["t"].as_f64().unwrap(), s["predicted"].as_f64().unwrap()))
        .collect()
}

/// Offsets recorded for axis `a`: (unix s, mm).
fn recorded(doc: &Value, by: &str, a: &str) -> Vec<(f64, f64)> {
    doc[by][a].as_array().unwrap().iter().map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap())).collect()
}

/// The rows of a live CSV log: (run, t, dz_predicted um, offset_Z um).
fn log_rows(path: &Path) -> Vec<(String, f64, f64, f64)> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let (p, z) = (col("dz_predicted"), col("offset_Z"));
    lines
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (c[0].to_string(), c[1].parse().unwrap(), c[p].parse().unwrap(), c[z].parse().unwrap())
        })
        .collect()
}

#[test]
fn opcua_offsets_equal_thermal_predict_over_the_whole_campaign() {
    let Some(opcua) = opcua() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (port, url) = (opcua.port, &opcua.url);
    // 3000 times real time: a row every 40 ms, two periods of trueaxis live (20 ms) per row, so
    // that a loaded machine (CI on 2 cores) still delivers every row before the next is due
    let srv = server(port, &["--speed", "3000", "--client"]);
    let (log, state) = (dir.path().join("live.csv"), dir.path().join("state.json"));
    let model = example("examples/live/dz_drift.toml");
    let proc = live_opcua(dir.path(), url, "3000", &["--hold", "86400"], &[]);
    let doc = report(srv);
    let (cpu_s, peak_kib) = load(proc.id());
    let stderr = stop(proc);
    // the load of one machine's process (docs/live.md §6): printed with --nocapture
    eprintln!("MEASURED trueaxis live (OPC UA, 964 samples): CPU {cpu_s:.2} s in all, peak resident {peak_kib} KiB");
    assert!(peak_kib > 0 && peak_kib < 200_000, "{peak_kib} KiB");
    let expected = predict(&model, &root().join("examples/thermal/campaign.csv"));
    let rows = doc["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 964);
    for by in ["server", "client"] {
        let z = recorded(&doc, by, "Z");
        let x = recorded(&doc, by, "X");
        let mut matched = 0;
        for (row, (run, t, p)) in rows.iter().zip(&expected) {
            assert_eq!(row[0].as_str().unwrap(), run);
            let ts = row[1].as_f64().unwrap();
            let at: Vec<f64> = z.iter().filter(|(s, _)| *s == ts).map(|(_, v)| *v).collect();
            if at.is_empty() {
                // what trueaxis live did around that sample
                let near: Vec<String> = std::fs::read_to_string(dir.path().join("live.jsonl"))
                    .unwrap()
                    .lines()
                    .filter(|l| {
                        serde_json::from_str::<Value>(l).is_ok_and(|e| e["time_s"].as_f64().is_some_and(|s| (s - ts).abs() <= 360.0))
                    })
                    .map(str::to_string)
                    .collect();
                panic!("{by}: no offset written for {run} t = {t} s; the live log around it:\n{}\n{stderr}", near.join("\n"));
            }
            for v in at {
                // the written offset (mm) is -dz; thermal predict prints um to 1e-4
                assert!((v * 1e3 + p).abs() <= 0.5e-4, "{by}: {run} t = {t}: offset {v} mm, predicted {p} um");
            }
            matched += 1;
        }
        assert_eq!(matched, 964, "{by}");
        assert!(x.iter().all(|(_, v)| *v == 0.0), "{by}: X moves no drift of dz");
    }
    // the log is a campaign: thermal predict on it gives its own predictions (and the campaign's)
    let logged = log_rows(&log);
    assert_eq!(logged.len(), 964);
    for ((lg, (run, t, p)), again) in logged.iter().zip(&expected).zip(predict(&model, &log)) {
        assert_eq!((&lg.0, lg.1), (run, *t));
        assert!((lg.2 - p).abs() <= 0.5e-4 && (again.2 - p).abs() <= 1e-9 && lg.3 == -lg.2, "{lg:?} {p} {again:?}");
    }
    // the state file is whole and counts every sample
    let saved: Value = serde_json::from_str(&std::fs::read_to_string(&state).unwrap()).unwrap();
    assert_eq!(saved["samples"], 964);
}

/// The phases and messages of a JSON-lines log.
fn events(path: &Path) -> Vec<Value> {
    std::fs::read_to_string(path).unwrap().lines().map(|l| serde_json::from_str(l).unwrap()).collect()
}

/// The messages of a JSON-lines log, in order.
fn messages(events: &[Value]) -> Vec<String> {
    events.iter().filter_map(|e| e["message"].as_str().map(str::to_string)).collect()
}

/// The index of the first message at or after `from` that contains `what`.
fn find(messages: &[String], what: &str, from: usize, stderr: &str) -> usize {
    from + messages[from..]
        .iter()
        .position(|m| m.contains(what))
        .unwrap_or_else(|| panic!("no `{what}` after {from} in {messages:#?}\n{stderr}"))
}

/// `trueaxis live` of examples/live/dz_drift.toml on the test server at `url` (the mapping
/// examples/live/vmc3_opcua.toml, a period of 20 ms) at `speed` times real time, with `timing`
/// (`--hold`, `--ramp`) and `more`; its state and logs (live.csv, live.jsonl) in `dir`.
fn live_opcua(dir: &Path, url: &str, speed: &str, timing: &[&str], more: &[&str]) -> Child {
    let (state, csv, jsonl) = (dir.join("state.json"), dir.join("live.csv"), dir.join("live.jsonl"));
    let (map, source) = (example("examples/live/vmc3_opcua.toml"), format!("opcua:{url}"));
    let head = ["--map", &map, "--source", &source, "--sink", "opcua", "--period", "0.02", "--speed", speed];
    let files = ["--state", arg(&state), "--log", arg(&csv), "--log", arg(&jsonl)];
    live(&on_vmc3(&example("examples/live/dz_drift.toml"), &[&head[..], timing, &files, more].concat()))
}

/// `trueaxis live` on the test server at 600 times real time, hold 300 s, ramp 600 s (1.5 s of
/// wall time together), logs in `dir`.
fn live_600(dir: &Path, url: &str, more: &[&str]) -> Child {
    live_opcua(dir, url, "600", &["--hold", "300", "--ramp", "600"], more)
}

#[test]
fn opcua_faults_outage_held_ramped_resumed_and_a_200_degc_jump_refused() {
    let Some(opcua) = opcua() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (port, url) = (opcua.port, &opcua.url);
    // 120 s rows at 600 times real time: a row every 0.2 s; the outage: 3 s = 1800 s of machine time
    let srv = server(port, &["--speed", "600", "--rows", "100", "--jump-row", "12", "--outage-after", "25", "--outage-s", "3"]);
    let (csv, jsonl) = (dir.path().join("live.csv"), dir.path().join("live.jsonl"));
    let model = example("examples/live/dz_drift.toml");
    let proc = live_600(dir.path(), url, &[]);
    let doc = report(srv);
    let stderr = stop(proc);
    let ev = events(&jsonl);
    let messages = messages(&ev);
    // the 200 degC jump (to 228.6 degC) is beyond the sensor's range [0, 80] of the mapping
    let jump = find(&messages, "refused: T:p1: 228.596 is outside the physical range [0, 80]", 0, &stderr);
    // after the jump: the outage is held, ramped, zero, then resumed, the connection lost before zero
    let ramp = find(&messages, "ramp to zero over 600 s", jump, &stderr);
    let held = messages[..ramp].iter().rposition(|m| m.contains("the offsets are held")).expect("held before the ramp");
    let zero = find(&messages, "the offsets are zero", ramp, &stderr);
    let resumed = find(&messages, "resumed after", zero, &stderr);
    let lost = find(&messages, "OPC UA connection lost", jump, &stderr);
    let reconnected = find(&messages, "OPC UA reconnected", lost, &stderr);
    assert!(held > jump && lost < zero && reconnected < resumed, "{messages:#?}");
    // the ramp is linear from the held offset to zero, on the source's clock
    let steps: Vec<&Value> = ev.iter().filter(|e| e["phase"].is_string()).collect();
    // the ramp of the outage: the ramping steps after the first one, until the phase changes
    let first_ramp = steps.iter().position(|e| e["phase"] == "ramping").unwrap();
    let ramps: Vec<(f64, f64)> = steps[first_ramp..]
        .iter()
        .take_while(|e| e["phase"] == "ramping")
        .map(|e| (e["time_s"].as_f64().unwrap(), e["offsets_um"]["Z"].as_f64().unwrap()))
        .collect();
    assert!(ramps.len() >= 3, "{ramps:?}");
    let before_gap = steps[..first_ramp].iter().rev().find(|e| e["drift_um"].is_object()).unwrap();
    let (t0, q) = (before_gap["time_s"].as_f64().unwrap(), before_gap["offsets_um"]["Z"].as_f64().unwrap());
    for (t, v) in &ramps {
        let expected = q * (1.0 - (t - t0 - 300.0) / 600.0);
        assert!((v - expected).abs() <= 1e-9 * q.abs().max(1.0), "ramp at {t}: {v} vs {expected}");
    }
    // after the outage the written offsets are the model's again: thermal predict on the log
    let logged = log_rows(&csv);
    let again = predict(&model, &csv);
    for (lg, p) in logged.iter().zip(&again) {
        assert!((lg.2 - p.2).abs() <= 0.5e-4 && lg.3 == -lg.2, "{lg:?} {p:?}");
    }
    let z = recorded(&doc, "server", "Z");
    let base = doc["base"].as_f64().unwrap();
    let resumed_rows: Vec<&(String, f64, f64, f64)> = logged.iter().filter(|r| r.1 > 26.0 * 120.0).collect();
    assert!(resumed_rows.len() > 10, "{logged:?}");
    // the first run starts at the server's base time
    for r in resumed_rows {
        let written = z.iter().find(|(s, _)| (*s - (base + r.1)).abs() < 1e-6).unwrap_or_else(|| panic!("no write at t = {}", r.1));
        assert!((written.1 * 1e3 - r.3).abs() <= 1e-6, "{r:?} {written:?}");
    }
    // the jump row is not in the log: only accepted samples are
    assert!(logged.iter().all(|r| r.1 != 12.0 * 120.0));
}

/// The rows the server played: (run, t s since its base time, T:p1, T:p5 as written).
fn played(doc: &Value) -> Vec<(String, f64, f64, f64)> {
    let base = doc["base"].as_f64().unwrap();
    let f = |r: &Value, k: usize| r[k].as_f64().unwrap();
    doc["rows"].as_array().unwrap().iter().map(|r| (r[0].as_str().unwrap().to_string(), f(r, 1) - base, f(r, 2), f(r, 3))).collect()
}

#[test]
fn opcua_server_restarted_twice_each_time_down_longer_than_the_hold_and_the_ramp() {
    let Some(opcua) = opcua() else { return };
    let dir = tempfile::tempdir().unwrap();
    let (port, url) = (opcua.port, &opcua.url);
    // a row every 0.2 s of wall time (120 s at 600 times real time); the outages, 3 s and 4 s of
    // wall time (1800 s and 2400 s of machine time), are longer than the hold and the ramp (900 s)
    let outages = ["--outage-after", "25", "--outage-s", "3", "--outage-after", "60", "--outage-s", "4"];
    let srv = server(port, &[&["--speed", "600", "--rows", "110"][..], &outages].concat());
    let proc = live_600(dir.path(), url, &[]);
    let doc = report(srv);
    let stderr = stop(proc);
    let ev = events(&dir.path().join("live.jsonl"));
    let messages = messages(&ev);
    // each outage: held, ramped, zero, the connection lost before zero, reconnected, then resumed
    let mut from = 0;
    for _ in 0..2 {
        let held = find(&messages, "the offsets are held", from, &stderr);
        let zero = find(&messages, "the offsets are zero", find(&messages, "ramp to zero over 600 s", held, &stderr), &stderr);
        let lost = find(&messages, "OPC UA connection lost", from, &stderr);
        let reconnected = find(&messages, "OPC UA reconnected", zero, &stderr);
        from = find(&messages, "resumed after", reconnected, &stderr) + 1;
        assert!(lost < zero, "{messages:#?}");
    }
    // (the server's stop at the end of its rows is a third loss)
    for what in ["OPC UA connection lost", "OPC UA reconnected"] {
        assert_eq!(messages[..from].iter().filter(|m| m.contains(what)).count(), 2, "{what}: {messages:#?}\n{stderr}");
    }
    // the step before each resume after the outages (a gap longer than the hold and the ramp,
    // 900 s; a loaded machine may add short gaps): zero offsets
    let steps: Vec<&Value> = ev.iter().filter(|e| e["phase"].is_string()).collect();
    let gap = |e: &Value| e["message"].as_str().and_then(|m| m.strip_prefix("resumed after ")?.split(' ').next()?.parse::<f64>().ok());
    let resumes: Vec<usize> = (1..steps.len()).filter(|&i| gap(steps[i]).is_some_and(|g| g > 900.0)).collect();
    assert_eq!(resumes.len(), 2, "{messages:#?}");
    for i in resumes {
        assert_eq!(steps[i - 1]["phase"], "zero", "{}", steps[i - 1]);
        assert!(["X", "Y", "Z"].iter().all(|a| steps[i - 1]["offsets_um"][a] == 0.0), "{}", steps[i - 1]);
    }
    // what the server recorded: after each restart the engine's present offsets (zero) first ...
    let base = doc["base"].as_f64().unwrap();
    let z = recorded(&doc, "server", "Z");
    let rows = played(&doc);
    let restarts: Vec<f64> = doc["restarts"].as_array().unwrap().iter().map(|r| r.as_f64().unwrap() - base).collect();
    assert_eq!(restarts.len(), 2);
    for r in &restarts {
        let last_before = rows.iter().filter(|row| row.1 < *r).map(|row| row.1).fold(f64::MIN, f64::max);
        let during: Vec<&(f64, f64)> = z.iter().filter(|(s, _)| *s - base > last_before + 1e-6 && *s - base < r - 1e-6).collect();
        assert!(during.last().is_some_and(|(_, v)| *v == 0.0), "restart at {r} s: written between {last_before} s and it: {during:?}");
        assert!(rows.iter().filter(|row| row.1 >= *r).count() >= 10, "{rows:?}");
    }
    // ... then for every row the server played, before and after the restarts, the offset of
    // thermal predict on those rows (the lags run on over each outage with the last readings held)
    let data = dir.path().join("played.csv");
    let text: String = rows.iter().map(|(run, t, p1, p5)| format!("{run},{t},{p1},{p5}\n")).collect();
    std::fs::write(&data, format!("run,t,T:p1,T:p5\n{text}")).unwrap();
    let expected = predict(&example("examples/live/dz_drift.toml"), &data);
    assert_eq!(expected.len(), rows.len());
    for ((_, t, _, _), (_, tp, p)) in rows.iter().zip(&expected) {
        assert_eq!(t, tp);
        let at: Vec<f64> = z.iter().filter(|(s, _)| (*s - base - t).abs() < 1e-6).map(|(_, v)| *v).collect();
        assert!(!at.is_empty(), "no offset written for t = {t} s (restarts at {restarts:?})\n{messages:#?}");
        for v in at {
            assert!((v * 1e3 + p).abs() <= 0.5e-4, "t = {t} s: offset {v} mm, predicted {p} um");
        }
    }
}

/// Waits at most `limit` for a `trueaxis live` to end: its status, stderr and how long it took.
fn ended_within(mut child: Child, limit: Duration) -> (Option<i32>, String, Duration) {
    let (pid, start) = (child.id(), Instant::now());
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || tx.send(child.wait()));
    match rx.recv_timeout(limit) {
        Ok(status) => {
            let took = start.elapsed();
            (status.unwrap().code(), stderr_of(pid), took)
        }
        Err(_) => {
            Command::new("kill").arg("-9").arg(pid.to_string()).status().ok();
            panic!("the process did not end within {limit:?}");
        }
    }
}

#[test]
fn opcua_server_that_never_comes_back_zero_offsets_attempts_logged_sigterm_and_give_up() {
    let Some(opcua) = opcua() else { return };
    let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let (port, url) = (opcua.port, &opcua.url);
    let srv = server(port, &["--speed", "600", "--rows", "15", "--end-wait", "0"]);
    let keeps_trying = live_600(a.path(), url, &[]);
    let gives_up = live_600(b.path(), url, &["--give-up-after", "3"]);
    report(srv);
    // the server is gone for good: the offsets go to zero, the attempts go on (0.5, 1.5, 3.5 s after the loss)
    let jsonl = a.path().join("live.jsonl");
    let start = Instant::now();
    let messages = loop {
        // the lines written so far (a line being written is left for the next look)
        let text = std::fs::read_to_string(&jsonl).unwrap_or_default();
        let m = messages(&text.lines().filter_map(|l| serde_json::from_str(l).ok()).collect::<Vec<Value>>());
        if m.iter().any(|m| m.contains("the offsets are zero")) && m.iter().any(|m| m.contains("reconnection attempt 3 failed")) {
            break m;
        }
        assert!(start.elapsed() < Duration::from_secs(60), "{m:#?}");
        std::thread::sleep(Duration::from_millis(200));
    };
    // --give-up-after 3: exit 3 at the first failed attempt 3 s after the loss, saying why
    let (code, stderr, _) = ended_within(gives_up, Duration::from_secs(60));
    assert_eq!(code, Some(3), "{stderr}");
    assert!(stderr.contains("(--give-up-after): ") && stderr.contains("cannot be reached"), "{stderr}");
    // SIGTERM ends the process that keeps trying, with status 0, within 2 s
    let mut keeps_trying = keeps_trying;
    assert!(keeps_trying.try_wait().unwrap().is_none(), "trueaxis live ended while the server was away");
    assert!(Command::new("kill").args(["-TERM", &keeps_trying.id().to_string()]).status().unwrap().success());
    let (code, stderr, took) = ended_within(keeps_trying, Duration::from_secs(30));
    assert_eq!(code, Some(0), "{stderr}");
    assert!(took <= Duration::from_secs(2), "SIGTERM took {took:?}");
    assert!(stderr.contains("stopped by SIGTERM"), "{stderr}");
    // one line per attempt while the wait grows, numbered from 1, and the offsets left at zero
    let attempts: Vec<&String> = messages.iter().filter(|m| m.contains("reconnection attempt")).collect();
    for (k, m) in attempts.iter().enumerate() {
        assert!(m.contains(&format!("attempt {} failed", k + 1)), "{attempts:#?}");
    }
    assert!((3..=4).contains(&attempts.len()), "{attempts:#?}");
    let last = events(&jsonl).into_iter().rfind(|e| e["phase"].is_string()).unwrap();
    assert_eq!(last["phase"], "zero", "{last}");
    assert!(["X", "Y", "Z"].iter().all(|k| last["offsets_um"][k] == 0.0), "{last}");
}

#[test]
fn kill_9_and_restart_continue_from_the_state_file() {
    // killed after a time: the samples taken by then depend on having the machine
    let _real_time = real_time();
    let dir = tempfile::tempdir().unwrap();
    let (state, log) = (dir.path().join("state.json"), dir.path().join("live.csv"));
    let model = example("examples/live/dz_drift.toml");
    let source = format!("csv:{}", example("examples/thermal/campaign.csv"));
    let args = on_vmc3(&model, &["--source", &source, "--speed", "24000", "--state", arg(&state), "--log", arg(&log)]);
    let mut first = live(&args);
    std::thread::sleep(Duration::from_millis(1500));
    first.kill().unwrap(); // SIGKILL
    first.wait().unwrap();
    let saved: Value = serde_json::from_str(&std::fs::read_to_string(&state).unwrap()).expect("the state file is whole JSON");
    let taken = saved["samples"].as_u64().unwrap();
    assert!(taken > 10 && taken < 964, "killed after {taken} samples: choose another --speed");
    let out = trueaxis(&live_args(&args));
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains(&format!("continuing from {} ({taken} samples", state.display())));
    // the log holds every row once, and equals thermal predict on the whole campaign
    let logged = log_rows(&log);
    let expected = predict(&model, &root().join("examples/thermal/campaign.csv"));
    assert_eq!(logged.len(), expected.len());
    for (lg, (run, t, p)) in logged.iter().zip(&expected) {
        assert_eq!((&lg.0, lg.1), (run, *t));
        assert!((lg.2 - p).abs() <= 0.5e-4 && lg.3 == -lg.2, "{lg:?} {p}");
    }
}

#[test]
fn a_node_id_that_does_not_exist_is_refused_with_exit_2() {
    let Some(opcua) = opcua() else { return };
    let dir = tempfile::tempdir().unwrap();
    let port = opcua.port;
    let srv = server(port, &["--rows", "1", "--start-wait", "30", "--end-wait", "0"]);
    let map = dir.path().join("map.toml");
    let text = std::fs::read_to_string(root().join("examples/live/vmc3_opcua.toml")).unwrap().replace("vmc3.T_p5", "vmc3.T_missing");
    std::fs::write(&map, text).unwrap();
    let (model, state) = (example("examples/live/dz_drift.toml"), dir.path().join("state.json"));
    let source = format!("opcua:opc.tcp://127.0.0.1:{port}/trueaxis/");
    let out = trueaxis(&live_args(&on_vmc3(&model, &["--map", arg(&map), "--source", &source, "--sink", "opcua", "--state", arg(&state)])));
    stop(srv);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("node `ns=2;s=vmc3.T_missing` (input T:p5) does not exist on the server"), "{stderr}");
    assert!(!dir.path().join("state.json").exists());
    // a server that is not there: exit 3 (the environment)
    let (map, source) = (example("examples/live/vmc3_opcua.toml"), format!("opcua:opc.tcp://127.0.0.1:{}/", free_port()));
    let out = trueaxis(&live_args(&on_vmc3(&model, &["--map", &map, "--source", &source, "--state", arg(&state)])));
    assert_eq!(out.status.code(), Some(3), "{}", String::from_utf8_lossy(&out.stderr));
}

/// Runs halcmd with arguments; its trimmed stdout.
fn halcmd(args: &[&str]) -> String {
    let out = Command::new("halcmd").args(args).output().unwrap();
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

#[test]
fn linuxcnc_external_offsets_that_reach_motion_equal_the_predictions() {
    if !tools::linuxcnc_found() {
        return;
    }
    if !Path::new("/usr/lib/linuxcnc/modules").exists() {
        assert!(!required("TRUEAXIS_REQUIRE_HALCOMPILE"), "halcompile / halrun are required but not found");
        eprintln!("SKIPPED: halcompile / halrun (Debian linuxcnc-uspace-dev) not installed");
        return;
    }
    let _real_time = real_time();
    let dir = tempfile::tempdir().unwrap();
    tools::open_to_all(dir.path());
    // the HAL component of compensate for vmc3 without geometric errors: its output is the thermal offset
    let name = format!("ta_live_{}", std::process::id());
    let hal_name = name.replace('_', "-");
    std::fs::write(dir.path().join("no_errors.toml"), "[constant]\nEXX = 0\n").unwrap();
    let hal_dir = dir.path().join("hal");
    let out = trueaxis(&[
        "compensate",
        "--machine",
        &example("examples/machines/vmc3.toml"),
        "--errors",
        &dir.path().join("no_errors.toml").display().to_string(),
        "--format",
        "linuxcnc-hal",
        "--hal-component",
        &name,
        "--out",
        &hal_dir.display().to_string(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let Some(installed) = tools::halcompile_install(&hal_dir, &format!("{name}.comp")) else { return };
    // LinuxCNC's motion module, the component wired by its own HAL file, two sensor pins (sum2 inputs)
    let hal_file = std::fs::read_to_string(hal_dir.join(format!("{name}.hal"))).unwrap();
    // halrun runs until the test creates the stop file, then unloads what it loaded
    let stop_file = dir.path().join("stop");
    let wait = dir.path().join("wait.sh");
    std::fs::write(&wait, format!("for i in $(seq 1200); do [ -e {} ] && exit 0; sleep 0.1; done\n", stop_file.display())).unwrap();
    let script = format!(
        "loadrt trivkins coordinates=XYZ\nloadrt tpmod\nloadrt homemod\nloadrt motmod servo_period_nsec=1000000 num_joints=3\n\
         loadrt sum2 names=sensors\n{hal_file}start\nloadusr -w sh {}\n",
        wait.display()
    );
    std::fs::write(dir.path().join("machine.hal"), script).unwrap();
    let mut cmd = Command::new("halrun");
    cmd.arg("-f").arg(dir.path().join("machine.hal")).stdout(Stdio::null()).stderr(Stdio::null());
    let root_user = Command::new("id").arg("-u").output().is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0");
    if root_user {
        let nobody = Command::new("id").args(["-u", "nobody"]).output().unwrap();
        cmd.env("RTAPI_UID", String::from_utf8_lossy(&nobody.stdout).trim()).env("RTAPI_FIFO_PATH", dir.path().join("rtapi_fifo"));
    }
    let halrun = cmd.spawn().unwrap();
    let start = Instant::now();
    while halcmd(&["-s", "getp", &format!("{hal_name}.0.thermal-z")]).is_empty() {
        assert!(start.elapsed() < Duration::from_secs(30), "halrun did not load the component");
        std::thread::sleep(Duration::from_millis(200));
    }
    // the mapping: the sensor pins, a wide rate limit (the rows of 120 s come every 0.5 s here)
    let map = dir.path().join("map.toml");
    let mut text = String::new();
    for (s, pin) in [("T:p1", "sensors.in0"), ("T:p5", "sensors.in1")] {
        text += &format!("[input.\"{s}\"]\npin = \"{pin}\"\nrange = [0.0, 80.0]\nrate_limit = 100\n");
    }
    for a in ["x", "y", "z"] {
        text += &format!("[output.{}]\npin = \"{hal_name}.0.thermal-{a}\"\n", a.to_uppercase());
    }
    std::fs::write(&map, text).unwrap();
    let campaign = std::fs::read_to_string(root().join("examples/thermal/campaign.csv")).unwrap();
    let rows: Vec<Vec<&str>> = campaign.lines().filter(|l| l.starts_with("warmup,")).take(16).map(|l| l.split(',').collect()).collect();
    halcmd(&["setp", "sensors.in0", rows[0][2]]);
    halcmd(&["setp", "sensors.in1", rows[0][3]]);
    let model = example("examples/live/dz_regression.toml");
    let log = dir.path().join("live.csv");
    let state = dir.path().join("state.json");
    let hal = ["--map", arg(&map), "--source", "hal", "--sink", "hal", "--period", "0.05", "--state", arg(&state), "--log", arg(&log)];
    let proc = live(&on_vmc3(&model, &hal));
    // the predictions of thermal predict on the same readings
    let mut data = String::from("run,t,T:p1,T:p5\n");
    for r in &rows {
        data += &format!("warmup,{},{},{}\n", r[1], r[2], r[3]);
    }
    std::fs::write(dir.path().join("rows.csv"), data).unwrap();
    let expected = predict(&model, &dir.path().join("rows.csv"));
    let mut checked = 0;
    for (r, (_, _, p)) in rows.iter().zip(&expected) {
        halcmd(&["setp", "sensors.in0", r[2]]);
        halcmd(&["setp", "sensors.in1", r[3]]);
        std::thread::sleep(Duration::from_millis(500));
        // motion's external-offset input of Z, in counts of 1e-6 mm
        let counts: f64 = halcmd(&["-s", "getp", "axis.z.eoffset-counts"]).parse().unwrap();
        let want = (-p * 1e-3 / 1e-6).round();
        assert!(
            (counts - want).abs() <= 1.0,
            "T:p1 {} T:p5 {}: axis.z.eoffset-counts {counts}, predicted {p} um = {want} counts",
            r[2],
            r[3]
        );
        let x: f64 = halcmd(&["-s", "getp", "axis.x.eoffset-counts"]).parse().unwrap();
        assert_eq!(x, 0.0);
        checked += 1;
    }
    assert_eq!(checked, 16);
    let stderr = stop(proc);
    std::fs::write(&stop_file, "").unwrap();
    let mut halrun = halrun;
    let _ = halrun.wait();
    if let Some(so) = installed {
        std::fs::remove_file(so).ok();
    }
    // the log is a campaign whose predictions thermal predict reproduces
    for (lg, p) in log_rows(&log).iter().zip(predict(&model, &log)) {
        assert!((lg.2 - p.2).abs() <= 0.5e-4 && lg.3 == -lg.2, "{lg:?} {p:?}\n{stderr}");
    }
}
