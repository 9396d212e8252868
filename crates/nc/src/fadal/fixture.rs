//! Fadal fixture offsets (Fadal VMC programming manual, NC word summary: "E Fixture offset"; `G10
//! L02 P0, 1-48` sets them): `E1`-`E48` select one, `E0` cancels it (the program's coordinates are
//! then the machine's). `E1`-`E6` are the offsets `G54`-`G59` select (the Autodesk post for Fadal
//! writes `E` numbers and `G54`-`G59` for the same work offsets 1-6), so their values come from
//! where those of `G54`-`G59` come from (`--offset G54=...` or `--offset E1=...`, the parameter
//! file); `E7`-`E48` are kept in the slots of the Fanuc's additional work offsets `G54.1 P7`-`P48`
//! (`#7121`...: `--offset E7=...`). Machine position = program position + the selected offset
//! (mm, deg), as for any work offset.

use crate::interpret::Exec;

/// The most fixture offsets a Fadal holds.
pub const E_MAX: u32 = 48;

/// The coordinate system an `E` word selects: 0 for `E0` (none), 1-6 for `E1`-`E6` (`G54`-`G59`),
/// the slot of `G54.1 P<n>` for `E7`-`E48`.
pub(crate) fn system(e: f64) -> Result<u8, String> {
    if !(0.0..=f64::from(E_MAX)).contains(&e) || e.fract() != 0.0 {
        return Err(format!("E{e}: a Fadal fixture offset is E0 (none) or E1-E{E_MAX}"));
    }
    let n = e as u8;
    Ok(match n {
        0..=6 => n,
        _ => 10 + n - 1,
    })
}

/// The coordinate system a work offset is named by (`--offset NAME=...`): `G54`-`G59` and
/// `G59.1`-`G59.3` (1-9), or a Fadal fixture offset `E1`-`E48` (`E1`-`E6` the same as `G54`-`G59`).
pub fn offset_system(name: &str) -> Option<u8> {
    const SYSTEMS: [&str; 9] = ["G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"];
    let name = name.trim().to_ascii_uppercase();
    if let Some(i) = SYSTEMS.iter().position(|s| *s == name) {
        return Some(i as u8 + 1);
    }
    let e: u32 = name.strip_prefix('E')?.parse().ok()?;
    (1..=E_MAX).contains(&e).then(|| system(f64::from(e)).ok()).flatten()
}

impl Exec<'_> {
    /// `E<n>` on a Fadal: selects fixture offset `n` (0: none), the program position kept at the
    /// same machine position until the next move.
    pub(crate) fn fadal_fixture(&mut self, e: f64) -> Result<(), String> {
        self.select_system(system(e)?)
    }
}

#[cfg(test)]
mod tests {
    use super::{offset_system, system};

    #[test]
    fn e_numbers() {
        assert_eq!(system(0.0), Ok(0));
        assert_eq!(system(1.0), Ok(1));
        assert_eq!(system(6.0), Ok(6));
        assert_eq!(system(7.0), Ok(16));
        assert_eq!(system(48.0), Ok(57));
        assert!(system(49.0).unwrap_err().contains("E0 (none) or E1-E48"));
        assert!(system(1.5).is_err());
        assert_eq!(offset_system("g59.1"), Some(7));
        assert_eq!(offset_system("E1"), Some(1));
        assert_eq!(offset_system("E48"), Some(57));
        assert_eq!(offset_system("E0"), None);
        assert_eq!(offset_system("G60"), None);
    }
}
