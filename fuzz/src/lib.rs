//! The fuzz targets of trueaxis: one function per parser or importer, taking any bytes.
//!
//! Each target reads the bytes as the command line reads a file (UTF-8 checked by
//! `trueaxis::io::text_of`, lossy where a reader takes any text) and, when the file is accepted,
//! pushes it through the computation that consumes it first (a prediction, an evaluation, a
//! correction), so that a value that parses but breaks the model is found too. A target passes
//! when it returns: a panic, an abort or a hang is the finding. A rejected file must name its
//! origin (`fuzz`) in the message, like every input error of trueaxis.
//!
//! Used by the cargo-fuzz binaries in `fuzz_targets/` and, through `#[path]`, by
//! `crates/trueaxis/tests/it/fuzz_replay.rs`, which replays the seed corpus (`seeds.txt`) and the
//! regressions (`regressions/<target>/`) in every `cargo test`.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use trueaxis::compensate::nc::{correct_program, NcOptions};
use trueaxis::compensate::Corrector;
use trueaxis::data::CsvTable;
use trueaxis::error_model::ErrorModel;
use trueaxis::evaluate::iso230_2::{evaluate, plausibility, read_runs_from_str, runs_of};
use trueaxis::instruments::ballbar::{ballbar_header, trace_of};
use trueaxis::io::{etalon, rtl, text_of};
use trueaxis::machine::{AxisKind, Machine};
use trueaxis::model::Predictor;
use trueaxis::poses::{poses_of, read_poses_from};
use trueaxis_nc::params::read_parameter_file;
use trueaxis_nc::{Controller, Dialect, ToolTable};

/// The name every message of a rejected fuzz input must start with.
pub const ORIGIN: &str = "fuzz";

/// A fuzz target: any bytes in, returns when they are handled (accepted or refused).
pub type Target = fn(&[u8]);

/// Every target, by name (the names of `fuzz_targets/*.rs` and of the corpus directories).
pub const TARGETS: [(&str, Target); 17] = [
    ("machine_toml", machine_toml),
    ("errors_toml", errors_toml),
    ("campaign_toml", campaign_toml),
    ("campaign_csv", campaign_csv),
    ("sources_toml", sources_toml),
    ("laser_csv", laser_csv),
    ("ballbar_csv", ballbar_csv),
    ("thermal_csv", thermal_csv),
    ("poses_csv", poses_csv),
    ("rtl", rtl),
    ("etalon", etalon),
    ("nc_linuxcnc", nc_linuxcnc),
    ("nc_fanuc", nc_fanuc),
    ("nc_tables", nc_tables),
    ("thermal_toml", thermal_toml),
    ("matrix_market", matrix_market),
    ("budget_toml", budget_toml),
];

/// The repository's `examples/` directory (this file is `fuzz/src/lib.rs`).
pub fn examples() -> PathBuf {
    Path::new(file!()).ancestors().nth(3).map_or_else(|| PathBuf::from("."), Path::to_path_buf).join("examples")
}

fn examples_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        // `file!()` is relative to the directory cargo ran rustc in: the fuzz crate, the workspace
        // root or a test crate; the first of these that holds the examples
        let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
        [manifest.join("../examples"), manifest.join("../../examples"), examples()]
            .into_iter()
            .find(|d| d.join("machines/vmc3.toml").is_file())
            .expect("the examples directory of the repository")
    })
}

fn machine(name: &str) -> &'static Machine {
    static MACHINES: OnceLock<Vec<(String, Machine)>> = OnceLock::new();
    let all = MACHINES.get_or_init(|| {
        ["vmc3", "kx8five", "lathe2"]
            .iter()
            .map(|n| {
                let path = examples_dir().join(format!("machines/{n}.toml"));
                (n.to_string(), Machine::load(&path).expect("a shipped machine"))
            })
            .collect()
    });
    &all.iter().find(|(n, _)| n == name).expect("a loaded machine").1
}

fn vmc3_errors() -> &'static ErrorModel {
    static ERRORS: OnceLock<ErrorModel> = OnceLock::new();
    ERRORS.get_or_init(|| ErrorModel::load(examples_dir().join("errors/vmc3.toml"), machine("vmc3")).expect("shipped errors"))
}

