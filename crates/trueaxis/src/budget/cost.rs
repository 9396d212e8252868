//! The cost-tolerance model of Zhu 2008 eq. B.5: `cost(e) = A / e^k` per component, on the
//! homogenised tolerance `e` (um/m for linear errors, urad otherwise), with a lower limit per
//! component (eq. B.8) below which a tolerance is not allocated.

use super::components::{BudgetComponent, ErrorKind};
use crate::error::Error;
use serde::Serialize;

/// Cost of one component: `a / e^k` with `e` its homogenised tolerance; `lower` is the smallest
/// tolerance that may be allocated, in the component's own unit (um or urad).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CostTerm {
    pub a: f64,
    pub k: f64,
    pub lower: f64,
}

/// Default unit cost `A` and exponent `k` of every component.
pub const DEFAULT_A: f64 = 1.0;
pub const DEFAULT_K: f64 = 2.0;
/// Default lower limits: 0.1 um for linear errors, 0.5 urad for angular and squareness errors.
pub const DEFAULT_LOWER: [f64; 3] = [0.1, 0.5, 0.5];

/// The cost model of a budget: one term per component, in the component order of the budget.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CostModel {
    pub terms: Vec<CostTerm>,
}

impl CostModel {
    /// The same `a` and `k` for every component, lower limits by kind (um, urad, urad).
    pub fn uniform(components: &[BudgetComponent], a: f64, k: f64, lower_by_kind: [f64; 3]) -> CostModel {
        let terms = components
            .iter()
            .map(|c| {
                let lower = lower_by_kind[ErrorKind::ALL.iter().position(|k| *k == c.kind).expect("three kinds")];
                CostTerm { a, k, lower }
            })
            .collect();
        CostModel { terms }
    }

    /// Total cost of tolerances in their own units (um, urad): `sum a_j / (t_j / scale_j)^k_j`.
    pub fn total(&self, components: &[BudgetComponent], tolerances: &[f64]) -> f64 {
        self.terms.iter().zip(components).zip(tolerances).map(|((term, c), t)| term.a / (t / c.scale()).powf(term.k)).sum()
    }

    /// Checks the terms: `a > 0`, `k > 0`, `lower >= 0`, all finite; the error names the component.
    pub fn check(&self, components: &[BudgetComponent]) -> Result<(), Error> {
        for (term, c) in self.terms.iter().zip(components) {
            if !(term.a.is_finite() && term.a > 0.0 && term.k.is_finite() && term.k > 0.0 && term.lower.is_finite() && term.lower >= 0.0) {
                return Err(Error::input(format!(
                    "cost of {}: a = {}, k = {}, lower = {} {}; a and k must be positive and the lower limit zero or positive",
                    c.id,
                    term.a,
                    term.k,
                    term.lower,
                    c.kind.unit()
                )));
            }
        }
        Ok(())
    }
}
