//! The thermal model file (TOML, SI units named in the keys; docs/design.md, Command line).
//!
//! ```toml
//! kind = "bar1d"                # or "grid2d", "grid3d", "matrix_market"
//! length_m = 1.0                # bar1d
//! area_m2 = 0.0314
//! perimeter_m = 0.6283
//! conductivity_w_mk = 60.5
//! density_kg_m3 = 7800.0
//! specific_heat_j_kgk = 434.0
//! convection_w_m2k = 20.0       # lateral surface (bar perimeter; both faces of a plate)
//! elements = 22
//! left_end = "insulated"        # or a convection coefficient (W/m^2/K)
//! right_end = "insulated"
//! flux_node = 0                 # where the representative step heat flux enters
//! flux_w = 100.0                # its size (default 1 W; the weight shares do not depend on it)
//! ```
//! `grid2d` / `grid3d`: `size_m = [lx, ly(, lz)]`, `cells = [nx, ny(, nz)]`, `thickness_m` (2D),
//! `boundary = { xmin = 50.0, ymax = "insulated", ... }` (faces not named are insulated),
//! `flux_node = [i, j(, k)]` (grid indices). `matrix_market`: `capacity = "C.mtx"`,
//! `conductivity = "K.mtx"` (paths relative to the model file), and `load = "Q.mtx"` or
//! `flux_node = n` (0-based). Optional everywhere: `name`, `candidates = [..]` (sensor candidate
//! nodes, 0-based; default every node).

use super::assembly::{assemble, Boundary, Material, Section, ThermalProblem, ThermalSystem};
use super::matrix_market::{read_matrix, read_vector};
use super::mesh::StructuredMesh;
use crate::error::Error;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ModelFile {
    kind: String,
    name: Option<String>,
    length_m: Option<f64>,
    area_m2: Option<f64>,
    perimeter_m: Option<f64>,
    elements: Option<usize>,
    left_end: Option<toml::Value>,
    right_end: Option<toml::Value>,
    size_m: Option<Vec<f64>>,
    cells: Option<Vec<usize>>,
    thickness_m: Option<f64>,
    boundary: Option<BTreeMap<String, toml::Value>>,
    conductivity_w_mk: Option<f64>,
    density_kg_m3: Option<f64>,
    specific_heat_j_kgk: Option<f64>,
    convection_w_m2k: Option<f64>,
    flux_node: Option<toml::Value>,
    flux_w: Option<f64>,
    capacity: Option<String>,
    conductivity: Option<String>,
    load: Option<String>,
    candidates: Option<Vec<usize>>,
}

/// A loaded thermal model.
#[derive(Clone, Debug)]
pub struct ThermalModel {
    pub name: String,
    pub system: ThermalSystem,
    /// The mesh, for generated models.
    pub mesh: Option<StructuredMesh>,
    /// The material, for generated models.
    pub material: Option<Material>,
    /// Sensor candidate nodes.
    pub candidates: Vec<usize>,
    /// Nodes where the step flux enters.
    pub flux_nodes: Vec<usize>,
}

/// Reads a thermal model file.
pub fn load_model(path: impl AsRef<Path>) -> Result<ThermalModel, Error> {
    let path = path.as_ref();
    let origin = path.display().to_string();
    let text = crate::files::inputs::read_to_string(path).map_err(|e| Error::input(format!("{origin}: cannot read thermal model: {e}")))?;
    parse_model(&text, &origin, path.parent().unwrap_or(Path::new(".")))
}

