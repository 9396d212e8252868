//! Arithmetic of the SINUMERIK 840D sl (Programming Manual Fundamentals, "Arithmetic parameters
//! (R)" and Job Planning, "Arithmetic operations and functions", "Comparison and logic
//! operations", "Precedence of the operations"): from the tightest binding, `NOT`; `*` `/`; `+`
//! `-` (left to right within a level, `( )` group); `AND`; `XOR`; `OR`; the comparisons `==` `<>`
//! `>` `<` `>=` `<=` last (so `IF (R1 > 0) AND (R2 < 5)` needs its parentheses, as the manual
//! writes it; two comparisons without them are refused rather than guessed). Values: numbers, R
//! parameters `R0`-`R999`, `TRUE` (1) and `FALSE` (0), user variables (`DEF`, [`super::variables`])
//! by their names, and the functions `SIN COS TAN ASIN ACOS` (degrees), `ATAN2(y,x)` (degrees,
//! -180 to 180), `SQRT ABS EXP LN`, `POT(x)` (the square), `TRUNC(x)` (towards zero) and
//! `ROUND(x)` (half away from zero). The tree is the interpreter's ([`crate::expr::Node`]): TRUNC is
//! built from LinuxCNC's floor and ceiling, `FIX(x) + (x < 0) * (FUP(x) - FIX(x))`; a comparison or
//! logic operation is 1 (TRUE) or 0 (FALSE), `NOT x` is `x == 0`.

use super::{R_BASE, R_COUNT};
use crate::expr::{ExprId, Func, Node, Op, ParamRef};
use crate::lexer::{push, MAX_NESTING};

/// Reads an expression from `s` at `*i` (blanks allowed between items); the R parameters it reads
/// are added to `reads`, the user variables to `names`.
pub struct Parser<'a> {
    pub s: &'a [u8],
    pub i: usize,
    pub reads: Vec<u32>,
    pub names: Vec<Box<str>>,
    depth: usize,
}

/// Words that are operators, not variable names.
const OPERATORS: &[&str] = &["AND", "OR", "XOR", "NOT", "DIV", "MOD", "B_AND", "B_OR", "B_XOR", "B_NOT", "TO"];

impl<'a> Parser<'a> {
    pub fn new(s: &'a [u8], i: usize) -> Parser<'a> {
        Parser { s, i, reads: Vec::new(), names: Vec::new(), depth: 0 }
    }

    /// A condition or value: sums, logic and at most one comparison.
    pub(crate) fn expression(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(format!("an expression nested more than {MAX_NESTING} levels deep"));
        }
        let left = self.logic(arena, 0)?;
        let result = match self.comparison() {
            Some(op) => {
                let right = self.logic(arena, 0)?;
                if self.comparison().is_some() {
                    return Err(format!(
                        "two comparisons without parentheses at column {}: write each in ( ), as (R1 > 0) AND (R2 < 5)",
                        self.i + 1
                    ));
                }
                push(arena, Node::Binary(op, left, right))
            }
            None => left,
        };
        self.depth -= 1;
        Ok(result)
    }

    /// A comparison operator at the cursor, read.
    fn comparison(&mut self) -> Option<Op> {
        let two = [self.peek(), self.s.get(self.i + 1).copied().unwrap_or(0)];
        let (op, len) = match two {
            [b'=', b'='] => (Op::Eq, 2),
            [b'<', b'>'] => (Op::Ne, 2),
            [b'>', b'='] => (Op::Ge, 2),
            [b'<', b'='] => (Op::Le, 2),
            [b'>', _] => (Op::Gt, 1),
            [b'<', _] => (Op::Lt, 1),
            _ => return None,
        };
        self.i += len;
        Some(op)
    }

    /// `OR` (level 0) of `XOR` (1) of `AND` (2) of sums.
    fn logic(&mut self, arena: &mut Vec<Node>, level: usize) -> Result<ExprId, String> {
        const LEVELS: [(&str, Op); 3] = [("OR", Op::Or), ("XOR", Op::Xor), ("AND", Op::And)];
        let next = |p: &mut Self, arena: &mut Vec<Node>| if level == 2 { p.sum(arena) } else { p.logic(arena, level + 1) };
        let mut left = next(self, arena)?;
        while self.upcoming_word() == LEVELS[level].0 {
            self.i += LEVELS[level].0.len();
            let right = next(self, arena)?;
            left = push(arena, Node::Binary(LEVELS[level].1, left, right));
        }
        Ok(left)
    }

