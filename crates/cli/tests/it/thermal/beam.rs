//! `thermal beam`: the stress-free beam model (Soons 1993 §3.4.3) of the vmc3 X guideway. A uniform
//! vertical gradient gives the closed forms eps_y = alpha d x, e_z = -alpha d x^2 / 2, e_x =
//! alpha a x; a field that varies along the beam and across it, over three stations, equals an
//! independent numerical integration of eqs. 3.58-3.62 (Simpson, 1 mm steps). Both through the
//! written error terms, read back as an error model of the machine.

use crate::support::{arg, json, trueaxis, vmc3, ROOT};
use std::fmt::Write;
use std::path::Path;
use trueaxis::error_model::{ErrorModel, MachineState};
use trueaxis::machine::{Machine, ParameterId};

/// Motion errors of X (um, urad) at X = `x` with the beam's sensors at `readings`.
fn values(errors: &ErrorModel, m: &Machine, x: f64, readings: &[(&str, f64)]) -> [f64; 6] {
    let temps: Vec<f64> = errors.sensors().iter().map(|s| readings.iter().find(|(n, _)| n == s).map_or(20.0, |(_, v)| *v)).collect();
    let mut q = [0.0; 3];
    m.pose_to_internal(&[x, 0.0, 0.0], &mut q);
    let mut v = vec![0.0; m.parameter_count()];
    errors.values_at_state(m, &q, &MachineState { directions: None, temperatures: &temps }, &mut v);
    ["EXX", "EYX", "EZX", "EAX", "EBX", "ECX"].map(|n| {
        let id = ParameterId::parse(n).unwrap();
        v[m.parameter_index(&id).unwrap()] / id.component().to_internal()
    })
}

fn write_terms(beam: &Path, dir: &Path) -> ErrorModel {
    let out = dir.join("beam_terms.toml");
    crate::support::ok(&trueaxis(&vmc3(&["thermal", "beam"], &["--beam", arg(beam), "--out", arg(&out)])));
    ErrorModel::load(&out, &Machine::load(Path::new(ROOT).join("examples/machines/vmc3.toml")).unwrap()).unwrap()
}

#[test]
fn uniform_vertical_gradient_is_the_closed_form() {
    let dir = tempfile::tempdir().unwrap();
    let m = Machine::load(Path::new(ROOT).join("examples/machines/vmc3.toml")).unwrap();
    let errors = write_terms(&Path::new(ROOT).join("examples/thermal/beam_x.toml"), dir.path());
    // top sensors 23 degC, bottom 21: a = 2 K, d = 2 K / 200 mm; alpha 11.5 um/m/K; fixed at X = 0
    let readings: Vec<(&str, f64)> = ["T:x1", "T:x2", "T:x5", "T:x6"]
        .map(|s| (s, 23.0))
        .into_iter()
        .chain(["T:x3", "T:x4", "T:x7", "T:x8"].map(|s| (s, 21.0)))
        .collect();
    let (alpha, a, d) = (11.5, 2.0, 0.01);
    for x in [-400.0, -250.0, 0.0, 130.0, 399.0] {
        let (e_x, eps_y, e_z) = (alpha * 1e-3 * a * x, alpha * d * x, -1e-3 * alpha * d * x * x / 2.0);
        let v = values(&errors, &m, x, &readings);
        // beam frame to M: x along -x, y along -y, z along +z
        let want = [-e_x, 0.0, e_z, 0.0, -eps_y, 0.0];
        for k in 0..6 {
            assert!((v[k] - want[k]).abs() < 1e-9, "X {x}, component {k}: {} vs {}", v[k], want[k]);
        }
    }
    // the printed profile at the same readings
    let at = readings.iter().map(|(n, t)| format!("{n}={t}")).collect::<Vec<_>>().join(",");
    let doc = json(&trueaxis(&vmc3(&["thermal", "beam"], &["--beam", "examples/thermal/beam_x.toml", "--at", &at, "--json"])));
    let end = doc["profile"].as_array().unwrap().last().unwrap();
    assert!((end["e_z_um"].as_f64().unwrap() + 9.2).abs() < 1e-9 && (end["eps_y_urad"].as_f64().unwrap() - 46.0).abs() < 1e-9);
}

/// The field of the varied beam at station k: `(a, c, d)`.
const FIELD: [(f64, [f64; 3]); 3] = [(-400.0, [3.0, 0.02, -0.01]), (100.0, [1.0, -0.01, 0.03]), (400.0, [2.5, 0.005, 0.0])];

