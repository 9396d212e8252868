//! Outputs that would destroy an input, refused before a run starts (docs/reliability.md): an output
//! that is the same file as an input (by identity: a hard link, a symbolic link, `./p.csv` and
//! `p.csv` alike, [`crate::files::inputs::FileIdentity`]), a directory replaced whole that holds an
//! input, and standard output (`-`) given to two outputs.

use super::DataError;
use crate::files::inputs::FileIdentity;
use std::path::PathBuf;

/// An output of a command: the option that names it, its path, and whether it is a directory the
/// run replaces whole (`compensate --out DIR`).
#[derive(Clone, Debug)]
pub struct NamedOutput {
    pub option: String,
    pub path: PathBuf,
    pub whole_directory: bool,
}

/// Refuses, before a run starts, an output that is the same file as one of the inputs `(option,
/// path)`, or a directory replaced whole that holds one; and standard output (`-`) given to two
/// outputs. Bad input: the message names both options and the file.
pub fn refuse_overlap(outputs: &[NamedOutput], inputs: &[(String, PathBuf)]) -> Result<(), DataError> {
    let to_stdout: Vec<&str> = outputs.iter().filter(|o| super::is_standard_output(&o.path)).map(|o| o.option.as_str()).collect();
    if to_stdout.len() > 1 {
        return Err(DataError::Invalid {
            origin: "standard output".into(),
            message: format!("given to {}; one output at most can go there", to_stdout.join(" and ")),
        });
    }
    for output in outputs {
        let Some(out) = FileIdentity::of(&output.path) else { continue };
        for (option, path) in inputs {
            let Some(input) = FileIdentity::of(path) else { continue };
            let what = if input.same(&out) {
                "is the same file as"
            } else if output.whole_directory && input.inside(&out) {
                "is a directory this run replaces whole, and it holds"
            } else {
                continue;
            };
            return Err(DataError::Invalid {
                origin: output.path.display().to_string(),
                message: format!(
                    "{} {what} the input {option} {}: writing it would destroy the input; choose another output path",
                    output.option,
                    path.display()
                ),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn output(option: &str, path: &Path, whole_directory: bool) -> NamedOutput {
        NamedOutput { option: option.into(), path: path.to_path_buf(), whole_directory }
    }

    #[test]
    fn the_same_file_by_any_path_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let poses = dir.path().join("p.csv");
        std::fs::write(&poses, "X\n1\n").unwrap();
        let inputs = [("--poses".to_string(), poses.clone())];
        let mut same = vec![dir.path().join("./p.csv"), dir.path().join("sub/../p.csv")];
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&poses, dir.path().join("link.csv")).unwrap();
            std::fs::hard_link(&poses, dir.path().join("hard.csv")).unwrap();
            same.extend([dir.path().join("link.csv"), dir.path().join("hard.csv")]);
        }
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        for path in same {
            let e = refuse_overlap(&[output("--out", &path, false)], &inputs).unwrap_err().to_string();
            assert!(e.contains("--out is the same file as the input --poses") && e.contains("p.csv"), "{e}");
        }
        // a new file, another file, and a directory of plots beside the input are outputs
        std::fs::write(dir.path().join("other.csv"), "x").unwrap();
        for (path, whole) in [(dir.path().join("new.csv"), false), (dir.path().join("other.csv"), false), (dir.path().to_path_buf(), false)]
        {
            refuse_overlap(&[output("--out", &path, whole)], &inputs).unwrap();
        }
        // a directory replaced whole must not hold an input
        let e = refuse_overlap(&[output("--out", dir.path(), true)], &inputs).unwrap_err().to_string();
        assert!(e.contains("replaces whole, and it holds the input --poses"), "{e}");
        let e = refuse_overlap(&[output("--out", Path::new("-"), false), output("--residuals", Path::new("-"), false)], &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("standard output: given to --out and --residuals"), "{e}");
    }
}