    /// The word of letters and `_` at the cursor (after blanks), upper case, not read.
    fn upcoming_word(&mut self) -> String {
        self.peek();
        let end = (self.i..self.s.len()).find(|&j| !(self.s[j].is_ascii_alphanumeric() || self.s[j] == b'_')).unwrap_or(self.s.len());
        String::from_utf8_lossy(&self.s[self.i..end]).to_ascii_uppercase()
    }

    pub(crate) fn peek(&mut self) -> u8 {
        while self.i < self.s.len() && matches!(self.s[self.i], b' ' | b'\t' | b'\r') {
            self.i += 1;
        }
        self.s.get(self.i).map_or(0, |c| c.to_ascii_uppercase())
    }

    /// A sum of terms.
    fn sum(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        let mut left = self.term(arena)?;
        loop {
            let op = match self.peek() {
                b'+' => Op::Plus,
                b'-' => Op::Minus,
                _ => break,
            };
            self.i += 1;
            let right = self.term(arena)?;
            left = push(arena, Node::Binary(op, left, right));
        }
        Ok(left)
    }

    fn term(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        let mut left = self.unary(arena)?;
        loop {
            let op = match self.peek() {
                b'*' => Op::Times,
                b'/' => Op::Divide,
                _ => break,
            };
            self.i += 1;
            let right = self.unary(arena)?;
            left = push(arena, Node::Binary(op, left, right));
        }
        Ok(left)
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
            b'N' if self.upcoming_word() == "NOT" => {
                self.i += 3;
                let v = self.unary(arena)?;
                let zero = push(arena, Node::Const(0.0));
                Ok(push(arena, Node::Binary(Op::Eq, v, zero)))
            }
            _ => self.primary(arena),
        }
    }

    fn primary(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        let c = self.peek();
        if c == b'(' {
            self.i += 1;
            let v = self.expression(arena)?;
            self.close()?;
            return Ok(v);
        }
        if c.is_ascii_digit() || c == b'.' {
            let v = self.number()?;
            return Ok(push(arena, Node::Const(v)));
        }
        if !c.is_ascii_alphabetic() {
            return Err(format!("a value expected at column {}", self.i + 1));
        }
        let name = self.name();
        if let Some(n) = name.strip_prefix('R').and_then(|d| d.parse::<u32>().ok()) {
            if n >= R_COUNT {
                return Err(format!("R{n}: R parameters R0-R{} are read", R_COUNT - 1));
            }
            self.reads.push(n);
            return Ok(push(arena, Node::Param(ParamRef::Numbered(R_BASE + n))));
        }
        if self.peek() != b'(' {
            return match name.as_str() {
                "TRUE" => Ok(push(arena, Node::Const(1.0))),
                "FALSE" => Ok(push(arena, Node::Const(0.0))),
                n if super::variables::is_variable_name(n) && !OPERATORS.contains(&n) => {
                    self.names.push(n.into());
                    Ok(push(arena, Node::Param(ParamRef::Named(n.into()))))
                }
                _ => Err(format!("`{name}` is not read in an expression (numbers, R parameters and DEF variables are)")),
            };
        }
        self.i += 1;
        let a = self.expression(arena)?;
        let node = match name.as_str() {
            "ATAN2" => {
                if self.peek() != b',' {
                    return Err("ATAN2 takes two values: ATAN2(y,x)".into());
                }
                self.i += 1;
                let x = self.expression(arena)?;
                Node::Atan2(a, x)
            }
            "POT" => Node::Binary(Op::Times, a, a),
            "TRUNC" => {
                let (floor, ceil) = (push(arena, Node::Func(Func::Fix, a)), push(arena, Node::Func(Func::Fup, a)));
                let zero = push(arena, Node::Const(0.0));
                let negative = push(arena, Node::Binary(Op::Lt, a, zero));
                let step = push(arena, Node::Binary(Op::Minus, ceil, floor));
                let up = push(arena, Node::Binary(Op::Times, negative, step));
                Node::Binary(Op::Plus, floor, up)
            }
            other => {
                let f = match other {
                    "SIN" => Func::Sin,
                    "COS" => Func::Cos,
                    "TAN" => Func::Tan,
                    "ASIN" => Func::Asin,
                    "ACOS" => Func::Acos,
                    "SQRT" => Func::Sqrt,
                    "ABS" => Func::Abs,
                    "EXP" => Func::Exp,
                    "LN" => Func::Ln,
                    "ROUND" => Func::Round,
                    _ => return Err(format!("the function {other} is not read")),
                };
                Node::Func(f, a)
            }
        };
        self.close()?;
        Ok(push(arena, node))
    }

    fn close(&mut self) -> Result<(), String> {
        if self.peek() != b')' {
            return Err(format!("`)` expected at column {}", self.i + 1));
        }
        self.i += 1;
        Ok(())
    }

    /// Letters, digits and `_` from a letter on, upper case.
    pub fn name(&mut self) -> String {
        self.peek();
        let start = self.i;
        while self.i < self.s.len() && (self.s[self.i].is_ascii_alphanumeric() || self.s[self.i] == b'_') {
            self.i += 1;
        }
        String::from_utf8_lossy(&self.s[start..self.i]).to_ascii_uppercase()
    }

    /// An unsigned number: digits with at most one decimal point.
    pub(crate) fn number(&mut self) -> Result<f64, String> {
        self.peek();
        let start = self.i;
        while self.i < self.s.len() && (self.s[self.i].is_ascii_digit() || self.s[self.i] == b'.') {
            self.i += 1;
        }
        let text = std::str::from_utf8(&self.s[start..self.i]).unwrap_or("");
        text.parse::<f64>().map_err(|_| format!("`{text}` is not a number"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dialect::Dialect;
    use crate::expr::{evaluate, Environment};

    struct Rs(Vec<f64>);
    impl Environment for Rs {
        fn read(&mut self, p: &ParamRef, _: Option<u32>) -> Result<f64, String> {
            match p {
                ParamRef::Numbered(n) => Ok(self.0[(n - R_BASE) as usize]),
                _ => Err("no".into()),
            }
        }
        fn exists(&self, _: &str) -> bool {
            false
        }
    }

    fn value(text: &str, r: &[f64]) -> f64 {
        let mut arena = Vec::new();
        let mut p = Parser::new(text.as_bytes(), 0);
        let id = p.expression(&mut arena).unwrap_or_else(|e| panic!("{text}: {e}"));
        assert_eq!(p.i, text.len(), "{text}: read to the end");
        evaluate(&arena, id, &mut Rs(r.to_vec()), Dialect::LinuxCnc).unwrap()
    }

    #[test]
    fn precedence_functions_and_r_parameters() {
        let r = [0.0, 2.0, -3.5, 9.0];
        assert_eq!(value("1+2*3", &r), 7.0);
        assert_eq!(value("(1+2)*3", &r), 9.0);
        assert_eq!(value("10-4-3", &r), 3.0);
        assert_eq!(value("12/3/2", &r), 2.0);
        assert_eq!(value("-R1*R2", &r), 7.0);
        assert_eq!(value("R1 + -R2", &r), 5.5);
        assert_eq!(value("SQRT(R3)+POT(R1)", &r), 7.0);
        assert_eq!(value("TRUNC(R2)", &r), -3.0);
        assert_eq!(value("TRUNC(2.7)", &r), 2.0);
        assert_eq!(value("TRUNC(-4)", &r), -4.0);
        assert_eq!(value("ROUND(-2.5)", &r), -3.0);
        assert_eq!(value("ABS(R2)", &r), 3.5);
        assert!((value("SIN(30)", &r) - 0.5).abs() < 1e-15);
        assert!((value("ATAN2(-1,-1)", &r) + 135.0).abs() < 1e-12);
        assert!((value("COS(ACOS(0.25))", &r) - 0.25).abs() < 1e-15);
    }

    #[test]
    fn comparisons_bind_last_and_logic_before_them() {
        let r = [0.0, 2.0, -3.5, 9.0];
        assert_eq!(value("R1==2", &r), 1.0);
        assert_eq!(value("R1 <> 2", &r), 0.0);
        assert_eq!(value("R3>=9", &r), 1.0);
        assert_eq!(value("R2<R1*2-10", &r), 0.0);
        assert_eq!(value("R1+1 > R3-7", &r), 1.0);
        // (R1 > 0) AND (R2 < 0): the manual's form
        assert_eq!(value("(R1 > 0) AND (R2 < 0)", &r), 1.0);
        assert_eq!(value("(R1 > 5) OR (R2 < 0) AND FALSE", &r), 0.0);
        assert_eq!(value("TRUE XOR TRUE", &r), 0.0);
        assert_eq!(value("NOT (R1 == 2)", &r), 0.0);
        assert_eq!(value("NOT R0 AND TRUE", &r), 1.0);
        // AND before the comparison: 1 AND 0 is 0, == 0 holds
        assert_eq!(value("1 AND 0 == 0", &r), 1.0);
    }

    #[test]
    fn bad_expressions_say_why() {
        for bad in ["1+", "(1+2", "FOO(1)", "R1000", "ATAN2(1)", "X1", "R1 > 0 AND R2 < 5", "R1 =="] {
            let mut p = Parser::new(bad.as_bytes(), 0);
            assert!(p.expression(&mut Vec::new()).is_err(), "{bad}");
        }
    }
}