#[test]
fn varying_field_equals_numerical_integration() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("axis = \"X\"\ny_direction = [0, -1, 0]\nalpha_um_per_m_k = 10.8\nfixed_at_mm = -150.0\n");
    let corners = [(-80.0, 60.0), (80.0, 60.0), (-80.0, -60.0), (80.0, -60.0), (0.0, 0.0)];
    let mut readings = Vec::new();
    for (k, (x, [a, c, d])) in FIELD.iter().enumerate() {
        let _ = write!(text, "[[station]]\nat_mm = {x}\nsensors = [");
        for (j, (y, z)) in corners.iter().enumerate() {
            let name = format!("T:s{k}{j}");
            let _ = write!(text, "{{ name = \"{name}\", y = {y}, z = {z} }}, ");
            readings.push((name, 20.0 + a + c * y + d * z));
        }
        text += "]\n";
    }
    let beam = dir.path().join("beam.toml");
    std::fs::write(&beam, text).unwrap();
    let m = Machine::load(Path::new(ROOT).join("examples/machines/vmc3.toml")).unwrap();
    let errors = write_terms(&beam, dir.path());
    let named: Vec<(&str, f64)> = readings.iter().map(|(n, t)| (n.as_str(), *t)).collect();
    // the interpolated field and the integrals by Simpson's rule from the fixed point
    let field = |x: f64| -> [f64; 3] {
        let i = if x < FIELD[1].0 { 0 } else { 1 };
        let (x0, f0) = FIELD[i];
        let (x1, f1) = FIELD[i + 1];
        let t = (x - x0) / (x1 - x0);
        [0, 1, 2].map(|k| f0[k] + t * (f1[k] - f0[k]))
    };
    let integral = |f: &dyn Fn(f64) -> f64, from: f64, to: f64| -> f64 {
        let n = ((to - from).abs().ceil() as usize).max(1) * 2;
        let h = (to - from) / n as f64;
        (0..=n)
            .map(|i| {
                f(from + i as f64 * h)
                    * if i == 0 || i == n {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    }
            })
            .sum::<f64>()
            * h
            / 3.0
    };
    let alpha = 10.8;
    let fixed = -150.0;
    let eps_y = |x: f64| integral(&|s| alpha * field(s)[2], fixed, x);
    let eps_z = |x: f64| -integral(&|s| alpha * field(s)[1], fixed, x);
    for x in [-400.0, -150.0, 0.0, 100.0, 250.0, 400.0] {
        // the station at 100 mm (a kink of the field) falls on a Simpson node for these x
        let e_x = alpha * 1e-3 * integral(&|s| field(s)[0], fixed, x);
        let e_y = 1e-3 * integral(&eps_z, fixed, x);
        let e_z = -1e-3 * integral(&eps_y, fixed, x);
        let v = values(&errors, &m, x, &named);
        let want = [-e_x, -e_y, e_z, 0.0, -eps_y(x), eps_z(x)];
        for k in 0..6 {
            assert!((v[k] - want[k]).abs() < 1e-6 * (1.0 + want[k].abs()), "X {x}, component {k}: {} vs {}", v[k], want[k]);
        }
    }
}

#[test]
fn beam_input_errors() {
    let dir = tempfile::tempdir().unwrap();
    let bad = |text: &str, fragment: &str| {
        let p = dir.path().join("b.toml");
        std::fs::write(&p, text).unwrap();
        let out = trueaxis(&vmc3(&["thermal", "beam"], &["--beam", arg(&p)]));
        assert_eq!(out.status.code(), Some(2));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(fragment), "expected `{fragment}` in {stderr}");
    };
    let head = "axis = \"X\"\ny_direction = [0, -1, 0]\nalpha_um_per_m_k = 11.5\n";
    let two = "[[station]]\nat_mm = -400\nsensors = [{ name = \"T:a\", y = 0, z = 1 }, { name = \"T:b\", y = 0, z = -1 }]\n\
               [[station]]\nat_mm = 400\nsensors = [{ name = \"T:c\", y = 0, z = 1 }, { name = \"T:d\", y = 1, z = -1 }, { name = \"T:e\", y = -1, z = 0 }]\n";
    bad(&format!("{head}{two}"), "station at -400 mm: a linear field a + c y + d z needs at least three sensors not on one line");
    let short = "[[station]]\nat_mm = -100\nsensors = [{ name = \"T:a\", y = 0, z = 1 }, { name = \"T:b\", y = 1, z = -1 }, { name = \"T:f\", y = -1, z = 0 }]\n\
                 [[station]]\nat_mm = 100\nsensors = [{ name = \"T:c\", y = 0, z = 1 }, { name = \"T:d\", y = 1, z = -1 }, { name = \"T:e\", y = -1, z = 0 }]\n";
    bad(&format!("{head}{short}"), "must span the travel of axis X [-400, 400] mm");
    bad(&format!("axis = \"X\"\ny_direction = [1, 0, 0]\nalpha_um_per_m_k = 11.5\n{short}"), "perpendicular to the direction of axis X");
}
