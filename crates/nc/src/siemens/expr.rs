//! Arithmetic of the SINUMERIK 840D sl (Programming Manual Fundamentals, "Arithmetic parameters
//! (R)" and Job Planning, "Arithmetic operations and functions"): `*` and `/` bind tighter than
//! `+` and `-`, left to right within a level, `( )` group; a sign before a value; numbers, R
//! parameters `R0`-`R999`, and the functions `SIN COS TAN ASIN ACOS` (degrees), `ATAN2(y,x)`
//! (degrees, -180 to 180), `SQRT ABS EXP LN`, `POT(x)` (the square), `TRUNC(x)` (towards zero) and
//! `ROUND(x)` (half away from zero). The tree is the interpreter's ([`crate::expr::Node`]): TRUNC is
//! built from LinuxCNC's floor and ceiling, `FIX(x) + (x < 0) * (FUP(x) - FIX(x))`.

use super::{R_BASE, R_COUNT};
use crate::expr::{ExprId, Func, Node, Op, ParamRef};
use crate::lexer::{push, MAX_NESTING};

/// Reads an expression from `s` at `*i` (blanks allowed between items); the R parameters it reads
/// are added to `reads`.
pub struct Parser<'a> {
    pub s: &'a [u8],
    pub i: usize,
    pub reads: Vec<u32>,
    depth: usize,
}

impl<'a> Parser<'a> {
    pub fn new(s: &'a [u8], i: usize) -> Parser<'a> {
        Parser { s, i, reads: Vec::new(), depth: 0 }
    }

    fn peek(&mut self) -> u8 {
        while self.i < self.s.len() && matches!(self.s[self.i], b' ' | b'\t' | b'\r') {
            self.i += 1;
        }
        self.s.get(self.i).map_or(0, |c| c.to_ascii_uppercase())
    }

    /// A sum of terms.
    pub(crate) fn expression(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(format!("an expression nested more than {MAX_NESTING} levels deep"));
        }
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
        self.depth -= 1;
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
            return Err(format!("`{name}` is not read in an expression (R parameters and numbers are)"));
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
    fn bad_expressions_say_why() {
        for bad in ["1+", "(1+2", "FOO(1)", "R1000", "ATAN2(1)", "X1"] {
            let mut p = Parser::new(bad.as_bytes(), 0);
            assert!(p.expression(&mut Vec::new()).is_err(), "{bad}");
        }
    }
}
