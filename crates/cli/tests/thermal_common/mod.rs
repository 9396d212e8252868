//! Shared by the `thermal` command-line tests: run the binary from the repository root, read its
//! JSON document.
#![allow(dead_code)]

use std::process::{Command, Output};

/// `trueaxis ARGS` run in the repository root (so that `examples/...` resolves).
pub fn trueaxis(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_trueaxis")).args(args).current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).output().unwrap()
}

/// The JSON document of a successful run.
pub fn json(out: &Output) -> serde_json::Value {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// A successful run.
pub fn ok(out: &Output) {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// `trueaxis thermal fit` of the error `dz` of the shipped campaign (examples/thermal/campaign.csv)
/// trained on `train_runs`, with the further arguments `extra`.
pub fn fit_dz(train_runs: &str, extra: &[&str]) -> Output {
    let mut args = vec!["thermal", "fit", "--data", "examples/thermal/campaign.csv", "--error", "dz", "--train-runs", train_runs];
    args.extend_from_slice(extra);
    trueaxis(&args)
}
