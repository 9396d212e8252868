//! Error functions of the own axis position: constants, tables with linear interpolation, and
//! polynomials (docs/design.md, Files, error-values TOML). Values are in user units (um, urad),
//! positions in mm (linear axes) or deg (rotary axes).

use super::basis::Basis;
use crate::error::{Error, Result};

/// One parametric error as a function of its own axis position.
#[derive(Clone, Debug, PartialEq)]
pub enum ErrorFunction {
    /// A constant value.
    Constant(f64),
    /// Linear interpolation between strictly increasing `positions`; outside the table the end
    /// value is held. With `period = Some(p)` the position is first wrapped into
    /// `[positions[0], positions[0] + p)` (a rotary-axis table over one full turn).
    Table { positions: Vec<f64>, values: Vec<f64>, period: Option<f64> },
    /// `sum_k coefficients[k] * q^k`, ascending powers of the position.
    Polynomial { coefficients: Vec<f64> },
    /// `sum_l coefficients[l] p_l(q)` over a parametric basis (Soons 1993 eq. 3.1).
    Basis { basis: Basis, coefficients: Vec<f64> },
}

impl ErrorFunction {
    /// Builds a table after checking it: equal lengths, at least two points, finite numbers,
    /// strictly increasing positions.
    pub fn table(positions: Vec<f64>, values: Vec<f64>, period: Option<f64>) -> Result<ErrorFunction> {
        let n = positions.len();
        crate::ensure!(n == values.len(), input, "`position` has {n} entries but `value` has {}", values.len());
        crate::ensure!(n >= 2, input, "a table needs at least two points");
        if let Some(i) = positions.iter().chain(&values).position(|x| !x.is_finite()) {
            crate::bail!(input, "entry {} is not a finite number", i % n + 1);
        }
        if let Some(i) = positions.windows(2).position(|w| w[1] <= w[0]) {
            crate::bail!(input, "`position` must increase strictly, but entry {} ({}) follows {}", i + 2, positions[i + 1], positions[i]);
        }
        Ok(ErrorFunction::Table { positions, values, period })
    }

    /// Builds a polynomial after checking it has finite coefficients.
    pub fn polynomial(coefficients: Vec<f64>) -> Result<ErrorFunction> {
        if coefficients.is_empty() {
            return Err(Error::input("`coefficients` must not be empty"));
        }
        if coefficients.iter().any(|c| !c.is_finite()) {
            return Err(Error::input("`coefficients` must be finite numbers"));
        }
        Ok(ErrorFunction::Polynomial { coefficients })
    }

    /// Builds a basis function after checking the number of coefficients.
    pub fn basis(basis: Basis, coefficients: Vec<f64>) -> Result<ErrorFunction> {
        if coefficients.len() != basis.len() {
            return Err(Error::input(format!(
                "the basis has {} functions ({}) but {} coefficients are given",
                basis.len(),
                basis.names().join(", "),
                coefficients.len()
            )));
        }
        if coefficients.iter().any(|c| !c.is_finite()) {
            return Err(Error::input("`coefficients` must be finite numbers"));
        }
        Ok(ErrorFunction::Basis { basis, coefficients })
    }

    /// Value (um or urad) at position `q` (mm or deg).
    pub fn evaluate(&self, q: f64) -> f64 {
        match self {
            ErrorFunction::Constant(v) => *v,
            ErrorFunction::Table { positions, values, period } => {
                let q = match period {
                    Some(p) => positions[0] + (q - positions[0]).rem_euclid(*p),
                    None => q,
                };
                interpolate(positions, values, q)
            }
            ErrorFunction::Polynomial { coefficients } => coefficients.iter().rev().fold(0.0, |acc, c| acc * q + c),
            ErrorFunction::Basis { basis, coefficients } => basis.eval(coefficients, q),
        }
    }
}

/// Piecewise-linear interpolation, end values held outside `[positions[0], positions[n-1]]`.
pub(crate) fn interpolate(positions: &[f64], values: &[f64], q: f64) -> f64 {
    let n = positions.len();
    if q <= positions[0] {
        return values[0];
    }
    if q >= positions[n - 1] {
        return values[n - 1];
    }
    // the interval is first guessed as if the positions were equally spaced (exact for the usual
    // tables, so no search), then moved to the one that holds q
    let guess = ((q - positions[0]) / (positions[n - 1] - positions[0]) * (n - 1) as f64) as usize;
    let mut i = guess.min(n - 2);
    while i > 0 && positions[i] > q {
        i -= 1;
    }
    while i < n - 2 && positions[i + 1] <= q {
        i += 1;
    }
    let t = (q - positions[i]) / (positions[i + 1] - positions[i]);
    values[i] + t * (values[i + 1] - values[i])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_interpolates_linearly_and_holds_ends() {
        let f = ErrorFunction::table(vec![-300.0, 0.0, 300.0], vec![0.0, 4.0, 9.0], None).unwrap();
        assert_eq!(f.evaluate(0.0), 4.0);
        assert!((f.evaluate(150.0) - 6.5).abs() < 1e-12);
        assert!((f.evaluate(-75.0) - 3.0).abs() < 1e-12);
        assert_eq!(f.evaluate(400.0), 9.0);
        assert_eq!(f.evaluate(-301.0), 0.0);
    }

    #[test]
    fn periodic_table_wraps_one_turn() {
        let f = ErrorFunction::table(vec![0.0, 90.0, 180.0, 270.0, 360.0], vec![0.0, 2.0, 0.0, -2.0, 0.0], Some(360.0)).unwrap();
        assert!((f.evaluate(405.0) - f.evaluate(45.0)).abs() < 1e-12);
        assert!((f.evaluate(-45.0) - f.evaluate(315.0)).abs() < 1e-12);
    }

    #[test]
    fn polynomial_uses_ascending_powers() {
        let f = ErrorFunction::polynomial(vec![1.0, 0.5, 0.25]).unwrap();
        assert!((f.evaluate(2.0) - (1.0 + 1.0 + 1.0)).abs() < 1e-15);
    }

    #[test]
    fn bad_tables_are_refused() {
        assert!(ErrorFunction::table(vec![0.0, 1.0], vec![0.0], None).unwrap_err().to_string().contains("2 entries"));
        assert!(ErrorFunction::table(vec![0.0, 0.0], vec![0.0, 1.0], None).unwrap_err().to_string().contains("increase"));
        assert!(ErrorFunction::table(vec![0.0], vec![0.0], None).is_err());
        assert!(ErrorFunction::table(vec![0.0, f64::NAN], vec![0.0, 1.0], None).is_err());
        assert!(ErrorFunction::polynomial(vec![]).is_err());
    }

    #[test]
    fn interpolation_finds_the_interval_of_uneven_tables() {
        // reference: binary search for the interval
        let positions = [-3.0, 0.0, 0.5, 10.0, 11.0, 50.0];
        let values = [1.0, -2.0, 4.0, 0.5, 7.0, -1.0];
        for k in 0..=1060 {
            let q = -5.0 + 0.05 * k as f64;
            let want = if q <= positions[0] {
                values[0]
            } else if q >= positions[5] {
                values[5]
            } else {
                let i = positions.partition_point(|&p| p <= q) - 1;
                values[i] + (q - positions[i]) / (positions[i + 1] - positions[i]) * (values[i + 1] - values[i])
            };
            assert!((interpolate(&positions, &values, q) - want).abs() < 1e-12, "q = {q}");
        }
    }
}
