//! The ideal form-shaping function of a configuration as formulas (Zhu 2008 Table C.1): the tool
//! position `(l, m, n)` and direction `(u, v, w)` in the workpiece frame as sums of products of
//! `sin`/`cos` of the rotary positions `a b c` with one of the linear positions `x y z` or the tool
//! length `p`. Built by applying each axis's ideal motion, from the tool back to the workpiece, to
//! `(0, 0, p)` and `(0, 0, 1)`.

use std::fmt;

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Trig {
    Sin,
    Cos,
}

/// `coefficient * prod trig(angle) * variable` (`variable` is `x y z p`, or none for 1).
#[derive(Clone, Debug, PartialEq)]
pub struct Term {
    pub coefficient: f64,
    /// `(angle letter a b c, sin or cos)`, sorted.
    pub factors: Vec<(char, Trig)>,
    pub variable: Option<char>,
}

/// A sum of terms.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Expression(pub Vec<Term>);

impl Expression {
    fn variable(v: char) -> Expression {
        Expression(vec![Term { coefficient: 1.0, factors: Vec::new(), variable: Some(v) }])
    }

    fn constant(c: f64) -> Expression {
        Expression(if c == 0.0 { Vec::new() } else { vec![Term { coefficient: c, factors: Vec::new(), variable: None }] })
    }

    fn times(&self, coefficient: f64, factor: (char, Trig)) -> Expression {
        Expression(
            self.0
                .iter()
                .map(|t| {
                    let mut factors = t.factors.clone();
                    factors.push(factor);
                    factors.sort();
                    Term { coefficient: t.coefficient * coefficient, factors, variable: t.variable }
                })
                .collect(),
        )
    }

    fn plus(&self, other: &Expression) -> Expression {
        let mut terms = self.0.clone();
        for t in &other.0 {
            match terms.iter_mut().find(|s| s.factors == t.factors && s.variable == t.variable) {
                Some(s) => s.coefficient += t.coefficient,
                None => terms.push(t.clone()),
            }
        }
        terms.retain(|t| t.coefficient != 0.0);
        Expression(terms)
    }

    /// The value at rotary positions `angle(letter)` (rad) and variables `value(letter)` (mm).
    pub fn evaluate(&self, angle: impl Fn(char) -> f64, value: impl Fn(char) -> f64) -> f64 {
        self.0
            .iter()
            .map(|t| {
                let trig: f64 = t
                    .factors
                    .iter()
                    .map(|(a, f)| match f {
                        Trig::Sin => angle(*a).sin(),
                        Trig::Cos => angle(*a).cos(),
                    })
                    .product();
                t.coefficient * trig * t.variable.map_or(1.0, &value)
            })
            .sum()
    }

    /// The letters of the axes the expression depends on (lower case angles and variables).
    pub fn letters(&self) -> Vec<char> {
        let mut out: Vec<char> = self.0.iter().flat_map(|t| t.factors.iter().map(|f| f.0).chain(t.variable)).collect();
        out.sort();
        out.dedup();
        out
    }
}

impl fmt::Display for Expression {
    /// Terms ordered as the appendix prints them (`p`, `z`, `y`, `x`, constant), e.g.
    /// `sin(b)*p + sin(b)*z + cos(b)*x`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            return write!(f, "0");
        }
        let rank = |v: Option<char>| match v {
            Some('p') => 0,
            Some('z') => 1,
            Some('y') => 2,
            Some('x') => 3,
            _ => 4,
        };
        let mut terms = self.0.clone();
        terms.sort_by(|a, b| rank(a.variable).cmp(&rank(b.variable)).then(a.factors.cmp(&b.factors)));
        for (i, t) in terms.iter().enumerate() {
            let negative = t.coefficient < 0.0;
            match (i, negative) {
                (0, true) => write!(f, "-")?,
                (0, false) => {}
                (_, true) => write!(f, " - ")?,
                (_, false) => write!(f, " + ")?,
            }
            let mut parts: Vec<String> = Vec::new();
            let magnitude = t.coefficient.abs();
            if (magnitude - 1.0).abs() > 1e-12 || (t.factors.is_empty() && t.variable.is_none()) {
                parts.push(format!("{magnitude}"));
            }
            for (a, trig) in &t.factors {
                parts.push(format!("{}({a})", if *trig == Trig::Sin { "sin" } else { "cos" }));
            }
            if let Some(v) = t.variable {
                parts.push(v.to_string());
            }
            write!(f, "{}", parts.join("*"))?;
        }
        Ok(())
    }
}

/// The tool position `(l, m, n)` and direction `(u, v, w)` of a configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct FormShaping {
    pub position: [Expression; 3],
    pub orientation: [Expression; 3],
}

/// The ideal form-shaping function of the axes `sequence` (workpiece to tool, letters X Y Z A B C).
pub fn form_shaping(sequence: &[char]) -> FormShaping {
    let mut position = [Expression::default(), Expression::default(), Expression::variable('p')];
    let mut orientation = [Expression::default(), Expression::default(), Expression::constant(1.0)];
    for &axis in sequence.iter().rev() {
        match axis {
            'X' | 'Y' | 'Z' => {
                let i = "XYZ".find(axis).expect("linear");
                position[i] = position[i].plus(&Expression::variable(axis.to_ascii_lowercase()));
            }
            _ => {
                let angle = axis.to_ascii_lowercase();
                // rotation about coordinate i: (j, k) -> (cos j - sin k, sin j + cos k), (i, j, k) cyclic
                let i = "ABC".find(axis).expect("rotary");
                let (j, k) = ((i + 1) % 3, (i + 2) % 3);
                for v in [&mut position, &mut orientation] {
                    let (vj, vk) = (v[j].clone(), v[k].clone());
                    v[j] = vj.times(1.0, (angle, Trig::Cos)).plus(&vk.times(-1.0, (angle, Trig::Sin)));
                    v[k] = vj.times(1.0, (angle, Trig::Sin)).plus(&vk.times(1.0, (angle, Trig::Cos)));
                }
            }
        }
    }
    FormShaping { position, orientation }
}
