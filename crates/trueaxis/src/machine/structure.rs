//! Structure codes: `wCAbYXZt` (workpiece, workpiece-side axes down to the base, `b`, tool-side axes
//! up to the tool, `t`) and the equivalent `WCAYFXZT` (`F` = frame = base). docs/design.md, Conventions.

use super::parameter::is_axis_letter;
use crate::error::{Error, Result};
use std::fmt;

/// The two serial chains of a machine, each listed from the base outward.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Structure {
    /// Workpiece-side axes, base first (`wCAbYXZt` gives `[A, C]`).
    pub workpiece_side: Vec<char>,
    /// Tool-side axes, base first (`wCAbYXZt` gives `[Y, X, Z]`).
    pub tool_side: Vec<char>,
}

impl Structure {
    /// Parses either accepted form; the error says what is wrong with the code.
    pub fn parse(code: &str) -> Result<Structure> {
        let code = code.trim();
        let chars: Vec<char> = code.chars().collect();
        let (work, tool): (&[char], &[char]) = match (chars.first(), chars.last()) {
            (Some('w'), Some('t')) => {
                let inner = &chars[1..chars.len() - 1];
                let splits: Vec<usize> = inner.iter().enumerate().filter(|(_, c)| **c == 'b').map(|(i, _)| i).collect();
                if splits.len() != 1 {
                    return Err(Error::input(format!("structure `{code}` must contain exactly one `b` (base) between `w` and `t`")));
                }
                (&inner[..splits[0]], &inner[splits[0] + 1..])
            }
            (Some('W'), Some('T')) if chars.len() >= 2 => {
                let inner = &chars[1..chars.len() - 1];
                let splits: Vec<usize> = inner.iter().enumerate().filter(|(_, c)| **c == 'F').map(|(i, _)| i).collect();
                if splits.len() != 1 {
                    return Err(Error::input(format!("structure `{code}` must contain exactly one `F` (frame) between `W` and `T`")));
                }
                (&inner[..splits[0]], &inner[splits[0] + 1..])
            }
            _ => {
                return Err(Error::input(format!(
                    "structure `{code}` must read workpiece to tool, as `wCAbYXZt` (w ... b ... t) or `WCAYFXZT` (W ... F ... T)"
                )))
            }
        };
        let mut seen = Vec::new();
        for &c in work.iter().chain(tool) {
            if !is_axis_letter(c) {
                return Err(Error::input(format!("structure `{code}`: `{c}` is not an axis letter (X Y Z U V W A B C)")));
            }
            if seen.contains(&c) {
                return Err(Error::input(format!("structure `{code}`: axis {c} appears twice")));
            }
            seen.push(c);
        }
        Ok(Structure { workpiece_side: work.iter().rev().copied().collect(), tool_side: tool.to_vec() })
    }

    /// Every axis letter of the code.
    pub fn letters(&self) -> impl Iterator<Item = char> + '_ {
        self.workpiece_side.iter().chain(&self.tool_side).copied()
    }
}

impl fmt::Display for Structure {
    /// The canonical `w...b...t` form.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let work: String = self.workpiece_side.iter().rev().collect();
        let tool: String = self.tool_side.iter().collect();
        write!(f, "w{work}b{tool}t")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_forms_give_the_same_chains() {
        let a = Structure::parse("wCAYbXZt").unwrap();
        let b = Structure::parse("WCAYFXZT").unwrap();
        assert_eq!(a, b);
        assert_eq!(b.workpiece_side, vec!['Y', 'A', 'C']);
        assert_eq!(b.tool_side, vec!['X', 'Z']);
        assert_eq!(b.to_string(), "wCAYbXZt");
        let c600u = Structure::parse("wCAbYXZt").unwrap();
        assert_eq!(c600u.workpiece_side, vec!['A', 'C']);
        assert_eq!(c600u.tool_side, vec!['Y', 'X', 'Z']);
        let lathe = Structure::parse("wCbZXt").unwrap();
        assert_eq!(lathe.workpiece_side, vec!['C']);
    }

    #[test]
    fn malformed_codes_are_rejected() {
        for code in ["CAbYXZt", "wCAYXZt", "wCAbYbXZt", "wCAbYXXt", "wCAbYQZt", "WCAYXZT", ""] {
            assert!(Structure::parse(code).is_err(), "{code}");
        }
    }
}
