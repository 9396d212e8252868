//! The controller formats read back by readers that do not share trueaxis code: pyLSV2's table
//! reader for Heidenhain (PyPI `pyLSV2`), parsers of the Siemens and Fanuc syntax written here from
//! the public manuals, and LinuxCNC itself (halcompile and halrun) for the HAL component; the numbers
//! read back equal the corrections trueaxis predicts. The error each format leaves
//! (`residual_of_format`) against closed forms.

use std::collections::HashMap;
use std::path::Path;
use std::process::Command;
use trueaxis::compensate::export::{self, fanuc::FanucLimits, siemens::SiemensLimits, Export, ExportInput, ExportedFile, Limits};
use trueaxis::compensate::{
    axis_tables, residual_of_format, volumetric_grid, CompensateError, CorrectionWorkspace, Corrector, TableSet, TableSpec,
};
use trueaxis::error_model::{Direction, ErrorFunction, ErrorModel, MachineState};
use trueaxis::machine::{Machine, ParameterId};

mod five_axis;

use crate::support::examples::load;
use crate::support::tools;

fn spec(points: usize) -> TableSpec {
    TableSpec { points, reference: None, temperatures: vec![] }
}

fn input<'a>(m: &'a Machine, e: &'a ErrorModel, t: &'a TableSet, g: Option<&'a trueaxis::compensate::VolumetricGrid>) -> ExportInput<'a> {
    // the read-back tests use corner references, where the C600U's cross-axis table A -> Y reaches
    // 1.23 mm (a 400 mm lever on its rotary errors), beyond the default 1 mm limit; the limit is
    // tested in formats.rs and the command line's bad_input.rs, not here
    let limits = Limits::with_overrides(m, Some(10_000.0), None).unwrap();
    ExportInput { machine: m, errors: e, tables: t, grid: g, limits }
}

fn file<'a>(files: &'a [ExportedFile], name: &str) -> &'a str {
    &files.iter().find(|f| f.name == name).unwrap_or_else(|| panic!("no {name}")).contents
}

/// The exact correction (user units) at a user pose, all axes moving in `direction` (None: at rest).
fn exact(corrector: &Corrector, user: &[f64], direction: Option<Direction>) -> Vec<f64> {
    let m = corrector.machine;
    let mut q = vec![0.0; m.axis_count()];
    m.pose_to_internal(user, &mut q);
    let dirs = vec![direction; m.axis_count()];
    let state = MachineState { directions: Some(&dirs), temperatures: &[] };
    corrector.correct_state(&q, &state, &mut CorrectionWorkspace::new(m)).dq_user(m)
}

fn write_files(dir: &Path, files: &[ExportedFile]) {
    std::fs::create_dir_all(dir).unwrap();
    for f in files {
        std::fs::write(dir.join(&f.name), &f.contents).unwrap();
    }
}

