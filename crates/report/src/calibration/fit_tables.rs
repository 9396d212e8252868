//! The `[[fit]]` tables of report.toml: each holds the long options of `trueaxis fit` by name
//! (`data = "laser_x.csv"`, `parameter = "EXX"`, `knot_spacing = 100`, `stepwise = 0.9999`,
//! `direction = "both"`, `optics_offset = [0, 150]`, `periodic = ["25.4", "5:2"]`), turned here into
//! the arguments of the command so that the command line parses them with the same definition and
//! fits them with the same code: the report then has the numbers of `trueaxis fit --json`. The
//! machine is the report's; file names are relative to report.toml.

use std::path::Path;
use trueaxis::Error;

/// Options a `[[fit]]` table may not set: the report gives the machine, and writes nothing else.
const REFUSED: [&str; 4] = ["machine", "json", "errors_out", "plot"];
/// Options that name a file, relative to report.toml.
const FILES: [&str; 2] = ["data", "errors_in"];

/// `folder/name` with each `..` after a folder name taken out (`examples/report/../data/x.csv` is
/// `examples/data/x.csv`), as the report names the file.
fn joined(folder: &Path, name: &str) -> String {
    use std::path::Component;
    let path = folder.join(name);
    let mut out: Vec<Component> = Vec::new();
    for c in path.components() {
        match (c, out.last()) {
            (Component::ParentDir, Some(Component::Normal(_))) => {
                out.pop();
            }
            _ => out.push(c),
        }
    }
    out.iter().collect::<std::path::PathBuf>().display().to_string()
}

/// The `trueaxis fit` arguments of one table (`--knot-spacing 100` for `knot_spacing = 100`; true
/// for a flag; a list of texts as a repeated option, a list of numbers joined by commas), file
/// names joined to `folder`.
pub fn fit_arguments(table: &toml::Table, folder: &Path) -> Result<Vec<String>, Error> {
    let mut argv = Vec::new();
    for (key, value) in table {
        let key = key.replace('-', "_");
        if REFUSED.contains(&key.as_str()) {
            trueaxis::bail!(input, "`{key}` is not an option of a reported fit (the report gives the machine and writes the results)");
        }
        let option = format!("--{}", key.replace('_', "-"));
        let scalar = |v: &toml::Value| match v {
            toml::Value::String(s) if FILES.contains(&key.as_str()) => Some(joined(folder, s)),
            toml::Value::String(s) => Some(s.clone()),
            toml::Value::Integer(i) => Some(i.to_string()),
            toml::Value::Float(f) => Some(f.to_string()),
            _ => None,
        };
        match value {
            toml::Value::Boolean(true) => argv.push(option),
            toml::Value::Boolean(false) => {}
            toml::Value::Array(items) if items.iter().all(toml::Value::is_str) => {
                for item in items {
                    argv.extend([option.clone(), scalar(item).unwrap_or_default()]);
                }
            }
            toml::Value::Array(items) => {
                let numbers: Option<Vec<String>> =
                    items.iter().all(|v| v.is_integer() || v.is_float()).then(|| items.iter().filter_map(scalar).collect());
                let numbers = numbers.ok_or_else(|| Error::input(format!("`{key}`: a list of numbers or of texts")))?;
                argv.extend([option, numbers.join(",")]);
            }
            other => argv.extend([option, scalar(other).ok_or_else(|| Error::input(format!("`{key}`: a number, a text or true")))?]),
        }
    }
    Ok(argv)
}
