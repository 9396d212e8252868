//! Thermal links (Zhu 2008 ch. 4, eqs. 4.1-4.2) and thermal error models as error terms of the
//! kinematic chain, so that `predict` (and later `compensate`) evaluate them from `T:<sensor>`
//! columns without any change to the chain code.
//!
//! A link is a part of the structure between a joint and the next (a column, a ram, a bed). Its
//! thermal deformation moves the free end by `epsilon` along the link (`u`), `delta` across it
//! (`v`) and turns it by `theta` about `w = u x v` (the Table 4.2 convention, eps/delta/theta).
//! Everything carried beyond the free end moves with it: a point x goes to
//! `x + epsilon u + delta v + theta w x (x - f)`, f the free end. That is a location error of the
//! next axis k (a small transform about its reference point r: the axis point of a rotary axis, the
//! origin of M for a linear axis; docs/design.md, Conventions): rotation `theta w` and translation
//! `e = epsilon u + delta v + theta w x (r - f)`. On the tool (after the last axis) only the
//! translation of the tool point can be given (`TX TY TZ`).
//!
//! Each of epsilon, delta, theta is a [`RegressionModel`] (um, um, urad) in the sensor readings
//! (degC). The error-values file uses `T - 20`, so `c T = c (T - 20) + 20 c`: every model becomes
//! product terms `[[term.NAME]] coefficient, factors = {P = k, "T:s" = 1}`.

use super::regression::RegressionModel;
use crate::error::Error;
use crate::error_model::{Direction, ErrorModel, InputKind, REFERENCE_TEMPERATURE};
use crate::machine::{AxisKind, Machine, ParameterId};
use std::fmt::Write;

/// One product term of an error-values file.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorTerm {
    /// ISO 230 parameter (`EZZ`, `EX0Z`, `TZ`).
    pub parameter: String,
    /// um or urad per unit of the factors.
    pub coefficient: f64,
    /// `(axis letter, power)`.
    pub axes: Vec<(char, i32)>,
    /// `(input, power)`: `T:<sensor>` with the factor `T - 20 degC`, other inputs as they are.
    pub sensors: Vec<(String, i32)>,
    /// `+` or `-`: the term holds for that direction of motion of the own axis only.
    pub direction: Option<char>,
    /// `[lo, hi)` of the own axis position the term holds in.
    pub range: Option<[f64; 2]>,
}

/// The terms of `scale * model` on `parameter`, with the temperatures referred to 20 degC.
pub fn model_terms(parameter: &str, model: &RegressionModel, scale: f64) -> Result<Vec<ErrorTerm>, Error> {
    model.validate()?;
    let axis = match &model.position {
        Some(a) if a.chars().count() == 1 => a.chars().next(),
        Some(a) => return Err(Error::input(format!("position `{a}` is not an axis letter"))),
        None => None,
    };
    let mut terms = Vec::new();
    for (k, row) in model.coefficients.iter().enumerate() {
        let axes: Vec<(char, i32)> = match (k, axis) {
            (0, _) => Vec::new(),
            (k, Some(a)) => vec![(a, k as i32)],
            (_, None) => unreachable!("validated: powers of the position need an axis"),
        };
        // c x = c (x - x_ref) + c x_ref: a temperature refers to 20 degC, other inputs to 0
        let references: Vec<f64> =
            model.sensors.iter().map(|s| InputKind::parse(s).map_or(REFERENCE_TEMPERATURE, |k| k.reference())).collect();
        let constant = row[0] + row[1..].iter().zip(&references).map(|(c, r)| c * r).sum::<f64>();
        if constant != 0.0 {
            terms.push(ErrorTerm {
                parameter: parameter.into(),
                coefficient: scale * constant,
                axes: axes.clone(),
                sensors: Vec::new(),
                direction: None,
                range: None,
            });
        }
        for (s, c) in model.sensors.iter().zip(&row[1..]) {
            if *c != 0.0 {
                terms.push(ErrorTerm {
                    parameter: parameter.into(),
                    coefficient: scale * c,
                    axes: axes.clone(),
                    sensors: vec![(s.clone(), 1)],
                    direction: None,
                    range: None,
                });
            }
        }
    }
    Ok(terms)
}

/// Where a link's deformation enters the chain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LinkTarget {
    /// Location errors `EX0k .. EC0k` of the axis carried by the link's free end.
    Axis(char),
    /// The tool point offsets `TX TY TZ` (translation only).
    Tool,
    /// The workpiece point offsets `WX WY WZ` (translation only): a link whose free end carries the
    /// workpiece (a table, a fixture).
    Workpiece,
}

