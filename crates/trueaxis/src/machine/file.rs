//! The machine TOML of docs/design.md, Files: parsing and validation.

use super::axis::{Axis, AxisKind, Side};
use super::error::MachineError;
use super::limits::CorrectionLimits;
use super::parameter::is_rotary_letter;
use super::structure::Structure;
use super::Machine;
use crate::error::{Error, Result};
use crate::geometry::Vec3;
use crate::io::ranges::{line_of_key, MACHINE_LENGTH_MM, ROTARY_POSITION_DEG};
use serde::Deserialize;
use std::collections::BTreeMap;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MachineFile {
    name: String,
    structure: String,
    #[serde(default)]
    source: Option<String>,
    axes: BTreeMap<String, AxisFile>,
    tool: ToolFile,
    /// `[limits]`: the largest corrections trueaxis may write (module `limits`).
    #[serde(default)]
    limits: Option<LimitsFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LimitsFile {
    #[serde(default)]
    correction_um: Option<f64>,
    #[serde(default)]
    correction_urad: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisFile {
    kind: KindFile,
    direction: [f64; 3],
    #[serde(default)]
    point: Option<[f64; 3]>,
    #[serde(default)]
    range: Option<[f64; 2]>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum KindFile {
    Linear,
    Rotary,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ToolFile {
    point: [f64; 3],
}

/// Tolerance on the norm of an axis direction: `|norm - 1| <= 1e-4` is accepted (and normalised),
/// so that directions written with 5 decimals, such as `[0, 0.70711, 0.70711]`, load.
pub const DIRECTION_NORM_TOLERANCE: f64 = 1e-4;

pub(super) fn parse(text: &str, origin: &str) -> Result<Machine, MachineError> {
    crate::io::toml_numbers::refuse_underflow(text)
        .map_err(|e| MachineError::Syntax { origin: origin.to_string(), message: e.to_string() })?;
    let file: MachineFile =
        toml::from_str(text).map_err(|e| MachineError::Syntax { origin: origin.to_string(), message: one_line(&e.to_string()) })?;
    let invalid = |message: String| MachineError::Invalid { origin: origin.to_string(), message };

    for key in file.axes.keys() {
        let mut chars = key.chars();
        if !matches!((chars.next(), chars.next()), (Some(c), None) if super::parameter::is_axis_letter(c)) {
            return Err(invalid(format!("[axes] has an unknown axis `{key}`: axes are named X Y Z U V W A B C")));
        }
    }
    let structure = Structure::parse(&file.structure).map_err(|e| invalid(e.to_string()))?;
    if structure.letters().next().is_none() {
        return Err(invalid(format!("structure `{}` has no axes; a machine needs at least one", file.structure)));
    }
    for letter in structure.letters() {
        if !file.axes.contains_key(&letter.to_string()) {
            let defined: Vec<&str> = file.axes.keys().map(String::as_str).collect();
            return Err(invalid(format!(
                "structure `{}` names axis {letter}, which is not defined under [axes] (defined: {})",
                file.structure,
                defined.join(" ")
            )));
        }
    }
    let mut axes = Vec::new();
    for (key, spec) in &file.axes {
        let letter = key.chars().next().expect("checked above");
        let side = if structure.workpiece_side.contains(&letter) {
            Side::Workpiece
        } else if structure.tool_side.contains(&letter) {
            Side::Tool
        } else {
            return Err(invalid(format!("axis {letter} is defined under [axes] but does not appear in structure `{}`", file.structure)));
        };
        axes.push(axis(letter, side, spec).map_err(|m| invalid(format!("{}axis {letter}: {m}", at_line(text, key))))?);
    }
    super::independence::refuse_dependent_linear_axes(&axes).map_err(|e| invalid(e.to_string()))?;
    let tool_point = finite_vector(file.tool.point).ok_or_else(|| invalid("[tool] point must be finite numbers (mm)".into()))?;
    if let Some((i, m)) = MACHINE_LENGTH_MM.first_outside(&file.tool.point) {
        let line = text
            .find("[tool]")
            .and_then(|s| line_of_key(&text[s..], "point").map(|l| text[..s].matches('\n').count() + l))
            .map_or(String::new(), |l| format!("line {l}: "));
        return Err(invalid(format!("{line}[tool] point, component {}: {m}", i + 1)));
    }
    if file.name.trim().is_empty() {
        return Err(invalid("`name` must not be empty".into()));
    }
    let limits = file.limits.map_or_else(CorrectionLimits::default, |l| CorrectionLimits {
        correction_um: l.correction_um,
        correction_urad: l.correction_urad,
    });
    limits.validate().map_err(|e| invalid(e.to_string()))?;
    let mut machine = Machine::assemble(file.name, file.source, structure, axes, tool_point);
    machine.correction_limits = limits;
    Ok(machine)
}

fn axis(letter: char, side: Side, spec: &AxisFile) -> Result<Axis> {
    let kind = match spec.kind {
        KindFile::Linear => AxisKind::Linear,
        KindFile::Rotary => AxisKind::Rotary,
    };
    if is_rotary_letter(letter) != (kind == AxisKind::Rotary) {
        let expected = if is_rotary_letter(letter) { "rotary" } else { "linear" };
        return Err(Error::input(format!(
            "ISO 841 names {letter} a {expected} axis, but kind = \"{}\"",
            if kind == AxisKind::Rotary { "rotary" } else { "linear" }
        )));
    }
    let direction = finite_vector(spec.direction).ok_or_else(|| Error::input("direction must be finite numbers"))?;
    let norm = direction.norm();
    if norm == 0.0 {
        return Err(Error::input("direction is the zero vector; give a unit vector such as [1, 0, 0]"));
    }
    if (norm - 1.0).abs() > DIRECTION_NORM_TOLERANCE {
        return Err(Error::input(format!(
            "direction [{}, {}, {}] is not a unit vector (norm {norm:.6}); divide it by its norm",
            spec.direction[0], spec.direction[1], spec.direction[2]
        )));
    }
    let point = match (kind, spec.point) {
        (_, Some(p)) => {
            let point = finite_vector(p).ok_or_else(|| Error::input("point must be finite numbers (mm)"))?;
            if let Some((i, m)) = MACHINE_LENGTH_MM.first_outside(&p) {
                return Err(Error::input(format!("point, component {}: {m}", i + 1)));
            }
            point
        }
        (AxisKind::Linear, None) => Vec3::zeros(),
        (AxisKind::Rotary, None) => return Err(Error::input("missing field `point`: a rotary axis needs a point on its axis line (mm)")),
    };
    let range = match (kind, spec.range) {
        (_, Some([lo, hi])) => {
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(Error::input(format!("range [{lo}, {hi}] must be two finite numbers, the smaller first")));
            }
            let physical = if kind == AxisKind::Rotary { ROTARY_POSITION_DEG } else { MACHINE_LENGTH_MM };
            if let Some((_, m)) = physical.first_outside(&[lo, hi]) {
                return Err(Error::input(format!("range [{lo}, {hi}]: {m}")));
            }
            Some([lo, hi])
        }
        (AxisKind::Linear, None) => return Err(Error::input("missing field `range`: a linear axis needs its travel [min, max] (mm)")),
        (AxisKind::Rotary, None) => None,
    };
    Ok(Axis { letter, kind, side, direction: direction / norm, point, range })
}

/// `line N: ` of the first assignment of `key` in `text`, or nothing.
fn at_line(text: &str, key: &str) -> String {
    line_of_key(text, key).map_or(String::new(), |l| format!("line {l}: "))
}

fn finite_vector(v: [f64; 3]) -> Option<Vec3> {
    v.iter().all(|x| x.is_finite()).then(|| Vec3::new(v[0], v[1], v[2]))
}

/// TOML errors span several lines (with a source excerpt); docs/design.md asks for one line.
pub(crate) fn one_line(message: &str) -> String {
    let is_excerpt = |l: &str| l.trim_start_matches(|c: char| c.is_ascii_digit() || c == ' ').starts_with('|');
    message.lines().map(str::trim).filter(|l| !l.is_empty() && !is_excerpt(l)).collect::<Vec<_>>().join(": ")
}
