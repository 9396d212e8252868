//! Andolfatto et al. 2011 Table 5 (Andolfatto, Mayer, Lavernhe 2011 §5.3: the width of the 95 % interval of
//! each link error with each uncertainty source alone, their root-sum-square and the total) against
//! trueaxis, and which assumption makes the difference (docs/uncertainty.md, "Andolfatto et al. 2011 Table 5").
//!
//! Every width here is also computed in closed form, independently of the Monte Carlo: the
//! identification is linear, `p = P y` with `P` the pseudo-inverse of the design, so
//! - a Gaussian source of standard deviation `sigma_c` on channel `c` gives a Gaussian parameter
//!   with `u_j^2 = sum_r P_jr^2 sigma_c(r)^2`, and a 95 % width `2 z u_j`, `z = 1.959964`;
//! - a sinusoidal drift `D_c(t) = (E_c / 2) sin(w (t + tau))`, `tau` uniform over the period, gives
//!   `p_j = g_j sin(w tau) + h_j cos(w tau)`, an arc-sine distribution of amplitude
//!   `a_j = hypot(g_j, h_j)` whose symmetric 95 % width is `2 a_j sin(0.475 pi)`.

use crate::support::kx8five_capball;

use kx8five_capball::{try_capball_design, Trajectory};
use nalgebra::DMatrix;
use trueaxis::uncertainty::{run_budget, DesignMatrix, Evaluation, IdentificationMap, McSettings, Sources};

/// Andolfatto et al. 2011 Table 5, the 8 link errors: width with the drift (cyclic method), the sensors, the
/// frame transformation alone, their root-sum-square, the total (um/m = urad; the last row um).
const PAPER: [[f64; 5]; 8] = [
    [8.1, 0.49, 0.68, 8.1, 8.4],    // d_gamma_Y
    [7.4, 0.65, 0.85, 7.5, 7.8],    // d_alpha_Z
    [7.9, 0.88, 1.41, 8.1, 8.2],    // d_beta_Z
    [9.8, 0.48, 0.87, 9.9, 10.0],   // d_beta_A
    [13.9, 0.29, 0.64, 13.9, 14.0], // d_gamma_A
    [8.4, 0.38, 0.75, 8.4, 8.6],    // d_alpha_C
    [5.9, 0.48, 0.81, 6.0, 6.0],    // d_beta_C
    [5.1, 0.12, 0.21, 5.1, 5.2],    // d_gamma_C (um), the offset of C
];

/// The 14 parameters of the shipped design (`examples/uncertainty/kx8five_design.csv`): the paper's
/// link errors in ISO names with the tilts of A and the offset of C taken normal to the tilted A
/// axis (EA0A, EX0C), so that all 14 are separable from one ball.
const SHIPPED: [&str; 14] = ["EC0Y", "EA0Z", "EB0Z", "EB0A", "EA0A", "EA0C", "EB0C", "EX0C", "TX", "TY", "TZ", "WX", "WY", "WZ"];
/// The mapping of `examples/errors/kx8five.toml` (tilts of A about machine y and z, C offset in y):
/// two combinations are unseen by one ball, so only the minimum-norm solution exists (the paper's
/// own estimator is the Moore-Penrose pseudo-inverse, its eq. 5).
const PAPER_NAMES: [&str; 14] = ["EC0Y", "EA0Z", "EB0Z", "EB0A", "EC0A", "EA0C", "EB0C", "EY0C", "TX", "TY", "TZ", "WX", "WY", "WZ"];

/// Andolfatto et al. 2011 Table 3 (sensor noise) and §4.3 (frame transformation): standard deviations (um) of
/// the x, y, z channels; Table 4: drift magnitude E_VE (um, peak to valley).
const SENSORS_U: [f64; 3] = [0.28, 0.28, 0.40];
const TRANSFORMATION_U: [f64; 3] = [0.56, 0.27, 0.69];
const E_VE: [f64; 3] = [6.95, 3.42, 6.63];
/// The drift period of the shipped sources file (s) and the time per pose (s).
const PERIOD_S: f64 = 1000.0;
const POINT_TIME_S: f64 = 0.75;
/// The normal quantile of 97.5 %.
const Z_975: f64 = 1.959_963_984_540_054;

/// Closed-form widths of the 95 % intervals: [drift, sensors, transformation] per parameter.
fn closed_form(design: &DesignMatrix, period_s: f64) -> Vec<[f64; 3]> {
    let p = pseudo_inverse(&design.x);
    let channel = |r: usize| ["x", "y", "z"].iter().position(|c| design.channels[design.channel[r]] == *c).expect("channels x, y, z");
    let w = 2.0 * std::f64::consts::PI / period_s;
    (0..p.nrows())
        .map(|j| {
            let (mut sensors, mut transformation, mut g, mut h) = (0.0, 0.0, 0.0, 0.0);
            for r in 0..p.ncols() {
                let (c, pjr) = (channel(r), p[(j, r)]);
                sensors += (pjr * SENSORS_U[c]).powi(2);
                transformation += (pjr * TRANSFORMATION_U[c]).powi(2);
                g += pjr * 0.5 * E_VE[c] * (w * design.time[r]).cos();
                h += pjr * 0.5 * E_VE[c] * (w * design.time[r]).sin();
            }
            let drift = 2.0 * g.hypot(h) * (0.475 * std::f64::consts::PI).sin();
            [drift, 2.0 * Z_975 * sensors.sqrt(), 2.0 * Z_975 * transformation.sqrt()]
        })
        .collect()
}

