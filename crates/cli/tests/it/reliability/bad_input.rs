//! The bad-input suite (docs/limits.md): every input kind (machine file, error values, campaign
//! CSV and TOML, ballbar table, laser CSV and .rtl, thermal campaign, uncertainty sources, NC
//! programs in both dialects) x every class of bad value (malformed, huge finite, NaN / inf text,
//! outside the physical range, duplicated column, missing column, empty), each run through the
//! command that reads it. Every case asserts exit status 2, a one-line message naming the file
//! and the line or parameter and the cause, and that no output file was written. Fixtures are the
//! shipped examples with one value changed, written to a temporary directory.

use crate::support::{alone, arg, read as example, vmc3, Run, ROOT};
use std::path::Path;
use std::time::Duration;

/// One case: the file to write (name, text), the command (`{f}` = that file, `{out}` = the output
/// path that must stay absent), and what the message must contain besides the file name.
struct Case {
    what: &'static str,
    name: &'static str,
    text: String,
    args: Vec<&'static str>,
    expect: Vec<&'static str>,
}

fn case(what: &'static str, name: &'static str, text: String, args: &[&'static str], expect: &[&'static str]) -> Case {
    Case { what, name, text, args: args.to_vec(), expect: expect.to_vec() }
}

/// `text` with its first occurrence of `from` replaced (the fixture must contain it).
fn with(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "fixture lacks `{from}`");
    text.replacen(from, to, 1)
}

/// One damage of a fixture: what it is, the text replaced, its replacement, what the message must
/// contain.
type Damage<'a> = (&'static str, &'a str, &'a str, &'a [&'static str]);

/// Damaged copies of `fixture` written as `name` and read by `args`: each damage is (what, the text
/// replaced, its replacement, what the message must contain).
fn damaged(name: &'static str, fixture: &str, args: &[&'static str], damages: &[Damage]) -> Vec<Case> {
    damages.iter().map(|&(what, from, to, expect)| case(what, name, with(fixture, from, to), args, expect)).collect()
}

/// Whole files written as `name` and read by `args`: (what, the text, what the message must contain).
fn written(name: &'static str, args: &[&'static str], files: &[(&'static str, &str, &[&'static str])]) -> Vec<Case> {
    files.iter().map(|&(what, text, expect)| case(what, name, text.to_string(), args, expect)).collect()
}

