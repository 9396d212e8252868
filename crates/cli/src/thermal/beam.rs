//! `trueaxis thermal beam`: the stress-free beam model of a guideway or scale (Soons 1993 §3.4.3) as
//! error terms of the axis's motion errors (`thermal::beam`).

use super::links::write_terms;
use crate::output::{self, print};
use crate::Failure;
use std::fmt::Write;
use std::path::PathBuf;
use trueaxis::machine::Machine;
use trueaxis::thermal::beam::{read_beam, Beam};

/// The thermal motion errors of a linear axis from the temperatures of its guideway (or scale)
/// beam, stress-free deformation of a Bernoulli-Euler beam with a temperature field linear in each
/// cross-section and piecewise linear along the beam, written exactly as error terms of the axis
/// (position ranges between the sensor stations, factors T - 20 degC) for predict and compensate.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
trueaxis thermal beam --machine examples/machines/vmc3.toml --beam examples/thermal/beam_x.toml \\\n      \
--at T:x1=23,T:x2=23,T:x3=21,T:x4=21,T:x5=23,T:x6=23,T:x7=21,T:x8=21\n  \
trueaxis thermal beam --machine examples/machines/vmc3.toml --beam examples/thermal/beam_x.toml \\\n      \
--errors-in examples/errors/vmc3.toml --out vmc3_beam.toml --json\n\n\
Units: station positions and sensor offsets in mm, alpha in um/m/K, readings in degC; errors in um and urad.")]
pub struct BeamArgs {
    /// Machine description (TOML).
    #[arg(long)]
    machine: PathBuf,
    /// The beam (TOML): axis, y_direction, alpha_um_per_m_k, [[station]] with sensors at (y, z).
    #[arg(long)]
    beam: PathBuf,
    /// Error values to add the terms to; else the terms alone.
    #[arg(long)]
    errors_in: Option<PathBuf>,
    /// Write the error-values file here (atomically).
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
    /// Print the errors along the axis at these readings, `T:name=degC` comma separated (others 20).
    #[arg(long, value_delimiter = ',')]
    at: Option<Vec<String>>,
    /// Print one JSON document.
    #[arg(long)]
    json: bool,
}

pub fn beam(args: BeamArgs) -> Result<(), Failure> {
    let machine = Machine::load(&args.machine).map_err(Failure::input)?;
    let text = trueaxis::files::inputs::read_to_string(&args.beam)
        .map_err(|e| Failure::input(anyhow::anyhow!("{}: cannot read: {e}", args.beam.display())))?;
    let origin = args.beam.display().to_string();
    let file = read_beam(&text, &origin).map_err(Failure::of)?;
    let beam = Beam::new(&file, &machine, &origin).map_err(Failure::of)?;
    let terms = beam.terms();
    let header = format!("stress-free beam {} (trueaxis thermal beam): thermal motion errors of axis {}", args.beam.display(), file.axis);
    let name = file.name.clone().unwrap_or_else(|| "beam".into());
    let (model, out) = write_terms(&machine, args.errors_in.as_deref(), args.out.as_deref(), &header, &[(name, terms.as_slice())])?;
    let given = crate::inputs::parse_given(args.at.as_deref().unwrap_or(&[]), "--at")?;
    let readings: Vec<f64> = beam.sensors.iter().map(|s| given.iter().find(|(n, _)| n == s).map_or(20.0, |(_, v)| *v)).collect();
    if let Some((n, _)) = given.iter().find(|(n, _)| !beam.sensors.contains(n)) {
        return Err(Failure::input(anyhow::anyhow!("--at: the beam has no sensor `{n}` (sensors: {})", beam.sensors.join(", "))));
    }
    let (lo, hi) = (beam.knots[0], beam.knots[beam.knots.len() - 1]);
    let profile: Vec<(f64, [f64; 3], [f64; 2])> = (0..=10)
        .map(|k| {
            let x = lo + (hi - lo) * k as f64 / 10.0;
            let (e, eps) = beam.errors_at(x, &readings);
            (x, e, eps)
        })
        .collect();
    if args.json {
        let doc = serde_json::json!({
            "sensors": beam.sensors,
            "stations_mm": beam.knots,
            "terms": terms.len(),
            "inputs": model.sensors(),
            "profile": args.at.as_ref().map(|_| profile.iter().map(|(x, e, eps)| serde_json::json!({
                "position_mm": x, "e_x_um": e[0], "e_y_um": e[1], "e_z_um": e[2], "eps_y_urad": eps[0], "eps_z_urad": eps[1]})).collect::<Vec<_>>()),
            "out": args.out.as_ref().map(|p| p.display().to_string()),
        });
        return output::json(&doc);
    }
    let mut s = String::new();
    if args.at.is_some() {
        let _ = writeln!(s, "errors of axis {} in the beam frame at the given readings (um, urad):", file.axis);
        let _ = writeln!(s, "{:>10} {:>10} {:>10} {:>10} {:>10} {:>10}", "position", "e_x", "e_y", "e_z", "eps_y", "eps_z");
        for (x, e, eps) in &profile {
            let _ = writeln!(s, "{x:>10.1} {:>10.4} {:>10.4} {:>10.4} {:>10.4} {:>10.4}", e[0], e[1], e[2], eps[0], eps[1]);
        }
    }
    match (&args.out, args.at.is_some()) {
        (Some(path), _) => {
            let _ = writeln!(
                s,
                "wrote {}: {} error terms of axis {} (inputs {})",
                path.display(),
                terms.len(),
                file.axis,
                beam.sensors.join(", ")
            );
        }
        (None, false) => s += &out,
        (None, true) => {}
    }
    print(&s)
}
