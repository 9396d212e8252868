//! Thermal links from the command line (Zhu 2008 ch. 4): the steady-state link deformations of
//! the reconfigurable arch machine of Zhu 2008 Table 4.2 (epsilon um along x, delta um along y,
//! theta arcsec about z) in a 2D arch machine (X table; Y slide on the arch; the spindle swivel C at
//! -10, 0, +10 deg, the three configurations), through `thermal links` and `predict`, against the
//! chain of link HTMs of Zhu 2008 eq. 4.2 multiplied out independently with 4x4 matrices. The link
//! terms are first order: the difference is second order (0.005 um for errors of 227 um, and
//! 100 times smaller at a tenth of the deformations). And the vmc3 example file against its closed
//! form.

use crate::support::{arg, json, read, trueaxis, vmc3};
use std::fmt::Write;

const MACHINE: &str = r#"
name = "2D arch-type reconfigurable machine (Zhu 2008 ch. 4)"
structure = "wXbYCt"
[axes]
X = { kind = "linear", direction = [1, 0, 0], range = [-200, 200] }
Y = { kind = "linear", direction = [0, 1, 0], range = [0, 300] }
C = { kind = "rotary", direction = [0, 0, 1], point = [0, 600, 0], range = [-10, 10] }
[tool]
point = [0, 400, 0]
"#;

const ARCSEC_URAD: f64 = std::f64::consts::PI / 648_000.0 * 1e6;

/// A link of Table 4.2: name, target, free end (mm), [eps um, delta um, theta arcsec] at C = -10, 0, +10.
type Link = (&'static str, &'static str, [f64; 3], [[f64; 3]; 3]);

/// Table 4.2, the deformations times `scale`.
fn table_4_2(scale: f64) -> Vec<Link> {
    let same = |v: [f64; 3]| [v, v, v];
    let s = |v: [[f64; 3]; 3]| v.map(|r| r.map(|x| x * scale));
    vec![
        ("M-0 base, workpiece side", "X", [0.0, -150.0, 0.0], s(same([-74.38, 62.62, 4.48]))),
        ("M1 X unit", "X", [100.0, -50.0, 0.0], s([[10.99, 44.81, -2.34], [8.53, 38.04, -48.17], [7.83, 30.96, -2.11]])),
        ("M0 base, arch foot", "Y", [-300.0, 0.0, 0.0], s(same([27.14, 47.87, -20.43]))),
        ("M2 arch", "Y", [0.0, 700.0, 0.0], s(same([41.39, 21.14, 3.37]))),
        ("M3 Y unit", "C", [0.0, 650.0, 0.0], s(same([11.18, -22.83, 0.24]))),
    ]
}

/// An inline model of the value at C = -10, 0, 10 deg: the quadratic in C through the three.
fn quadratic(v: [f64; 3]) -> String {
    let (a0, a1, a2) = (v[1], (v[2] - v[0]) / 20.0, (v[2] + v[0] - 2.0 * v[1]) / 200.0);
    format!("{{ sensors = [], position = \"C\", coefficients = [[{a0:e}], [{a1:e}], [{a2:e}]] }}")
}

fn links_file(scale: f64) -> String {
    let mut text = String::new();
    for (name, target, f, v) in table_4_2(scale) {
        let column = |k: usize| [v[0][k], v[1][k], v[2][k]];
        let theta = column(2).map(|a| a * ARCSEC_URAD);
        let _ = write!(
            text,
            "[[link]]\nname = \"{name}\"\ntarget = \"{target}\"\nfree_end_mm = [{}, {}, {}]\nalong = [1, 0, 0]\nacross = [0, 1, 0]\n\
             epsilon = {}\ndelta = {}\ntheta = {}\n\n",
            f[0],
            f[1],
            f[2],
            quadratic(column(0)),
            quadratic(column(1)),
            quadratic(theta)
        );
    }
    text
}

type M4 = [[f64; 4]; 4];

