//! Parameters (LinuxCNC) and macro variables (Fanuc): storage, scopes and the parameter file.
//!
//! LinuxCNC 2.9: numbered parameters `#1`-`#5601` (all 0 at the start or read from the parameter
//! file); `#1`-`#30` are local to a subroutine call (the call's arguments, saved and restored around
//! it); named parameters `#<name>` are local to the call, `#<_name>` global; the system parameters
//! of the current position, tool and modes are computed by the interpreter. Fanuc: local variables
//! `#1`-`#33` per macro level (`G65` opens one, `M98` does not), common variables `#100`-`#199` and
//! `#500`-`#999`, all vacant until set.

use crate::dialect::Dialect;
use crate::NcError;
use std::collections::HashMap;

/// Number of numbered parameters LinuxCNC keeps (`RS274NGC_MAX_PARAMETERS`).
pub const LINUXCNC_PARAMETERS: usize = 5602;
/// Fanuc variables kept: locals, commons, the work offsets `#5201`-`#5329` and the tool offset
/// memory `#2001`-`#2400`, `#10001`-`#13999`.
pub const FANUC_VARIABLES: usize = 14_000;

/// A parameter that can be written, for restoring values after an expanded part of a program.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ParamKey {
    Numbered(u32),
    Named(Box<str>),
}

impl std::fmt::Display for ParamKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ParamKey::Numbered(n) => write!(f, "#{n}"),
            ParamKey::Named(s) => write!(f, "#<{s}>"),
        }
    }
}

/// One level of local parameters.
#[derive(Clone, Debug, Default)]
struct Level {
    /// The caller's `#1`-`#33`, restored when this level ends.
    saved: Vec<f64>,
    named: HashMap<Box<str>, f64>,
}

/// The parameters of a running program.
#[derive(Clone, Debug)]
pub struct Params {
    dialect: Dialect,
    numbered: Vec<f64>,
    named_global: HashMap<Box<str>, f64>,
    levels: Vec<Level>,
}

/// Number of local parameters of a call: `#1`-`#30` (LinuxCNC), `#1`-`#33` (Fanuc).
pub fn local_count(dialect: Dialect) -> usize {
    match dialect {
        Dialect::LinuxCnc => 30,
        Dialect::Fanuc => 33,
    }
}

impl Params {
    /// All zero (LinuxCNC) or vacant (Fanuc), one level.
    pub fn new(dialect: Dialect) -> Params {
        let numbered = match dialect {
            Dialect::LinuxCnc => vec![0.0; LINUXCNC_PARAMETERS],
            Dialect::Fanuc => vec![f64::NAN; FANUC_VARIABLES],
        };
        Params { dialect, numbered, named_global: HashMap::new(), levels: vec![Level::default()] }
    }

    /// The current call depth (0 for the main program).
    pub fn depth(&self) -> usize {
        self.levels.len() - 1
    }

    /// Whether numbered parameter `n` is one this store holds.
    pub fn holds(&self, n: u32) -> bool {
        (n as usize) < self.numbered.len() && n > 0
    }

    /// A numbered parameter (NaN: vacant); `None` when this store does not hold it.
    pub fn numbered(&self, n: u32) -> Option<f64> {
        self.holds(n).then(|| self.numbered[n as usize])
    }

    /// Sets a numbered parameter; an error when it does not exist.
    pub(crate) fn set_numbered(&mut self, n: u32, value: f64) -> Result<(), String> {
        if !self.holds(n) {
            return Err(format!("parameter #{n} does not exist (1 to {})", self.numbered.len() - 1));
        }
        self.numbered[n as usize] = value;
        Ok(())
    }

    /// A named parameter: local to the current call, or global (`_name`); `None` when undefined.
    pub fn named(&self, name: &str) -> Option<f64> {
        if name.starts_with('_') {
            self.named_global.get(name).copied()
        } else {
            self.levels.last().expect("a level").named.get(name).copied()
        }
    }

    pub fn set_named(&mut self, name: &str, value: f64) {
        let map = if name.starts_with('_') { &mut self.named_global } else { &mut self.levels.last_mut().expect("a level").named };
        match map.get_mut(name) {
            Some(v) => *v = value,
            None => {
                map.insert(name.into(), value);
            }
        }
    }

    /// Whether a write to `key` stays visible after the current call returns.
    pub fn is_global(&self, key: &ParamKey) -> bool {
        match key {
            ParamKey::Numbered(n) => *n as usize > local_count(self.dialect),
            ParamKey::Named(s) => s.starts_with('_'),
        }
    }

