//! The units of the design criteria of [`super::optimal_design`], and their conversion to the units of
//! Soons 1993 §4.4 (Table 4.1).
//!
//! trueaxis computes the criteria on rows weighted by `1/sigma` with sigma in um, and the unknowns
//! in their user units (um, urad, um/mm^k, urad/deg^k, ...): `n M^-1` is the covariance of the
//! unknowns per unit variance of the readings (sigma = 1 um), in the unknowns' units squared. So
//! - D = `det(n M^-1)^(1/p)` has the unit `(u_1^2 ... u_p^2)^(1/p)`, the geometric mean of the
//!   squared units;
//! - A = `trace(n M^-1)/p` and E = `lambda_max(n M^-1)` add variances of the unknowns, so they
//!   have a unit only when every unknown has the same one;
//! - G (and the reading variances) are variances of readings over sigma^2: dimensionless.
//!
//! Soons 1993 writes its parameters without units (rad for a squareness, mm/mm for a scale error)
//! with lengths in mm and `sigma = 1` in the same unit as the lengths (Table 4.1: det^(1/3) =
//! 2.98e-5 for 400 mm bars). With `c_j` the factor from the user unit of unknown j to mm and rad
//! (um -> mm: 1e-3; urad -> rad: 1e-6; per deg -> per rad: 180/pi) and sigma = 1 um = 1e-3 mm:
//! - `D_seed000 = D (c_1 ... c_p)^(2/p) / (1e-3)^2`;
//! - `A_seed000 = A c^2 / (1e-3)^2` and `E_seed000 = E c^2 / (1e-3)^2` when every `c_j = c`.

/// The units of the criteria of a design over unknowns with `units` (user units, one per unknown).
#[derive(Clone, Debug, PartialEq)]
pub struct CriteriaUnits {
    /// The unit of D, e.g. `urad^2` or `(urad^2 (um/mm)^2 (um/mm)^2)^(1/3)`.
    pub d: String,
    /// The unit of A and E, or `None` when the unknowns' units differ (the sum mixes them).
    pub a_e: Option<String>,
    /// Factor that turns D into Soons 1993's units, `None` when a unit is not a length or an angle
    /// (per powers of mm or deg).
    pub d_to_seed000: Option<f64>,
    /// Factor that turns A and E into Soons 1993's units, when every unknown has the same factor.
    pub a_e_to_seed000: Option<f64>,
}

/// Factor from a user unit (`um`, `urad`, `um/mm^2`, `urad/deg`, ...) to mm or rad per mm^k or
/// rad^k; `None` for anything else.
pub fn to_mm_rad(unit: &str) -> Option<f64> {
    let (numerator, denominator) = match unit.split_once('/') {
        Some((n, d)) => (n, Some(d)),
        None => (unit, None),
    };
    let mut factor = match numerator {
        "um" => 1e-3,
        "urad" => 1e-6,
        _ => return None,
    };
    if let Some(d) = denominator {
        let (base, power) = match d.split_once('^') {
            Some((b, p)) => (b, p.parse::<i32>().ok()?),
            None => (d, 1),
        };
        // a value per deg^k is (180/pi)^k times the value per rad^k
        factor *= match base {
            "mm" => 1.0,
            "deg" => (180.0 / std::f64::consts::PI).powi(power),
            _ => return None,
        };
    }
    Some(factor)
}

/// The units of D, A and E (module documentation) for unknowns with `units`.
pub fn criteria_units(units: &[String]) -> CriteriaUnits {
    let p = units.len();
    let all_equal = units.windows(2).all(|w| w[0] == w[1]);
    let squared = |u: &str| if u.contains('/') { format!("({u})^2") } else { format!("{u}^2") };
    let d = if all_equal && p > 0 {
        squared(&units[0])
    } else {
        format!("({})^(1/{p})", units.iter().map(|u| squared(u)).collect::<Vec<_>>().join(" "))
    };
    let factors: Option<Vec<f64>> = units.iter().map(|u| to_mm_rad(u)).collect();
    // sigma = 1 um is 1e-3 mm: variances per sigma^2 grow by 1e6
    let sigma = 1e-3f64;
    let d_to_seed000 = factors.as_ref().map(|c| c.iter().map(|c| (c * c).ln()).sum::<f64>() / p as f64).map(|l| l.exp() / (sigma * sigma));
    let a_e_to_seed000 =
        factors.filter(|c| c.windows(2).all(|w| (w[0] - w[1]).abs() <= 1e-12 * w[0].abs())).map(|c| c[0] * c[0] / (sigma * sigma));
    CriteriaUnits { d, a_e: (all_equal && p > 0).then(|| squared(&units[0])), d_to_seed000, a_e_to_seed000 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_factors() {
        assert_eq!(to_mm_rad("um"), Some(1e-3));
        assert_eq!(to_mm_rad("urad"), Some(1e-6));
        assert_eq!(to_mm_rad("um/mm"), Some(1e-3));
        assert_eq!(to_mm_rad("um/mm^2"), Some(1e-3));
        let per_deg = to_mm_rad("urad/deg").unwrap();
        assert!((per_deg - 1e-6 * 180.0 / std::f64::consts::PI).abs() < 1e-18);
        assert_eq!(to_mm_rad("kg"), None);
        assert_eq!(to_mm_rad("um/s"), None);
    }

    #[test]
    fn seed000_conversion_of_the_2d_cmm() {
        // squareness urad, two scales um/mm: (1e-6 1e-3 1e-3)^(2/3) / 1e-6 = 1e-2
        let units: Vec<String> = ["urad", "um/mm", "um/mm"].map(String::from).to_vec();
        let u = criteria_units(&units);
        assert!((u.d_to_seed000.unwrap() - 1e-2).abs() < 1e-15);
        assert_eq!(u.a_e, None);
        assert_eq!(u.a_e_to_seed000, None);
        assert_eq!(u.d, "(urad^2 (um/mm)^2 (um/mm)^2)^(1/3)");
        let same: Vec<String> = ["um", "um"].map(String::from).to_vec();
        let u = criteria_units(&same);
        assert_eq!((u.d.as_str(), u.a_e.as_deref()), ("um^2", Some("um^2")));
        assert!((u.a_e_to_seed000.unwrap() - 1.0).abs() < 1e-12);
    }
}