fn cases() -> Vec<Case> {
    let machine = example("examples/machines/vmc3.toml");
    let errors = example("examples/ballbar/vmc3_circle.toml");
    let station = example("examples/campaigns/vmc3_tracer/station1.csv");
    let ballbar = example("examples/ballbar/vmc3_xy.csv");
    let laser = example("examples/data/laser_x.csv");
    let rtl = example("examples/data/laser_x.rtl");
    let thermal = example("examples/thermal/campaign.csv");
    let sources = example("examples/uncertainty/kx8five_statistical.toml");
    let predict_m =
        &["predict", "--machine", "{f}", "--errors", "examples/errors/vmc3.toml", "--poses", "examples/poses/vmc3.csv", "--out", "{out}"];
    let predict_e = &vmc3(&["predict"], &["--errors", "{f}", "--poses", "examples/poses/vmc3.csv", "--out", "{out}"]);
    let predict_p = &vmc3(&["predict"], &["--errors", "examples/errors/vmc3.toml", "--poses", "{f}", "--out", "{out}"]);
    let iso4 = &["ballbar", "iso230-4", "{f}", "--radius", "100", "--plot", "{out}"];
    let iso2 = &["iso230-2", "{f}", "--plot", "{out}"];
    let tfit = &["thermal", "fit", "--data", "{f}", "--error", "dz", "--train-runs", "warmup", "--plot", "{out}"];
    let unc = &["uncertainty", "--design", "examples/uncertainty/kx8five_design.csv", "--sources", "{f}", "--plots", "{out}"];
    let identify = &vmc3(&["identify"], &["--campaign", "{dir}/campaign.toml", "--out", "{out}"]);
    let nc = &vmc3(&["nc"], &["--errors", "examples/errors/vmc3.toml", "{f}", "--out", "{out}"]);
    let mut cases = Vec::new();
    // machine file
    cases.extend(damaged(
        "m.toml",
        &machine,
        predict_m,
        &[
            ("machine malformed", "structure = \"wXYbZt\"", "structure = ", &["line"]),
            ("machine huge", "point = [0, 0, 400]", "point = [0, 0, 1e200]", &["line 22", "[tool] point", "physical range"]),
            ("machine 1e308", "range = [-400, 400]", "range = [-400, 1e308]", &["axis X", "physical range"]),
            ("machine nan", "point = [0, 0, 400]", "point = [0, 0, nan]", &["[tool] point", "finite"]),
            ("machine out of range", "range = [-250, 250]", "range = [-250, 250000000]", &["axis Y", "100 m"]),
        ],
    ));
    cases.push(case(
        "machine limit",
        "m.toml",
        machine.clone() + "\n[limits]\ncorrection_um = -1\n",
        predict_m,
        &["[limits] correction_um"],
    ));
    cases.push(case("machine empty", "m.toml", String::new(), predict_m, &["missing field"]));
    // error values
    cases.extend(damaged(
        "e.toml",
        &errors,
        predict_e,
        &[
            ("errors malformed", "EC0X = 25.0", "EC0X = 25.0.0", &["line"]),
            ("errors huge", "EC0X = 25.0", "EC0X = 1e200", &["line 7", "EC0X", "physical range of an angular error"]),
            ("errors 1e308", "coefficients = [1.5, -0.012]", "coefficients = [1.5, 1e308]", &["EXX+", "at X", "physical range"]),
            ("errors nan", "EC0X = 25.0", "EC0X = nan", &["EC0X", "finite"]),
            ("errors out of range", "EC0X = 25.0", "EC0X = 2e5", &["EC0X", "0.1 rad"]),
        ],
    ));
    cases.push(case("errors empty", "e.toml", "name = \"nothing\"\n".into(), predict_e, &["defines no error"]));
    // pose CSV
    cases.extend(written(
        "p.csv",
        predict_p,
        &[
            ("poses duplicated column", "X,X,Y,Z\n1,2,3,-4\n", &["line 1", "same column `X`"]),
            ("poses nan", "X,Y,Z\n1,nan,-4\n", &["line 2", "finite"]),
            ("poses missing column", "X,Y\n1,2\n", &["Z"]),
            ("poses huge temperature", "X,Y,Z,T:bed\n1,2,-4,1e200\n", &["line 2", "T:bed", "temperature"]),
            ("poses empty", "", &["empty"]),
        ],
    ));
    // ballbar table
    cases.extend(damaged(
        "b.csv",
        &ballbar,
        iso4,
        &[
            ("ballbar huge", ",ccw,1.7906", ",ccw,1e200", &["line 3", "dL", "physical range"]),
            ("ballbar nan", ",ccw,1.7906", ",ccw,nan", &["line 3", "dL"]),
            ("ballbar out of range", ",ccw,1.7906", ",ccw,250000", &["line 3", "dL", "physical range"]),
            ("ballbar duplicated column", "X,Y,Z,angle,dir,dL", "X,Y,Z,angle,dL,dL", &["line 2", "same column"]),
        ],
    ));
    cases.push(case("ballbar empty", "b.csv", String::new(), iso4, &["empty"]));
    // laser CSV and .rtl
    cases.extend(damaged(
        "l.csv",
        &laser,
        iso2,
        &[
            ("laser huge", "-400,-1.914,", "-400,1e200,", &["line 5", "dev", "physical range"]),
            ("laser inf", "-400,-1.914,", "-400,inf,", &["line 5", "dev"]),
            ("laser duplicated column", "target,dev,dir,run,t", "target,dev,dir,run,dev", &["same column `dev`"]),
            ("laser missing column", "target,dev,dir,run,t", "target,deviation_x,dir,run,t", &["dev"]),
        ],
    ));
    cases.push(case("laser empty", "l.csv", String::new(), iso2, &["empty"]));
    cases.extend(damaged(
        "l.rtl",
        &rtl,
        iso2,
        &[
            ("rtl huge", "1   1      -0.001914", "1   1      1e200", &["physical range"]),
            ("rtl malformed", "1   1      -0.001914", "1   1      minus", &["minus"]),
        ],
    ));
    // campaign readings (the campaign TOML next to it, copied by the runner)
    cases.extend(damaged(
        "station1.csv",
        &station,
        identify,
        &[
            ("campaign huge", "2.1063", "1e200", &["line 3", "dL", "physical range"]),
            ("campaign nan", "2.1063", "NaN", &["line 3", "dL"]),
            ("campaign duplicated column", "X,Y,Z,dL", "X,X,Z,dL", &["same column `X`"]),
            ("campaign missing column", "X,Y,Z,dL", "X,Y,dL", &["Z"]),
        ],
    ));
    cases.push(case("campaign empty", "station1.csv", String::new(), identify, &["empty"]));
    // thermal campaign
    cases.extend(damaged(
        "t.csv",
        &thermal,
        tfit,
        &[
            ("thermal huge temperature", "warmup,0,20.002,", "warmup,0,1e200,", &["line 3", "T:p1", "temperature"]),
            ("thermal out of range", "warmup,0,20.002,", "warmup,0,500,", &["line 3", "T:p1", "temperature"]),
            ("thermal huge drift", "20.009,-0.13", "20.009,1e300", &["line 3", "dz", "physical range"]),
            ("thermal nan", "20.009,-0.13", "20.009,nan", &["line 3", "dz"]),
            ("thermal duplicated column", "run,t,T:p1,T:p5,dz", "run,t,T:p1,T:p1,dz", &["same column"]),
        ],
    ));
    cases.push(case("thermal empty", "t.csv", String::new(), tfit, &["empty"]));
    // uncertainty sources
    cases.extend(damaged(
        "s.toml",
        &sources,
        unc,
        &[
            ("sources malformed", "coverage = 0.95", "coverage = ", &["line"]),
            ("sources nan", "tolerance = 0.05", "tolerance = nan", &["tolerance"]),
            (
                "sources trials",
                "trials_per_sequence = 10000",
                "trials_per_sequence = 1000000000000000",
                &["trials_per_sequence", "more than"],
            ),
        ],
    ));
    // NC, both dialects (rs274 refuses the same programs: crates/trueaxis/tests/it/compensate/nc/bad_programs.rs)
    cases.extend(written(
        "p.ngc",
        nc,
        &[
            ("nc arc radius", "G21 G90 G17\nG0 X0 Y0 Z-10\nG2 X10 Y0 I1 J0 F100\nM2\n", &["line 3", "radius"]),
            ("nc two motion codes", "G21 G90\nG0 G1 X10 F100\nM2\n", &["line 2", "G0 and G1", "modal group"]),
            ("nc malformed", "G21 G90\nG1 X1..2 F100\nM2\n", &["line 2"]),
            ("nc huge", "G21 G90\nG1 X1e200 F100\nM2\n", &["line 2", "E word"]),
        ],
    ));
    cases.push(case(
        "fanuc two motion codes",
        "p.nc",
        "%\nO1000\nG21 G90\nG00 G01 X10. F100.\nM30\n%\n".into(),
        nc,
        &["line 4", "modal group"],
    ));
    cases.push(case(
        "nc correction limit",
        "p.ngc",
        "G21 G90\nG0 X-400 Y-250 Z-100\nM2\n".into(),
        &vmc3(&["nc"], &["--errors", "{dir}/e.toml", "{f}", "--out", "{out}"]),
        &["line 2", "beyond the limit of 1000 um", "correction_um"],
    ));
    // an error table shorter than the travel: compensation beyond its ends is refused
    let short = "name = \"short\"\n[table.EXX]\nposition = [-300, 300]\nvalue = [0, 5]\n".to_string();
    cases.push(case(
        "compensate table shorter than the travel",
        "e.toml",
        short.clone(),
        &vmc3(&["compensate"], &["--errors", "{f}", "--format", "csv", "--out", "{out}"]),
        &["EXX", "covers X from -300 to 300 mm", "the travel of X reaches -400 mm"],
    ));
    cases.push(case(
        "nc beyond a table",
        "e.toml",
        short,
        &vmc3(&["nc"], &["--errors", "{f}", "{dir}/p.ngc", "--out", "{out}"]),
        &["p.ngc: line 2", "EXX", "the program reaches -350 mm"],
    ));
    // the unit slip of the issue: EC0X = 1e12 is refused by the physical range before any table
    cases.push(case(
        "compensate unit slip",
        "e.toml",
        "name = \"slip\"\n[constant]\nEC0X = 1e12\n".into(),
        &vmc3(&["compensate"], &["--errors", "{f}", "--format", "linuxcnc", "--out", "{out}"]),
        &["line 3", "EC0X", "physical range"],
    ));
    cases
}