/// Parses a thermal model; `origin` names it in messages, `dir` resolves relative matrix paths.
pub fn parse_model(text: &str, origin: &str, dir: &Path) -> Result<ThermalModel, Error> {
    crate::io::toml_numbers::refuse_underflow(text).map_err(|e| e.in_file(origin))?;
    let f: ModelFile = toml::from_str(text).map_err(|e| Error::input(format!("{origin}: {}", one_line(&e.to_string()))))?;
    let bad = |m: String| Error::input(format!("{origin}: {m}"));
    let need = |key: &str, v: Option<f64>| -> Result<f64, Error> {
        match v {
            Some(x) if x.is_finite() && x > 0.0 => Ok(x),
            Some(x) => Err(bad(format!("`{key}` must be a positive finite number (got {x})"))),
            None => Err(bad(format!("missing key `{key}` (kind = \"{}\")", f.kind))),
        }
    };
    let flux_w = match f.flux_w {
        Some(w) if !w.is_finite() => return Err(bad("`flux_w` must be a finite number of W".into())),
        Some(w) => w,
        None => 1.0,
    };
    let convection = match f.convection_w_m2k {
        Some(h) if !(h.is_finite() && h >= 0.0) => return Err(bad(format!("`convection_w_m2k` must be >= 0 (got {h})"))),
        Some(h) => h,
        None => 0.0,
    };
    let material = || -> Result<Material, Error> {
        Ok(Material {
            conductivity_w_mk: need("conductivity_w_mk", f.conductivity_w_mk)?,
            density_kg_m3: need("density_kg_m3", f.density_kg_m3)?,
            specific_heat_j_kgk: need("specific_heat_j_kgk", f.specific_heat_j_kgk)?,
        })
    };
    let (system, mesh, material, flux_nodes) = match f.kind.as_str() {
        "bar1d" | "grid2d" | "grid3d" => {
            let material = material()?;
            let (mesh, section, boundaries) = match f.kind.as_str() {
                "bar1d" => {
                    let elements = f.elements.ok_or_else(|| bad("missing key `elements`".into()))?;
                    let mesh = StructuredMesh::bar(need("length_m", f.length_m)?, elements).map_err(|e| bad(e.to_string()))?;
                    let section = Section::Bar { area_m2: need("area_m2", f.area_m2)?, perimeter_m: need("perimeter_m", f.perimeter_m)? };
                    let ends = [end(&f.left_end, "left_end", origin)?, end(&f.right_end, "right_end", origin)?];
                    (mesh, section, vec![ends])
                }
                kind => {
                    let dim = if kind == "grid2d" { 2 } else { 3 };
                    let size = f.size_m.clone().ok_or_else(|| bad("missing key `size_m`".into()))?;
                    let cells = f.cells.clone().ok_or_else(|| bad("missing key `cells`".into()))?;
                    if size.len() != dim || cells.len() != dim {
                        return Err(bad(format!("`size_m` and `cells` need {dim} entries for kind = \"{kind}\"")));
                    }
                    let mesh = StructuredMesh::new(cells, size).map_err(|e| bad(e.to_string()))?;
                    let section =
                        if dim == 2 { Section::Plate { thickness_m: need("thickness_m", f.thickness_m)? } } else { Section::Solid };
                    (mesh, section, faces(f.boundary.as_ref(), dim, origin)?)
                }
            };
            let flux_node = match &f.flux_node {
                None => return Err(bad("missing key `flux_node` (where the step heat flux enters)".into())),
                Some(v) => grid_node(v, &mesh).map_err(|m| bad(format!("`flux_node`: {m}")))?,
            };
            let problem = ThermalProblem {
                mesh: mesh.clone(),
                material,
                section,
                lateral_convection_w_m2k: convection,
                boundaries,
                fluxes: vec![(flux_node, flux_w)],
            };
            (assemble(&problem).map_err(|e| bad(e.to_string()))?, Some(mesh), Some(material), vec![flux_node])
        }
        "matrix_market" => {
            let read = |key: &str, file: &Option<String>| -> Result<String, Error> {
                let name = file.as_ref().ok_or_else(|| bad(format!("missing key `{key}` (a Matrix Market file)")))?;
                let p = dir.join(name);
                crate::files::inputs::read_to_string(&p).map_err(|e| bad(format!("`{key}`: cannot read {}: {e}", p.display())))
            };
            let c = read_matrix(&read("capacity", &f.capacity)?, &dir.join(f.capacity.as_deref().unwrap_or("")).display().to_string())?;
            let k = read_matrix(
                &read("conductivity", &f.conductivity)?,
                &dir.join(f.conductivity.as_deref().unwrap_or("")).display().to_string(),
            )?;
            let n = c.nrows();
            let (load, flux_nodes) = match (&f.load, &f.flux_node) {
                (Some(_), _) => {
                    let q = read_vector(&read("load", &f.load)?, &dir.join(f.load.as_deref().unwrap_or("")).display().to_string())?;
                    let nodes = q.iter().enumerate().filter(|(_, v)| **v != 0.0).map(|(i, _)| i).collect();
                    (q, nodes)
                }
                (None, Some(v)) => {
                    let node = v.as_integer().filter(|i| *i >= 0 && (*i as usize) < n).ok_or_else(|| {
                        bad(format!("`flux_node` must be a node number in 0..{} for kind = \"matrix_market\"", n.saturating_sub(1)))
                    })? as usize;
                    let mut q = vec![0.0; n];
                    q[node] = flux_w;
                    (q, vec![node])
                }
                (None, None) => return Err(bad("give `load` (a Matrix Market vector) or `flux_node`".into())),
            };
            (ThermalSystem::from_matrices(c, k, load).map_err(|e| bad(e.to_string()))?, None, None, flux_nodes)
        }
        other => return Err(bad(format!("unknown kind `{other}` (bar1d, grid2d, grid3d, matrix_market)"))),
    };
    let n = system.node_count();
    let candidates = match f.candidates {
        Some(c) => {
            if let Some(bad_node) = c.iter().find(|&&i| i >= n) {
                return Err(bad(format!("`candidates`: node {bad_node} does not exist (nodes 0..{})", n - 1)));
            }
            c
        }
        None => (0..n).collect(),
    };
    Ok(ThermalModel { name: f.name.unwrap_or_else(|| origin.to_string()), system, mesh, material, candidates, flux_nodes })
}

