//! An error function prepared for the hot path of the exact volumetric error: evaluated at an axis
//! position in internal units (mm, rad) and giving the value in internal units (mm, rad), with the
//! unit conversions of docs/design.md, Conventions folded in once, and a table's interval found by one
//! multiplication when its positions are equally spaced (the usual laser or compensation table),
//! instead of divisions and a search at every evaluation.

use super::function::{interpolate, ErrorFunction};

/// How a motion or location error is evaluated (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Evaluator {
    /// A constant, in internal units.
    Constant(f64),
    /// A table in internal units.
    Table(TableEvaluator),
    /// Any other function: evaluated in user units, `f(q * position_scale) * value_scale`.
    General { position_scale: f64, value_scale: f64 },
}

impl Evaluator {
    /// Prepares `function`; `position_scale` converts an internal position to the user unit of
    /// the function (1 for mm, 180/pi for deg), `value_scale` a user value to internal units
    /// (1e-3 for um, 1e-6 for urad).
    pub(crate) fn new(function: &ErrorFunction, position_scale: f64, value_scale: f64) -> Evaluator {
        match function {
            ErrorFunction::Constant(v) => Evaluator::Constant(v * value_scale),
            ErrorFunction::Table { positions, values, period } => Evaluator::Table(TableEvaluator::new(
                positions.iter().map(|p| p / position_scale).collect(),
                values.iter().map(|v| v * value_scale).collect(),
                period.map(|p| p / position_scale),
            )),
            _ => Evaluator::General { position_scale, value_scale },
        }
    }

    /// Value (mm or rad) at position `q` (mm or rad); `function` is the one this was made from.
    #[inline]
    pub(crate) fn value(&self, function: &ErrorFunction, q: f64) -> f64 {
        match self {
            Evaluator::Constant(v) => *v,
            Evaluator::Table(t) => t.value(q),
            Evaluator::General { position_scale, value_scale } => function.evaluate(q * position_scale) * value_scale,
        }
    }
}

/// Linear interpolation in a table, end values held outside it (the semantics of
/// [`ErrorFunction::Table`]), periodic tables wrapped into their first period.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TableEvaluator {
    start: f64,
    /// `1 / step` when the positions are equally spaced (to 1e-12 of the step), else 0 (search).
    inverse_step: f64,
    /// Index of the last point, as a number.
    last: f64,
    /// The period and its inverse; 0 when the table is not periodic.
    period: f64,
    inverse_period: f64,
    positions: Vec<f64>,
    values: Vec<f64>,
}

impl TableEvaluator {
    fn new(positions: Vec<f64>, values: Vec<f64>, period: Option<f64>) -> TableEvaluator {
        let n = positions.len();
        let step = (positions[n - 1] - positions[0]) / (n - 1) as f64;
        let equal = positions.windows(2).all(|w| ((w[1] - w[0]) - step).abs() <= 1e-12 * step.abs());
        let period = period.unwrap_or(0.0);
        TableEvaluator {
            start: positions[0],
            inverse_step: if equal { 1.0 / step } else { 0.0 },
            last: (n - 1) as f64,
            period,
            inverse_period: if period > 0.0 { 1.0 / period } else { 0.0 },
            positions,
            values,
        }
    }

    /// Value (internal units) at position `q` (mm or rad).
    #[inline]
    pub(crate) fn value(&self, q: f64) -> f64 {
        let x = self.offset(q);
        if self.inverse_step == 0.0 {
            return interpolate(&self.positions, &self.values, self.start + x);
        }
        self.equally_spaced_value(x)
    }

    /// Adds the value (internal units) at each position of `q` (mm or rad) to `out`: the batch form
    /// of [`TableEvaluator::value`], the equally spaced case one loop over the lanes (index
    /// arithmetic and two loads per lane, no search) that the compiler vectorises.
    #[inline(always)]
    pub(crate) fn add_lanes<const N: usize>(&self, q: &[f64; N], out: &mut [f64; N]) {
        if self.inverse_step == 0.0 {
            for (o, &q) in out.iter_mut().zip(q) {
                *o += self.value(q);
            }
        } else {
            // three passes, so that the arithmetic is vectorised and only the loads go lane by
            // lane: the interval of each lane, its two values, the interpolation
            let mut x: [f64; N] = std::array::from_fn(|l| q[l] - self.start);
            if self.period > 0.0 {
                for x in &mut x {
                    *x = self.wrapped(*x);
                }
            }
            let mut u = [0.0; N];
            let mut i = [0.0; N];
            for l in 0..N {
                (u[l], i[l]) = self.interval(x[l]);
            }
            let mut a = [0.0; N];
            let mut b = [0.0; N];
            for l in 0..N {
                (a[l], b[l]) = self.interval_values(i[l]);
            }
            for l in 0..N {
                out[l] += a[l] + (u[l] - i[l]) * (b[l] - a[l]);
            }
        }
    }