/// The text of a file as the command line reads it; `None` when it is refused (not UTF-8 ...).
fn text(data: &[u8]) -> Option<String> {
    match text_of(data.to_vec(), ORIGIN) {
        Ok(t) => Some(t),
        Err(e) => {
            named(&e);
            None
        }
    }
}

/// A refusal must name the file: the message starts with the origin (or names it).
fn named(e: &dyn std::fmt::Display) {
    let message = e.to_string();
    assert!(message.contains(ORIGIN), "a message that does not name the file: {message}");
}

/// Predicts the error at the home pose and at the ends of the travel; never a panic.
fn predict_around(machine: &Machine, errors: &ErrorModel) {
    let predictor = Predictor::new(machine, errors);
    let mut q = vec![0.0; machine.axis_count()];
    let _ = predictor.predict(&q);
    for (k, axis) in machine.axes().iter().enumerate() {
        // the ends of the travel, in internal units (mm, rad)
        let internal = |v: f64| if axis.kind == AxisKind::Rotary { v.to_radians() } else { v };
        for end in axis.range.into_iter().flatten() {
            q[k] = internal(end);
            let _ = predictor.predict(&q);
        }
        q[k] = 0.0;
    }
}

/// A machine file (`examples/machines/*.toml`); accepted ones predict with zero errors.
pub fn machine_toml(data: &[u8]) {
    let Some(text) = text(data) else { return };
    match Machine::from_toml_str(&text, ORIGIN) {
        Ok(m) => predict_around(&m, &ErrorModel::zero(&m)),
        Err(e) => named(&e),
    }
}

/// An error-values file (`examples/errors/*.toml`) on a 3-axis mill, a 5-axis machine and a lathe;
/// accepted ones predict over the travel.
pub fn errors_toml(data: &[u8]) {
    let Some(text) = text(data) else { return };
    for name in ["vmc3", "kx8five", "lathe2"] {
        let m = machine(name);
        match ErrorModel::from_toml_str(&text, ORIGIN, m) {
            Ok(e) => predict_around(m, &e),
            Err(e) => named(&e),
        }
    }
}

/// An identification campaign (`examples/campaigns/*/campaign.toml`), its data files resolved in
/// the vmc3 tracer example; accepted ones build their design matrix.
pub fn campaign_toml(data: &[u8]) {
    let Some(text) = text(data) else { return };
    let m = machine("vmc3");
    let dir = examples_dir().join("campaigns/vmc3_tracer");
    match trueaxis::identify::Campaign::from_toml_str(&text, ORIGIN, &dir, m) {
        Ok(c) => {
            if let Ok(nominal) = c.nominal_errors(m) {
                let _ = c.design_matrix(m, &nominal);
            }
        }
        Err(e) => named(&e),
    }
}

