//! The fuzz targets (`fuzz/src/lib.rs`, the functions cargo-fuzz runs) replayed on their seed
//! corpus (`fuzz/seeds.txt`, files of examples/), on the inputs that once crashed a parser
//! (`fuzz/regressions/<target>/`) and on truncations of every seed, so that every `cargo test`
//! runs each target even where cargo-fuzz cannot be installed (docs/reliability.md).

#[path = "../../../../fuzz/src/lib.rs"]
mod targets;

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The seed files of each target, from `fuzz/seeds.txt`.
fn seeds() -> Vec<(String, Vec<PathBuf>)> {
    let text = std::fs::read_to_string(root().join("fuzz/seeds.txt")).unwrap();
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|l| {
            let mut words = l.split_whitespace();
            let target = words.next().unwrap().to_string();
            (target, words.map(|f| root().join(f)).collect())
        })
        .collect()
}

fn target(name: &str) -> targets::Target {
    targets::TARGETS.iter().find(|(n, _)| *n == name).unwrap_or_else(|| panic!("fuzz/seeds.txt names no target {name}")).1
}

#[test]
fn every_target_has_seeds_and_a_cargo_fuzz_binary() {
    let seeds = seeds();
    for (name, _) in targets::TARGETS {
        let files = &seeds.iter().find(|(t, _)| t == name).unwrap_or_else(|| panic!("no seeds for {name}")).1;
        assert!(!files.is_empty(), "{name}");
        for f in files {
            assert!(f.is_file(), "{name}: seed {} missing", f.display());
        }
        let binary = root().join(format!("fuzz/fuzz_targets/{name}.rs"));
        let source = std::fs::read_to_string(&binary).unwrap_or_else(|e| panic!("{}: {e}", binary.display()));
        assert!(source.contains(&format!("trueaxis_fuzz::{name}(data)")), "{}", binary.display());
    }
    let manifest = std::fs::read_to_string(root().join("fuzz/Cargo.toml")).unwrap();
    assert_eq!(manifest.matches("[[bin]]").count(), targets::TARGETS.len());
}

#[test]
fn seeds_and_their_truncations_pass_every_target() {
    let mut runs = 0;
    for (name, files) in seeds() {
        let run = target(&name);
        for f in files {
            let bytes = std::fs::read(&f).unwrap();
            run(&bytes);
            // cut at 16 places: half-written files, a line cut in the middle
            for k in 1..16 {
                run(&bytes[..bytes.len() * k / 16]);
            }
            runs += 16;
        }
    }
    assert!(runs >= 16 * targets::TARGETS.len(), "{runs} runs");
}

#[test]
fn regressions_pass_their_target() {
    let dir = root().join("fuzz/regressions");
    let mut replayed = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let entry = entry.unwrap();
        let name = entry.file_name().to_string_lossy().into_owned();
        let run = target(&name);
        for input in std::fs::read_dir(entry.path()).unwrap() {
            run(&std::fs::read(input.unwrap().path()).unwrap());
            replayed += 1;
        }
    }
    assert!(replayed > 0, "fuzz/regressions holds no input");
}

#[test]
fn empty_and_binary_inputs_pass_every_target() {
    for (_, run) in targets::TARGETS {
        run(b"");
        run(&[0xff, 0xfe, 0x00, 0x41]);
        run(b"\n\n\n");
    }
}
