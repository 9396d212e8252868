//! `trueaxis uncertainty` end to end: the shipped Andolfatto et al. 2011 example against the library, JSON keys,
//! reproducibility with a seed, plots, exit codes and messages for bad input.

use crate::support::{arg, trueaxis, utf8, ROOT};
use trueaxis::uncertainty::{run_budget, DesignMatrix, Evaluation, IdentificationMap, Sources};

const DESIGN: &str = "examples/uncertainty/kx8five_design.csv";
const CYCLIC: &str = "examples/uncertainty/kx8five_cyclic.toml";
const STATISTICAL: &str = "examples/uncertainty/kx8five_statistical.toml";

/// The JSON document of a successful run that printed nothing on stderr.
fn json(args: &[&str]) -> serde_json::Value {
    let out = trueaxis(args);
    let doc = crate::support::json(&out);
    assert!(out.stderr.is_empty(), "quiet with --json: {}", utf8(&out.stderr));
    doc
}

#[test]
fn json_matches_the_library_and_is_reproducible() {
    let doc = json(&["uncertainty", "--design", DESIGN, "--sources", CYCLIC, "--json"]);
    let root = std::path::Path::new(ROOT);
    let map = IdentificationMap::new(DesignMatrix::read_csv(root.join(DESIGN)).unwrap()).unwrap();
    let sources = Sources::load(root.join(CYCLIC)).unwrap();
    let budget = run_budget(&map, &sources.sources, &sources.settings, Evaluation::Reduced, true, &mut |_, _, _| {}).unwrap();
    assert_eq!(doc["observations"], 2421);
    assert_eq!(doc["sequences"].as_u64().unwrap() as usize, budget.total.sequences);
    assert_eq!(doc["converged"], true);
    assert_eq!(doc["seed"], 4);
    assert_eq!(doc["sources"], serde_json::json!(["drift", "sensors", "transformation"]));
    assert_eq!(doc["parameter_order"][0], "EC0Y");
    for (j, row) in budget.rows.iter().enumerate() {
        let p = &doc["parameters"][&row.parameter];
        assert_eq!(p["unit"], row.unit.as_str());
        // the binary and this test may be compiled with other optimisations: equal to rounding
        let same = |v: &serde_json::Value, x: f64| (v.as_f64().unwrap() - x).abs() <= 1e-9 * (1.0 + x.abs());
        assert!(same(&p["std_uncertainty"], budget.total.outputs[j].std_uncertainty));
        assert!(same(&p["interval"][1], budget.total.outputs[j].symmetric.high));
        assert!(same(&p["budget_interval_widths"]["drift"], row.widths[0]));
        assert!(same(&p["budget_interval_widths"]["total"], row.total));
        assert!((p["gum"]["std_uncertainty"].as_f64().unwrap() - row.gum_total_u).abs() < 1e-12);
    }
    // same seed, same document; another seed, other trials
    assert_eq!(doc, json(&["uncertainty", "--design", DESIGN, "--sources", CYCLIC, "--json"]));
    let other = json(&["uncertainty", "--design", DESIGN, "--sources", CYCLIC, "--json", "--seed", "5", "--no-budget"]);
    assert_eq!(other["seed"], 5);
    assert_ne!(other["parameters"]["EC0Y"]["std_uncertainty"], doc["parameters"]["EC0Y"]["std_uncertainty"]);
    assert!(other["parameters"]["EC0Y"]["budget_interval_widths"].get("drift").is_none());
}

#[test]
fn statistical_intervals_are_narrower_and_plots_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let plots = dir.path().join("plots");
    let cyc = json(&["uncertainty", "--design", DESIGN, "--sources", CYCLIC, "--json", "--no-budget"]);
    let stat = json(&["uncertainty", "--design", DESIGN, "--sources", STATISTICAL, "--json", "--plots", arg(&plots)]);
    for name in ["EC0Y", "EA0Z", "EB0Z", "EB0A", "EA0A", "EA0C", "EB0C", "EX0C"] {
        let width = |d: &serde_json::Value| {
            let i = &d["parameters"][name]["interval"];
            i[1].as_f64().unwrap() - i[0].as_f64().unwrap()
        };
        assert!(width(&stat) < width(&cyc), "{name}");
    }
    for file in ["histograms.svg", "convergence.svg"] {
        let svg = std::fs::read_to_string(plots.join(file)).unwrap();
        assert!(svg.starts_with("<svg") && !svg.contains("NaN"), "{file}");
    }
    // the readable table names the budget columns
    let out = trueaxis(&["uncertainty", "--design", DESIGN, "--sources", STATISTICAL]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && text.contains("budget") && text.contains("transformation") && text.contains("converged"));
}

#[test]
fn bad_input_exits_2_with_one_line_naming_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        arg(&p).to_string()
    };
    let design = write("d.csv", "channel,t,a,b\nx,1,1,0\ny,2,0,1\nx,3,1,1\ny,4,1,-1\n");
    let good = "[[source]]\nname = \"s\"\nkind = \"noise\"\nchannels.x = { distribution = \"normal\", u = 0.3 }\n";
    let cases = [
        (write("d1.csv", "chan,t,a\nx,1,1\n"), write("s1.toml", good), "needs the columns `channel` and `t`"),
        (design.clone(), write("s2.toml", &good.replace("u = 0.3", "u = 0.3, sigma = 1")), "unknown field `sigma`"),
        (design.clone(), write("s3.toml", &good.replace("channels.x", "channels.w")), "channel `w` is not in the design"),
        (design.clone(), write("s4.toml", &good.replace("normal", "lognormal")), "lognormal"),
        (design.clone(), write("s5.toml", &format!("coverage = 1.5\n{good}")), "coverage probability 1.5"),
        (design.clone(), write("s6.toml", &format!("trials_per_sequence = 100\n{good}")), "at least 100 / (1 - p) = 2000"),
        (design.clone(), write("s7.toml", "seed = 1\n"), "no [[source]] given"),
        (
            design.clone(),
            write(
                "s8.toml",
                "[[source]]\nname = \"d\"\nkind = \"drift_cyclic\"\nperiod_s = 10\nchannels.x = { peak_to_valley = 1, samples = [1, 2] }\n",
            ),
            "give exactly one of",
        ),
        ("missing.csv".to_string(), write("s9.toml", good), "missing.csv"),
    ];
    for (d, s, expected) in cases {
        let out = trueaxis(&["uncertainty", "--design", &d, "--sources", &s, "--json"]);
        assert_eq!(out.status.code(), Some(2), "{expected}: {}", utf8(&out.stderr));
        let err = utf8(&out.stderr);
        assert!(err.contains(expected), "expected `{expected}` in: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(out.stdout.is_empty());
    }
    // a rank-deficient design is a failed computation (exit 1) naming the parameters
    let deficient = write("d2.csv", "channel,t,a,b\nx,1,1,2\ny,2,2,4\nx,3,1,2\ny,4,3,6\n");
    let out = trueaxis(&["uncertainty", "--design", &deficient, "--sources", &write("s10.toml", good)]);
    assert_eq!(out.status.code(), Some(1), "{}", utf8(&out.stderr));
    assert!(utf8(&out.stderr).contains("b cannot be separated from a"), "{}", utf8(&out.stderr));
}
