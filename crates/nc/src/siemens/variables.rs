//! Local user variables of the SINUMERIK 840D sl (Programming Manual Job Planning, "Flexible NC
//! programming": "Variables", "Definition of user variables (DEF)", "Data types"): `DEF REAL
//! DEPTH=5, WIDTH`, `DEF INT COUNT=0`, `DEF BOOL DONE=FALSE`, at the top of a program (before its
//! first other statement), local to it (a subprogram has its own), 0 (FALSE) when not set. A
//! name has letters, digits and `_`, starts with two letters or `_`, and is at most 31
//! characters long. A value given to an INT is rounded (half away from zero: the 840D rounds
//! .5 up in magnitude), to a BOOL it is TRUE (1) when not 0.
//!
//! A variable is the interpreter's named parameter of its name (local to the call level, as
//! LinuxCNC's `#<name>`); its type is kept beside it as the parameter `NAME:TYPE`, a name no
//! program can write. A value given to a name no `DEF` declared is refused (the 840D stops with
//! alarm 12550, name not defined), so that a command this reader does not know, written with
//! `=`, is never taken for a variable. Arrays, `STRING`, `CHAR`, `AXIS`, `FRAME` and global
//! (`NCK`, `CHAN`) definitions are refused with the line.

use crate::expr::{Node, ParamRef};
use crate::lexer::{push, Assignment, Line};
use crate::params::Params;

use super::expr::Parser;

/// The types read.
const TYPES: [&str; 3] = ["REAL", "INT", "BOOL"];

/// Whether `name` (upper case) is a user variable's name.
pub fn is_variable_name(name: &str) -> bool {
    let b = name.as_bytes();
    b.len() >= 2
        && b.len() <= 31
        && b[..2].iter().all(|c| c.is_ascii_alphabetic() || *c == b'_')
        && b.iter().all(|c| c.is_ascii_alphanumeric() || *c == b'_')
}

/// The parameter that holds the type of variable `name`.
fn type_key(name: &str, ty: &str) -> Box<str> {
    format!("{name}:{ty}").into()
}

/// `DEF TYPE NAME[=value], ...` from after `DEF`: the assignments of the type marks and the
/// values (in that order: a value is converted to the type when it is written).
pub(crate) fn definition(p: &mut Parser, line: &mut Line, arena: &mut Vec<Node>) -> Result<(), String> {
    let ty = p.name();
    if !TYPES.contains(&ty.as_str()) {
        return Err(match ty.as_str() {
            "NCK" | "CHAN" => format!("DEF {ty}: global user data is not read (local REAL, INT and BOOL variables are)"),
            _ => format!("DEF {ty}: of the data types, REAL, INT and BOOL are read"),
        });
    }
    line.siemens_def = true;
    loop {
        let name = p.name();
        if !is_variable_name(&name) {
            return Err(format!("DEF {ty} `{name}`: a variable's name starts with two letters or _"));
        }
        let one = push(arena, Node::Const(1.0));
        line.assignments.push(Assignment { target: ParamRef::Named(type_key(&name, &ty)), value: one });
        let value = match p.peek() {
            b'[' => return Err(format!("DEF {ty} {name}[...]: arrays are not read yet")),
            b'=' => {
                p.i += 1;
                p.names.clear();
                let v = p.expression(arena)?;
                if let Some(n) = p.names.iter().find(|n| line.assignments.iter().any(|a| a.target == ParamRef::Named((*n).clone()))) {
                    return Err(format!("{n} is defined and read on one block: define it on a block of its own"));
                }
                v
            }
            _ => push(arena, Node::Const(0.0)),
        };
        line.assignments.push(Assignment { target: ParamRef::Named(name.into()), value });
        match p.peek() {
            b',' => p.i += 1,
            0 | b';' => return Ok(()),
            c => return Err(format!("DEF: `,` or the end of the block expected, found `{}`", c as char)),
        }
    }
}

/// `value` given to variable `name` as its type makes it; an error when no `DEF` declared it.
pub(crate) fn typed(params: &Params, name: &str, value: f64) -> Result<f64, String> {
    if name.contains(':') {
        return Ok(value);
    }
    match TYPES.iter().find(|ty| params.named(&type_key(name, ty)).is_some()) {
        Some(&"INT") => Ok(value.round()),
        Some(&"BOOL") => Ok(f64::from(u8::from(value != 0.0 && !value.is_nan()))),
        Some(_) => Ok(value),
        None => Err(format!(
            "{name}=...: {name} is neither a variable defined by DEF nor a command trueaxis reads (the 840D stops with alarm 12550)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dialect::Dialect;

    #[test]
    fn names_types_and_conversions() {
        assert!(is_variable_name("HH1") && is_variable_name("_X") && is_variable_name("DEPTH_2"));
        assert!(!is_variable_name("X") && !is_variable_name("X1") && !is_variable_name("1AB") && !is_variable_name("A-B"));
        let mut params = Params::new(Dialect::LinuxCnc);
        params.set_named("COUNT:INT", 1.0);
        params.set_named("DONE:BOOL", 1.0);
        params.set_named("DEPTH:REAL", 1.0);
        assert_eq!(typed(&params, "COUNT", 2.5), Ok(3.0));
        assert_eq!(typed(&params, "COUNT", -2.5), Ok(-3.0));
        assert_eq!(typed(&params, "COUNT", 2.49), Ok(2.0));
        assert_eq!(typed(&params, "DONE", -0.1), Ok(1.0));
        assert_eq!(typed(&params, "DONE", 0.0), Ok(0.0));
        assert_eq!(typed(&params, "DEPTH", 2.5), Ok(2.5));
        assert!(typed(&params, "OFFN", 2.0).unwrap_err().contains("alarm 12550"));
    }
}