#[test]
fn every_bad_input_is_refused_with_its_file_line_and_cause_and_nothing_is_written() {
    let mut failures = Vec::new();
    let cases = cases();
    for c in &cases {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        // the campaign of the shipped tracer example, next to the changed data file
        for f in ["campaign.toml", "station1.csv", "station2.csv", "station3.csv", "station4.csv"] {
            std::fs::copy(Path::new(ROOT).join("examples/campaigns/vmc3_tracer").join(f), d.join(f)).unwrap();
        }
        std::fs::write(d.join("p.ngc"), "G21 G90\nG0 X-350 Y0 Z-100\nM2\n").unwrap();
        // an error file whose corrections pass the physical range but not the default limit (1.25 mm)
        std::fs::write(d.join("e.toml"), "name = \"big\"\n[constant]\nEC0X = 5000\n").unwrap();
        let file = d.join(c.name);
        std::fs::write(&file, &c.text).unwrap();
        let out = d.join("out");
        let args: Vec<String> =
            c.args.iter().map(|a| a.replace("{f}", arg(&file)).replace("{out}", arg(&out)).replace("{dir}", arg(d))).collect();
        let o = Run::new(&args).output();
        let stderr = String::from_utf8_lossy(&o.stderr).to_string();
        let message = stderr.lines().find(|l| l.starts_with("trueaxis: error:")).unwrap_or("").to_string();
        let mut problems = Vec::new();
        if o.status.code() != Some(2) {
            problems.push(format!("exit {:?}", o.status.code()));
        }
        let names_file = message.contains(arg(&file))
            || (c.name.starts_with("station") && message.contains("station1.csv"))
            || message.contains("p.ngc");
        if !names_file {
            problems.push("the file is not named".into());
        }
        problems.extend(c.expect.iter().filter(|e| !message.contains(*e)).map(|e| format!("`{e}` missing")));
        if out.exists() {
            problems.push("an output was written".into());
        }
        if !problems.is_empty() {
            failures.push(format!("{}: {}: {message:?} {stderr:?}", c.what, problems.join(", ")));
        }
    }
    assert!(failures.is_empty(), "{} of {} cases fail:\n{}", failures.len(), cases.len(), failures.join("\n"));
}

