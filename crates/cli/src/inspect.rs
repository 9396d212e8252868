//! `trueaxis inspect`: what trueaxis reads in a file.

use crate::output::{self, print};
use crate::Failure;
use serde_json::{json, Value};
use std::path::PathBuf;
use trueaxis::data::{CsvTable, Layout};
use trueaxis::evaluate::iso230_2::{plausibility, runs_of};
use trueaxis::instruments::ballbar::{ballbar_header, trace_of};
use trueaxis::io::{etalon, read_text, Finding, Format, Severity};

/// Show what trueaxis detects in an instrument file: its format, separator and decimal mark,
/// layout, columns with their units, runs and directions, metadata (machine, date, operator,
/// environment), the test parameters of a ballbar export, the findings of the plausibility checks,
/// and what each command would read from it.
#[derive(clap::Args)]
#[command(
    after_help = "Examples:\n  trueaxis inspect examples/data/laser_x.rtl\n  trueaxis inspect examples/ballbar/export_xy.txt --json\n  \
trueaxis inspect examples/data/vmc3_etalon.exc\n\n\
Exit status 0 when the file can be read (a finding that a command would refuse is listed, not an\n\
error), 2 when it cannot."
)]
pub struct InspectArgs {
    /// The file: a table (CSV, `;` or tab separated), a Renishaw .rtl laser file, a ballbar text
    /// export or an Etalon exchange file.
    file: PathBuf,
    /// Print one JSON document instead of text.
    #[arg(long)]
    json: bool,
}

fn finding_json(f: &Finding) -> Value {
    json!({"severity": if f.severity == Severity::Refuse { "refuse" } else { "warn" }, "message": f.message})
}

