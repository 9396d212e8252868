//! The thermal figures (`report::thermal`): each SVG is well-formed XML (roxmltree) and draws the
//! expected series at the expected places: normalised mode shapes, the dominant and truncated
//! stems and the truncation share, measured and predicted drift with the residual band, training
//! and validation told apart; non-finite data refused; `--plot` on the `thermal` commands.

use crate::support::thermal::{fit_dz, place_elongation};
use crate::support::{ok, trueaxis};
use roxmltree::Document;
use trueaxis_report::{
    drift_svg, mode_shapes_svg, time_constants_svg, DriftPlot, DriftRun, ModeBar, ModeShapeCurve, ModeShapesPlot, RunRole,
    TimeConstantsPlot,
};

/// A polyline: stroke colour, stroke width, points (px).
type Polyline = (String, String, Vec<(f64, f64)>);

/// Texts (trimmed) and polylines of an SVG document.
struct Svg {
    texts: Vec<String>,
    polylines: Vec<Polyline>,
    circles: usize,
}

fn parse(svg: &str) -> Svg {
    let doc = Document::parse(svg).expect("well-formed SVG");
    let mut out = Svg { texts: Vec::new(), polylines: Vec::new(), circles: 0 };
    for node in doc.descendants() {
        match node.tag_name().name() {
            "text" => out.texts.push(node.text().unwrap_or("").trim().to_string()),
            "circle" => out.circles += 1,
            "polyline" => {
                let points = node
                    .attribute("points")
                    .unwrap_or("")
                    .split_whitespace()
                    .map(|p| {
                        let (x, y) = p.split_once(',').unwrap();
                        (x.parse().unwrap(), y.parse().unwrap())
                    })
                    .collect();
                let attr = |a: &str| node.attribute(a).unwrap_or("").to_string();
                out.polylines.push((attr("stroke"), attr("stroke-width"), points));
            }
            _ => {}
        }
    }
    out
}

impl Svg {
    fn has_text(&self, t: &str) -> bool {
        self.texts.iter().any(|x| x == t)
    }

    /// Polylines of a colour and width with `n` points.
    fn lines(&self, stroke: &str, width: &str, n: usize) -> Vec<&Vec<(f64, f64)>> {
        self.polylines.iter().filter(|(s, w, p)| s == stroke && w == width && p.len() == n).map(|(_, _, p)| p).collect()
    }
}

const BLUE: &str = "#1F61B5";
const RED: &str = "#CC3C28";
const GREY: &str = "#AAAAAA";

#[test]
fn mode_shapes_are_normalised_and_markers_drawn() {
    // mode 1 rises 0 -> 2 (drawn 0 -> 1), mode 2 runs -3 -> 3 (drawn -1 -> 1)
    let plot = ModeShapesPlot {
        title: "shapes".into(),
        x_label: "x (m)".into(),
        positions: vec![0.0, 0.5, 1.0],
        modes: vec![
            ModeShapeCurve { label: "mode 1, tau 10.00 min".into(), values: vec![0.0, 1.0, 2.0] },
            ModeShapeCurve { label: "mode 2, tau 5.00 min".into(), values: vec![-3.0, 0.0, 3.0] },
        ],
        markers: vec![(0.5, "sensor, node 7".into())],
    };
    let svg = parse(&mode_shapes_svg(&plot).unwrap());
    assert!(svg.has_text("mode 1, tau 10.00 min") && svg.has_text("mode 2, tau 5.00 min") && svg.has_text("sensor, node 7"));
    // the first mode is drawn wider (3 px) than the second (2 px)
    let first = svg.lines(BLUE, "3", 3);
    let second = svg.lines(RED, "2", 3);
    assert_eq!((first.len(), second.len()), (1, 1));
    let (a, b) = (first[0], second[0]);
    // both end at the normalised value 1 (same pixel), both pass the middle at 0.5 and 0 (linear)
    assert!((a[2].1 - b[2].1).abs() <= 1.0, "{a:?} {b:?}");
    assert!((b[1].1 - a[0].1).abs() <= 1.0, "zero of mode 2 at the zero of mode 1");
    assert!(((a[0].1 - a[1].1) - (a[1].1 - a[2].1)).abs() <= 1.0);
    // mode 2 is symmetric about zero: -1 as far below as +1 above
    assert!(((b[0].1 - b[1].1) + (b[2].1 - b[1].1)).abs() <= 1.0);
    // the marker: a vertical line at the middle abscissa
    let middle = a[1].0;
    assert!(svg.polylines.iter().any(|(_, _, p)| p.len() == 2 && (p[0].0 - middle).abs() <= 1.0 && (p[1].0 - middle).abs() <= 1.0));
    // non-finite values are refused rather than drawn
    let mut bad = plot.clone();
    bad.modes[0].values[1] = f64::NAN;
    assert!(mode_shapes_svg(&bad).is_err());
}