#[test]
fn heidenhain_tables_read_back_by_pylsv2() {
    let (m, e) = load("c600u", "c600u");
    let corrector = Corrector::new(&m, &e);
    let tables = axis_tables(&corrector, &spec(37)).unwrap();
    let out = export::heidenhain::export(&input(&m, &e, &tables, None)).unwrap();
    let dir = std::env::temp_dir().join(format!("trueaxis-heidenhain-{}", std::process::id()));
    write_files(&dir, &out.files);
    // pyLSV2's NCTable: a value is the text under its column name, up to the next name
    let script = r#"
import json, sys, pathlib
from pyLSV2.table_reader import NCTable
out = {}
for p in sorted(pathlib.Path(sys.argv[1]).iterdir()):
    t = NCTable.parse_table(p)
    out[p.name] = {"name": t.name, "suffix": t.suffix, "metric": t.is_metric, "columns": t.column_names, "rows": t.rows}
print(json.dumps(out))
"#;
    let run = Command::new("python3").arg("-c").arg(script).arg(&dir).output();
    let ok = run.as_ref().is_ok_and(|o| o.status.success());
    if !ok {
        let why = run.map(|o| String::from_utf8_lossy(&o.stderr).into_owned()).unwrap_or_else(|e| e.to_string());
        assert!(!tools::required("TRUEAXIS_REQUIRE_PYLSV2"), "pyLSV2 is required but failed: {why}");
        eprintln!("SKIPPED: pyLSV2 (pip install pyLSV2) not available: {}", why.lines().last().unwrap_or(""));
        return;
    }
    let doc: serde_json::Value = serde_json::from_slice(&run.unwrap().stdout).unwrap();
    let cma = &doc["COMP.CMA"];
    assert_eq!(cma["suffix"], "cma");
    assert_eq!(cma["columns"], serde_json::json!(["NR", "X", "Y", "Z", "A", "C", "ACTIVE"]));
    assert_eq!(cma["rows"][0]["C"], "C.COM");
    assert_eq!(cma["rows"][0]["ACTIVE"], "*");
    let mut values = 0;
    for (driver, axis) in m.axes().iter().enumerate() {
        let t = &doc[format!("{}.COM", axis.letter)];
        assert_eq!(
            (t["name"].as_str(), t["suffix"].as_str(), t["metric"].as_bool()),
            (Some(axis.letter.to_string().as_str()), Some("com"), Some(true))
        );
        let rows = t["rows"].as_array().unwrap();
        assert_eq!(rows.len(), 37);
        let number = |row: &serde_json::Value, column: &str| row[column].as_str().unwrap().parse::<f64>().unwrap();
        for (i, row) in rows.iter().enumerate() {
            let x = number(row, "AXISPOS");
            let mut pose = tables.reference.clone();
            pose[driver] = x;
            // the own column at forward traverse and BACKLASH at reverse are the exact corrections of
            // the driving axis on its line; cross columns the change of the mean from the reference
            let forward = exact(&corrector, &pose, Some(Direction::Positive));
            let reverse = exact(&corrector, &pose, Some(Direction::Negative));
            assert!((number(row, &axis.letter.to_string()) - forward[driver]).abs() < 1e-6, "{} row {i}", axis.letter);
            assert!((number(row, "BACKLASH") - reverse[driver]).abs() < 1e-6);
            for (k, other) in m.axes().iter().enumerate().filter(|(k, _)| *k != driver) {
                let t = tables.table(driver, k).unwrap();
                let expected = 0.5 * (t.forward[i] + t.reverse[i]);
                assert!((number(row, &other.letter.to_string()) - expected).abs() < 1e-6);
                values += 1;
            }
        }
    }
    assert_eq!(values, 5 * 4 * 37);
    std::fs::remove_dir_all(dir).ok();
}

/// A reader of SINUMERIK init programs (K3 examples): `$NAME[i,j,...]=value` with `;` comments,
/// `%_N_..._INI`, `CHANDATA(..)` and `M17` lines; axis names in parentheses.
fn read_siemens(text: &str) -> HashMap<(String, Vec<String>), String> {
    let mut vars = HashMap::new();
    for line in text.lines() {
        let line = line.split(';').next().unwrap().trim();
        if line.is_empty() || line.starts_with("%_N_") || line.starts_with("CHANDATA") || line == "M17" {
            continue;
        }
        let (lhs, rhs) = line.split_once('=').unwrap_or_else(|| panic!("not an assignment: {line}"));
        let (name, index) = lhs.split_once('[').unwrap();
        let index: Vec<String> = index.trim_end_matches(']').split(',').map(|s| s.trim().to_string()).collect();
        assert!(name.starts_with('$'), "{line}");
        vars.insert((name.to_string(), index), rhs.trim().trim_start_matches('(').trim_end_matches(')').to_string());
    }
    vars
}