    /// `q - start`, wrapped into the first period of a periodic table.
    #[inline(always)]
    fn offset(&self, q: f64) -> f64 {
        let x = q - self.start;
        if self.period > 0.0 {
            self.wrapped(x)
        } else {
            x
        }
    }

    /// An offset from the first position wrapped into the first period.
    #[inline(always)]
    fn wrapped(&self, x: f64) -> f64 {
        x - self.period * floor(x * self.inverse_period)
    }

    /// The value at offset `x` from the first position of an equally spaced table: the interval by
    /// one multiplication; u = last (the end) uses the last interval with t = 1.
    #[inline(always)]
    fn equally_spaced_value(&self, x: f64) -> f64 {
        let (u, i) = self.interval(x);
        let (a, b) = self.interval_values(i);
        a + (u - i) * (b - a)
    }

    /// The position in steps `u` of offset `x` (in [0, last]; a NaN offset gives the first point)
    /// and the start `i <= last - 1` of its interval, a whole number.
    #[inline(always)]
    fn interval(&self, x: f64) -> (f64, f64) {
        // clamped by compare and select (the vector max and min instructions; NaN gives 0)
        let u = x * self.inverse_step;
        let u = if u > 0.0 { u } else { 0.0 };
        let u = if u < self.last { u } else { self.last };
        let i = floor(u);
        (u, if i < self.last - 1.0 { i } else { self.last - 1.0 })
    }

    /// The values at the ends of the interval that starts at point `i` (from [`Self::interval`]).
    #[inline(always)]
    fn interval_values(&self, i: f64) -> (f64, f64) {
        let k = index_of(i);
        debug_assert!(k + 1 < self.values.len());
        // SAFETY: 0 <= i <= last - 1 = values.len() - 2 (Self::interval), so k and k + 1 index
        // `values`; unchecked so that the loop over the lanes has no branch
        unsafe { (*self.values.get_unchecked(k), *self.values.get_unchecked(k + 1)) }
    }
}

/// A non-directional function of its own axis's position, as the evaluation plan of
/// [`super::ErrorModel`] holds it: the part of the error values that depends on the axis positions
/// alone, and which the batch kernel evaluates over its lanes ([`PositionFunction::add_lanes`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum PositionFunction {
    /// A table in internal units.
    Table(TableEvaluator),
    /// `sum_k coefficients[k] x^k` at the user position `x = q * position_scale` (mm or deg), times
    /// `value_scale` (user value to internal units): the scalar evaluation of
    /// [`ErrorFunction::Polynomial`], operation for operation.
    Polynomial { coefficients: Vec<f64>, position_scale: f64, value_scale: f64 },
    /// Any other function (a basis of `fit` or `identify`), evaluated as [`Evaluator::value`] does.
    General { function: ErrorFunction, position_scale: f64, value_scale: f64 },
}

impl PositionFunction {
    /// The plan's form of a non-directional function; `None` for a constant (summed instead).
    pub(crate) fn of(evaluator: &Evaluator, function: &ErrorFunction) -> Option<PositionFunction> {
        match (evaluator, function) {
            (Evaluator::Constant(_), _) => None,
            (Evaluator::Table(t), _) => Some(PositionFunction::Table(t.clone())),
            (&Evaluator::General { position_scale, value_scale }, ErrorFunction::Polynomial { coefficients }) => {
                Some(PositionFunction::Polynomial { coefficients: coefficients.clone(), position_scale, value_scale })
            }
            (&Evaluator::General { position_scale, value_scale }, function) => {
                Some(PositionFunction::General { function: function.clone(), position_scale, value_scale })
            }
        }
    }

