//! The results do not depend on the number of threads (docs/reliability.md): identification,
//! adaptive Monte Carlo, the thermal fit and the HTML report, run end to end with
//! `RAYON_NUM_THREADS` = 1, 2 and 8, write byte-identical files and print byte-identical JSON.
//! (Parallel sums are reduced in a fixed order and every Monte Carlo trial draws from its own
//! seeded stream, so the thread count cannot change a bit.)

use crate::support::{utf8, vmc3, Run};
use std::path::Path;

/// Runs `args` with `threads` worker threads; `{out}` in an argument is replaced by `dir`.
/// Returns stdout and every file written into `dir` (name, bytes), sorted.
fn run(args: &[&str], threads: usize, dir: &Path) -> (Vec<u8>, Vec<(String, Vec<u8>)>) {
    let args: Vec<String> = args.iter().map(|a| a.replace("{out}", &dir.display().to_string())).collect();
    let out = Run::new(&args)
        .env("RAYON_NUM_THREADS", threads.to_string())
        // the report's date: fixed, as reproducible builds fix it
        .env("SOURCE_DATE_EPOCH", "1767225600")
        .output();
    assert_eq!(out.status.code(), Some(0), "{args:?} with {threads} threads: {}", utf8(&out.stderr));
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (e.file_name().to_string_lossy().into_owned(), std::fs::read(e.path()).unwrap())
        })
        .collect();
    files.sort();
    (out.stdout, files)
}

/// The same bytes for 1, 2 and 8 threads; at least `files` files written and a non-empty output.
fn same_for_every_thread_count(args: &[&str], files: usize) {
    let tmp = tempfile::tempdir().unwrap();
    let results: Vec<_> = [1usize, 2, 8]
        .iter()
        .map(|&t| {
            // the same path every time: outputs may name it
            let dir = tmp.path().join("out");
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir(&dir).unwrap();
            (t, run(args, t, &dir))
        })
        .collect();
    let (_, (stdout, written)) = &results[0];
    assert!(!stdout.is_empty() || !written.is_empty(), "{args:?}: no output");
    assert!(written.len() >= files, "{args:?}: {} files written, {files} expected", written.len());
    for (t, (other_stdout, other_written)) in &results[1..] {
        assert!(other_stdout == stdout, "{args:?}: stdout with {t} threads differs from 1 thread");
        assert_eq!(other_written.len(), written.len(), "{args:?}");
        for ((name, bytes), (other_name, other_bytes)) in written.iter().zip(other_written) {
            assert_eq!(name, other_name);
            assert!(bytes == other_bytes, "{args:?}: {name} with {t} threads differs from 1 thread");
        }
    }
}

#[test]
fn identification_is_the_same_for_1_2_and_8_threads() {
    same_for_every_thread_count(
        &[
            "identify",
            "--machine",
            "examples/machines/kx8five.toml",
            "--campaign",
            "examples/campaigns/kx8five/campaign.toml",
            "--refine",
            "--json",
            "--out",
            "{out}/identified.toml",
            "--residuals",
            "{out}/residuals.csv",
        ],
        2,
    );
}

#[test]
fn monte_carlo_is_the_same_for_1_2_and_8_threads() {
    same_for_every_thread_count(
        &[
            "uncertainty",
            "--design",
            "examples/uncertainty/kx8five_design.csv",
            "--sources",
            "examples/uncertainty/kx8five_cyclic.toml",
            "--seed",
            "7",
            "--json",
            "--plots",
            "{out}",
        ],
        1,
    );
}

#[test]
fn thermal_fit_is_the_same_for_1_2_and_8_threads() {
    same_for_every_thread_count(
        &vmc3(
            &[
                "thermal",
                "fit",
                "--data",
                "examples/thermal/campaign.csv",
                "--error",
                "dz",
                "--train-runs",
                "warmup",
                "--json",
                "--out",
                "{out}/dz_model.toml",
                "--parameter",
                "EZZ",
                "--terms-out",
                "{out}/dz_terms.toml",
            ],
            &[],
        ),
        2,
    );
}

#[test]
fn the_report_is_the_same_for_1_2_and_8_threads() {
    same_for_every_thread_count(
        &[
            "report",
            "--machine",
            "examples/machines/kx8five.toml",
            "--campaign",
            "examples/campaigns/kx8five/campaign.toml",
            "--sources",
            "examples/uncertainty/kx8five_cyclic.toml",
            "--out",
            "{out}/report.html",
        ],
        1,
    );
}