/// An elongation (epsilon only) or bending (epsilon, delta, theta) link.
#[derive(Clone, Debug)]
pub struct ThermalLink {
    pub name: String,
    pub target: LinkTarget,
    /// Free end f, in M at home (mm).
    pub free_end_mm: [f64; 3],
    /// Unit direction u along the link (fixed end to free end).
    pub along: [f64; 3],
    /// Unit direction v of the deflection, perpendicular to u.
    pub across: [f64; 3],
    /// Elongation along u (um).
    pub epsilon: Option<RegressionModel>,
    /// Deflection along v (um).
    pub delta: Option<RegressionModel>,
    /// Slope about `w = u x v` (urad).
    pub theta: Option<RegressionModel>,
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// The error terms of a link on `machine` (see the module documentation).
pub fn link_terms(link: &ThermalLink, machine: &Machine) -> Result<Vec<ErrorTerm>, Error> {
    let bad = |m: String| Error::input(format!("link `{}`: {m}", link.name));
    let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let (u, v) = (link.along, link.across);
    if (norm(u) - 1.0).abs() > 1e-6 || (norm(v) - 1.0).abs() > 1e-6 || (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]).abs() > 1e-6 {
        return Err(bad("`along` and `across` must be perpendicular unit vectors".into()));
    }
    let w = cross(u, v);
    let (names, rotations, reference): ([String; 3], Option<[String; 3]>, [f64; 3]) = match link.target {
        LinkTarget::Axis(letter) => {
            let axis = machine
                .axes()
                .iter()
                .find(|a| a.letter == letter)
                .ok_or_else(|| bad(format!("machine `{}` has no axis {letter} (axes: {})", machine.name, machine.axis_letters())))?;
            let r = if axis.kind == AxisKind::Rotary { [axis.point.x, axis.point.y, axis.point.z] } else { [0.0; 3] };
            let t = ["X", "Y", "Z"].map(|c| format!("E{c}0{letter}"));
            let rot = ["A", "B", "C"].map(|c| format!("E{c}0{letter}"));
            (t, Some(rot), r)
        }
        LinkTarget::Tool => {
            let tp = machine.tool_point;
            (["TX".into(), "TY".into(), "TZ".into()], None, [tp.x, tp.y, tp.z])
        }
        LinkTarget::Workpiece => (["WX".into(), "WY".into(), "WZ".into()], None, [0.0; 3]),
    };
    if rotations.is_none() && link.theta.is_some() {
        return Err(bad(
            "a slope theta cannot be given to the tool or workpiece offsets (TX TY TZ, WX WY WZ: translations only); attach the link to an axis"
                .into(),
        ));
    }
    let f = link.free_end_mm;
    // translation of the reference point per urad of theta: w x (r - f), mm * 1e-6 rad -> um: * 1e-3
    let lever = cross(w, [reference[0] - f[0], reference[1] - f[1], reference[2] - f[2]]).map(|x| x * 1e-3);
    let mut terms = Vec::new();
    for (model, direction, rotation) in [(&link.epsilon, u, None), (&link.delta, v, None), (&link.theta, lever, Some(w))] {
        let Some(model) = model else { continue };
        for (name, scale) in names.iter().zip(direction) {
            if scale.abs() > 1e-12 {
                terms.extend(model_terms(name, model, scale)?);
            }
        }
        if let (Some(rot), Some(w)) = (&rotations, rotation) {
            for (name, scale) in rot.iter().zip(w) {
                if scale.abs() > 1e-12 {
                    terms.extend(model_terms(name, model, scale)?);
                }
            }
        }
    }
    for t in &terms {
        machine.parse_parameter(&t.parameter).map_err(|e| e.context(format!("link `{}`", link.name)))?;
    }
    Ok(terms)
}

/// Adds terms to an error model (the parameters must exist on `machine`).
pub fn add_terms(model: &mut ErrorModel, machine: &Machine, terms: &[ErrorTerm]) -> Result<(), Error> {
    for t in terms {
        let id = ParameterId::parse(&t.parameter)?;
        let sensors: Vec<(&str, i32)> = t.sensors.iter().map(|(s, p)| (s.as_str(), *p)).collect();
        let direction = match t.direction {
            Some('+') => Some(Direction::Positive),
            Some('-') => Some(Direction::Negative),
            _ => None,
        };
        model
            .add_segment_term(machine, id, direction, t.range.map(|[lo, hi]| (lo, hi)), t.coefficient, &t.axes, &sensors)
            .map_err(|m| Error::input(format!("{}: {m}", t.parameter)))?;
    }
    Ok(())
}

/// The `[[term.NAME]]` TOML of an error-values file for `terms`.
pub fn terms_toml(terms: &[ErrorTerm]) -> String {
    let mut out = String::new();
    for t in terms {
        let factors: Vec<String> =
            t.axes.iter().map(|(a, p)| format!("{a} = {p}")).chain(t.sensors.iter().map(|(s, p)| format!("\"{s}\" = {p}"))).collect();
        let name = match t.direction {
            Some(d) => format!("\"{}{d}\"", t.parameter),
            None => t.parameter.clone(),
        };
        let range = t.range.map_or(String::new(), |[lo, hi]| format!("range = [{}, {}]\n", toml_number(lo), toml_number(hi)));
        let _ = writeln!(out, "[[term.{name}]]\ncoefficient = {:e}\nfactors = {{ {} }}\n{range}", t.coefficient, factors.join(", "));
    }
    out
}