/// Moore-Penrose pseudo-inverse by SVD, singular values below 1e-9 of the largest dropped (the
/// minimum-norm least-squares solution of a rank-deficient design).
fn pseudo_inverse(x: &DMatrix<f64>) -> DMatrix<f64> {
    let svd = x.clone().svd(true, true);
    let cut = 1e-9 * svd.singular_values.max();
    svd.pseudo_inverse(cut).unwrap()
}

/// How far apart two columns of widths are: (RMS, largest) of the natural logarithm of the ratios
/// (0.1: about 10 %).
fn log_ratio_spread(ours: &[f64], paper: &[f64]) -> (f64, f64) {
    let logs: Vec<f64> = ours.iter().zip(paper).map(|(a, b)| (a / b).ln().abs()).collect();
    ((logs.iter().map(|l| l * l).sum::<f64>() / logs.len() as f64).sqrt(), logs.iter().fold(0.0, |m, l| m.max(*l)))
}

/// The sensor and transformation columns of the 8 link errors (16 widths), ours divided by `reading`
/// (1: the paper's "size" is the width; 2: it is the half width) against the paper's.
fn gaussian_mismatch(table: &[[f64; 3]], reading: f64) -> (f64, f64) {
    let ours: Vec<f64> = (1..3).flat_map(|k| table[..8].iter().map(move |row| row[k] / reading)).collect();
    let paper: Vec<f64> = (1..3).flat_map(|k| PAPER.iter().map(move |row| row[k])).collect();
    log_ratio_spread(&ours, &paper)
}

fn shipped_design() -> DesignMatrix {
    DesignMatrix::read_csv("../../examples/uncertainty/kx8five_design.csv").unwrap()
}

#[test]
fn monte_carlo_budget_equals_the_closed_forms() {
    // the shipped example exactly as `trueaxis uncertainty --design ... --sources ...` runs it
    let design = shipped_design();
    let sources = Sources::load("../../examples/uncertainty/kx8five_cyclic.toml").unwrap();
    let settings: McSettings = sources.settings.clone();
    let map = IdentificationMap::new(design.clone()).unwrap();
    let budget = run_budget(&map, &sources.sources, &settings, Evaluation::Reduced, true, &mut |_, _, _| {}).unwrap();
    assert_eq!(budget.source_names, ["drift", "sensors", "transformation"]);
    let closed = closed_form(&design, PERIOD_S);
    for (row, expected) in budget.rows.iter().zip(&closed) {
        // the drift's arc-sine quantile is sharp (density peaks at the ends): 1 %; the Gaussian
        // 97.5 % quantile from 2 x 10^4 or more trials: about 1 % standard deviation, 3 % allowed
        for (k, (mc, cf)) in row.widths.iter().zip(expected).enumerate() {
            let tolerance = if k == 0 { 0.01 } else { 0.03 };
            assert!((mc / cf - 1.0).abs() < tolerance, "{} source {k}: Monte Carlo {mc:.4} vs closed form {cf:.4}", row.parameter);
        }
        // the total is not below the largest single source (Andolfatto et al. 2011: drift dominates)
        assert!(row.total >= 0.99 * expected[0], "{}: total {} vs drift {}", row.parameter, row.total, expected[0]);
    }
}

#[test]
fn table_5_differs_by_the_trajectory_not_by_the_monte_carlo() {
    let table = closed_form(&shipped_design(), PERIOD_S);
    for (name, (ours, paper)) in SHIPPED.iter().zip(table.iter().zip(&PAPER)) {
        eprintln!(
            "{name}: drift {:.2} ({:.2}x), sensors {:.3} ({:.2}x), transformation {:.3} ({:.2}x)",
            ours[0],
            ours[0] / paper[0],
            ours[1],
            ours[1] / paper[1],
            ours[2],
            ours[2] / paper[2]
        );
    }
    // X-Y squareness, the one link error defined alike in the paper and in ISO 230-7 and seen alike
    // by every trajectory: twice the paper's width in all three columns
    for k in 0..3 {
        let ratio = table[0][k] / PAPER[0][k];
        assert!((1.8..2.1).contains(&ratio), "EC0Y column {k}: ratio {ratio}");
    }
    // the Gaussian columns depend on nothing but the design and the paper's u: their ratios to the
    // paper spread from 0.7 to 3.2 over the 8 link errors, so the design differs, not the sources
    let ratios: Vec<f64> = (1..3).flat_map(|k| table[..8].iter().zip(&PAPER).map(move |(o, p)| o[k] / p[k])).collect();
    let (lo, hi) = ratios.iter().fold((f64::INFINITY, 0.0f64), |(a, b), r| (a.min(*r), b.max(*r)));
    assert!(lo < 0.75 && hi > 3.0, "ratios {lo:.2} .. {hi:.2}");
    // ... while the ratio transformation / sensors, which depends only on which channels see a
    // parameter, agrees with the paper's within 25 % for every link error
    for (j, (ours, paper)) in table[..8].iter().zip(&PAPER).enumerate() {
        let (r_ours, r_paper) = (ours[2] / ours[1], paper[2] / paper[1]);
        assert!((r_ours / r_paper - 1.0).abs() < 0.25, "{}: {r_ours:.2} vs {r_paper:.2}", SHIPPED[j]);
    }
}

