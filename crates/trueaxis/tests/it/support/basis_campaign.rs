//! Multilateration campaigns on the 3-axis `examples/machines/vmc3.toml` whose unknowns are
//! parametric error functions (campaign `[basis.NAME]`): laser distances (instrument `length`) from
//! fixed stations on the table to the tool point at seeded random poses, as a laser tracer measures
//! them (Soons 1993 §4.2, the artefact-free case). Random poses give every axis function many distinct
//! positions, so a basis of high degree stays identifiable.
//!
//! Used by `crates/cli/tests/it/identify/basis.rs`. A benchmark can include it
//! (`#[path = "../tests/it/support/basis_campaign.rs"] mod basis_campaign;`) and build the large problem
//! of BENCHMARKS.md (targets), 10^5 readings x 501 B-spline and squareness coefficients:
//!
//! ```text
//! let m = Machine::load("../../examples/machines/vmc3.toml")?;
//! let path = write_campaign(dir, &m, &SQUARENESS, &bspline_bases(&m, 53), &random_poses(&m, 25_000, 1), 0.2);
//! let campaign = simulate_into(&path, &m, &ErrorModel::zero(&m), 1);      // or with known errors
//! let design = campaign.design_matrix(&m, &ErrorModel::zero(&m))?;        // 100000 x 501
//! ```
#![allow(dead_code)]

use std::fmt::Write;
use std::path::{Path, PathBuf};
use trueaxis::error_model::ErrorModel;
use trueaxis::identify::{measurement_csv, simulate_campaign, Campaign};
use trueaxis::machine::Machine;

/// Station positions on the table (mm, in M at home; the table surface is z = 0).
pub const STATIONS: [[f64; 3]; 4] = [[-350.0, -220.0, 0.0], [350.0, -220.0, 0.0], [350.0, 220.0, 0.0], [-350.0, 220.0, 0.0]];

/// The three squareness errors of vmc3, identified with the straightness-constrained bases.
pub const SQUARENESS: [&str; 3] = ["EC0X", "EB0Z", "EA0Z"];

/// Fraction of each axis range left out at both ends by [`random_poses`].
pub const POSE_MARGIN: f64 = 0.05;

/// `count` poses (mm) uniform in the axis ranges less [`POSE_MARGIN`] at each end, from a seeded generator
/// (a 64-bit linear congruential generator: reproducible without extra crates).
pub fn random_poses(machine: &Machine, count: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut uniform = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..count)
        .map(|_| {
            machine
                .axes()
                .iter()
                .map(|a| {
                    let [lo, hi] = a.range.unwrap_or([-180.0, 180.0]);
                    let margin = POSE_MARGIN * (hi - lo);
                    lo + margin + (hi - lo - 2.0 * margin) * uniform()
                })
                .collect()
        })
        .collect()
}

/// `[basis.NAME]` tables for the nine translational motion errors of the three linear axes:
/// piecewise cubics, C2 at `knots` equally spaced interior knots over each axis range, no constant
/// term; the six straightness errors constrained to have no linear trend (Soons 1993 eqs. 3.4-3.8), so
/// that the squareness errors stay separable. Coefficients: 3 + knots per positioning error,
/// 2 + knots per straightness error, `21 + 9 knots` in all (with [`SQUARENESS`]: `24 + 9 knots`).
/// Truncated powers are ill-conditioned with many knots (beyond ~10 per axis the scaled design
/// matrix has singular values below the rank tolerance): use [`bspline_bases`] for large problems.
pub fn piecewise_bases(machine: &Machine, knots: usize) -> String {
    axis_bases(machine, 0.0, |lo, hi| {
        format!("family = \"piecewise\"\ndegree = 3\nknots = [{}]\ncontinuity = [2]\n", equally_spaced(lo, hi, knots))
    })
}