#[test]
fn time_constants_mark_the_dominant_modes_and_the_truncation_share() {
    let modes = vec![
        ModeBar { mode: 1, tau_min: 140.98, share: 0.6, dominant: true },
        ModeBar { mode: 2, tau_min: 56.57, share: 0.25, dominant: true },
        ModeBar { mode: 3, tau_min: 20.23, share: 0.1, dominant: false },
        ModeBar { mode: 4, tau_min: 9.77, share: 0.05, dominant: false },
    ];
    let svg = parse(&time_constants_svg(&TimeConstantsPlot { title: "fin".into(), modes, share: 0.8 }).unwrap());
    assert!(svg.has_text("truncation share 80 %: 2 modes") && svg.has_text("dominant (first 80 % of the weight)"));
    assert!(svg.has_text("truncated"));
    // stems 3 px wide: two dominant (blue) and two truncated (grey), plus one legend line each
    let vertical = |stroke: &str| svg.lines(stroke, "3", 2).into_iter().filter(|p| p[0].0 == p[1].0).count();
    assert_eq!((vertical(BLUE), vertical(GREY)), (2, 2));
    // the stems' heights are proportional to the shares: 0.6 vs 0.25
    let heights: Vec<f64> = svg.lines(BLUE, "3", 2).into_iter().filter(|p| p[0].0 == p[1].0).map(|p| p[0].1 - p[1].1).collect();
    assert!((heights[0] / heights[1] - 0.6 / 0.25).abs() < 0.05, "{heights:?}");
    // cumulative share by decreasing weight: 0.6, 0.85, 0.95, 1.0 (4 points, blue, 2 px)
    let cumulative = svg.lines(BLUE, "2", 4);
    assert_eq!(cumulative.len(), 1);
    let c = cumulative[0];
    assert!(c.windows(2).all(|w| w[1].0 > w[0].0 && w[1].1 < w[0].1));
}

fn run(name: &str, role: RunRole, measured: Option<Vec<f64>>) -> DriftRun {
    let times_s: Vec<f64> = (0..11).map(|i| 600.0 * i as f64).collect();
    let predicted = times_s.iter().map(|t| 10.0 * (1.0 - (-t / 3000.0).exp())).collect();
    DriftRun { name: name.into(), role, times_s, measured, predicted }
}

#[test]
fn drift_plot_tells_training_from_validation_and_draws_the_residual_band() {
    let predicted = run("a", RunRole::Training, None).predicted;
    // residuals +0.5 at one sample and -0.25 at another, zero elsewhere
    let mut measured = predicted.clone();
    measured[3] += 0.5;
    measured[7] -= 0.25;
    let plot = DriftPlot {
        title: "dz".into(),
        quantity: "dz (um)".into(),
        model_label: "predicted".into(),
        runs: vec![run("warmup", RunRole::Training, Some(measured.clone())), run("cycle", RunRole::Validation, Some(measured))],
    };
    let svg = parse(&drift_svg(&plot).unwrap());
    for t in [
        "warmup: training",
        "cycle: validation",
        "warmup: residual band [-0.250, 0.500]",
        "cycle: residual band [-0.250, 0.500]",
        "predicted (training)",
        "predicted (validation)",
    ] {
        assert!(svg.has_text(t), "missing `{t}` in {:?}", svg.texts);
    }
    // per run: the prediction (2 px, training blue, validation red) and the residual (1 px) with
    // 11 points, and 11 measured points (plus one legend circle per run)
    assert_eq!((svg.lines(BLUE, "2", 11).len(), svg.lines(RED, "2", 11).len()), (1, 1));
    assert_eq!((svg.lines(BLUE, "1", 11).len(), svg.lines(RED, "1", 11).len()), (1, 1));
    assert_eq!(svg.circles, 2 * (11 + 1));
    // the residual: zero line crossed; the sample of +0.5 is the highest point
    let residual = svg.lines(BLUE, "1", 11)[0];
    let top = residual.iter().enumerate().min_by(|a, b| a.1 .1.total_cmp(&b.1 .1)).unwrap().0;
    let bottom = residual.iter().enumerate().max_by(|a, b| a.1 .1.total_cmp(&b.1 .1)).unwrap().0;
    assert_eq!((top, bottom), (3, 7));
    // a prediction without measurements is a single panel; a NaN is refused
    let alone = DriftPlot { runs: vec![run("p", RunRole::Prediction, None)], ..plot.clone() };
    let svg = parse(&drift_svg(&alone).unwrap());
    assert!(svg.has_text("p: prediction") && !svg.texts.iter().any(|t| t.contains("residual band")));
    let mut bad = plot;
    bad.runs[1].predicted[2] = f64::INFINITY;
    assert!(drift_svg(&bad).is_err());
}

