//! Fadal macro statements: a line whose code starts with `#` (blanks after it optional), as the
//! published Fadal macro programs and the Fusion 360 Fadal probing posts write them:
//!
//! - `# V1 = <expr>`, `# R1 = <expr>`: assign macro variable `V1`-`V100` or R parameter `R0`-`R9`;
//! - `# IF <cond> THEN GOTO :NAME`, `# GOTO :NAME`: jump to the line `#:NAME`;
//! - `# PRINT ...`, `# CLEAR`, `# WAIT`: text for the operator's screen; they move nothing and
//!   pass through (as Haas `DPRNT`);
//! - refused with the reason: `# INPUT` (a value typed at the machine), machine values (`AZ`,
//!   `H(..)`, `FX1`...), functions whose definition is not confirmed here (trigonometry, `INT`).
//!
//! Expressions: numbers, `V`n, `R`n, `( )`, a sign before a value, `*` `/` before `+` `-`, then the
//! comparisons `EQ NE GT GE LT LE`, then `AND`, then `OR`; `ABS( )`, `SQR( )` (the square root).

use super::{label_number, R_BASE, R_COUNT, V_BASE, V_COUNT};
use crate::expr::{ExprId, Func, Node, Op, ParamRef};
use crate::lexer::{push, Assignment, Line, Statement, MAX_NESTING};

/// Reads the macro statement of `text` whose `#` is at `at`.
pub(crate) fn parse(text: &str, at: usize, number: usize, arena: &mut Vec<Node>) -> Result<Line, String> {
    let mut line = Line { number, end_of_items: text.trim_end().len(), ..Line::default() };
    // an `N` number before the `#`
    let before = text[..at].trim();
    if let Some(n) = before.strip_prefix(['N', 'n']) {
        line.sequence = Some(n.parse().map_err(|_| format!("the line number N{n} is not a whole number"))?);
    }
    let body = &text[at + 1..];
    let mut p = Parser { s: body.as_bytes(), i: 0, depth: 0 };
    let keyword = p.name();
    match keyword.as_str() {
        "" if p.eat(b':') => {
            let name = p.name();
            if name.is_empty() || !p.at_end() {
                return Err(format!("`#:{}` is not a label (letters, digits and `_`)", body[1..].trim()));
            }
            if line.sequence.is_some() {
                return Err("a label line `#:NAME` with an N number".into());
            }
            line.sequence = Some(label_number(&name));
        }
        "IF" => {
            let cond = p.expression(arena)?;
            if p.name() != "THEN" || p.name() != "GOTO" {
                return Err(format!(
                    "`# IF ...` is read as `# IF <condition> THEN GOTO :LABEL` (after the condition: `{}`)",
                    body[p.i..].trim()
                ));
            }
            let target = p.target(arena)?;
            line.statement = Some(Statement::IfGoto(cond, target));
        }
        "GOTO" => line.statement = Some(Statement::Goto(p.target(arena)?)),
        "PRINT" | "CLEAR" | "WAIT" => {
            // the text for the screen, whatever it holds
            line.statement = Some(Statement::Output);
            p.i = p.s.len();
        }
        "INPUT" => return Err("`# INPUT` waits for a value typed at the machine: the moves after it are not known beforehand".into()),
        name => {
            let target = variable(name).ok_or_else(|| match name {
                "" => format!("`#{body}` is not a Fadal macro statement"),
                other => format!("`# {other}` is not a Fadal macro statement read here (V1-V100 and R0-R9 assignments, IF/GOTO, labels, PRINT, CLEAR, WAIT)"),
            })??;
            if !p.eat(b'=') {
                return Err(format!("`# {name}` without `=`"));
            }
            let value = p.expression(arena)?;
            line.assignments.push(Assignment { target, value });
        }
    }
    if !p.at_end() {
        return Err(format!("`{}` after the macro statement", body[p.i..].trim()));
    }
    Ok(line)
}

/// The Fanuc variable of macro variable `name` (`V7`, `R1`); `None`: not a variable's name.
fn variable(name: &str) -> Option<Result<ParamRef, String>> {
    let (letter, digits) = name.split_at(1.min(name.len()));
    let n: u32 = digits.parse().ok()?;
    Some(match letter {
        "V" if (1..=V_COUNT).contains(&n) => Ok(ParamRef::Numbered(V_BASE + n)),
        "R" if n < R_COUNT => Ok(ParamRef::Numbered(R_BASE + n)),
        "V" | "R" => Err(format!("{name}: the variables read are V1-V{V_COUNT} and R0-R{}", R_COUNT - 1)),
        _ => return None,
    })
}

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
    depth: usize,
}