fn end(v: &Option<toml::Value>, key: &str, origin: &str) -> Result<Boundary, Error> {
    boundary(v.as_ref(), &format!("{origin}: `{key}`"))
}

fn boundary(v: Option<&toml::Value>, what: &str) -> Result<Boundary, Error> {
    match v {
        None => Ok(Boundary::Insulated),
        Some(toml::Value::String(s)) if s == "insulated" => Ok(Boundary::Insulated),
        Some(v) => match v.as_float().or_else(|| v.as_integer().map(|i| i as f64)) {
            Some(h) if h.is_finite() && h >= 0.0 => Ok(Boundary::Convection(h)),
            _ => Err(Error::input(format!("{what} must be \"insulated\" or a convection coefficient >= 0 in W/m^2/K"))),
        },
    }
}

fn faces(map: Option<&BTreeMap<String, toml::Value>>, dim: usize, origin: &str) -> Result<Vec<[Boundary; 2]>, Error> {
    let names = ["x", "y", "z"];
    let mut out = vec![[Boundary::Insulated; 2]; dim];
    for (key, v) in map.into_iter().flatten() {
        let d = names.iter().position(|n| key.starts_with(n)).filter(|&d| d < dim);
        let side = match &key.get(1..) {
            Some("min") => Some(0),
            Some("max") => Some(1),
            _ => None,
        };
        match (d, side) {
            (Some(d), Some(s)) => out[d][s] = boundary(Some(v), &format!("{origin}: `boundary.{key}`"))?,
            _ => {
                let valid: Vec<String> = names[..dim].iter().flat_map(|n| [format!("{n}min"), format!("{n}max")]).collect();
                return Err(Error::input(format!("{origin}: `boundary.{key}` is not a face ({})", valid.join(", "))));
            }
        }
    }
    Ok(out)
}

fn grid_node(v: &toml::Value, mesh: &StructuredMesh) -> Result<usize, Error> {
    let ijk: Vec<usize> = match v {
        toml::Value::Integer(i) if mesh.dimensions() == 1 => vec![usize::try_from(*i).map_err(|_| Error::input("must not be negative"))?],
        toml::Value::Array(a) => a
            .iter()
            .map(|x| x.as_integer().and_then(|i| usize::try_from(i).ok()).ok_or_else(|| Error::input("grid indices must be integers >= 0")))
            .collect::<Result<_, _>>()?,
        _ => return Err(Error::input(format!("expected {} grid indices", mesh.dimensions()))),
    };
    if ijk.len() != mesh.dimensions() || ijk.iter().zip(mesh.cells()).any(|(i, c)| i > c) {
        return Err(Error::input(format!("{ijk:?} is not a node of a grid with {:?} cells", mesh.cells())));
    }
    Ok(mesh.node_index(&ijk))
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
