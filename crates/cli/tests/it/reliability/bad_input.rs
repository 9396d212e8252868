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
    let mut cases = vec![
        // machine file
        case("machine malformed", "m.toml", with(&machine, "structure = \"wXYbZt\"", "structure = "), predict_m, &["line"]),
        case(
            "machine huge",
            "m.toml",
            with(&machine, "point = [0, 0, 400]", "point = [0, 0, 1e200]"),
            predict_m,
            &["line 22", "[tool] point", "physical range"],
        ),
        case(
            "machine 1e308",
            "m.toml",
            with(&machine, "range = [-400, 400]", "range = [-400, 1e308]"),
            predict_m,
            &["axis X", "physical range"],
        ),
        case("machine nan", "m.toml", with(&machine, "point = [0, 0, 400]", "point = [0, 0, nan]"), predict_m, &["[tool] point", "finite"]),
        case(
            "machine out of range",
            "m.toml",
            with(&machine, "range = [-250, 250]", "range = [-250, 250000000]"),
            predict_m,
            &["axis Y", "100 m"],
        ),
        case("machine limit", "m.toml", machine.clone() + "\n[limits]\ncorrection_um = -1\n", predict_m, &["[limits] correction_um"]),
        case("machine empty", "m.toml", String::new(), predict_m, &["missing field"]),
        // error values
        case("errors malformed", "e.toml", with(&errors, "EC0X = 25.0", "EC0X = 25.0.0"), predict_e, &["line"]),
        case(
            "errors huge",
            "e.toml",
            with(&errors, "EC0X = 25.0", "EC0X = 1e200"),
            predict_e,
            &["line 7", "EC0X", "physical range of an angular error"],
        ),
        case(
            "errors 1e308",
            "e.toml",
            with(&errors, "coefficients = [1.5, -0.012]", "coefficients = [1.5, 1e308]"),
            predict_e,
            &["EXX+", "at X", "physical range"],
        ),
        case("errors nan", "e.toml", with(&errors, "EC0X = 25.0", "EC0X = nan"), predict_e, &["EC0X", "finite"]),
        case("errors out of range", "e.toml", with(&errors, "EC0X = 25.0", "EC0X = 2e5"), predict_e, &["EC0X", "0.1 rad"]),
        case("errors empty", "e.toml", "name = \"nothing\"\n".into(), predict_e, &["defines no error"]),
        // pose CSV
        case("poses duplicated column", "p.csv", "X,X,Y,Z\n1,2,3,-4\n".into(), predict_p, &["line 1", "same column `X`"]),
        case("poses nan", "p.csv", "X,Y,Z\n1,nan,-4\n".into(), predict_p, &["line 2", "finite"]),
        case("poses missing column", "p.csv", "X,Y\n1,2\n".into(), predict_p, &["Z"]),
        case("poses huge temperature", "p.csv", "X,Y,Z,T:bed\n1,2,-4,1e200\n".into(), predict_p, &["line 2", "T:bed", "temperature"]),
        case("poses empty", "p.csv", String::new(), predict_p, &["empty"]),
        // ballbar table
        case("ballbar huge", "b.csv", with(&ballbar, ",ccw,1.7906", ",ccw,1e200"), iso4, &["line 3", "dL", "physical range"]),
        case("ballbar nan", "b.csv", with(&ballbar, ",ccw,1.7906", ",ccw,nan"), iso4, &["line 3", "dL"]),
        case("ballbar out of range", "b.csv", with(&ballbar, ",ccw,1.7906", ",ccw,250000"), iso4, &["line 3", "dL", "physical range"]),
        case(
            "ballbar duplicated column",
            "b.csv",
            with(&ballbar, "X,Y,Z,angle,dir,dL", "X,Y,Z,angle,dL,dL"),
            iso4,
            &["line 2", "same column"],
        ),
        case("ballbar empty", "b.csv", String::new(), iso4, &["empty"]),
        // laser CSV and .rtl
        case("laser huge", "l.csv", with(&laser, "-400,-1.914,", "-400,1e200,"), iso2, &["line 5", "dev", "physical range"]),
        case("laser inf", "l.csv", with(&laser, "-400,-1.914,", "-400,inf,"), iso2, &["line 5", "dev"]),
        case(
            "laser duplicated column",
            "l.csv",
            with(&laser, "target,dev,dir,run,t", "target,dev,dir,run,dev"),
            iso2,
            &["same column `dev`"],
        ),
        case("laser missing column", "l.csv", with(&laser, "target,dev,dir,run,t", "target,deviation_x,dir,run,t"), iso2, &["dev"]),
        case("laser empty", "l.csv", String::new(), iso2, &["empty"]),
        case("rtl huge", "l.rtl", with(&rtl, "1   1      -0.001914", "1   1      1e200"), iso2, &["physical range"]),
        case("rtl malformed", "l.rtl", with(&rtl, "1   1      -0.001914", "1   1      minus"), iso2, &["minus"]),
        // campaign readings (the campaign TOML next to it, copied by the runner)
        case("campaign huge", "station1.csv", with(&station, "2.1063", "1e200"), identify, &["line 3", "dL", "physical range"]),
        case("campaign nan", "station1.csv", with(&station, "2.1063", "NaN"), identify, &["line 3", "dL"]),
        case("campaign duplicated column", "station1.csv", with(&station, "X,Y,Z,dL", "X,X,Z,dL"), identify, &["same column `X`"]),
        case("campaign missing column", "station1.csv", with(&station, "X,Y,Z,dL", "X,Y,dL"), identify, &["Z"]),
        case("campaign empty", "station1.csv", String::new(), identify, &["empty"]),
        // thermal campaign
        case(
            "thermal huge temperature",
            "t.csv",
            with(&thermal, "warmup,0,20.002,", "warmup,0,1e200,"),
            tfit,
            &["line 3", "T:p1", "temperature"],
        ),
        case(
            "thermal out of range",
            "t.csv",
            with(&thermal, "warmup,0,20.002,", "warmup,0,500,"),
            tfit,
            &["line 3", "T:p1", "temperature"],
        ),
        case("thermal huge drift", "t.csv", with(&thermal, "20.009,-0.13", "20.009,1e300"), tfit, &["line 3", "dz", "physical range"]),
        case("thermal nan", "t.csv", with(&thermal, "20.009,-0.13", "20.009,nan"), tfit, &["line 3", "dz"]),
        case("thermal duplicated column", "t.csv", with(&thermal, "run,t,T:p1,T:p5,dz", "run,t,T:p1,T:p1,dz"), tfit, &["same column"]),
        case("thermal empty", "t.csv", String::new(), tfit, &["empty"]),
        // uncertainty sources
        case("sources malformed", "s.toml", with(&sources, "coverage = 0.95", "coverage = "), unc, &["line"]),
        case("sources nan", "s.toml", with(&sources, "tolerance = 0.05", "tolerance = nan"), unc, &["tolerance"]),
        case(
            "sources trials",
            "s.toml",
            with(&sources, "trials_per_sequence = 10000", "trials_per_sequence = 1000000000000000"),
            unc,
            &["trials_per_sequence", "more than"],
        ),
        // NC, both dialects (rs274 refuses the same programs: crates/trueaxis/tests/it/compensate/nc/bad_programs.rs)
        case("nc arc radius", "p.ngc", "G21 G90 G17\nG0 X0 Y0 Z-10\nG2 X10 Y0 I1 J0 F100\nM2\n".into(), nc, &["line 3", "radius"]),
        case("nc two motion codes", "p.ngc", "G21 G90\nG0 G1 X10 F100\nM2\n".into(), nc, &["line 2", "G0 and G1", "modal group"]),
        case("nc malformed", "p.ngc", "G21 G90\nG1 X1..2 F100\nM2\n".into(), nc, &["line 2"]),
        case("nc huge", "p.ngc", "G21 G90\nG1 X1e200 F100\nM2\n".into(), nc, &["line 2", "E word"]),
        case("fanuc two motion codes", "p.nc", "%\nO1000\nG21 G90\nG00 G01 X10. F100.\nM30\n%\n".into(), nc, &["line 4", "modal group"]),
        case(
            "nc correction limit",
            "p.ngc",
            "G21 G90\nG0 X-400 Y-250 Z-100\nM2\n".into(),
            &vmc3(&["nc"], &["--errors", "{dir}/e.toml", "{f}", "--out", "{out}"]),
            &["line 2", "beyond the limit of 1000 um", "correction_um"],
        ),
    ];
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
            vec![
                "compensate",
                "--machine",
                "examples/machines/vmc3.toml",
                "--errors",
                "examples/errors/vmc3.toml",
                "--format",
                "lattice",
                "--grid",
                "100000,100000,100000",
                "--max-lattice-points",
                "1000",
            ],
            "at most 1000000",
        ),
        (
            vec![
                "compensate",
                "--machine",
                "examples/machines/vmc3.toml",
                "--errors",
                "examples/errors/vmc3.toml",
                "--format",
                "csv",
                "--points",
                "10000000",
            ],
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