#[test]
fn options_beyond_what_memory_and_time_allow_are_refused_before_allocating() {
    // a time limit: on a machine not shared with the other tests
    let _alone = alone();
    for (args, expect) in [
        (
            vmc3(
                &["compensate"],
                &[
                    "--errors",
                    "examples/errors/vmc3.toml",
                    "--format",
                    "lattice",
                    "--grid",
                    "100000,100000,100000",
                    "--max-lattice-points",
                    "1000",
                ],
            ),
            "at most 1000000",
        ),
        (
            vmc3(&["compensate"], &["--errors", "examples/errors/vmc3.toml", "--format", "csv", "--points", "10000000"]),
            "more than the 100000 allowed",
        ),
        (
            vec![
                "design",
                "optimal",
                "--machine",
                "examples/machines/kx8five.toml",
                "--campaign",
                "examples/campaigns/kx8five/campaign.toml",
                "--count",
                "40",
                "--starts",
                "100000000",
            ],
            "more than the 100000 allowed",
        ),
        (vec!["thermal", "modes", "--model", "examples/thermal/fin.toml", "--count", "1000000"], "more than the 1000 allowed"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let mut args: Vec<String> = args.iter().map(|s| s.to_string()).collect();
        if args[0] == "compensate" {
            args.extend(["--out".to_string(), dir.path().join("o").display().to_string()]);
        }
        let start = std::time::Instant::now();
        let o = Run::new(&args).limit(Duration::from_secs(20)).output();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(expect), "{args:?}: {stderr}");
        assert!(start.elapsed().as_secs_f64() < 20.0, "{args:?} took {:?}", start.elapsed());
        assert!(!dir.path().join("o").exists());
    }
}
