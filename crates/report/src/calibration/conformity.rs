//! Conformity with tolerances under a stated decision rule (ISO 14253-1:2017; ILAC-G8:09/2019):
//! - simple acceptance: conforms when the measured value is within the tolerance, the measurement
//!   uncertainty not taken into account (the rule must be stated, and agreed with the customer);
//! - guard band of the expanded uncertainty U: conformity is proven when the value is within the
//!   tolerance reduced by U, non-conformity when it is outside the tolerance enlarged by U, and
//!   neither is proven in between.
//!
//! Tolerances are upper limits of a magnitude (ISO 230-2 A, E, M, R, B; ISO 230-4 G; a ballbar
//! diagnostic's |value|; the largest volumetric error): the value compared is `|value|`.

use super::super::html::{Cell, Mark, Section};
use super::quantity::{quantity, uncertainty, value_by};
use serde::Deserialize;

/// How measured values are compared with their tolerances.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum DecisionRule {
    /// The value against the tolerance; U stated but not used.
    #[default]
    Simple,
    /// ISO 14253-1: acceptance zone = tolerance minus U, rejection zone = beyond tolerance plus U.
    GuardBand,
}

impl DecisionRule {
    /// The statement printed in the report.
    pub fn statement(self) -> &'static str {
        match self {
            DecisionRule::Simple => "Simple acceptance (ILAC-G8, shared risk): an item passes when its measured value is within its tolerance; the expanded uncertainty U is stated but not taken into account, so a value close to its limit may be out of tolerance with a probability of up to 50 %.",
            DecisionRule::GuardBand => "Guard band of the expanded uncertainty (ISO 14253-1): an item passes when its measured value plus U is within the tolerance and fails when its value minus U is beyond it; in between, neither conformity nor non-conformity is proven. The probability of a wrong pass is at most about 2.5 %.",
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            DecisionRule::Simple => "simple acceptance",
            DecisionRule::GuardBand => "guard band of U (ISO 14253-1)",
        }
    }
}

/// The decision for `|value|` against the upper limit `tolerance` with expanded uncertainty `u`
/// (all in one unit). Under the guard band rule an item without U proves nothing either way.
pub fn decide(rule: DecisionRule, value: f64, u: Option<f64>, tolerance: f64) -> Mark {
    let v = value.abs();
    match rule {
        DecisionRule::Simple => {
            if v <= tolerance {
                Mark::Pass
            } else {
                Mark::Fail
            }
        }
        DecisionRule::GuardBand => {
            let u = u.filter(|u| u.is_finite() && *u >= 0.0);
            match u {
                Some(u) if v + u <= tolerance => Mark::Pass,
                Some(u) if v - u > tolerance => Mark::Fail,
                _ => Mark::Undecided,
            }
        }
    }
}

/// One toleranced item.
#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    /// What is toleranced, e.g. `X: positioning accuracy A (ISO 230-2)`.
    pub name: String,
    /// The section that shows the result and its uncertainty budget.
    pub section: String,
    pub value: f64,
    /// Expanded uncertainty (k = 2).
    pub expanded: Option<f64>,
    pub tolerance: f64,
    pub unit: String,
    pub mark: Mark,
}

impl Item {
    pub fn new(name: String, section: &str, value: f64, expanded: Option<f64>, tolerance: f64, unit: &str, rule: DecisionRule) -> Item {
        let mark = decide(rule, value, expanded, tolerance);
        Item { name, section: section.into(), value, expanded, tolerance, unit: unit.into(), mark }
    }
}

/// The overall statement of a list of decisions.
pub fn statement(items: &[Item]) -> String {
    let fails = items.iter().filter(|i| i.mark == Mark::Fail).count();
    let open = items.iter().filter(|i| i.mark == Mark::Undecided).count();
    match (fails, open) {
        (0, 0) => format!("The machine conforms to the {} tolerances given.", items.len()),
        (0, k) => format!(
            "No item is out of tolerance, but conformity is not proven for {k} of the {} items: their values lie within U of the limit.",
            items.len()
        ),
        (f, _) => format!("The machine does NOT conform: {f} of the {} items are out of tolerance.", items.len()),
    }
}

/// The section of decisions.
pub fn section(items: &[Item], rule: DecisionRule) -> Section {
    let rows = items
        .iter()
        .map(|i| {
            let value = match i.expanded {
                Some(u) => format!("{} {}", value_by(i.value.abs(), u), i.unit),
                None => quantity(i.value.abs(), 2, &i.unit),
            };
            vec![
                Cell::link(i.name.clone(), &i.section),
                Cell::from(value),
                Cell::from(i.expanded.map_or("not evaluated".to_string(), |u| format!("{} {}", uncertainty(u), i.unit))),
                Cell::from(format!("≤ {} {}", i.tolerance, i.unit)),
                Cell::mark(i.mark),
            ]
        })
        .collect();
    Section::new("conformity", "Conformity with the tolerances")
        .paragraph(format!("Decision rule: {}", rule.statement()))
        .cells(
            "Toleranced items: measured magnitude, its expanded uncertainty U (k = 2, about 95 %), the tolerance (upper limit) and the decision",
            &["item", "measured", "U (k = 2)", "tolerance", "decision"],
            rows,
        )
        .paragraph(statement(items))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simple_acceptance_and_the_guard_band() {
        use DecisionRule::*;
        // simple: the value against the limit, U ignored; the sign does not matter
        assert_eq!(decide(Simple, 9.9, Some(2.0), 10.0), Mark::Pass);
        assert_eq!(decide(Simple, -10.1, Some(0.1), 10.0), Mark::Fail);
        // guard band: pass below T - U, fail above T + U, not proven in between
        assert_eq!(decide(GuardBand, 7.9, Some(2.0), 10.0), Mark::Pass);
        assert_eq!(decide(GuardBand, 8.1, Some(2.0), 10.0), Mark::Undecided);
        assert_eq!(decide(GuardBand, 11.9, Some(2.0), 10.0), Mark::Undecided);
        assert_eq!(decide(GuardBand, -12.1, Some(2.0), 10.0), Mark::Fail);
        // without U nothing is proven
        assert_eq!(decide(GuardBand, 1.0, None, 10.0), Mark::Undecided);
        assert_eq!(decide(GuardBand, 11.0, None, 10.0), Mark::Undecided);
    }
}
