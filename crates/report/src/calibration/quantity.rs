//! Numbers as a calibration certificate prints them: a result with its expanded uncertainty U
//! (k = 2, about 95 %) rounded by the uncertainty (JCGM 100 §7.2.6: U to two significant digits,
//! the value to the same decimal place), and every number with its unit. A quantity per length
//! (`um/mm`, `urad/mm^2`, `um/mm^3`: the slope and curvature terms of polynomial error functions)
//! too small to read in its file's unit is shown per metre (`um/m`, `urad/m^2`, `um/m^3`: times
//! 10^3, 10^6, 10^9), so that no number needs more than 4 zeros after the point.

/// Decimal places that give `u` two significant digits (negative: round to tens, hundreds ...).
/// A zero or non-finite `u` gives `None`.
pub fn decimals_for(u: f64) -> Option<i32> {
    if !(u.is_finite() && u > 0.0) {
        return None;
    }
    let mut d = 1 - u.log10().floor() as i32;
    // 9.96 rounds to 10.0 at one decimal: three digits; one decimal place fewer gives "10"
    if round_to(u, d) >= 10f64.powi(2 - d) {
        d -= 1;
    }
    Some(d)
}

/// `v` rounded to `decimals` places (negative: to tens, hundreds ...), printed without a
/// superfluous sign of zero.
pub fn fixed(v: f64, decimals: i32) -> String {
    if !v.is_finite() {
        return "-".into();
    }
    let r = round_to(v, decimals);
    let text = format!("{:.*}", decimals.max(0) as usize, r);
    if text.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        text.trim_start_matches('-').to_string()
    } else {
        text
    }
}

fn round_to(v: f64, decimals: i32) -> f64 {
    let scale = 10f64.powi(decimals);
    (v * scale).round() / scale
}

/// The unit a quantity of `magnitude` (its U, else its value) in `unit` is shown in, and the factor
/// from `unit` to it: per metre instead of per millimetre (`um/mm^3` to `um/m^3`, x 10^9) when the
/// magnitude is below 0.01 of the file's unit; else the unit itself (factor 1).
pub fn display_unit(magnitude: f64, unit: &str) -> (f64, String) {
    let per_mm = unit.split_once("/mm").and_then(|(head, power)| match power {
        "" => Some((head, 1)),
        "^2" => Some((head, 2)),
        "^3" => Some((head, 3)),
        _ => None,
    });
    match per_mm {
        Some((head, power)) if magnitude.is_finite() && magnitude > 0.0 && magnitude < 0.01 => {
            let unit = if power == 1 { format!("{head}/m") } else { format!("{head}/m^{power}") };
            (1e3f64.powi(power), unit)
        }
        _ => (1.0, unit.to_string()),
    }
}

/// `value ± U unit`, rounded by U (two significant digits of U), per metre when per millimetre
/// needs zeros ([`display_unit`]); without a usable U, the value with `fallback_decimals` and the
/// unit.
pub fn with_uncertainty(value: f64, expanded: Option<f64>, unit: &str, fallback_decimals: i32) -> String {
    let (factor, unit) = display_unit(expanded.unwrap_or(value.abs()), unit);
    let (value, expanded) = (value * factor, expanded.map(|u| u * factor));
    match expanded.and_then(|u| decimals_for(u).map(|d| (u, d))) {
        Some((u, d)) => format!("{} ± {} {unit}", fixed(value, d), fixed(u, d)),
        None => quantity(value, fallback_decimals, &unit),
    }
}

/// The value alone rounded as [`with_uncertainty`] would round it.
pub fn value_by(value: f64, expanded: f64) -> String {
    decimals_for(expanded).map_or_else(|| fixed(value, 3), |d| fixed(value, d))
}

/// U alone with two significant digits.
pub fn uncertainty(expanded: f64) -> String {
    decimals_for(expanded).map_or_else(|| "-".into(), |d| fixed(expanded, d))
}

/// A pose with axis names and units, `X 346.7 mm, Y 183.3 mm, A 45 deg`: each position to 0.1 mm
/// or 0.1 deg (the resolution a pose is stated to), trailing zeros dropped; A, B and C are rotary
/// (ISO 841).
pub fn pose(axes: &[(char, f64)]) -> String {
    axes.iter()
        .map(|(letter, v)| {
            let t = fixed(*v, 1);
            let t = t.strip_suffix(".0").unwrap_or(&t);
            format!("{letter} {t} {}", if matches!(letter, 'A' | 'B' | 'C') { "deg" } else { "mm" })
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// `value unit` with `decimals` places.
pub fn quantity(value: f64, decimals: i32, unit: &str) -> String {
    if unit.is_empty() {
        fixed(value, decimals)
    } else {
        format!("{} {unit}", fixed(value, decimals))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_significant_digits_of_u_and_the_value_to_the_same_place() {
        assert_eq!(with_uncertainty(-7.4372, Some(2.3641), "urad", 2), "-7.4 ± 2.4 urad");
        assert_eq!(with_uncertainty(138.6, Some(0.2451), "urad", 2), "138.60 ± 0.25 urad");
        assert_eq!(with_uncertainty(1234.5, Some(123.0), "um", 2), "1230 ± 120 um");
        // U close to a power of ten: 9.96 -> "10", not "10.0"
        assert_eq!(with_uncertainty(41.23, Some(9.96), "um", 2), "41 ± 10 um");
        assert_eq!(with_uncertainty(41.23, Some(0.0996), "um", 2), "41.23 ± 0.10 um");
        // no sign on a rounded zero; no U: the fallback decimals
        assert_eq!(with_uncertainty(-0.004, Some(0.21), "um", 2), "0.00 ± 0.21 um");
        assert_eq!(with_uncertainty(3.25049, None, "deg", 2), "3.25 deg");
        assert_eq!(with_uncertainty(3.25049, Some(0.0), "deg", 1), "3.3 deg");
        assert_eq!(quantity(f64::NAN, 2, "um"), "- um");
    }

    #[test]
    fn poses_carry_axis_names_units_and_a_stated_resolution() {
        let p = pose(&[('X', 346.66666666666663), ('Y', 183.33333333333331), ('Z', -373.3333333333333), ('A', 45.0), ('C', -0.04)]);
        assert_eq!(p, "X 346.7 mm, Y 183.3 mm, Z -373.3 mm, A 45 deg, C 0 deg");
    }

    #[test]
    fn per_millimetre_terms_too_small_to_read_are_shown_per_metre() {
        // the example: 0.000000061 ± 0.000000013 um/mm^3 is 61 ± 13 um/m^3
        assert_eq!(with_uncertainty(6.1e-8, Some(1.3e-8), "um/mm^3", 2), "61 ± 13 um/m^3");
        assert_eq!(with_uncertainty(-2.34e-6, Some(4.1e-7), "urad/mm^2", 2), "-2.34 ± 0.41 urad/m^2");
        assert_eq!(with_uncertainty(0.01234, Some(0.000456), "um/mm", 2), "12.34 ± 0.46 um/m");
        // readable as it is: unchanged
        assert_eq!(with_uncertainty(0.1234, Some(0.0456), "um/mm", 2), "0.123 ± 0.046 um/mm");
        assert_eq!(display_unit(1e-6, "um"), (1.0, "um".to_string()));
        assert_eq!(display_unit(1e-6, "um/mm^4"), (1.0, "um/mm^4".to_string()));
        assert_eq!(display_unit(0.0, "um/mm"), (1.0, "um/mm".to_string()));
    }
}