impl Parser<'_> {
    fn peek(&mut self) -> u8 {
        while self.i < self.s.len() && matches!(self.s[self.i], b' ' | b'\t' | b'\r') {
            self.i += 1;
        }
        self.s.get(self.i).map_or(0, |c| c.to_ascii_uppercase())
    }

    fn at_end(&mut self) -> bool {
        self.peek() == 0
    }

    fn eat(&mut self, c: u8) -> bool {
        let hit = self.peek() == c;
        self.i += usize::from(hit);
        hit
    }

    /// A name (letters, then letters, digits and `_`), upper case; empty if none.
    fn name(&mut self) -> String {
        if !self.peek().is_ascii_alphabetic() {
            return String::new();
        }
        let start = self.i;
        while self.i < self.s.len() && (self.s[self.i].is_ascii_alphanumeric() || self.s[self.i] == b'_') {
            self.i += 1;
        }
        String::from_utf8_lossy(&self.s[start..self.i]).to_ascii_uppercase()
    }

    /// The `:NAME` a `GOTO` jumps to, as the sequence number of its label line.
    fn target(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        let name = if self.eat(b':') { self.name() } else { String::new() };
        if name.is_empty() {
            return Err("GOTO needs a label, `GOTO :NAME`".into());
        }
        Ok(push(arena, Node::Const(f64::from(label_number(&name)))))
    }

    /// The operators of precedence level `depth` (0 `OR`, 1 `AND`, 2 the comparisons, 3 `+ -`, 4
    /// `* /`; 5: a value), left to right.
    fn level(&mut self, arena: &mut Vec<Node>, depth: u8) -> Result<ExprId, String> {
        if depth == 5 {
            return self.unary(arena);
        }
        let mut left = self.level(arena, depth + 1)?;
        loop {
            let save = self.i;
            let op = match depth {
                0..=2 => {
                    let word = self.name();
                    match (depth, word.as_str()) {
                        (0, "OR") => Op::Or,
                        (1, "AND") => Op::And,
                        (2, "EQ") => Op::Eq,
                        (2, "NE") => Op::Ne,
                        (2, "GT") => Op::Gt,
                        (2, "GE") => Op::Ge,
                        (2, "LT") => Op::Lt,
                        (2, "LE") => Op::Le,
                        _ => {
                            self.i = save;
                            break;
                        }
                    }
                }
                3 => match self.peek() {
                    b'+' => Op::Plus,
                    b'-' => Op::Minus,
                    _ => break,
                },
                _ => match self.peek() {
                    b'*' => Op::Times,
                    b'/' => Op::Divide,
                    _ => break,
                },
            };
            if depth >= 3 {
                self.i += 1;
            }
            let right = self.level(arena, depth + 1)?;
            left = push(arena, Node::Binary(op, left, right));
        }
        Ok(left)
    }

    fn expression(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(format!("an expression nested more than {MAX_NESTING} levels deep"));
        }
        let v = self.level(arena, 0);
        self.depth -= 1;
        v
    }

    fn unary(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        match self.peek() {
            b'-' => {
                self.i += 1;
                let v = self.unary(arena)?;
                Ok(push(arena, Node::Neg(v)))
            }
            b'+' => {
                self.i += 1;
                self.unary(arena)
            }
            _ => self.primary(arena),
        }
    }

    fn primary(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        let c = self.peek();
        if c == b'(' {
            self.i += 1;
            let v = self.expression(arena)?;
            return if self.eat(b')') { Ok(v) } else { Err("a `(` without its `)`".into()) };
        }
        if c.is_ascii_digit() || c == b'.' {
            let start = self.i;
            while self.i < self.s.len() && (self.s[self.i].is_ascii_digit() || self.s[self.i] == b'.') {
                self.i += 1;
            }
            let text = String::from_utf8_lossy(&self.s[start..self.i]).to_string();
            let v: f64 = text.parse().map_err(|_| format!("`{text}` is not a number"))?;
            return Ok(push(arena, Node::Const(v)));
        }
        let name = self.name();
        if name.is_empty() {
            return Err(if c == 0 {
                "a value expected at the end of the line".into()
            } else {
                format!("a value expected, not `{}`", c as char)
            });
        }
        if let Some(target) = variable(&name) {
            return Ok(push(arena, Node::Param(target?)));
        }
        if self.peek() != b'(' {
            return Err(format!(
                "`{name}` is not read in a Fadal expression (V1-V{V_COUNT}, R0-R{} and numbers are; machine values are not known to the corrector)",
                R_COUNT - 1
            ));
        }
        let f = match name.as_str() {
            "ABS" => Func::Abs,
            "SQR" => Func::Sqrt,
            other => {
                return Err(format!(
                    "`{other}( )` is not read in a Fadal expression (its definition is not confirmed here; ABS and SQR are)"
                ))
            }
        };
        self.i += 1;
        let a = self.expression(arena)?;
        if !self.eat(b')') {
            return Err(format!("`{name}(` without its `)`"));
        }
        Ok(push(arena, Node::Func(f, a)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dialect::Dialect;
    use crate::expr::Environment;

    struct Vars(Vec<(u32, f64)>);
    impl Environment for Vars {
        fn read(&mut self, p: &ParamRef, _: Option<u32>) -> Result<f64, String> {
            let ParamRef::Numbered(n) = p else { unreachable!() };
            Ok(self.0.iter().find(|(k, _)| k == n).map_or(f64::NAN, |(_, v)| *v))
        }
        fn exists(&self, _: &str) -> bool {
            false
        }
    }

    fn value(text: &str, vars: &[(u32, f64)]) -> f64 {
        let mut arena = Vec::new();
        let l = parse(text, text.find('#').unwrap(), 1, &mut arena).unwrap();
        let e = match &l.statement {
            Some(Statement::IfGoto(c, _)) => *c,
            _ => l.assignments[0].value,
        };
        crate::expr::evaluate(&arena, e, &mut Vars(vars.to_vec()), Dialect::Fanuc).unwrap()
    }

    #[test]
    fn statements_and_arithmetic() {
        assert_eq!(value("# V1 = 2 + 3 * 4", &[]), 14.0);
        assert_eq!(value("#V2=(2+3)*-4/5", &[]), -4.0);
        assert_eq!(value("# R1 = V1 * 2 - R0", &[(301, 1.5), (290, 0.5)]), 2.5);
        assert_eq!(value("# V3 = SQR(V1 * V1 + 16) + ABS(-1)", &[(301, 3.0)]), 6.0);
        assert_eq!(value("# IF V3 LT V1 AND V1 LT V4 THEN GOTO :OK", &[(303, 1.0), (301, 2.0), (304, 3.0)]), 1.0);
        assert_eq!(value("# IF V3 GT V1 OR V1 GE 2 THEN GOTO :OK", &[(303, 1.0), (301, 2.0)]), 1.0);
        assert_eq!(value("# IF V1 EQ 2 THEN GOTO :OK", &[(301, 3.0)]), 0.0);
        let mut arena = Vec::new();
        let l = parse("N20 #:LOOP", 4, 1, &mut arena);
        assert!(l.unwrap_err().contains("N number"));
        let l = parse("#:LOOP", 0, 1, &mut arena).unwrap();
        assert_eq!(l.sequence, Some(label_number("LOOP")));
        assert!(l.is_empty());
        let l = parse("N30 # GOTO :LOOP", 4, 1, &mut arena).unwrap();
        assert_eq!(l.sequence, Some(30));
        assert!(matches!(l.statement, Some(Statement::Goto(_))));
        for text in ["# PRINT \"DONE\", V3", "# CLEAR", "#WAIT"] {
            assert_eq!(parse(text, 0, 1, &mut arena).unwrap().statement, Some(Statement::Output), "{text}");
        }
        let refused = |text: &str| parse(text, 0, 1, &mut arena.clone()).unwrap_err();
        assert!(refused("# INPUT V1").contains("typed at the machine"));
        assert!(refused("# R1 = AZ").contains("`AZ` is not read"));
        assert!(refused("# V1 = SIN(30)").contains("`SIN( )` is not read"));
        assert!(refused("# V101 = 1").contains("V1-V100"));
        assert!(refused("# V1 = (1 + 2").contains("without its `)`"));
        assert!(refused("# IF V1 GT 0 GOTO :A").contains("THEN GOTO"));
        assert!(refused("# FOO").contains("not a Fadal macro statement"));
        assert!(refused("# V1 = 1 2").contains("after the macro statement"));
    }
}