/// The description of a table: its form, columns, and what the commands read from it.
fn table_doc(table: &CsvTable) -> Value {
    let columns: Vec<Value> = table
        .headers()
        .iter()
        .map(|h| {
            json!({"header": h.text, "name": h.name, "unit": h.unit.map(|u| u.symbol),
                   "read_as": table.unit_returned(&h.name).map(|u| u.symbol)})
        })
        .collect();
    let layout = match table.layout() {
        Layout::Long => json!("long (one row per reading)"),
        Layout::Wide { run_columns } => json!({"wide": run_columns}),
    };
    let mut commands: Vec<Value> = Vec::new();
    let mut findings: Vec<Value> = table.warnings().iter().map(|w| json!({"severity": "warn", "message": w})).collect();
    let mut readings = Value::Null;
    let has = |c: &str| table.has_column(c);
    let positioning = has("target") && has("dev") && has("dir") && has("run");
    if positioning {
        match runs_of(table) {
            Ok(data) => {
                let mut runs: Vec<(i64, &'static str, usize)> = Vec::new();
                for r in &data.readings {
                    match runs.iter_mut().find(|x| x.0 == r.run && x.1 == r.direction.symbol()) {
                        Some(x) => x.2 += 1,
                        None => runs.push((r.run, r.direction.symbol(), 1)),
                    }
                }
                let mut targets: Vec<f64> = data.readings.iter().map(|r| r.target).collect();
                targets.sort_by(f64::total_cmp);
                targets.dedup_by(|a, b| (*a - *b).abs() <= 1e-6);
                let (pu, u) = (data.position_unit(), data.unit());
                readings = json!({
                    "kind": "positioning test",
                    "readings": data.readings.len(),
                    "targets": targets.len(),
                    "target_range": [targets.first(), targets.last()],
                    "position_unit": pu,
                    "deviation_unit": u,
                    "runs": runs.iter().map(|(r, d, n)| json!({"run": r, "dir": d, "readings": n})).collect::<Vec<_>>(),
                });
                commands.push(json!({"command": "iso230-2", "reads": format!(
                    "{} readings at {} targets ({pu}), deviations in {u}, {} runs with directions", data.readings.len(), targets.len(), runs.len())}));
                commands.push(json!({"command": "fit", "reads": format!(
                    "positions `target` ({pu}), values `dev` ({u}); --direction + / - / both from `dir`, --drift needs `t`")}));
                let distinct_runs = runs.iter().map(|r| r.0).fold(Vec::new(), |mut v, r| {
                    if !v.contains(&r) {
                        v.push(r)
                    }
                    v
                });
                if distinct_runs.len() == 2 {
                    commands.push(json!({"command": "reversal arbor|disk", "reads": "run 1 as m1 and run 2 as m2 at the targets (um)"}));
                }
                match plausibility(table, &data) {
                    Ok(f) => findings.extend(f.iter().map(finding_json)),
                    Err(e) => findings.push(json!({"severity": "refuse", "message": e.to_string()})),
                }
            }
            Err(e) => findings.push(json!({"severity": "refuse", "message": e.to_string()})),
        }
    } else if has("target") && has("dev") {
        commands.push(json!({"command": "fit", "reads": "positions `target`, values `dev` (um, or urad for angular errors)"}));
    }
    let header = ballbar_header(table);
    let ballbar_like = (!positioning && (has("dL") || has("radius"))) || header.as_ref().is_ok_and(|h| !h.is_empty());
    if ballbar_like {
        let angle = ["angle", "A", "B", "C"].into_iter().find(|c| has(c));
        match trace_of(table, &["angle", "C", "A", "B"]) {
            Ok(trace) => {
                let h = &trace.header;
                readings = json!({
                    "kind": "ballbar readings",
                    "samples": trace.dl_um.len(),
                    "runs": trace.run_numbers(),
                    "angles_from": angle.map_or("sample numbers, radius, feed rate and sample rate".to_string(), |a| format!("column {a}")),
                    "angle_range_deg": [trace.angles_deg.iter().copied().fold(f64::INFINITY, f64::min), trace.angles_deg.iter().copied().fold(f64::NEG_INFINITY, f64::max)],
                    "header": {"radius_mm": h.radius_mm, "feed_mm_per_min": h.feed_mm_per_min, "sample_rate_hz": h.sample_rate_hz,
                               "arc_deg": h.arc_deg, "start_deg": h.start_deg, "plane": h.plane,
                               "direction": h.sense.map(|s| format!("{s:?}").to_lowercase())},
                });
                findings.extend(trace.warnings.iter().map(|w| json!({"severity": "warn", "message": w})));
                commands.push(json!({"command": "ballbar iso230-4", "reads": format!(
                    "{} bar deviations (um) at angles in the plane{}", trace.dl_um.len(),
                    h.radius_mm.map_or(String::from("; give --radius"), |r| format!("; radius {r} mm from the header")))}));
                if angle.is_some() {
                    commands
                        .push(json!({"command": "ballbar identify|tmbb", "reads": "the swept axis angle and dL (um) of one step or bar"}));
                }
            }
            Err(e) => findings.push(json!({"severity": "refuse", "message": e.to_string()})),
        }
    }
    if has("m1") && has("m2") {
        commands.push(json!({"command": "reversal arbor|disk", "reads": "positions (mm) and the two scans m1, m2 (um)"}));
    }
    if has("probe1_location1") {
        commands.push(json!({"command": "reversal parallelism", "reads": "four probe columns (um)"}));
    }
    let axes: String = ["X", "Y", "Z", "A", "B", "C"].into_iter().filter(|a| has(a)).collect();
    if axes.len() >= 2 {
        commands.push(json!({"command": "predict|compensate --poses|uncertainty --poses", "reads": format!("poses of the axes {axes} (mm, deg) for a machine with those axes")}));
    }
    if table.headers().iter().any(|h| h.name.starts_with("T:")) && has("t") {
        commands.push(json!({"command": "thermal fit|predict", "reads": "time t (s), temperatures T:* (degC) and error columns (um)"}));
    }
    if has("channel") && has("t") {
        commands.push(json!({"command": "uncertainty --design", "reads": "channels, times and sensitivities of a linear model"}));
    }
    json!({
        "format": if table.format() == Format::Rtl { Format::Rtl.name() } else { Format::Table.name() },
        "separator": match table.separator() { '\t' => "tab".to_string(), c => c.to_string() },
        "decimal_comma": table.decimal_comma(),
        "layout": layout,
        "rows": table.len(),
        "columns": columns,
        "metadata": table.metadata().to_json(),
        "readings": readings,
        "commands": commands,
        "findings": findings,
    })
}

fn etalon_doc(text: &str, name: &str) -> Result<Value, Failure> {
    let file = etalon::parse(text, name).map_err(Failure::input)?;
    let parameters: Vec<Value> = file
        .parameters
        .iter()
        .map(|p| {
            let iso = trueaxis::error_model::etalon::parameter_id(&p.name).ok().flatten().map(|id| id.to_string());
            match &p.value {
                etalon::EtalonValue::Constant(v) => json!({"name": p.name, "iso": iso, "line": p.line, "value": v}),
                etalon::EtalonValue::Table(points) => json!({"name": p.name, "iso": iso, "line": p.line, "points": points.len(),
                    "argument_range": [points.iter().map(|x| x.0).fold(f64::INFINITY, f64::min), points.iter().map(|x| x.0).fold(f64::NEG_INFINITY, f64::max)]}),
            }
        })
        .collect();
    Ok(json!({
        "format": Format::Etalon.name(),
        "units": "values mm (translations) and rad (rotations); arguments mm (linear axes) and deg (rotary axes)",
        "parameters": parameters,
        "commands": [{"command": "convert --to errors --machine M.toml", "reads": "every error parameter, into [constant] and [table.NAME] (um, urad)"}],
        "findings": file.warnings.iter().map(|w| json!({"severity": "warn", "message": w})).collect::<Vec<_>>(),
    }))
}

/// The readable form of the document.
fn text_of(name: &str, doc: &Value) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let s = |v: &Value| match v {
        Value::String(t) => t.clone(),
        other => other.to_string(),
    };
    let _ = writeln!(out, "{name}: {}", s(&doc["format"]));
    if let Some(sep) = doc.get("separator") {
        let _ = writeln!(
            out,
            "  separator `{}`, decimal {}, {} rows, layout {}",
            s(sep),
            if doc["decimal_comma"] == json!(true) { "comma or point" } else { "point" },
            doc["rows"],
            s(&doc["layout"])
        );
        let _ = writeln!(out, "  columns:");
        for c in doc["columns"].as_array().into_iter().flatten() {
            let unit = match (&c["unit"], &c["read_as"]) {
                (Value::String(u), Value::String(r)) if u != r => format!("{u}, read as {r}"),
                (Value::String(u), _) => u.clone(),
                _ => "no unit (values as written)".into(),
            };
            let _ = writeln!(out, "    {:<24} {unit}", s(&c["header"]));
        }
    }
    if let Some(units) = doc.get("units") {
        let _ = writeln!(out, "  units: {}", s(units));
        for p in doc["parameters"].as_array().into_iter().flatten() {
            let what = match p.get("value") {
                Some(v) => format!("value {v}"),
                None => format!("table of {} points over {}", p["points"], p["argument_range"]),
            };
            let _ = writeln!(
                out,
                "    [{}] {} (line {}): {what}",
                s(&p["name"]),
                p["iso"].as_str().unwrap_or("not an error parameter"),
                p["line"]
            );
        }
    }
    if let Some(m) = doc.get("metadata").and_then(Value::as_object).filter(|m| !m.is_empty()) {
        let _ = writeln!(out, "  metadata:");
        for (k, v) in m {
            match v.as_object() {
                Some(inner) => {
                    for (k2, v2) in inner {
                        let _ = writeln!(out, "    {k2}: {}", s(v2));
                    }
                }
                None => {
                    let _ = writeln!(out, "    {k}: {}", s(v));
                }
            }
        }
    }
    if let Some(r) = doc.get("readings").filter(|r| !r.is_null()) {
        let _ = writeln!(out, "  readings: {}", s(&r["kind"]));
        for (k, v) in r.as_object().into_iter().flatten().filter(|(k, _)| k.as_str() != "kind") {
            let _ = writeln!(out, "    {k}: {}", s(v));
        }
    }
    let _ = writeln!(out, "  what the commands read:");
    let commands = doc["commands"].as_array().cloned().unwrap_or_default();
    if commands.is_empty() {
        let _ = writeln!(out, "    no command recognises these columns (see docs/user-guide.md, Instrument files)");
    }
    for c in &commands {
        let _ = writeln!(out, "    {:<28} {}", s(&c["command"]), s(&c["reads"]));
    }
    for f in doc["findings"].as_array().into_iter().flatten() {
        let word = if f["severity"] == json!("refuse") { "refused" } else { "warning" };
        let _ = writeln!(out, "  {word}: {}", s(&f["message"]));
    }
    out
}

pub fn run(args: InspectArgs) -> Result<(), Failure> {
    let name = args.file.display().to_string();
    let text = read_text(&args.file).map_err(Failure::input)?;
    let mut doc = match trueaxis::io::detect(&text) {
        Format::Etalon => etalon_doc(&text, &name)?,
        _ => table_doc(&CsvTable::from_text(&text, &name).map_err(Failure::input)?),
    };
    doc["file"] = json!(name);
    if args.json {
        return output::json(&doc);
    }
    print(&text_of(&name, &doc))
}