/// The data file of a campaign measurement (`station1.csv`: poses and length readings), read
/// through a fixed campaign with three instruments in turn (length, 3D ball, probing).
pub fn campaign_csv(data: &[u8]) {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    let dir = DIR.get_or_init(|| {
        let d = std::env::temp_dir().join(format!("trueaxis-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&d).expect("a scratch directory");
        d
    });
    let path = dir.join(ORIGIN);
    if std::fs::write(&path, data).is_err() {
        return;
    }
    let m = machine("vmc3");
    for instrument in ["length", "ball3d", "probe"] {
        let campaign = format!(
            "parameters = [\"EC0X\", \"EB0Z\", \"EA0Z\"]\n[[measurement]]\ninstrument = \"{instrument}\"\ndata = \"{ORIGIN}\"\n\
             work_point = [-350, -220, 0]\nsigma_um = 0.2\n"
        );
        match trueaxis::identify::Campaign::from_toml_str(&campaign, "campaign.toml", dir, m) {
            Ok(c) => {
                if let Ok(nominal) = c.nominal_errors(m) {
                    let _ = c.design_matrix(m, &nominal);
                }
            }
            Err(e) => {
                let message = e.to_string();
                assert!(message.contains("campaign.toml") || message.contains(ORIGIN), "{message}");
            }
        }
    }
}

/// An uncertainty sources file (`examples/uncertainty/*.toml`).
pub fn sources_toml(data: &[u8]) {
    let Some(text) = text(data) else { return };
    if let Err(e) = trueaxis::uncertainty::Sources::from_toml_str(&text, ORIGIN) {
        named(&e);
    }
}

/// A laser table (`examples/data/*.csv`, the forgiving reader: separators, decimal commas, units,
/// the wide layout) evaluated by ISO 230-2.
pub fn laser_csv(data: &[u8]) {
    let Some(text) = text(data) else { return };
    match CsvTable::from_text(&text, ORIGIN) {
        Ok(table) => {
            if let Ok(runs) = runs_of(&table) {
                let _ = plausibility(&table, &runs);
                let _ = evaluate(&runs);
            }
            let _ = table.to_canonical_csv();
        }
        Err(e) => named(&e),
    }
    match read_runs_from_str(&text, ORIGIN) {
        Ok(runs) => {
            let _ = evaluate(&runs);
        }
        Err(e) => named(&e),
    }
}

/// A ballbar trace (`examples/ballbar/*.csv`) or a ballbar text export (`export_xy.txt`).
pub fn ballbar_csv(data: &[u8]) {
    let Some(text) = text(data) else { return };
    match CsvTable::from_text(&text, ORIGIN) {
        Ok(table) => {
            let _ = trace_of(&table, &["angle", "C", "A"]);
            let _ = ballbar_header(&table);
        }
        Err(e) => named(&e),
    }
}

/// A thermal campaign (`examples/thermal/campaign.csv`: time, temperatures, drifts, runs).
pub fn thermal_csv(data: &[u8]) {
    let Some(text) = text(data) else { return };
    if let Err(e) = trueaxis::thermal::thermal_campaign::Campaign::parse(&text, ORIGIN) {
        named(&e);
    }
}

/// A pose table (`examples/poses/*.csv`) of the 5-axis machine, predicted at every pose.
pub fn poses_csv(data: &[u8]) {
    let m = machine("kx8five");
    match read_poses_from(data, ORIGIN, m) {
        Ok(poses) => {
            let zero = ErrorModel::zero(m);
            let _ = Predictor::new(m, &zero).predict_batch(&poses.internal(m));
        }
        Err(e) => named(&e),
    }
    if let Some(text) = text(data) {
        if let Ok(table) = CsvTable::from_text(&text, ORIGIN) {
            let _ = poses_of(&table, m);
        }
    }
}

/// A Renishaw `.rtl` laser file (`examples/data/laser_x.rtl`), evaluated by ISO 230-2.
pub fn rtl(data: &[u8]) {
    let Some(text) = text(data) else { return };
    match rtl::parse(&text, ORIGIN) {
        Ok(file) => {
            let _ = file.to_text();
            // the table reader detects the format and reads the file again, into runs
            if let Ok(table) = CsvTable::from_text(&text, ORIGIN) {
                if let Ok(runs) = runs_of(&table) {
                    let _ = evaluate(&runs);
                }
            }
        }
        Err(e) => named(&e),
    }
}

/// An Etalon exchange file (LaserTRACER / TRAC-CAL, `examples/data/vmc3_etalon.exc`) converted
/// into error values of the 3-axis mill, which then predict.
pub fn etalon(data: &[u8]) {
    let Some(text) = text(data) else { return };
    match etalon::parse(&text, ORIGIN) {
        Ok(file) => match file.to_error_values(machine("vmc3"), ORIGIN) {
            Ok(values) => {
                if let Ok(e) = ErrorModel::from_toml_str(&values.toml, ORIGIN, machine("vmc3")) {
                    predict_around(machine("vmc3"), &e);
                }
            }
            Err(e) => named(&e),
        },
        Err(e) => named(&e),
    }
}

/// An NC program (any bytes: the byte reader of `trueaxis_nc::source` takes them) corrected for
/// the vmc3 example errors in a dialect of `family`: the controller picked by the input's length
/// (LinuxCNC, Mach3, Mach4, grbl; Fanuc, Haas, Fadal), read in parts of 1 to 8 lines.
fn nc(data: &[u8], family: Dialect) {
    let m = machine("vmc3");
    let mut options = NcOptions::new(m);
    let of_family: Vec<Controller> = Controller::ALL.into_iter().filter(|&c| c.family() == family && c != Controller::Siemens).collect();
    options.dialect = Some(of_family[data.len() % of_family.len()]);
    // an endless loop is refused after `max_blocks` blocks; the default (20 million) costs over a
    // minute unoptimised, far beyond the smoke run's 10 s timeout; the bound itself is the same
    // code path at any size
    options.setup.max_blocks = FUZZ_MAX_BLOCKS;
    // parts of a few lines (the last byte chooses how many), so that the fuzzed programs cross the
    // parts a long program is read in
    options.part_lines = 1 + usize::from(data.last().copied().unwrap_or(0) % 8);
    if let Err(e) = correct_program(&Corrector::new(m, vmc3_errors()), data, ORIGIN, &options, &[]) {
        named(&e);
    }
}

/// Most blocks one fuzzed program may run (see [`nc`]).
const FUZZ_MAX_BLOCKS: usize = 20_000;

/// A LinuxCNC (RS274/NGC) program (`examples/nc/*.ngc`).
pub fn nc_linuxcnc(data: &[u8]) {
    nc(data, Dialect::LinuxCnc)
}

/// A Fanuc program with Macro B (`examples/nc/drilling.nc`).
pub fn nc_fanuc(data: &[u8]) {
    nc(data, Dialect::Fanuc)
}

/// The side files of NC programs: a LinuxCNC tool table (`examples/nc/tools.tbl`) and a parameter
/// file (`.var`).
pub fn nc_tables(data: &[u8]) {
    let Some(text) = text(data) else { return };
    if let Err(e) = ToolTable::parse(&text, ORIGIN) {
        named(&e);
    }
    if let Err(e) = read_parameter_file(&text, ORIGIN) {
        named(&e);
    }
}

/// The TOML files of the thermal commands (`examples/thermal/*.toml`): model (mesh, materials,
/// boundary conditions), thermal links, stress-free beam, temperature, regression and error models.
pub fn thermal_toml(data: &[u8]) {
    use trueaxis::thermal::{beam, error_model, links, model_file, regression, temperature_model};
    let Some(text) = text(data) else { return };
    let dir = examples_dir().join("thermal");
    if let Err(e) = model_file::parse_model(&text, ORIGIN, &dir) {
        named(&e);
    }
    if let Err(e) = links::read_links(&text, ORIGIN, &dir) {
        named(&e);
    }
    if let Err(e) = beam::read_beam(&text, ORIGIN) {
        named(&e);
    }
    if let Err(e) = temperature_model::TemperatureModel::from_toml_str(&text, ORIGIN) {
        named(&e);
    }
    if let Err(e) = regression::RegressionModel::from_toml_str(&text, ORIGIN) {
        named(&e);
    }
    if let Err(e) = error_model::ThermalErrorModel::from_toml_str(&text, ORIGIN) {
        named(&e);
    }
}

/// A Matrix Market file of a thermal model (`examples/thermal/fin_K.mtx`).
pub fn matrix_market(data: &[u8]) {
    let Some(text) = text(data) else { return };
    if let Err(e) = trueaxis::thermal::matrix_market::read_matrix(&text, ORIGIN) {
        named(&e);
    }
    if let Err(e) = trueaxis::thermal::matrix_market::read_vector(&text, ORIGIN) {
        named(&e);
    }
}

/// An error-budget specification on the 5-axis machine.
pub fn budget_toml(data: &[u8]) {
    use trueaxis::budget::spec::KindValues;
    let Some(text) = text(data) else { return };
    if let Err(e) = trueaxis::budget::BudgetSpec::from_toml_str(&text, ORIGIN, machine("kx8five"), KindValues([1.0, 1.0, 1.0])) {
        named(&e);
    }
}