/// Linear interpolation of a Siemens table (first / last value held outside, modulo wraps).
fn siemens_table(values: &[f64], min: f64, max: f64, step: f64, modulo: bool, x: f64) -> f64 {
    let x = if modulo { min + (x - min).rem_euclid(max - min) } else { x.clamp(min, max) };
    let u = (x - min) / step;
    let i = (u.floor() as usize).min(values.len() - 2);
    values[i] + (u - i as f64) * (values[i + 1] - values[i])
}

#[test]
fn siemens_programs_read_back_give_the_corrections() {
    for (machine, errors) in [("vmc3", "vmc3_backlash"), ("c600u", "c600u")] {
        let (m, e) = load(machine, errors);
        let corrector = Corrector::new(&m, &e);
        // the reference at the first point of every table, so that every table is read at its points
        let reference: Vec<f64> = m.axes().iter().map(|a| a.range.map_or(0.0, |r| r[0])).collect();
        let tables = axis_tables(&corrector, &TableSpec { reference: Some(reference), ..spec(41) }).unwrap();
        let limits = SiemensLimits { max_points: 200, max_cec_tables: 62 };
        let out = export::siemens::export(&input(&m, &e, &tables, None), limits).unwrap();
        let lec = file(&out.files, "AX_EEC.INI");
        assert!(lec.starts_with("%_N_AX_EEC_INI\n") && lec.ends_with("M17\n"));
        assert!(lec.contains("MD38000 $MA_MM_ENC_COMP_MAX_POINTS[0,X1] >= 41"));
        let mut vars = read_siemens(lec);
        if let Some(f) = out.files.iter().find(|f| f.name == "NC_CEC.INI") {
            assert!(f.contents.starts_with("%_N_NC_CEC_INI\n") && f.contents.contains("MD32710 $MA_CEC_ENABLE"));
            vars.extend(read_siemens(&f.contents));
        }
        let get = |name: &str, index: &[&str]| -> f64 {
            vars[&(name.to_string(), index.iter().map(|s| s.to_string()).collect())].parse().unwrap()
        };
        let name = |k: usize| format!("{}1", m.axes()[k].letter);
        let cec_count = vars.keys().filter(|(n, _)| n == "$AN_CEC_INPUT_AXIS").count();
        // the controller's total compensation value of each axis at a pose, while all axes move in
        // `direction` (K3: LEC of the axis plus every CEC table whose output it is)
        let siemens = |pose: &[f64], direction: i32| -> Vec<f64> {
            (0..m.axis_count())
                .map(|j| {
                    let a = name(j);
                    let n = (0..200)
                        .take_while(|i| vars.contains_key(&("$AA_ENC_COMP".into(), vec!["0".into(), i.to_string(), a.clone()])))
                        .count();
                    let values: Vec<f64> = (0..n).map(|i| get("$AA_ENC_COMP", &["0", &i.to_string(), &a])).collect();
                    let modulo = get("$AA_ENC_COMP_IS_MODULO", &["0", &a]) == 1.0;
                    let mut total = siemens_table(
                        &values,
                        get("$AA_ENC_COMP_MIN", &["0", &a]),
                        get("$AA_ENC_COMP_MAX", &["0", &a]),
                        get("$AA_ENC_COMP_STEP", &["0", &a]),
                        modulo,
                        pose[j],
                    );
                    for t in 0..cec_count {
                        let ts = t.to_string();
                        if vars[&("$AN_CEC_OUTPUT_AXIS".to_string(), vec![ts.clone()])] != a {
                            continue;
                        }
                        let dir = get("$AN_CEC_DIRECTION", &[&ts]) as i32;
                        if dir != 0 && dir != direction {
                            continue;
                        }
                        let input = &vars[&("$AN_CEC_INPUT_AXIS".to_string(), vec![ts.clone()])];
                        let k = (0..m.axis_count()).find(|&k| &name(k) == input).unwrap();
                        let n = (0..200).take_while(|i| vars.contains_key(&("$AN_CEC".into(), vec![ts.clone(), i.to_string()]))).count();
                        let values: Vec<f64> = (0..n).map(|i| get("$AN_CEC", &[&ts, &i.to_string()])).collect();
                        assert_eq!(get("$AN_CEC_MULT_BY_TABLE", &[&ts]), 0.0);
                        total += siemens_table(
                            &values,
                            get("$AN_CEC_MIN", &[&ts]),
                            get("$AN_CEC_MAX", &[&ts]),
                            get("$AN_CEC_STEP", &[&ts]),
                            get("$AN_CEC_IS_MODULO", &[&ts]) == 1.0,
                            pose[k],
                        );
                    }
                    total
                })
                .collect()
        };
        // on every axis line through the reference, at table points: compensation value = minus the
        // exact correction, both directions of motion (1 nm or 1e-6 deg: the written resolution)
        let mut checked = 0;
        for k in 0..m.axis_count() {
            for &x in tables.table(k, k).unwrap().positions.iter().step_by(4) {
                let mut pose = tables.reference.clone();
                pose[k] = x;
                for (direction, sign) in [(Direction::Positive, 1), (Direction::Negative, -1)] {
                    let c = exact(&corrector, &pose, Some(direction));
                    let s = siemens(&pose, sign);
                    for j in 0..m.axis_count() {
                        assert!((s[j] + c[j]).abs() < 2.5e-6, "{machine}: {} at {pose:?} dir {sign}: {} vs {}", name(j), -s[j], c[j]);
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked >= 3 * 11 * 2 * 3);
    }
    // too many CEC tables for the default (828D) size, or too many points, are refused
    let (m, e) = load("c600u", "c600u");
    let corrector = Corrector::new(&m, &e);
    let tables = axis_tables(&corrector, &spec(41)).unwrap();
    let err = export::siemens::export(&input(&m, &e, &tables, None), SiemensLimits::default()).unwrap_err();
    assert!(matches!(err, CompensateError::Limit(_)) && err.to_string().contains("--max-cec-tables"), "{err}");
    let err = export::siemens::export(&input(&m, &e, &tables, None), SiemensLimits { max_points: 40, max_cec_tables: 62 }).unwrap_err();
    assert!(err.to_string().contains("at most 40"), "{err}");
}

/// A reader of Fanuc programmable parameter input: `G10 L50` ... `G11`, `N<number> [P<axis>] R<value>`.
fn read_fanuc(text: &str) -> (HashMap<(u32, u32), i64>, HashMap<u32, i64>) {
    let mut inside = false;
    let (mut params, mut pitch) = (HashMap::new(), HashMap::new());
    for line in text.lines() {
        let line = line.split('(').next().unwrap().trim().trim_end_matches(';').trim();
        match line {
            "G10 L50" => inside = true,
            "G11" => inside = false,
            _ if inside => {
                let words: HashMap<char, i64> =
                    line.split_whitespace().map(|w| (w.chars().next().unwrap(), w[1..].parse().unwrap())).collect();
                let n = words[&'N'] as u32;
                if n >= 10000 {
                    pitch.insert(n - 10000, words[&'R']);
                } else {
                    params.insert((n, words[&'P'] as u32), words[&'R']);
                }
            }
            _ => {}
        }
    }
    (params, pitch)
}

#[test]
fn fanuc_program_read_back_gives_the_pitch_corrections() {
    let (m, e) = load("vmc3", "vmc3_backlash");
    let corrector = Corrector::new(&m, &e);
    let tables = axis_tables(&corrector, &spec(41)).unwrap();
    let out = export::fanuc::export(&input(&m, &e, &tables, None), FanucLimits::default()).unwrap();
    let text = file(&out.files, "pitch_error.nc");
    assert!(text.contains("DETECTION UNIT 0.001 MM") && text.contains("MAGNIFICATION"));
    let (params, pitch) = read_fanuc(text);
    let mut used = std::collections::HashSet::new();
    for k in 0..m.axis_count() {
        let p = (k + 1) as u32;
        let (r, lo, hi, mag, interval) =
            (params[&(3620, p)], params[&(3621, p)], params[&(3622, p)], params[&(3623, p)], params[&(3624, p)]);
        assert!(lo <= r && r <= hi && hi - lo < 128 && (1..=100).contains(&mag));
        for point in lo..=hi {
            assert!(used.insert(point), "point {point} used twice");
            assert!(pitch[&(point as u32)].abs() <= 127);
        }
        // the compensation at the end of each section: the increments summed from the reference
        // position (up: added, down: subtracted), detection unit 0.001 mm times the magnification
        let unit = 1e-3 * mag as f64;
        let step = interval as f64 * 1e-3;
        let [t_lo, t_hi] = m.axes()[k].range.unwrap();
        let at_zero = {
            let mut pose = tables.reference.clone();
            pose[k] = 0.0f64.clamp(t_lo, t_hi);
            exact(&corrector, &pose, None)[k]
        };
        for point in lo..=hi {
            let x = (point - r) as f64 * step;
            if x < t_lo - 1e-9 || x > t_hi + 1e-9 {
                continue;
            }
            let absolute: i64 = if point >= r {
                (r + 1..=point).map(|q| pitch[&(q as u32)]).sum()
            } else {
                -(point + 1..=r).map(|q| pitch[&(q as u32)]).sum::<i64>()
            };
            let mut pose = tables.reference.clone();
            pose[k] = x;
            let expected = exact(&corrector, &pose, None)[k] - at_zero;
            // cumulative rounding: within half a compensation unit
            assert!(
                (absolute as f64 * unit - expected).abs() <= 0.5 * unit + 1e-9,
                "{} at {x}: {} vs {expected}",
                m.axes()[k].letter,
                absolute as f64 * unit
            );
        }
    }
    // the constant at the reference position and the cross-axis tables are reported as left out
    assert!(out.left_out.iter().any(|l| l.contains("at the reference position")));
    assert!(out.left_out.iter().any(|l| l.contains("cross-axis")));
    // fewer points allowed than the interval needs: refused
    let err =
        export::fanuc::export(&input(&m, &e, &tables, None), FanucLimits { max_points_per_axis: 30, max_point_number: 1023 }).unwrap_err();
    assert!(err.to_string().contains("at most 30 per axis"), "{err}");
}

#[test]
fn residual_of_each_format_against_the_squareness_closed_form() {
    // EC0X = 12 urad alone: the tool-to-table error is dx = 12e-6 * Y, a cross-axis correction
    // linear in Y that tables and grids represent exactly. Judged up to the placement of the
    // workpiece (its least-squares rigid fit over the poses), the rotation part of that shear goes:
    // over the full factorial of X in +-400 and Y in +-250 mm the fitted rotation about z is
    // 12 sum(Y^2) / (sum(X^2) + sum(Y^2)) = 12 * 250^2 / (400^2 + 250^2) urad, and what is left is
    // ((12 - theta) Y, theta X) 1e-6 mm, largest at the corners.
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let mut e = ErrorModel::zero(&m);
    e.set(&m, ParameterId::parse("EC0X").unwrap(), ErrorFunction::Constant(12.0)).unwrap();
    let corrector = Corrector::new(&m, &e);
    let tables = axis_tables(&corrector, &spec(9)).unwrap();
    let grid = volumetric_grid(&corrector, [3, 3, 3], &spec(9)).unwrap();
    let inp = input(&m, &e, &tables, Some(&grid));
    let residual = |out: &Export| residual_of_format(&corrector, &[], out.applied.as_ref()).unwrap();
    let theta = 12.0 * 250f64.powi(2) / (400f64.powi(2) + 250f64.powi(2));
    let corner = (((12.0 - theta) * 250.0).powi(2) + (theta * 400.0).powi(2)).sqrt() * 1e-3;
    for (name, out) in [
        ("linuxcnc", export::linuxcnc::export(&inp, export::linuxcnc::CompType::Trims).unwrap()),
        ("fanuc", export::fanuc::export(&inp, FanucLimits::default()).unwrap()),
    ] {
        // own-axis formats leave all of it, at the corners of the XY travel
        let r = residual(&out);
        // to first order in the 12 urad (the exact chain and the fit differ from it by ~1e-5 um)
        assert!((r.worst_um - corner).abs() < 2e-5 && (r.worst_error_um - corner).abs() < 2e-5, "{name}: {r:?} vs {corner}");
        assert!((r.worst_pose[0].abs() - 400.0).abs() < 1e-9 && (r.worst_pose[1].abs() - 250.0).abs() < 1e-9);
        assert!((r.error_there_um - r.worst_um).abs() < 2e-5);
        let w = r.placement_after.rotation_vector() * 1e6;
        assert!((w.z + theta).abs() < 1e-6 && w.x.abs() < 1e-9 && w.y.abs() < 1e-9, "{name}: placement {w:?} vs -{theta}");
        assert!(
            out.left_out.iter().any(|l| l.starts_with("X as a function of Y (cross-axis): up to 3.000 um")),
            "{name}: {:?}",
            out.left_out
        );
    }
    for (name, out) in [
        ("heidenhain", export::heidenhain::export(&inp).unwrap()),
        ("siemens", export::siemens::export(&inp, SiemensLimits::default()).unwrap()),
        ("linuxcnc-hal", export::linuxcnc_hal::export(&inp, "trueaxis_comp").unwrap()),
        ("lattice", export::lattice::export(&inp, None).unwrap()),
        ("isg", export::isg::export(&inp).unwrap()),
    ] {
        let r = residual(&out);
        assert!(r.worst_um < 2e-3 && (r.worst_error_um - corner).abs() < 2e-5, "{name}: {r:?}");
    }
}

/// One LinuxCNC realtime session at a time: the tests of this binary that run halrun take it.
static HALRUN: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Runs a halcmd script with halrun; as root, rtapi_app needs a fallback user and a FIFO path it can
/// write (LinuxCNC uspace).
fn halrun(script: &Path, fifo_dir: &Path) -> std::process::Output {
    let _session = HALRUN.lock().unwrap_or_else(|e| e.into_inner());
    let mut cmd = Command::new("halrun");
    cmd.arg("-f").arg(script);
    let root = Command::new("id").arg("-u").output().is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0");
    if root {
        let nobody = Command::new("id").args(["-u", "nobody"]).output().unwrap();
        cmd.env("RTAPI_UID", String::from_utf8_lossy(&nobody.stdout).trim()).env("RTAPI_FIFO_PATH", fifo_dir.join("rtapi_fifo"));
    }
    cmd.output().unwrap()
}

#[test]
fn hal_component_built_and_run_by_linuxcnc_outputs_the_corrections() {
    if !tools::linuxcnc_found() {
        return;
    }
    for (machine, errors) in [("vmc3", "vmc3"), ("c600u", "c600u")] {
        let (m, e) = load(machine, errors);
        let corrector = Corrector::new(&m, &e);
        let tables = axis_tables(&corrector, &spec(19)).unwrap();
        let grid = volumetric_grid(&corrector, [5, 5, 5], &spec(19)).unwrap();
        let name = format!("ta_test_{machine}_{}", std::process::id());
        let hal_name = name.replace('_', "-");
        let out = export::linuxcnc_hal::export(&input(&m, &e, &tables, Some(&grid)), &name).unwrap();
        let dir = std::env::temp_dir().join(format!("trueaxis-hal-{name}"));
        write_files(&dir, &out.files);
        tools::open_to_all(&dir);
        let Some(installed) = tools::halcompile_install(&dir, &format!("{name}.comp")) else { return };
        // poses: grid nodes with the rotary axes at the reference, and poses anywhere in the travel
        let n = m.axis_count();
        let mut poses: Vec<Vec<f64>> = Vec::new();
        for (i, j, k) in [(0, 0, 0), (4, 2, 1), (2, 3, 4), (1, 4, 3)] {
            let mut p = tables.reference.clone();
            for (d, idx) in [i, j, k].into_iter().enumerate() {
                p[grid.axes[d]] = grid.node_position(i, j, k)[d];
                let _ = idx;
            }
            poses.push(p);
        }
        let ranges: Vec<[f64; 2]> = m.axes().iter().map(|a| a.range.unwrap_or([0.0, 360.0])).collect();
        for s in 0..8 {
            poses.push(
                (0..n).map(|k| ranges[k][0] + (ranges[k][1] - ranges[k][0]) * (((s * 7 + k * 3) % 11) as f64 + 0.37) / 11.0).collect(),
            );
        }
        let mut script = format!("loadrt {name}\nloadrt threads name1=t1 period1=1000000\naddf {hal_name}.0 t1\nstart\n");
        for p in &poses {
            for (k, a) in m.axes().iter().enumerate() {
                script += &format!("setp {hal_name}.0.pos-{} {}\n", a.letter.to_ascii_lowercase(), p[k]);
            }
            script += "loadusr -w sleep 0.02\n";
            for a in m.axes() {
                script += &format!(
                    "getp {hal_name}.0.offset-{}\ngetp {hal_name}.0.counts-{}\n",
                    a.letter.to_ascii_lowercase(),
                    a.letter.to_ascii_lowercase()
                );
            }
        }
        script += "stop\n";
        std::fs::write(dir.join("run.hal"), script).unwrap();
        let run = halrun(&dir.join("run.hal"), &dir);
        let stdout = String::from_utf8_lossy(&run.stdout);
        let numbers: Vec<f64> = stdout.lines().filter_map(|l| l.trim().parse().ok()).collect();
        assert_eq!(numbers.len(), poses.len() * n * 2, "halrun: {stdout}\n{}", String::from_utf8_lossy(&run.stderr));
        let mut applied = vec![0.0; n];
        for (i, p) in poses.iter().enumerate() {
            out.applied.applied(p, &vec![None; n], &mut applied);
            let exact_here = exact(&corrector, p, None);
            for k in 0..n {
                let (offset, counts) = (numbers[(i * n + k) * 2], numbers[(i * n + k) * 2 + 1]);
                // the component equals the library's model of the format: the counts to the nanometre
                // (or 1e-6 deg), the printed offset to its 7 significant digits
                assert!((counts - (applied[k] / 1e-6).round()).abs() <= 1.0, "{machine} pose {p:?} axis {k}: {counts} vs {}", applied[k]);
                assert!(
                    (offset - applied[k]).abs() <= 1e-6 * applied[k].abs() + 1e-12,
                    "{machine} pose {p:?} axis {k}: {offset} vs {}",
                    applied[k]
                );
                // at the grid nodes (other axes at the reference) it is the exact correction
                if i < 4 {
                    assert!(
                        (applied[k] - exact_here[k]).abs() < 1e-9,
                        "{machine} node {p:?} axis {k}: {} vs {}",
                        applied[k],
                        exact_here[k]
                    );
                    assert!((counts - (exact_here[k] / 1e-6).round()).abs() <= 1.0);
                }
            }
        }
        // the HAL file wires the component to LinuxCNC 2.9's own motion module (trivkins)
        let letters: String = m.axes().iter().map(|a| a.letter).collect();
        let wiring = format!(
            "loadrt trivkins coordinates={letters}\nloadrt tpmod\nloadrt homemod\nloadrt motmod servo_period_nsec=1000000 num_joints={n}\n{}\
             show sig ta-x-counts\n",
            file(&out.files, &format!("{name}.hal"))
        );
        std::fs::write(dir.join("wiring.hal"), wiring).unwrap();
        let run = halrun(&dir.join("wiring.hal"), &dir);
        let text = String::from_utf8_lossy(&run.stdout).into_owned() + &String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success() && text.contains("axis.x.eoffset-counts"), "{machine}: the HAL file does not load: {text}");
        if let Some(so) = installed {
            std::fs::remove_file(so).ok();
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