#[test]
fn thermal_commands_write_their_plots() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    // modes: shapes of the first 6 modes along the fin and the time constants of the 8 computed
    ok(&trueaxis(&["thermal", "modes", "--model", "examples/thermal/fin.toml", "--count", "8", "--plot", &path("modes.svg")]));
    let svg = parse(&std::fs::read_to_string(path("modes.svg")).unwrap());
    assert!(svg.has_text("mode 1, tau 140.98 min") && svg.has_text("mode 6, tau 3.53 min") && !svg.has_text("mode 7, tau 2.43 min"));
    assert!(svg.has_text("x (m) along the bar") && svg.texts.iter().any(|t| t.starts_with("truncation share 90 %")));
    // 23 nodes along the bar
    assert_eq!(svg.lines(BLUE, "7", 23).len(), 1);
    // place: the thesis's two sensors marked on the dominant shapes
    ok(&place_elongation(&["--plot", &path("place.svg")]));
    let svg = parse(&std::fs::read_to_string(path("place.svg")).unwrap());
    assert!(svg.has_text("sensor, node 12") && svg.has_text("sensor, node 0") && svg.has_text("mode 3, tau 19.57 min"));
    // fit: training and validation runs; predict: prediction on every run
    let model = path("dz.toml");
    ok(&fit_dz("warmup", &["--out", &model, "--plot", &path("fit.svg")]));
    let svg = parse(&std::fs::read_to_string(path("fit.svg")).unwrap());
    for t in ["warmup: training", "short: validation", "long: validation", "cycle: validation", "warmup: residual band [-2.848, 2.929]"] {
        assert!(svg.has_text(t), "missing `{t}`");
    }
    assert_eq!(svg.lines(BLUE, "2", 241).len() + svg.lines(RED, "2", 241).len(), 4);
    ok(&trueaxis(&["thermal", "predict", "--model", &model, "--data", "examples/thermal/campaign.csv", "--plot", &path("pred.svg")]));
    let svg = parse(&std::fs::read_to_string(path("pred.svg")).unwrap());
    assert!(svg.has_text("cycle: prediction") && svg.has_text("short: residual band [-3.218, 3.429]"));
    // eq. 3.17: each record with its fit
    ok(&trueaxis(&[
        "thermal",
        "fit",
        "--data",
        "examples/thermal/campaign.csv",
        "--time-constants",
        "2",
        "--train-runs",
        "warmup",
        "--until",
        "14400",
        "--plot",
        &path("taus.svg"),
    ]));
    let svg = parse(&std::fs::read_to_string(path("taus.svg")).unwrap());
    assert!(svg.has_text("warmup T:p1: training") && svg.has_text("eq. 3.17 fit (training)"));
    // a plot that cannot be written: exit 2, one line naming the file, nothing else written
    let missing = dir.path().join("no/such/dir/m.svg");
    let out = trueaxis(&["thermal", "modes", "--model", "examples/thermal/fin.toml", "--plot", missing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("m.svg") && err.lines().count() == 1, "{err}");
}