/// A number as TOML writes it (`inf`, `-inf` for the open ends of a range).
fn toml_number(x: f64) -> String {
    match x {
        f64::INFINITY => "inf".into(),
        f64::NEG_INFINITY => "-inf".into(),
        x => format!("{x:?}"),
    }
}

/// A links file (`trueaxis thermal links`): `[[link]]` tables with `name`, `target` (an axis letter,
/// `tool` or `workpiece`), `free_end_mm`, `along`, `across`, and any of `epsilon` (um), `delta`
/// (um), `theta` (urad), each a number (a constant), a table `{ model = "FILE.toml" }` (a model file
/// of `thermal fit --out`, relative to the links file) or an inline model
/// `{ sensors = [..], coefficients = [[..]] }` (optionally `position`, `intercept`).
pub fn read_links(text: &str, origin: &str, dir: &std::path::Path) -> Result<Vec<ThermalLink>, Error> {
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct File {
        #[serde(default, rename = "name")]
        _name: Option<String>,
        link: Vec<LinkFile>,
    }
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct LinkFile {
        name: String,
        target: String,
        free_end_mm: [f64; 3],
        along: [f64; 3],
        across: [f64; 3],
        epsilon: Option<toml::Value>,
        delta: Option<toml::Value>,
        theta: Option<toml::Value>,
    }
    let one_line = |e: &dyn std::fmt::Display| e.to_string().split_whitespace().collect::<Vec<_>>().join(" ");
    crate::io::toml_numbers::refuse_underflow(text).map_err(|e| e.in_file(origin))?;
    let file: File = toml::from_str(text).map_err(|e| Error::input(format!("{origin}: {}", one_line(&e))))?;
    let mut links = Vec::new();
    for l in file.link {
        let at = |m: String| Error::input(format!("{origin}: link `{}`: {m}", l.name));
        let target = match l.target.trim() {
            "tool" => LinkTarget::Tool,
            "workpiece" => LinkTarget::Workpiece,
            t if t.chars().count() == 1 => LinkTarget::Axis(t.chars().next().expect("one").to_ascii_uppercase()),
            t => return Err(at(format!("target `{t}` is not an axis letter, `tool` or `workpiece`"))),
        };
        let model = |key: &str, value: &Option<toml::Value>| -> Result<Option<RegressionModel>, Error> {
            let Some(value) = value else { return Ok(None) };
            let m = match value {
                toml::Value::Float(_) | toml::Value::Integer(_) => {
                    let c = value.as_float().or_else(|| value.as_integer().map(|i| i as f64)).expect("a number");
                    RegressionModel { error: key.into(), sensors: Vec::new(), position: None, intercept: true, coefficients: vec![vec![c]] }
                }
                toml::Value::Table(t) if t.contains_key("model") => {
                    let path = t.get("model").and_then(|v| v.as_str()).ok_or_else(|| at(format!("`{key}.model` must be a file name")))?;
                    let path = dir.join(path);
                    let text = crate::files::inputs::read_to_string(&path)
                        .map_err(|e| at(format!("`{key}`: {}: cannot read: {e}", path.display())))?;
                    RegressionModel::from_toml_str(&text, &path.display().to_string())?
                }
                toml::Value::Table(t) => {
                    let mut t = t.clone();
                    t.entry("error").or_insert_with(|| toml::Value::String(key.into()));
                    t.entry("intercept").or_insert(toml::Value::Boolean(true));
                    let m: RegressionModel =
                        toml::Value::Table(t).try_into().map_err(|e: toml::de::Error| at(format!("`{key}`: {}", one_line(&e))))?;
                    m.validate().map_err(|e| at(format!("`{key}`: {e}")))?;
                    m
                }
                _ => {
                    return Err(at(format!(
                        "`{key}` must be a number, {{ model = \"FILE\" }} or {{ sensors = [..], coefficients = [[..]] }}"
                    )))
                }
            };
            if m.coefficients.iter().flatten().any(|c| !c.is_finite()) {
                return Err(at(format!("`{key}` must have finite coefficients")));
            }
            Ok(Some(m))
        };
        links.push(ThermalLink {
            name: l.name.clone(),
            target,
            free_end_mm: l.free_end_mm,
            along: l.along,
            across: l.across,
            epsilon: model("epsilon", &l.epsilon)?,
            delta: model("delta", &l.delta)?,
            theta: model("theta", &l.theta)?,
        });
    }
    Ok(links)
}