fn mul(a: &M4, b: &M4) -> M4 {
    let mut c = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            c[i][j] = (0..4).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

fn trans(t: [f64; 3]) -> M4 {
    [[1.0, 0.0, 0.0, t[0]], [0.0, 1.0, 0.0, t[1]], [0.0, 0.0, 1.0, t[2]], [0.0, 0.0, 0.0, 1.0]]
}

fn rot_z(a: f64) -> M4 {
    let (s, c) = a.sin_cos();
    [[c, -s, 0.0, 0.0], [s, c, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
}

/// The link HTM about its free end f: rotation theta about z, then the translation (eps, delta)
/// (mm, rad): `Trans(f) [Rz(theta), (eps, delta, 0)] Trans(-f)`.
fn link(f: [f64; 3], v: [f64; 3]) -> M4 {
    let mut d = rot_z(v[2]);
    d[0][3] = v[0];
    d[1][3] = v[1];
    mul(&mul(&trans(f), &d), &trans([-f[0], -f[1], -f[2]]))
}

/// Tool point relative to the workpiece origin, in the workpiece frame (mm), and the tool direction
/// angle about z (rad): Zhu 2008 eq. 4.2 with the link HTMs, or nominal with `with_links = false`.
fn chain(x: f64, y: f64, c_deg: f64, config: usize, scale: f64, with_links: bool) -> ([f64; 2], f64) {
    let links: Vec<M4> = table_4_2(scale)
        .iter()
        .map(|(_, _, f, v)| {
            let v = v[config];
            let v = if with_links { [v[0] * 1e-3, v[1] * 1e-3, v[2] * ARCSEC_URAD * 1e-6] } else { [0.0; 3] };
            link(*f, v)
        })
        .collect();
    let c = c_deg.to_radians();
    let jc = mul(&mul(&trans([0.0, 600.0, 0.0]), &rot_z(c)), &trans([0.0, -600.0, 0.0]));
    // workpiece side: base link, X unit link, then the X slide
    let work = mul(&mul(&links[0], &links[1]), &trans([x, 0.0, 0.0]));
    // tool side: arch foot, arch, Y slide, Y unit, C swivel, tool point
    let tool = [&links[2], &links[3], &trans([0.0, y, 0.0]), &links[4], &jc, &trans([0.0, 400.0, 0.0])]
        .iter()
        .fold(trans([0.0; 3]), |a, b| mul(&a, b));
    // work^-1 tool for a rigid transform: R^T (t_tool - t_work), angle difference
    let (r, t) = (work, [tool[0][3] - work[0][3], tool[1][3] - work[1][3]]);
    let p = [r[0][0] * t[0] + r[1][0] * t[1], r[0][1] * t[0] + r[1][1] * t[1]];
    let angle = tool[1][0].atan2(tool[0][0]) - work[1][0].atan2(work[0][0]);
    (p, angle)
}

fn largest_difference(scale: f64) -> (f64, f64) {
    let dir = tempfile::tempdir().unwrap();
    let machine = dir.path().join("arch.toml");
    std::fs::write(&machine, MACHINE).unwrap();
    let links = dir.path().join("links.toml");
    std::fs::write(&links, links_file(scale)).unwrap();
    let errors = dir.path().join("errors.toml");
    let out = trueaxis(&["thermal", "links", "--machine", arg(&machine), "--links", arg(&links), "--out", arg(&errors), "--json"]);
    let doc = json(&out);
    assert_eq!(doc["links"].as_array().unwrap().len(), 5);
    assert_eq!(doc["sensors"].as_array().unwrap().len(), 0, "constant links need no inputs");
    let mut poses = String::from("X,Y,C\n");
    let mut states = Vec::new();
    for (config, c) in [-10.0, 0.0, 10.0].into_iter().enumerate() {
        for x in [-200.0, 0.0, 200.0] {
            for y in [0.0, 150.0, 300.0] {
                let _ = writeln!(poses, "{x},{y},{c}");
                states.push((x, y, c, config));
            }
        }
    }
    let poses_path = dir.path().join("poses.csv");
    std::fs::write(&poses_path, poses).unwrap();
    let predicted =
        json(&trueaxis(&["predict", "--machine", arg(&machine), "--errors", arg(&errors), "--poses", arg(&poses_path), "--json"]));
    let (mut worst, mut largest) = (0.0f64, 0.0f64);
    for ((x, y, c, config), p) in states.iter().zip(predicted["poses"].as_array().unwrap()) {
        let (actual, a1) = chain(*x, *y, *c, *config, scale, true);
        let (nominal, a0) = chain(*x, *y, *c, *config, scale, false);
        let want = [(actual[0] - nominal[0]) * 1e3, (actual[1] - nominal[1]) * 1e3, (a1 - a0) * 1e6];
        let got = [p["dx"].as_f64().unwrap(), p["dy"].as_f64().unwrap(), p["drz"].as_f64().unwrap()];
        for k in 0..3 {
            worst = worst.max((got[k] - want[k]).abs());
        }
        largest = largest.max(want[0].abs().max(want[1].abs()));
        assert!(p["dz"].as_f64().unwrap().abs() < 1e-4 && p["drx"].as_f64().unwrap().abs() < 1e-4, "in-plane deformations only");
    }
    (worst, largest)
}

#[test]
fn table_4_2_links_through_the_chain_equal_the_link_htms_to_second_order() {
    let (full, largest) = largest_difference(1.0);
    assert!(largest > 100.0, "the deformations are seen: {largest} um");
    assert!(full < 0.02, "first-order terms vs the exact HTM chain: {full} um");
    // second order: a tenth of the deformations gives a hundredth of the difference (+ rounding
    // of the 4-decimal output)
    let (tenth, _) = largest_difference(0.1);
    eprintln!("largest error {largest:.2} um; first order vs HTM chain {full:.5} um, at a tenth {tenth:.6} um");
    assert!(tenth < full / 50.0 + 2e-4, "{tenth} vs {full}");
}

#[test]
fn vmc3_links_example_is_its_closed_form() {
    let doc = json(&trueaxis(&vmc3(&["thermal", "links"], &["--links", "examples/thermal/links_vmc3.toml", "--json"])));
    assert_eq!(doc["sensors"], serde_json::json!(["T:col_front", "T:col_back", "T:spindle"]));
    // the column: theta = -18 urad/K of the front-back difference about w = z x y = -x gives EA0Z
    // = +18 urad per K of the front; the slope moves the Z reference (origin) by w x (0 - f) theta
    let sum = |name: &str, sensor: &str| -> f64 {
        doc["links"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|l| l["terms"].as_array().unwrap().clone())
            .filter(|t| t["parameter"] == name && t["factors"].get(sensor).is_some())
            .map(|t| t["coefficient"].as_f64().unwrap())
            .sum()
    };
    assert!((sum("EA0Z", "T:col_front") - 18.0).abs() < 1e-12);
    // EY0Z: delta -4.5 plus theta lever: (w x (0 - f))_y = -500 mm * 1e-3 um/urad * -18 = +9
    assert!((sum("EY0Z", "T:col_front") - (-4.5 + 9.0)).abs() < 1e-12);
    // EZ0Z: epsilon 2.7 plus (w x (0 - f))_z theta = -300e-3 * -18 = 5.4
    assert!((sum("EZ0Z", "T:col_front") - (2.7 + 5.4)).abs() < 1e-12);
    // the spindle grows down: TZ = -2.16 um/K
    assert!((sum("TZ", "T:spindle") + 2.16).abs() < 1e-12);
    // with the geometric errors, as one file predict and compensate read
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("vmc3_links.toml");
    crate::support::ok(&trueaxis(&vmc3(
        &["thermal", "links"],
        &["--links", "examples/thermal/links_vmc3.toml", "--errors-in", "examples/errors/vmc3.toml", "--out", arg(&out)],
    )));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with(&read("examples/errors/vmc3.toml")));
    // a slope on the tool is refused
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        "[[link]]\nname = \"ram\"\ntarget = \"tool\"\nfree_end_mm = [0, 0, 400]\nalong = [0, 0, 1]\nacross = [1, 0, 0]\ntheta = 3.0\n",
    )
    .unwrap();
    let o = trueaxis(&vmc3(&["thermal", "links"], &["--links", arg(&bad)]));
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("link `ram`: a slope theta cannot be given to the tool"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