#[test]
fn no_trajectory_on_a_grid_reproduces_the_gaussian_columns() {
    // the paper shows its 807-pose trajectory only as a figure (Fig. 2): ball radius, ball height
    // and the sweeps of A and C are searched on a grid, with both parameter mappings and both
    // readings of "size of the interval" (width, half width)
    let (mut best_rms, mut best_worst) = ((f64::INFINITY, String::new()), (f64::INFINITY, String::new()));
    let mut designs = 0;
    for radius in [100.0, 150.0, 200.0, 250.0] {
        for height in [0.0, 50.0, 100.0, 150.0, 200.0, 250.0] {
            for a_end_deg in [90.0, 120.0, 180.0] {
                for c_end_deg in [-720.0, -1080.0] {
                    let trajectory = Trajectory { ball: [radius, 0.0, height], a_end_deg, c_end_deg, poses: 807 };
                    for (mapping, names) in [("shipped", &SHIPPED), ("paper", &PAPER_NAMES)] {
                        let Some(design) = try_capball_design(&trajectory, names, POINT_TIME_S) else { continue };
                        designs += 1;
                        let table = closed_form(&design, PERIOD_S);
                        for reading in [1.0, 2.0] {
                            let (rms, worst) = gaussian_mismatch(&table, reading);
                            let label = || format!("{trajectory:?} {mapping} names, reading {reading}");
                            if rms < best_rms.0 {
                                best_rms = (rms, label());
                            }
                            if worst < best_worst.0 {
                                best_worst = (worst, label());
                            }
                        }
                    }
                }
            }
        }
    }
    eprintln!("{designs} designs; closest in RMS: log ratio {:.3} with {}", best_rms.0, best_rms.1);
    eprintln!("closest in the largest ratio: log ratio {:.3} with {}", best_worst.0, best_worst.1);
    assert!(designs >= 200, "{designs} designs inside the travel");
    // the closest designs are about 20 % apart in RMS, and every design has a width at least 40 %
    // off (log 1.4 = 0.34): the paper's 2-digit widths are not reproduced by any of them
    assert!((0.15..0.4).contains(&best_rms.0), "closest {best_rms:?}");
    assert!(best_worst.0 > 1.4f64.ln(), "closest {best_worst:?}");
}

#[test]
fn the_drift_column_depends_on_the_period_the_paper_does_not_give() {
    let design = shipped_design();
    let at = |period: f64| closed_form(&design, period);
    // EC0Y drift width (urad) at periods of 500, 1000, 2000, 5000 s; the Gaussian columns unchanged
    let expected = [(500.0, 13.6), (1000.0, 15.8), (2000.0, 9.7), (5000.0, 4.1)];
    let reference = at(PERIOD_S);
    for (period, width) in expected {
        let table = at(period);
        assert!((table[0][0] / width - 1.0).abs() < 0.01, "T = {period}: {}", table[0][0]);
        assert!(table.iter().zip(&reference).all(|(a, b)| a[1] == b[1] && a[2] == b[2]));
    }
    // no period brings the 8 drift widths of this design within 30 % RMS of the paper's, with
    // either reading of the interval
    let paper: Vec<f64> = PAPER.iter().map(|r| r[0]).collect();
    let mut best = (f64::INFINITY, 0.0, 0.0);
    for i in 0..400 {
        let period = 50.0 * (400.0f64).powf(i as f64 / 399.0); // 50 s .. 20000 s
        let table = at(period);
        for reading in [1.0, 2.0] {
            let ours: Vec<f64> = table[..8].iter().map(|r| r[0] / reading).collect();
            let (m, _) = log_ratio_spread(&ours, &paper);
            if m < best.0 {
                best = (m, period, reading);
            }
        }
    }
    eprintln!("closest drift column: RMS log ratio {:.3} at T = {:.0} s, reading {}", best.0, best.1, best.2);
    assert!(best.0 > 0.3, "{best:?}");
}