    /// Value (internal units) at position `q` (mm or rad).
    #[inline]
    pub(crate) fn value(&self, q: f64) -> f64 {
        match self {
            PositionFunction::Table(t) => t.value(q),
            PositionFunction::Polynomial { coefficients, position_scale, value_scale } => {
                horner(coefficients, q * position_scale) * value_scale
            }
            PositionFunction::General { function, position_scale, value_scale } => function.evaluate(q * position_scale) * value_scale,
        }
    }

    /// Adds the value (internal units) at each position of `q` (mm or rad) to `out`, lane by lane
    /// equal to [`Self::value`]: tables and polynomials in one loop over the lanes that the compiler
    /// vectorises, other functions one lane at a time.
    #[inline(always)]
    pub(crate) fn add_lanes<const N: usize>(&self, q: &[f64; N], out: &mut [f64; N]) {
        match self {
            PositionFunction::Table(t) => t.add_lanes(q, out),
            PositionFunction::Polynomial { coefficients, position_scale, value_scale } => {
                let x: [f64; N] = std::array::from_fn(|l| q[l] * position_scale);
                let mut acc = [0.0; N];
                for &c in coefficients.iter().rev() {
                    for (a, &x) in acc.iter_mut().zip(&x) {
                        *a = *a * x + c;
                    }
                }
                for (o, a) in out.iter_mut().zip(acc) {
                    *o += a * value_scale;
                }
            }
            PositionFunction::General { .. } => {
                for (o, &q) in out.iter_mut().zip(q) {
                    *o += self.value(q);
                }
            }
        }
    }
}

/// `sum_k coefficients[k] x^k` by Horner's rule from the highest power, as
/// [`ErrorFunction::evaluate`].
#[inline]
fn horner(coefficients: &[f64], x: f64) -> f64 {
    coefficients.iter().rev().fold(0.0, |acc, c| acc * x + c)
}

/// `floor(y)` by floating-point operations alone, for the periodic wrap and the interval of an
/// equally spaced table: no libm call (which `f64::floor` is on targets without SSE4.1) and no
/// conversion to a 64-bit integer (which AVX2 does not have for vectors), so that the loops over
/// the lanes stay vectorised. Exact for |y| < 2^51: adding and subtracting 1.5 * 2^52 rounds y to
/// the nearest integer (no significand bits are left for a fraction), one less if that is above
/// y. Beyond 2^51, y itself (an integer from 2^52 on); NaN stays NaN.
#[inline(always)]
fn floor(y: f64) -> f64 {
    const ROUNDING: f64 = 6_755_399_441_055_744.0; // 1.5 * 2^52
    const LIMIT: f64 = 2_251_799_813_685_248.0; // 2^51
    let nearest = (y + ROUNDING) - ROUNDING;
    let floor = if nearest > y { nearest - 1.0 } else { nearest };
    if y.abs() < LIMIT {
        floor
    } else {
        y
    }
}

