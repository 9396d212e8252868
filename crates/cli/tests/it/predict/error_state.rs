//! Bidirectional functions (`EXX+` / `EXX-`), cross-coupling and temperature product terms, from
//! the error-values file through `predict` with `dir:<axis>` and `T:<sensor>` columns
//! (Soons 1993 §3.2.5 and eq. 3.19; NISTIR 5236 §3.6).

use crate::support::{arg, failed, root, trueaxis, vmc3};

const ERRORS: &str = r#"
[constant]
"EXX+" = 0.4     # backlash: +0.4 um moving +, -0.4 um moving -
"EXX-" = -0.4

[[term.EXX]]     # scale expansion 11.5 um/m/K: 0.0115 um per mm per K
coefficient = 0.0115
factors = { X = 1, "T:scale" = 1 }

[[term.EYY]]     # Y positioning depends on X (carriage weight): 2e-6 um per mm^2
coefficient = 2e-6
factors = { X = 1, Y = 1 }
"#;

#[test]
fn predict_uses_directions_and_temperatures() {
    let dir = tempfile::tempdir().unwrap();
    let errors = dir.path().join("errors.toml");
    std::fs::write(&errors, ERRORS).unwrap();
    let poses = dir.path().join("poses.csv");
    std::fs::write(&poses, "X,Y,Z,dir:X,T:scale\n200,100,0,+,25\n200,100,0,-,25\n200,100,0,,20\n-300,-200,0,+,18\n").unwrap();
    let out = trueaxis(&vmc3(&["predict"], &["--errors", arg(&errors), "--poses", arg(&poses), "--json"]));
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // vmc3's X and Y carry the table (directions -x, -y): the tool moves opposite to the table
    // error, so dx = -EXX and dy = -EYY (no angular errors here, no Abbe terms).
    let exx = |backlash: f64, x: f64, t: f64| backlash + 0.0115 * x * (t - 20.0);
    let eyy = |x: f64, y: f64| 2e-6 * x * y;
    let expected = [
        (-exx(0.4, 200.0, 25.0), -eyy(200.0, 100.0)),
        (-exx(-0.4, 200.0, 25.0), -eyy(200.0, 100.0)),
        (-exx(0.0, 200.0, 20.0), -eyy(200.0, 100.0)),
        (-exx(0.4, -300.0, 18.0), -eyy(-300.0, -200.0)),
    ];
    for (row, (dx, dy)) in doc["poses"].as_array().unwrap().iter().zip(expected) {
        assert!((row["dx"].as_f64().unwrap() - dx).abs() < 1e-4, "{row} vs {dx}");
        assert!((row["dy"].as_f64().unwrap() - dy).abs() < 1e-4, "{row} vs {dy}");
    }
}

#[test]
fn missing_state_columns_and_bad_state_files_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let errors = dir.path().join("errors.toml");
    std::fs::write(&errors, ERRORS).unwrap();
    let e = arg(&errors);
    let run = |poses: &str| {
        let p = dir.path().join("p.csv");
        std::fs::write(&p, poses).unwrap();
        trueaxis(&vmc3(&["predict"], &["--errors", e, "--poses", arg(&p)]))
    };
    let out = run("X,Y,Z\n0,0,0\n");
    failed(&out, 2, &["missing column `T:scale`"]);
    let out = run("X,Y,Z,dir:X,T:scale\n0,0,0,sideways,20\n");
    failed(&out, 2, &["`sideways` is not +, - or empty"]);

    let machine = trueaxis::machine::Machine::load(root().join("examples/machines/vmc3.toml")).unwrap();
    let bad = |text: &str, fragment: &str| {
        let err = trueaxis::error_model::ErrorModel::from_toml_str(text, "e.toml", &machine).unwrap_err().to_string();
        assert!(err.contains(fragment), "expected `{fragment}` in {err}");
    };
    bad("[constant]\n\"EXX+\" = 0.4\n", "EXX+ is given without EXX-");
    bad("[constant]\nEXX = 1.0\n\"EXX-\" = 0.4\n", "both directions");
    bad("[constant]\n\"EX0Y+\" = 1.0\n\"EX0Y-\" = 1.0\n", "no direction of motion");
    bad("[[term.EXX]]\ncoefficient = 1.0\nfactors = { Q = 1 }\n", "no axis Q");
    bad("[[term.EXX]]\ncoefficient = 1.0\nfactors = { XY = 1 }\n", "neither an axis letter nor an input");
    bad("[[term.EXX]]\ncoefficient = 1.0\nfactors = { X = 12 }\n", "powers");
}
