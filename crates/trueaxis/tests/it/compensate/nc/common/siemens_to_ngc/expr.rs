//! The SINUMERIK 840D's arithmetic (SINUMERIK 840D sl Programming Manual Fundamentals,
//! "Arithmetic functions": `+ - * /`, `( )`, R parameters, `SIN COS TAN ASIN ACOS ATAN2 SQRT
//! ABS POT TRUNC ROUND EXP LN`, angles in degrees) written as RS274/NGC expressions (LinuxCNC 2.9
//! G-code manual, "Numbered parameters", "Expressions": `[ ]`, `#n`, the same functions in
//! degrees, `ATAN[y]/[x]`, `FIX`/`FUP`, comparisons giving 1 or 0).

/// A number as it is, an expression `(..)` translated.
pub(super) fn plain(v: &str) -> Option<String> {
    if v.parse::<f64>().is_ok() {
        Some(v.to_string())
    } else {
        expr(v)
    }
}

/// An 840D arithmetic expression as RS274/NGC (bracketed).
pub(super) fn expr(e: &str) -> Option<String> {
    let tokens = tokens(e)?;
    let mut p = Parser { t: &tokens, i: 0 };
    let out = p.sum()?;
    (p.i == tokens.len()).then(|| format!("[{out}]"))
}

#[derive(Clone, Debug, PartialEq)]
enum Token {
    Number(String),
    Param(u32),
    Name(String),
    Op(char),
}

fn tokens(e: &str) -> Option<Vec<Token>> {
    let b = e.as_bytes();
    let (mut out, mut i) = (Vec::new(), 0);
    while i < b.len() {
        let start = i;
        let c = b[i];
        if c.is_ascii_digit() || c == b'.' {
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                i += 1;
            }
            e[start..i].parse::<f64>().ok()?;
            out.push(Token::Number(e[start..i].to_string()));
        } else if c.is_ascii_alphabetic() {
            while i < b.len() && b[i].is_ascii_alphanumeric() {
                i += 1;
            }
            let word = &e[start..i];
            match word.strip_prefix('R').map(str::parse::<u32>) {
                Some(Ok(n)) if n < 1000 => out.push(Token::Param(1000 + n)),
                _ => out.push(Token::Name(word.to_string())),
            }
        } else if b"+-*/(),".contains(&c) {
            out.push(Token::Op(c as char));
            i += 1;
        } else {
            return None;
        }
    }
    Some(out)
}

/// Recursive descent over `+ -`, `* /`, unary minus, numbers, R parameters, functions, `( )`.
struct Parser<'a> {
    t: &'a [Token],
    i: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<&Token> {
        self.t.get(self.i)
    }

    fn eat(&mut self, op: char) -> bool {
        let hit = self.peek() == Some(&Token::Op(op));
        self.i += usize::from(hit);
        hit
    }

    fn sum(&mut self) -> Option<String> {
        let mut out = self.product()?;
        while let Some(Token::Op(op @ ('+' | '-'))) = self.peek().cloned() {
            self.i += 1;
            out = format!("{out}{op}{}", self.product()?);
        }
        Some(out)
    }

    fn product(&mut self) -> Option<String> {
        let mut out = self.unary()?;
        while let Some(Token::Op(op @ ('*' | '/'))) = self.peek().cloned() {
            self.i += 1;
            out = format!("{out}{op}{}", self.unary()?);
        }
        Some(out)
    }

    fn unary(&mut self) -> Option<String> {
        if self.eat('-') {
            return Some(format!("[0-{}]", self.unary()?));
        }
        self.eat('+');
        self.primary()
    }

    fn primary(&mut self) -> Option<String> {
        let token = self.peek()?.clone();
        self.i += 1;
        match token {
            Token::Number(n) => Some(n),
            Token::Param(p) => Some(format!("#{p}")),
            Token::Op('(') => {
                let inner = self.sum()?;
                self.eat(')').then(|| format!("[{inner}]"))
            }
            Token::Name(f) => self.function(&f),
            Token::Op(_) => None,
        }
    }

    /// `NAME(args)` in degrees, as LinuxCNC writes it.
    fn function(&mut self, name: &str) -> Option<String> {
        if !self.eat('(') {
            return None;
        }
        let a = self.sum()?;
        let b = if self.eat(',') { Some(self.sum()?) } else { None };
        if !self.eat(')') {
            return None;
        }
        match (name, b) {
            ("SIN" | "COS" | "TAN" | "ASIN" | "ACOS" | "SQRT" | "ABS" | "EXP" | "LN" | "ROUND", None) => Some(format!("{name}[{a}]")),
            ("ATAN2", Some(b)) => Some(format!("ATAN[{a}]/[{b}]")),
            ("POT", None) => Some(format!("[[{a}]*[{a}]]")),
            ("TRUNC", None) => Some(format!("[[FIX[{a}]*[[{a}] GE 0]]+[FUP[{a}]*[[{a}] LT 0]]]")),
            _ => None,
        }
    }
}
