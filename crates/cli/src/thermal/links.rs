//! `trueaxis thermal links`: thermal links of the structural loop (Zhu 2008 ch. 4) as error terms of
//! the kinematic chain, written into an error-values file for `predict`, `compensate` and `nc`.

use crate::output::{self, print};
use crate::Failure;
use std::path::PathBuf;
use trueaxis::data::write_atomically;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;
use trueaxis::thermal::links::{add_terms, link_terms, read_links, terms_toml, ErrorTerm};

/// Turns the thermal links of a links file (each link's elongation epsilon, deflection delta and
/// slope theta, constants or thermal error models) into error terms of the chain: location errors of
/// the axis each link carries (EX0k..EC0k) or tool / workpiece offsets. The terms are appended to
/// --errors-in (or written alone) in --out, an error-values file that predict and compensate read
/// with the sensors as T:<sensor> columns or --temperature values.
#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
trueaxis thermal links --machine examples/machines/vmc3.toml --links examples/thermal/links_vmc3.toml\n  \
trueaxis thermal links --machine examples/machines/vmc3.toml --links examples/thermal/links_vmc3.toml \\\n      \
--errors-in examples/errors/vmc3.toml --out vmc3_links.toml --json\n\n\
Units: epsilon and delta in um, theta in urad (1 arcsec = 4.8481 urad), positions in mm; a link's\n\
temperatures are sensor readings in degC (the terms use T - 20 degC). See docs/thermal.md.")]
pub struct LinksArgs {
    /// Machine description (TOML).
    #[arg(long)]
    machine: PathBuf,
    /// Thermal links (TOML, [[link]] tables).
    #[arg(long)]
    links: PathBuf,
    /// Error values to add the terms to (e.g. the geometric errors); else the terms alone.
    #[arg(long)]
    errors_in: Option<PathBuf>,
    /// Write the error-values file here (atomically); else print it.
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
    /// Print one JSON document: {"links": [{"name", "terms": [{"parameter", "coefficient", "factors"}]}], "sensors": [..]}.
    #[arg(long)]
    json: bool,
}

pub fn links(args: LinksArgs) -> Result<(), Failure> {
    let machine = Machine::load(&args.machine).map_err(Failure::input)?;
    let text = trueaxis::files::inputs::read_to_string(&args.links)
        .map_err(|e| Failure::input(anyhow::anyhow!("{}: cannot read: {e}", args.links.display())))?;
    let dir = args.links.parent().map(PathBuf::from).unwrap_or_default();
    let links = read_links(&text, &args.links.display().to_string(), &dir).map_err(Failure::of)?;
    let mut all: Vec<(String, Vec<ErrorTerm>)> = Vec::new();
    for link in &links {
        let terms = link_terms(link, &machine).map_err(|e| Failure::input(anyhow::anyhow!("{}: {e}", args.links.display())))?;
        all.push((link.name.clone(), terms));
    }
    let header = format!("thermal links of {} (trueaxis thermal links): location errors of the carried axes", args.links.display());
    let groups: Vec<(String, &[ErrorTerm])> = all.iter().map(|(name, t)| (format!("link `{name}`"), t.as_slice())).collect();
    let (model, out) = write_terms(&machine, args.errors_in.as_deref(), args.out.as_deref(), &header, &groups)?;
    if args.json {
        let doc = serde_json::json!({
            "links": all.iter().map(|(name, terms)| serde_json::json!({
                "name": name,
                "terms": terms.iter().map(|t| serde_json::json!({
                    "parameter": t.parameter,
                    "coefficient": t.coefficient,
                    "unit": if t.parameter.starts_with("EA") || t.parameter.starts_with("EB") || t.parameter.starts_with("EC") { "urad" } else { "um" },
                    "factors": t.sensors.iter().map(|(s, p)| (s.clone(), serde_json::json!(p))).collect::<serde_json::Map<_, _>>(),
                })).collect::<Vec<_>>(),
            })).collect::<Vec<_>>(),
            "sensors": model.sensors(),
            "out": args.out.as_ref().map(|p| p.display().to_string()),
        });
        return output::json(&doc);
    }
    match &args.out {
        Some(path) => {
            let count: usize = all.iter().map(|(_, t)| t.len()).sum();
            print(&format!(
                "wrote {}: {count} error terms of {} links; inputs {}\n",
                path.display(),
                all.len(),
                if model.sensors().is_empty() { "none (constant links)".to_string() } else { model.sensors().join(", ") }
            ))
        }
        None => print(&out),
    }
}

/// Appends groups of error terms (each under a `# comment`) to the error-values file `errors_in`
/// (or to nothing), checks that the result loads on `machine`, and writes it to `out` when given.
/// Returns the model (the base plus the terms) and the text.
pub fn write_terms(
    machine: &Machine,
    errors_in: Option<&std::path::Path>,
    out_path: Option<&std::path::Path>,
    header: &str,
    groups: &[(String, &[ErrorTerm])],
) -> Result<(ErrorModel, String), Failure> {
    let base = match errors_in {
        Some(p) => {
            trueaxis::files::inputs::read_to_string(p).map_err(|e| Failure::input(anyhow::anyhow!("{}: cannot read: {e}", p.display())))?
        }
        None => String::new(),
    };
    let mut out = base.clone();
    if !out.is_empty() && !out.ends_with('\n') {
        out.push('\n');
    }
    out += &format!("\n# {header}\n");
    for (name, terms) in groups {
        out += &format!("# {name}\n{}", terms_toml(terms));
    }
    // the result must load on the machine, with the terms added to what the base file gives
    let origin = errors_in.map_or("--errors-in".to_string(), |p| p.display().to_string());
    let mut model = ErrorModel::from_toml_str(&base, &origin, machine).map_err(Failure::input)?;
    for (_, terms) in groups {
        add_terms(&mut model, machine, terms).map_err(Failure::of)?;
    }
    ErrorModel::from_toml_str(&out, "the written error values", machine).map_err(Failure::computation)?;
    if let Some(path) = out_path {
        write_atomically(path, out.as_bytes()).map_err(Failure::input)?;
    }
    Ok((model, out))
}