/// The same cubic splines as [`piecewise_bases`] as B-splines (well conditioned with many knots),
/// over the part of each axis range that [`random_poses`] samples (every knot interval sees poses):
/// `knots + 3` coefficients per positioning error (no constant), `knots + 2` per straightness error
/// (no linear trend), `21 + 9 knots` in all as [`piecewise_bases`]; with [`SQUARENESS`] `24 + 9
/// knots` unknowns, 501 for 53 knots (BENCHMARKS.md (targets): piecewise-polynomial error maps).
pub fn bspline_bases(machine: &Machine, knots: usize) -> String {
    axis_bases(machine, POSE_MARGIN, |lo, hi| format!("family = \"bspline\"\ndegree = 3\nknots = [{}]\n", equally_spaced(lo, hi, knots)))
}

/// `count` interior knots dividing `[lo, hi]` into equal intervals, comma separated.
fn equally_spaced(lo: f64, hi: f64, count: usize) -> String {
    (1..=count).map(|i| format!("{}", lo + (hi - lo) * i as f64 / (count + 1) as f64)).collect::<Vec<_>>().join(", ")
}

/// The nine `[basis.E<direction><axis>]` tables with the family lines of `family(lo, hi)`, the
/// straightness constraint on the six straightness errors and the axis range less `margin` (a
/// fraction) at each end as domain.
fn axis_bases(machine: &Machine, margin: f64, family: impl Fn(f64, f64) -> String) -> String {
    let mut text = String::new();
    for axis in ['X', 'Y', 'Z'] {
        let a = &machine.axes()[machine.axis_index(axis).expect("vmc3 has X, Y, Z")];
        let [lo, hi] = a.range.expect("linear axes have a range");
        let [lo, hi] = [lo + margin * (hi - lo), hi - margin * (hi - lo)];
        for direction in ['X', 'Y', 'Z'] {
            let constraint = if direction == axis { "none" } else { "straightness" };
            let _ = write!(text, "[basis.E{direction}{axis}]\n{}constraint = \"{constraint}\"\ndomain = [{lo}, {hi}]\n\n", family(lo, hi));
        }
    }
    text
}

/// Writes the campaign (`campaign.toml`, one planned `length` measurement per station with its pose
/// file `station<k>.csv`) into `dir` and returns its path. `parameters` are constants (ISO names),
/// `bases` the `[basis.NAME]` tables, `sigma_um` the noise of every reading.
pub fn write_campaign(dir: &Path, machine: &Machine, parameters: &[&str], bases: &str, poses: &[Vec<f64>], sigma_um: f64) -> PathBuf {
    let letters: Vec<String> = machine.axes().iter().map(|a| a.letter.to_string()).collect();
    let mut csv = format!("{}\n", letters.join(","));
    for p in poses {
        let _ = writeln!(csv, "{}", p.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(","));
    }
    let list = parameters.iter().map(|p| format!("\"{p}\"")).collect::<Vec<_>>().join(", ");
    let mut toml = format!(
        "name = \"vmc3 laser multilateration, {} poses x {} stations\"\nparameters = [{list}]\n\n{bases}",
        poses.len(),
        STATIONS.len()
    );
    for (k, s) in STATIONS.iter().enumerate() {
        std::fs::write(dir.join(format!("station{}.csv", k + 1)), &csv).unwrap();
        let _ = write!(
            toml,
            "[[measurement]]\ninstrument = \"length\"\ndata = \"station{}.csv\"\nwork_point = [{}, {}, {}]\nsigma_um = {sigma_um}\n\n",
            k + 1,
            s[0],
            s[1],
            s[2]
        );
    }
    let path = dir.join("campaign.toml");
    std::fs::write(&path, toml).unwrap();
    path
}

/// Simulates the readings of the campaign at `path` with the errors `truth` (noise seed `seed`),
/// writes them into its data files and returns the loaded campaign.
pub fn simulate_into(path: &Path, machine: &Machine, truth: &ErrorModel, seed: u64) -> Campaign {
    let planned = Campaign::load(path, machine).unwrap();
    let readings = simulate_campaign(&planned, machine, truth, Some(seed)).unwrap();
    for (m, r) in planned.measurements.iter().zip(&readings) {
        std::fs::write(&m.data, measurement_csv(machine, m, r)).unwrap();
    }
    Campaign::load(path, machine).unwrap()
}
