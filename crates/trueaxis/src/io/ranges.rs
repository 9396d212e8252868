//! Physical ranges of the quantities trueaxis reads, one per quantity, shared by every reader
//! (machine file, error-values file, campaigns, ballbar and laser tables, thermal data). A value
//! outside its range is not a measurement of a machine tool: it is a unit slip (um for nm, mm for
//! um), a corrupted file, or a number such as 1e200 that would overflow the computation into inf
//! or NaN. Readers refuse it as bad input naming the file, the line or parameter,
//! and the range (docs/limits.md). The ranges are deliberately wide: they catch what no machine
//! can produce, and the unit-scale checks of [`super::plausibility`] catch the subtler slips.

/// The range of one quantity: `min <= value <= max`, in `unit`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysicalRange {
    /// What the quantity is, for messages ("a linear error value").
    pub quantity: &'static str,
    pub unit: &'static str,
    pub min: f64,
    pub max: f64,
    /// Why the range is where it is, for messages.
    pub why: &'static str,
}

/// Linear error values (motion, location and setup errors, error tables, drifts; um): at most
/// 100 mm. Machine-tool geometric errors are 0.1 um to a few hundred um (ISO 230-1 and -2 tests of
/// machines from micro-milling to large gantries); 100 mm is a wrong nominal geometry, not an error.
pub const LINEAR_ERROR_UM: PhysicalRange = PhysicalRange {
    quantity: "a linear error",
    unit: "um",
    min: -1e5,
    max: 1e5,
    why: "100 mm: beyond any machine-tool error; most likely another unit (nm, or mm written as um)",
};

/// Angular error values (urad): at most 0.1 rad (5.7 deg); machine-tool angular errors are
/// 1 to a few hundred urad.
pub const ANGULAR_ERROR_URAD: PhysicalRange = PhysicalRange {
    quantity: "an angular error",
    unit: "urad",
    min: -1e5,
    max: 1e5,
    why: "0.1 rad = 5.7 deg: beyond any machine-tool error; most likely another unit (nrad, or deg or mrad written as urad)",
};

/// Readings of an instrument in a campaign, a ballbar or a laser test (deviations, um): at most
/// 100 mm (a ballbar reads within +-1 mm of its length, Renishaw QC20-W).
pub const READING_UM: PhysicalRange = PhysicalRange {
    quantity: "a reading",
    unit: "um",
    min: -1e5,
    max: 1e5,
    why: "100 mm: beyond any instrument reading of a machine tool's deviation; most likely another unit",
};

/// Lengths of a machine's geometry (tool point, axis points, linear travels; mm): at most 100 m.
pub const MACHINE_LENGTH_MM: PhysicalRange = PhysicalRange {
    quantity: "a machine dimension",
    unit: "mm",
    min: -1e5,
    max: 1e5,
    why: "100 m: beyond the largest machine tools; most likely um written as mm",
};

/// Positions of a rotary axis (deg): at most 10^6 deg (about 2800 turns of a multi-turn table).
pub const ROTARY_POSITION_DEG: PhysicalRange =
    PhysicalRange { quantity: "a rotary axis position", unit: "deg", min: -1e6, max: 1e6, why: "about 2800 turns" };

/// Temperatures (degC): -100 to 300 degC, beyond any machine-tool structure, coolant, spindle or
/// motor temperature (and beyond the working range of the usual Pt100 / thermocouple probes' mounts).
pub const TEMPERATURE_DEGC: PhysicalRange = PhysicalRange {
    quantity: "a temperature",
    unit: "degC",
    min: -100.0,
    max: 300.0,
    why: "beyond any machine-tool temperature; most likely K written as degC, or another quantity",
};

/// Times of a recording (s): at most 10^9 s (32 years) either side of its origin.
pub const TIME_S: PhysicalRange =
    PhysicalRange { quantity: "a time", unit: "s", min: -1e9, max: 1e9, why: "32 years; most likely a timestamp in ms or another unit" };

/// Thermal drifts and displacements (um): the same range as linear errors.
pub const THERMAL_DRIFT_UM: PhysicalRange = PhysicalRange { quantity: "a thermal drift", ..LINEAR_ERROR_UM };

impl PhysicalRange {
    /// Whether `value` is finite and within the range.
    pub fn contains(&self, value: f64) -> bool {
        value.is_finite() && value >= self.min && value <= self.max
    }

    /// `None` when `value` is within the range; else the refusal, one line without the place
    /// (the caller prefixes the file and line or parameter).
    pub fn check(&self, value: f64) -> Option<String> {
        if self.contains(value) {
            return None;
        }
        Some(format!(
            "{value:e} {} is outside the physical range of {} ({} to {} {}; {})",
            self.unit, self.quantity, self.min, self.max, self.unit, self.why
        ))
    }

    /// The first value of `values` outside the range, as `(index, refusal)`.
    pub fn first_outside(&self, values: &[f64]) -> Option<(usize, String)> {
        values.iter().enumerate().find_map(|(i, &v)| self.check(v).map(|m| (i, m)))
    }
}

/// The 1-based line of `text` where `key` is assigned or opens a section (`key = ...`,
/// `"key" = ...`, `[section.key]`), for messages about a TOML value; `None` when not found.
pub fn line_of_key(text: &str, key: &str) -> Option<usize> {
    let quoted = format!("\"{key}\"");
    text.lines()
        .position(|l| {
            let l = l.trim_start();
            let assigns = |k: &str| l.strip_prefix(k).is_some_and(|rest| rest.trim_start().starts_with('='));
            let section = l.starts_with('[') && (l.contains(&format!(".{key}]")) || l.contains(&format!(".{quoted}]")));
            assigns(key) || assigns(&quoted) || section
        })
        .map(|i| i + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_refuse_huge_and_non_finite_values_and_keep_real_ones() {
        for v in [1e200, 1e308, -1e308, f64::NAN, f64::INFINITY, 100_001.0] {
            assert!(LINEAR_ERROR_UM.check(v).is_some(), "{v}");
        }
        for v in [0.0, -250.0, 99_999.0] {
            assert!(LINEAR_ERROR_UM.check(v).is_none(), "{v}");
        }
        assert!(TEMPERATURE_DEGC.check(20.0).is_none() && TEMPERATURE_DEGC.check(293.15 + 20.0).is_some());
        assert_eq!(READING_UM.first_outside(&[1.0, 2.0, 1e200]).map(|f| f.0), Some(2));
        let text = "name = \"x\"\n[constant]\nEC0X = 1e12\n[table.\"EXX+\"]\nposition = [0]\n";
        assert_eq!(line_of_key(text, "EC0X"), Some(3));
        assert_eq!(line_of_key(text, "EXX+"), Some(4));
        assert_eq!(line_of_key(text, "EYY"), None);
    }
}
