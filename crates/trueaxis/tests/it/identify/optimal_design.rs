//! Soons 1993 §4.4, Table 4.1: D-optimal design of 400 mm ball bars on a simulated 2D CMM with
//! three parameters (X-Y squareness, X and Y scale errors). The design matrix comes from the
//! kinematic model through the `point_length` instrument (two probed poses per bar); it must equal
//! eq. 4.21, and the three designs of Table 4.1 must give its det^(1/3) and maximum variance; the
//! exchange algorithm must find a design as good as design 3.

use nalgebra::DMatrix;
use std::fmt::Write;
use trueaxis::error_model::ErrorModel;
use trueaxis::identify::{Campaign, CandidateSet, Criterion, DesignMatrix};
use trueaxis::machine::Machine;

const MACHINE: &str = r#"
name = "2D CMM (Soons 1993 section 4.4)"
structure = "wbXYt"
[axes]
X = { kind = "linear", direction = [1, 0, 0], range = [0, 500] }
Y = { kind = "linear", direction = [0, 1, 0], range = [0, 500] }
[tool]
point = [0, 0, 0]
"#;
const L: f64 = 400.0;
/// Bars of Table 4.1, (X, Y, alpha deg) of the first sphere: indices 0-6.
const BARS: [(f64, f64, f64); 7] = [
    (50.0, 250.0, 0.0),
    (100.0, 100.0, 45.0),
    (250.0, 50.0, 90.0),
    (100.0, 400.0, 315.0),
    (50.0, 150.0, 45.0),
    (450.0, 50.0, 105.0),
    (450.0, 50.0, 165.0),
];

/// The Table 4.1 bars, then every bar on a 100 mm grid in 15-deg steps with both ends in range.
fn candidates() -> Vec<(f64, f64, f64)> {
    let mut bars = BARS.to_vec();
    for i in 0..=5 {
        for j in 0..=5 {
            for k in 0..24 {
                let (x, y, a) = (100.0 * i as f64, 100.0 * j as f64, 15.0 * k as f64);
                let (x2, y2) = (x + L * a.to_radians().cos(), y + L * a.to_radians().sin());
                if (-1e-9..=500.0 + 1e-9).contains(&x2) && (-1e-9..=500.0 + 1e-9).contains(&y2) {
                    bars.push((x, y, a));
                }
            }
        }
    }
    bars
}

/// Design matrix in the units of Soons 1993 (length deviation in mm per dimensionless parameter: rad
/// for the squareness, mm/mm for the scales) and the bars.
fn design() -> (DesignMatrix, DMatrix<f64>, Vec<(f64, f64, f64)>) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("cmm.toml"), MACHINE).unwrap();
    let machine = Machine::load(dir.path().join("cmm.toml")).unwrap();
    let bars = candidates();
    let mut csv = String::from("X,Y,X2,Y2,dL\n");
    for (x, y, a) in &bars {
        let (c, s) = (a.to_radians().cos(), a.to_radians().sin());
        let _ = writeln!(csv, "{x},{y},{},{},0", (x + L * c).clamp(0.0, 500.0), (y + L * s).clamp(0.0, 500.0));
    }
    std::fs::write(dir.path().join("bars.csv"), csv).unwrap();
    std::fs::write(
        dir.path().join("campaign.toml"),
        "parameters = [\"EC0Y\", \"EXX[1]\", \"EYY[1]\"]\n[[measurement]]\ninstrument = \"point_length\"\ndata = \"bars.csv\"\n\
         tool_point = [0, 0, 0]\nwork_point = [0, 0, 0]\nsigma_um = 1.0\n",
    )
    .unwrap();
    let campaign = Campaign::load(dir.path().join("campaign.toml"), &machine).unwrap();
    let design = campaign.design_matrix(&machine, &ErrorModel::zero(&machine)).unwrap();
    // um per urad -> mm per rad: x 1e-3 x 1e6; um per (um/mm) -> mm per (mm/mm): x 1e-3 x 1e3
    let factors = [1e3, 1.0, 1.0];
    let soons = DMatrix::from_fn(design.rows(), 3, |i, j| design.matrix[(i, j)] * factors[j]);
    (design, soons, bars)
}

