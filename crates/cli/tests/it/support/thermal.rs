//! Shared by the `thermal` command-line tests (and those of other commands that read thermal
//! models): the fit of the shipped campaign, reproducible normal numbers.

use super::trueaxis;
use std::process::Output;

/// `trueaxis thermal fit` of the error `dz` of the shipped campaign (examples/thermal/campaign.csv)
/// trained on `train_runs`, with the further arguments `extra`.
pub fn fit_dz(train_runs: &str, extra: &[&str]) -> Output {
    let mut args = vec!["thermal", "fit", "--data", "examples/thermal/campaign.csv", "--error", "dz", "--train-runs", train_runs];
    args.extend_from_slice(extra);
    trueaxis(&args)
}

/// `trueaxis thermal place` of three sensors on the shipped elongation model
/// (examples/thermal/elongation.toml) over the whole of its modes (`--share 1`), with the further
/// arguments `extra`.
pub fn place_elongation(extra: &[&str]) -> Output {
    let args = ["thermal", "place", "--model", "examples/thermal/elongation.toml", "--count", "3", "--share", "1"];
    trueaxis(&[&args[..], extra].concat())
}

/// Reproducible standard normal numbers without a test dependency: Box-Muller on a 64-bit linear
/// congruential generator seeded with `seed`.
pub fn normal(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        let mut u = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let (a, b) = (u(), u());
        (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
    }
}
