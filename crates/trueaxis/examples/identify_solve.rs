//! The weighted least-squares solve of `trueaxis::identify::solve` on a design matrix file, printed
//! as JSON for `bench/baseline_identify.py check` (the NumPy/SciPy baseline must compute the same).
//!
//! The file is the design CSV of `trueaxis uncertainty --design` (`channel,t,y,weight,<parameters>`,
//! docs/uncertainty.md); the solve starts from zero with the default options (unit-length scaling,
//! QR or Gram reduction, back substitution).
//!
//! Run: `cargo run --release -p trueaxis --example identify_solve -- DESIGN.csv`.

use trueaxis::identify::{solve, IndirectOptions};

#[path = "../benches/common/problems.rs"]
mod problems;

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: identify_solve DESIGN.csv (channel,t,y,weight,<parameters>)");
        std::process::exit(2);
    };
    let d = trueaxis::uncertainty::DesignMatrix::read_csv(&path).unwrap_or_else(|e| {
        eprintln!("{path}: {e}");
        std::process::exit(2);
    });
    let design = problems::design_of_file(&d, |i| (0, i));
    let result = solve(&design, &vec![0.0; d.parameters.len()], &IndirectOptions::default()).unwrap_or_else(|e| {
        eprintln!("{path}: {e}");
        std::process::exit(1);
    });
    let json = serde_json::json!({
        "solution": result.delta,
        "std_uncertainty": result.std_uncertainty,
        "sigma0": result.sigma0,
        "singular_values": result.identifiability.singular_values,
        "residual_rms_um": result.residual_rms_um,
    });
    println!("{json}");
}