    /// The value of a writable parameter (NaN: vacant or undefined).
    pub fn get(&self, key: &ParamKey) -> f64 {
        match key {
            ParamKey::Numbered(n) => self.numbered(*n).unwrap_or(f64::NAN),
            ParamKey::Named(s) => self.named(s).unwrap_or(f64::NAN),
        }
    }

    /// Opens a call level: the locals are saved and set to `args` (the rest 0 in LinuxCNC, vacant on
    /// a Fanuc). `new_locals` false (Fanuc `M98`) shares the caller's locals.
    pub fn enter(&mut self, args: &[f64], new_locals: bool) {
        let count = local_count(self.dialect);
        let mut level = Level::default();
        if new_locals {
            level.saved = self.numbered[1..=count].to_vec();
            let unset = if self.dialect == Dialect::Fanuc { f64::NAN } else { 0.0 };
            for k in 1..=count {
                self.numbered[k] = args.get(k - 1).copied().unwrap_or(unset);
            }
        }
        if !new_locals {
            level.named = self.levels.last().expect("a level").named.clone();
        }
        self.levels.push(level);
    }

    /// Closes the current call level, restoring the caller's locals.
    pub fn leave(&mut self) {
        let level = self.levels.pop().expect("a call level to leave");
        if !level.saved.is_empty() {
            self.numbered[1..=level.saved.len()].copy_from_slice(&level.saved);
        }
        if self.levels.is_empty() {
            self.levels.push(Level::default());
        }
    }
}

/// Reads a LinuxCNC parameter file (`.var`: one `number value` per line, in machine units) into
/// `(number, value)` pairs; an error names the line.
pub fn read_parameter_file(text: &str, origin: &str) -> Result<Vec<(u32, f64)>, NcError> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let at = |message: String| NcError { file: origin.to_string(), line: i + 1, message };
        let mut fields = line.split_whitespace();
        let (Some(n), Some(v)) = (fields.next(), fields.next()) else {
            if line.trim().is_empty() {
                continue;
            }
            return Err(at(format!("expected `number value`, found `{}`", line.trim())));
        };
        let number: u32 = n.parse().map_err(|_| at(format!("`{n}` is not a parameter number")))?;
        let value: f64 = v.parse().ok().filter(|v: &f64| v.is_finite()).ok_or_else(|| at(format!("`{v}` is not a number")))?;
        if number == 0 || number as usize >= LINUXCNC_PARAMETERS {
            return Err(at(format!("parameter #{number} is outside 1 to {}", LINUXCNC_PARAMETERS - 1)));
        }
        out.push((number, value));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn call_levels_save_and_restore_locals() {
        let mut p = Params::new(Dialect::LinuxCnc);
        p.set_numbered(1, 7.0).unwrap();
        p.set_numbered(31, 3.0).unwrap();
        p.set_named("depth", 2.0);
        p.set_named("_global", 5.0);
        p.enter(&[10.0, 20.0], true);
        assert_eq!((p.numbered(1), p.numbered(2), p.numbered(3)), (Some(10.0), Some(20.0), Some(0.0)));
        assert_eq!(p.named("depth"), None);
        assert_eq!(p.named("_global"), Some(5.0));
        p.set_numbered(31, 4.0).unwrap();
        p.set_named("depth", 9.0);
        p.leave();
        assert_eq!((p.numbered(1), p.numbered(31), p.named("depth")), (Some(7.0), Some(4.0), Some(2.0)));
        assert!(p.set_numbered(6000, 1.0).is_err());
        let mut f = Params::new(Dialect::Fanuc);
        assert!(f.numbered(100).unwrap().is_nan());
        f.set_numbered(1, 1.0).unwrap();
        f.enter(&[], false);
        assert_eq!(f.numbered(1), Some(1.0));
        f.leave();
        f.enter(&[2.0], true);
        assert_eq!(f.numbered(1), Some(2.0));
        assert!(f.numbered(2).unwrap().is_nan());
        f.leave();
        assert_eq!(f.numbered(1), Some(1.0));
        let pairs = read_parameter_file("5161 1.5\n\n5221\t-10.000000\n", "p.var").unwrap();
        assert_eq!(pairs, vec![(5161, 1.5), (5221, -10.0)]);
        assert!(read_parameter_file("5161 x\n", "p.var").unwrap_err().to_string().starts_with("p.var: line 1: "));
    }
}
