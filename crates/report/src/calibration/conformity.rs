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
use super::quantity::{display_unit, quantity, uncertainty, value_by};
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
/// (all in one unit). Under the guard band rule an item without U proves nothing either way; a
/// value beyond the limit by less than U is [`Mark::Beyond`]: out of tolerance as measured, its
/// non-conformity not proven.
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
                _ if v > tolerance => Mark::Beyond,
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
    /// Why U is not stated and how it will be, for an item without one.
    pub without_u: Option<String>,
}

impl Item {
    pub fn new(name: String, section: &str, value: f64, expanded: Option<f64>, tolerance: f64, unit: &str, rule: DecisionRule) -> Item {
        let mark = decide(rule, value, expanded, tolerance);
        Item { name, section: section.into(), value, expanded, tolerance, unit: unit.into(), mark, without_u: None }
    }

    /// An item whose U is not evaluated, with how it will be.
    pub fn without_u(mut self, how: impl Into<String>) -> Item {
        self.without_u = Some(how.into());
        self
    }

    /// The text of its U cell: `U unit`, or why there is none and how it will be evaluated.
    fn u_text(&self, factor: f64, unit: &str) -> String {
        match (self.expanded, &self.without_u) {
            (Some(u), _) => format!("{} {unit}", uncertainty(u * factor)),
            (None, Some(how)) => format!("not evaluated: {how}"),
            (None, None) => "not evaluated".into(),
        }
    }
}

fn items(n: usize) -> String {
    if n == 1 {
        "1 item".into()
    } else {
        format!("{n} items")
    }
}

/// The overall statement of a list of decisions under `rule`: an item whose measured value is
/// beyond its limit fails, in words, whatever the rule proves; what the rule proves follows.
pub fn statement(items_decided: &[Item], rule: DecisionRule) -> String {
    let count = |m: Mark| items_decided.iter().filter(|i| i.mark == m).count();
    let (fails, beyond, open, n) = (count(Mark::Fail), count(Mark::Beyond), count(Mark::Undecided), items_decided.len());
    let within_u = |k: usize| format!("conformity is not proven for {}, within the limit by less than U", items(k));
    if fails + beyond == 0 {
        let all = if n == 1 { "the toleranced item is".to_string() } else { format!("all {n} toleranced items are") };
        return match open {
            0 => format!("The machine conforms: {all} within tolerance (decision rule: {}).", rule.name()),
            k => format!(
                "No measured value is beyond its tolerance ({all} within it), but {} (decision rule: {}).",
                within_u(k),
                rule.name()
            ),
        };
    }
    let k = fails + beyond;
    let failing = match (n, k) {
        (1, _) => "the toleranced item fails, its measured value beyond the tolerance".to_string(),
        (_, 1) => format!("1 of the {n} items fails, its measured value beyond the tolerance"),
        _ => format!("{k} of the {n} items fail, their measured values beyond the tolerance"),
    };
    let mut text = format!("The machine does NOT conform: {failing}");
    if beyond > 0 {
        text.push_str(&format!(
            " ({}by less than U or with U unknown, so that under the {} non-conformity is not proven)",
            if k == 1 { String::new() } else { format!("{beyond} of them ") },
            rule.name()
        ));
    }
    if open > 0 {
        text.push_str(&format!("; {}", within_u(open)));
    }
    text.push('.');
    text
}

/// The section of decisions.
pub fn section(decided: &[Item], rule: DecisionRule) -> Section {
    let rows = decided
        .iter()
        .map(|i| {
            let (factor, unit) = display_unit(i.expanded.unwrap_or(i.value.abs()), &i.unit);
            let value = match i.expanded {
                Some(u) => format!("{} {unit}", value_by(i.value.abs() * factor, u * factor)),
                None => quantity(i.value.abs() * factor, 2, &unit),
            };
            vec![
                Cell::link(i.name.clone(), &i.section),
                Cell::from(value),
                Cell::from(i.u_text(factor, &unit)),
                Cell::from(format!("≤ {} {unit}", i.tolerance * factor)),
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
        .paragraph(statement(decided, rule))
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
        assert_eq!(decide(GuardBand, 11.9, Some(2.0), 10.0), Mark::Beyond);
        assert_eq!(decide(GuardBand, -12.1, Some(2.0), 10.0), Mark::Fail);
        // without U nothing is proven
        assert_eq!(decide(GuardBand, 1.0, None, 10.0), Mark::Undecided);
        assert_eq!(decide(GuardBand, 11.0, None, 10.0), Mark::Beyond);
    }

    #[test]
    fn a_value_beyond_its_limit_fails_in_words_whatever_the_guard_band_proves() {
        use DecisionRule::*;
        // the case: E = 9.7 um against 8 um and R = 3.3 um against 3 um, each with U larger
        // than its excess, and a third item within its limit but within U of it
        let e = Item::new("E".into(), "positioning", 9.7, Some(2.0), 8.0, "um", GuardBand);
        let r = Item::new("R".into(), "positioning", 3.3, Some(0.5), 3.0, "um", GuardBand);
        let a = Item::new("A".into(), "positioning", 7.9, Some(0.5), 8.0, "um", GuardBand);
        assert_eq!((e.mark, r.mark, a.mark), (Mark::Beyond, Mark::Beyond, Mark::Undecided));
        let text = statement(&[e.clone(), r, a], GuardBand);
        assert!(
            text.starts_with(
                "The machine does NOT conform: 2 of the 3 items fail, their measured values beyond the tolerance (2 of them by less than U"
            ),
            "{text}"
        );
        assert!(text.contains("guard band of U (ISO 14253-1)") && text.contains("not proven for 1 item,"), "{text}");
        let pass = Item::new("G".into(), "ballbar", 5.0, Some(0.5), 8.0, "um", GuardBand);
        assert_eq!(
            statement(&[pass], GuardBand),
            "The machine conforms: the toleranced item is within tolerance (decision rule: guard band of U (ISO 14253-1))."
        );
        // an item without U says how it will be evaluated
        let v = Item::new("V".into(), "volumetric", 20.0, None, 30.0, "um", GuardBand).without_u("identify with --sources");
        assert_eq!(v.u_text(1.0, "um"), "not evaluated: identify with --sources");
        assert_eq!(e.u_text(1.0, "um"), "2.0 um");
    }
}
