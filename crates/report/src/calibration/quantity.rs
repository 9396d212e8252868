//! Numbers as a calibration certificate prints them: a result with its expanded uncertainty U
//! (k = 2, about 95 %) rounded by the uncertainty (JCGM 100 §7.2.6: U to two significant digits,
//! the value to the same decimal place), and every number with its unit.

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

/// `value ± U unit`, rounded by U (two significant digits of U); without a usable U, the value
/// with `fallback_decimals` and the unit.
pub fn with_uncertainty(value: f64, expanded: Option<f64>, unit: &str, fallback_decimals: i32) -> String {
    match expanded.and_then(|u| decimals_for(u).map(|d| (u, d))) {
        Some((u, d)) => format!("{} ± {} {unit}", fixed(value, d), fixed(u, d)),
        None => quantity(value, fallback_decimals, unit),
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
        assert_eq!(with_uncertainty(0.01234, Some(0.000456), "um/mm", 2), "0.01234 ± 0.00046 um/mm");
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
}
