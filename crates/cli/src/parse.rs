//! The values the commands take on their command line, each parsed in one place: points and pairs
//! of numbers (mm, or as the option states), planes of a circular test, axis positions `X=10,C=90`
//! (mm for a linear axis, deg for a rotary one; docs/design.md, Conventions) and the correction
//! limits of `compensate` and `nc` (um, urad). A clap value parser returns its message as a
//! `String` (bad input, exit status 2); a parser that needs the machine returns a [`Failure`].

use crate::Failure;
use trueaxis::compensate::export::Limits;
use trueaxis::geometry::Vec3;
use trueaxis::instruments::ballbar::Plane;
use trueaxis::machine::Machine;

/// Comma-separated numbers (`None` when one of them is not a number).
fn numbers(text: &str) -> Option<Vec<f64>> {
    text.split(',').map(|p| p.trim().parse::<f64>().ok()).collect()
}

/// A point x,y,z in mm.
pub fn point(text: &str) -> Result<Vec3, String> {
    match numbers(text) {
        Some(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => Ok(Vec3::new(v[0], v[1], v[2])),
        _ => Err(format!("`{text}` is not a point x,y,z in mm (three finite numbers separated by commas)")),
    }
}

/// Two finite numbers a,b (positions along an axis, pivot offsets of a ballbar test).
pub fn pair(text: &str) -> Result<[f64; 2], String> {
    match numbers(text).as_deref() {
        Some([a, b]) if a.is_finite() && b.is_finite() => Ok([*a, *b]),
        _ => Err(format!("`{text}` is not two numbers a,b")),
    }
}

/// Two finite offsets A,B (of an optic from the tool point, mm).
pub fn offsets(text: &str) -> Result<[f64; 2], String> {
    match numbers(text).as_deref() {
        None => Err(format!("`{text}` is not two numbers A,B")),
        Some([a, b]) if a.is_finite() && b.is_finite() => Ok([*a, *b]),
        Some(_) => Err(format!("`{text}` is not two finite numbers A,B")),
    }
}

/// An interval MIN,MAX with MIN < MAX.
pub fn interval(text: &str) -> Result<[f64; 2], String> {
    match offsets(text) {
        Ok([a, b]) if a < b => Ok([a, b]),
        _ => Err(format!("`{text}` is not MIN,MAX with MIN < MAX")),
    }
}

/// The plane of a circular test: xy, yz or zx.
pub fn plane(text: &str) -> Result<Plane, String> {
    Plane::parse(text).ok_or_else(|| format!("`{text}` is not a plane (xy, yz, zx)"))
}

/// `X=1,Y=2` into a full pose (mm, deg) of `machine`, unspecified axes 0; `what` names the option.
pub fn axis_values(machine: &Machine, text: &str, what: &str) -> Result<Vec<f64>, Failure> {
    let mut pose = vec![0.0; machine.axis_count()];
    for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let bad = || Failure::input(anyhow::anyhow!("{what}: `{part}` is not AXIS=VALUE (e.g. X=10)"));
        let (letter, value) = part.split_once('=').ok_or_else(bad)?;
        let letter = letter.trim().chars().next().filter(|_| letter.trim().len() == 1).ok_or_else(bad)?.to_ascii_uppercase();
        let value: f64 = value.trim().parse().ok().filter(|v: &f64| v.is_finite()).ok_or_else(bad)?;
        let axis = machine.axis_index(letter).ok_or_else(|| {
            Failure::input(anyhow::anyhow!("{what}: machine `{}` has no axis {letter} (axes: {})", machine.name, machine.axis_letters()))
        })?;
        pose[axis] = value;
    }
    Ok(pose)
}

/// The correction limits (um, urad): the machine file's `[limits]` (or the defaults), replaced by
/// `--limit-um` / `--limit-urad` when given (each a positive number, at most ten times the default).
pub fn correction_limits(machine: &Machine, max_um: Option<f64>, max_urad: Option<f64>) -> Result<Limits, Failure> {
    for (name, v, rotary) in [("--limit-um", max_um, false), ("--limit-urad", max_urad, true)] {
        if let Some(v) = v {
            trueaxis::machine::check_limit_value(name, v, rotary).map_err(Failure::of)?;
        }
    }
    Limits::with_overrides(machine, max_um, max_urad).map_err(Failure::of)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_their_messages() {
        assert_eq!(point(" 1, -2.5 ,3").unwrap(), Vec3::new(1.0, -2.5, 3.0));
        assert!(point("1,2").unwrap_err().contains("is not a point x,y,z"));
        assert!(point("1,2,inf").is_err());
        assert_eq!(pair("-200,250").unwrap(), [-200.0, 250.0]);
        assert_eq!(pair("1,x").unwrap_err(), "`1,x` is not two numbers a,b");
        assert_eq!(pair("1,2,3").unwrap_err(), "`1,2,3` is not two numbers a,b");
        assert_eq!(offsets("0,150").unwrap(), [0.0, 150.0]);
        assert_eq!(offsets("0,y").unwrap_err(), "`0,y` is not two numbers A,B");
        assert_eq!(offsets("0,NaN").unwrap_err(), "`0,NaN` is not two finite numbers A,B");
        assert_eq!(interval("-5,5").unwrap(), [-5.0, 5.0]);
        assert_eq!(interval("5,5").unwrap_err(), "`5,5` is not MIN,MAX with MIN < MAX");
        assert!(matches!(plane("zx"), Ok(Plane::Zx)));
        assert_eq!(plane("xx").unwrap_err(), "`xx` is not a plane (xy, yz, zx)");
    }
}