#[test]
fn design_rows_are_seed_000_eq_4_21() {
    // Delta L = L [cos a sin a, -cos^2 a, -sin^2 a] beta, independent of the bar position
    let (design, x, bars) = design();
    assert_eq!(design.names, vec!["EC0Y", "EXX[1]", "EYY[1]"]);
    assert_eq!(design.units, vec!["urad", "um/mm", "um/mm"]);
    for (i, (_, _, a)) in bars.iter().enumerate() {
        let (c, s) = (a.to_radians().cos(), a.to_radians().sin());
        let expected = [L * c * s, -L * c * c, -L * s * s];
        for j in 0..3 {
            assert!((x[(i, j)] - expected[j]).abs() < 1e-9, "bar {i} column {j}: {} vs {}", x[(i, j)], expected[j]);
        }
    }
}

#[test]
fn table_4_1_designs_reproduce_det_and_maximum_variance() {
    let (_, x, _) = design();
    let set = CandidateSet::new((0..x.nrows()).map(|i| x.rows(i, 1).into_owned()).collect()).unwrap();
    // (design, det^(1/3) of Table 4.1, max variance, covariance x 2 L^2 / sigma^2)
    type Case<'a> = (&'a [usize], f64, f64, [[f64; 3]; 3]);
    let cases: [Case; 3] = [
        (&[0, 0, 1, 1, 2, 2], 2.98e-5, 9.0, [[6.0, 1.0, 1.0], [1.0, 1.0, 0.0], [1.0, 0.0, 1.0]]),
        (&[0, 0, 1, 3, 2, 2], 2.60e-5, 4.0, [[4.0, 0.0, 0.0], [0.0, 0.83, -0.17], [0.0, -0.17, 0.83]]),
        (&[4, 4, 5, 5, 6, 6], 2.50e-5, 3.0, [[2.67, 0.0, 0.0], [0.0, 1.0, -0.33], [0.0, -0.33, 1.0]]),
    ];
    for (k, (chosen, det, max_var, cov)) in cases.iter().enumerate() {
        let c = set.criteria(chosen).unwrap();
        // the table prints three digits
        assert!((c.d / det - 1.0).abs() < 0.005, "design {}: det^(1/3) {:.4e} vs {det:e}", k + 1, c.d);
        assert!((c.g - max_var).abs() < 1e-9, "design {}: max variance {} vs {max_var}", k + 1, c.g);
        let m: DMatrix<f64> = chosen.iter().map(|&i| x.rows(i, 1).transpose() * x.rows(i, 1)).fold(DMatrix::zeros(3, 3), |a, b| a + b);
        let inverse = m.try_inverse().unwrap() * (2.0 * L * L);
        for i in 0..3 {
            for j in 0..3 {
                assert!((inverse[(i, j)] - cov[i][j]).abs() < 0.005, "design {} cov[{i}][{j}] {} vs {}", k + 1, inverse[(i, j)], cov[i][j]);
            }
        }
    }
}

#[test]
fn exchange_algorithm_finds_a_design_as_good_as_design_3() {
    let (_, x, bars) = design();
    let set = CandidateSet::new((0..x.nrows()).map(|i| x.rows(i, 1).into_owned()).collect()).unwrap();
    assert!(set.len() > 200, "{} candidates", set.len());
    let design3 = set.criteria(&[4, 4, 5, 5, 6, 6]).unwrap();
    let (chosen, found) = set.exchange(6, Criterion::D, 4, 42).unwrap();
    assert!(found.d <= design3.d * (1.0 + 1e-9), "D {:.6e} vs design 3 {:.6e}", found.d, design3.d);
    // Kiefer-Wolfowitz: a D-optimal design has maximum variance p = 3
    assert!((found.g - 3.0).abs() < 1e-6, "G {}", found.g);
    // the design differs from design 3 only by orientations (the criteria do not depend on position)
    assert_eq!(chosen.len(), 6);
    assert!(chosen.iter().all(|&i| bars[i].2 % 15.0 == 0.0));
    // the A and E criteria can be optimised too and are never worse than design 1's
    let design1 = set.criteria(&[0, 0, 1, 1, 2, 2]).unwrap();
    for criterion in [Criterion::A, Criterion::E] {
        let (_, c) = set.exchange(6, criterion, 2, 3).unwrap();
        assert!(c.value(criterion) <= design1.value(criterion) + 1e-15, "{criterion:?}");
    }
}