/// The index of a whole number `i` (0 <= i < 2^52) held as a float, from its bits: `i + 2^52` has
/// `i` in the low bits of its significand (again no conversion instruction, see [`floor`]).
#[inline(always)]
fn index_of(i: f64) -> usize {
    const TWO_52: f64 = 4_503_599_627_370_496.0;
    ((i + TWO_52).to_bits() - TWO_52.to_bits()) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prepared_tables_equal_the_user_unit_function() {
        // equally and unequally spaced, plain and periodic (rotary, deg), against
        // ErrorFunction::evaluate in user units
        let deg = 180.0 / std::f64::consts::PI;
        let cases = [
            (ErrorFunction::table(vec![-300.0, -100.0, 100.0, 300.0], vec![1.0, -2.0, 4.0, 0.5], None).unwrap(), 1.0, 1e-3),
            (ErrorFunction::table(vec![-3.0, 0.0, 0.5, 10.0], vec![1.0, -2.0, 4.0, 0.5], None).unwrap(), 1.0, 1e-3),
            (ErrorFunction::table(vec![0.0, 90.0, 180.0, 270.0, 360.0], vec![0.0, 5.0, -1.0, 2.0, 0.0], Some(360.0)).unwrap(), deg, 1e-6),
            (ErrorFunction::table(vec![-30.0, 0.0, 45.0, 110.0], vec![3.0, 0.0, -7.0, 2.0], None).unwrap(), deg, 1e-6),
        ];
        for (function, position_scale, value_scale) in cases {
            let prepared = Evaluator::new(&function, position_scale, value_scale);
            for k in 0..=2000 {
                let user = -800.0 + 0.8 * k as f64 + 0.123;
                let q = user / position_scale;
                let want = function.evaluate(user) * value_scale;
                let got = prepared.value(&function, q);
                assert!((got - want).abs() <= 1e-12 * value_scale * 10.0, "{function:?} at {user}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn position_functions_over_lanes_equal_the_user_unit_function_bit_for_bit() {
        // a polynomial in deg of a rotary axis (urad), a Legendre basis and a table in mm (um):
        // each lane of add_lanes equals value, and value equals ErrorFunction::evaluate in user units
        let deg = 180.0 / std::f64::consts::PI;
        let spec = crate::error_model::basis::BasisSpec {
            family: "legendre".into(),
            degree: 4,
            knots: vec![],
            continuity: vec![1],
            constant: true,
            constraint: "none".into(),
            domain: [-400.0, 400.0],
            periodic: vec![],
        };
        let basis = crate::error_model::basis::Basis::new(spec).unwrap();
        let coefficients = vec![0.5, -1.0, 2.0, 0.25, 0.1][..basis.len()].to_vec();
        let cases = [
            (ErrorFunction::polynomial(vec![2.0, 0.02, -1.5e-5, 3e-9]).unwrap(), deg, 1e-6),
            (ErrorFunction::Basis { basis, coefficients }, 1.0, 1e-3),
            (ErrorFunction::table(vec![-400.0, -200.0, 0.0, 200.0, 400.0], vec![-5.0, -2.0, 0.0, 3.0, 6.5], None).unwrap(), 1.0, 1e-3),
        ];
        for (function, position_scale, value_scale) in cases {
            let f = PositionFunction::of(&Evaluator::new(&function, position_scale, value_scale), &function).expect("not a constant");
            for k in 0..100 {
                let q: [f64; 8] = std::array::from_fn(|l| (-450.0 + 0.9 * (8 * k + l) as f64 + 0.37) / position_scale);
                let mut lanes = [1.0; 8];
                f.add_lanes(&q, &mut lanes);
                for l in 0..8 {
                    let user = q[l] * position_scale;
                    assert_eq!(lanes[l], 1.0 + f.value(q[l]), "{function:?} lane {l}");
                    let want = function.evaluate(user) * value_scale;
                    assert!(
                        (f.value(q[l]) - want).abs() <= 1e-15 * want.abs().max(1e-3),
                        "{function:?} at {user}: {} vs {want}",
                        f.value(q[l])
                    );
                }
            }
        }
        assert_eq!(PositionFunction::of(&Evaluator::Constant(1.0), &ErrorFunction::Constant(1.0)), None);
    }

    #[test]
    fn floor_of_the_periodic_wrap() {
        for y in [
            -3.5,
            -3.0,
            -0.2,
            -0.0,
            0.0,
            0.7,
            1.0,
            2.999999,
            1e12 + 0.5,
            -1e12 - 0.5,
            2.0f64.powi(51) - 0.5,
            -(2.0f64.powi(51)) + 0.5,
            1e17,
            -1e17,
        ] {
            assert_eq!(floor(y), y.floor(), "{y}");
        }
        assert!(floor(f64::NAN).is_nan());
        for i in [0usize, 1, 2, 31, 32, 99_999, 1 << 40] {
            assert_eq!(index_of(i as f64), i);
        }
    }

    #[test]
    fn other_functions_are_evaluated_in_user_units() {
        let f = ErrorFunction::polynomial(vec![1.0, 0.5]).unwrap();
        let prepared = Evaluator::new(&f, 2.0, 1e-3);
        assert!((prepared.value(&f, 3.0) - (1.0 + 0.5 * 6.0) * 1e-3).abs() < 1e-18);
        assert_eq!(Evaluator::new(&ErrorFunction::Constant(7.0), 1.0, 1e-6).value(&f, 99.0), 7e-6);
    }
}
