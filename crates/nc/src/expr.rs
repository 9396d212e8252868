//! Expressions of NC programs: the tree the lexer builds and its evaluation with the operators and
//! functions of each dialect.
//!
//! LinuxCNC 2.9 (`interp_execute.cc`, `interp_internal.cc`): binary operators in five precedence
//! levels, left to right within a level: `**`; `*` `/` `MOD`; `+` `-`; `EQ NE GT GE LT LE`; `AND OR
//! XOR`. Comparisons and logic give 1 or 0 (any non-zero is true), `EQ`/`NE` compare within 1e-4,
//! `MOD` is never negative, angles are degrees, `FIX`/`FUP` are floor/ceiling, `ROUND` rounds half away
//! from zero, `ATAN[y]/[x]` is the two-argument arc tangent.
//!
//! Fanuc Custom Macro B: `*` `/` `AND` `MOD` bind tighter than `+` `-` `OR` `XOR`, comparisons only
//! in conditions; `AND OR XOR` work bit by bit on integers; `FIX`/`FUP` truncate towards / away from
//! zero; `ATAN` gives 0 to 360 degrees; a vacant variable (`#0`, an unset local or common variable)
//! counts as 0 in arithmetic, stays vacant when copied, and is equal only to another vacant value.

use crate::dialect::Dialect;

/// Index of a node in a file's expression arena.
pub type ExprId = u32;

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Power,
    Times,
    Divide,
    Modulo,
    Plus,
    Minus,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
}

impl Op {
    /// Binding strength in `dialect` (higher binds tighter).
    pub fn precedence(self, dialect: Dialect) -> u8 {
        use Op::*;
        match dialect {
            Dialect::LinuxCnc => match self {
                Power => 6,
                Times | Divide | Modulo => 5,
                Plus | Minus => 4,
                Eq | Ne | Gt | Ge | Lt | Le => 3,
                And | Or | Xor => 2,
            },
            Dialect::Fanuc => match self {
                Power => 3,
                Times | Divide | Modulo | And => 2,
                Plus | Minus | Or | Xor => 1,
                Eq | Ne | Gt | Ge | Lt | Le => 0,
            },
        }
    }
}

/// A function of one argument (angles in degrees).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Abs,
    Acos,
    Asin,
    Atan,
    Cos,
    Exp,
    Fix,
    Fup,
    Ln,
    Round,
    Sin,
    Sqrt,
    Tan,
}

impl Func {
    /// The function named `name` (lower case).
    pub fn named(name: &str) -> Option<Func> {
        Some(match name {
            "abs" => Func::Abs,
            "acos" => Func::Acos,
            "asin" => Func::Asin,
            "atan" => Func::Atan,
            "cos" => Func::Cos,
            "exp" => Func::Exp,
            "fix" => Func::Fix,
            "fup" => Func::Fup,
            "ln" => Func::Ln,
            "round" => Func::Round,
            "sin" => Func::Sin,
            "sqrt" => Func::Sqrt,
            "tan" => Func::Tan,
            _ => return None,
        })
    }
}

/// A parameter reference.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamRef {
    /// `#5221`.
    Numbered(u32),
    /// `#[expr]`, `##1`: the number is computed.
    Indirect(ExprId),
    /// `#<name>` (lower case, spaces removed); global when it starts with `_`.
    Named(Box<str>),
}

/// A node of an expression tree.
#[derive(Clone, Debug, PartialEq)]
pub enum Node {
    Const(f64),
    Param(ParamRef),
    /// Fanuc `#0`, always vacant.
    Vacant,
    Neg(ExprId),
    Func(Func, ExprId),
    /// `ATAN[y]/[x]` (LinuxCNC) or `ATAN[y]/[x]`, `ATAN[y,x]` (Fanuc).
    Atan2(ExprId, ExprId),
    /// Fanuc `POW[a,b]`.
    Pow(ExprId, ExprId),
    Binary(Op, ExprId, ExprId),
    /// LinuxCNC `EXISTS[#<name>]`.
    Exists(Box<str>),
}

/// Where an expression reads parameters from.
pub(crate) trait Environment {
    /// The value of a parameter (NaN: vacant, Fanuc only); an error names what is wrong.
    fn read(&mut self, param: &ParamRef, index: Option<u32>) -> Result<f64, String>;
    /// Whether the named parameter is defined (`EXISTS`).
    fn exists(&self, name: &str) -> bool;
}

/// Tolerance of `EQ` and `NE` in LinuxCNC (`TOLERANCE_EQUAL`).
const TOLERANCE_EQUAL: f64 = 1e-4;

/// Evaluates node `id` of `arena`. A vacant value (Fanuc) is NaN; an error names the cause.
pub(crate) fn evaluate(arena: &[Node], id: ExprId, env: &mut dyn Environment, dialect: Dialect) -> Result<f64, String> {
    let value = match &arena[id as usize] {
        Node::Const(v) => *v,
        Node::Vacant => f64::NAN,
        Node::Param(p) => {
            let index = match p {
                ParamRef::Indirect(e) => Some(parameter_number(evaluate(arena, *e, env, dialect)?)?),
                _ => None,
            };
            env.read(p, index)?
        }
        Node::Neg(e) => -number(evaluate(arena, *e, env, dialect)?),
        Node::Func(f, e) => function(*f, number(evaluate(arena, *e, env, dialect)?), dialect)?,
        Node::Atan2(y, x) => {
            let (y, x) = (number(evaluate(arena, *y, env, dialect)?), number(evaluate(arena, *x, env, dialect)?));
            let a = y.atan2(x).to_degrees();
            if dialect == Dialect::Fanuc && a < 0.0 {
                a + 360.0
            } else {
                a
            }
        }
        Node::Pow(a, b) => power(number(evaluate(arena, *a, env, dialect)?), number(evaluate(arena, *b, env, dialect)?))?,
        Node::Binary(op, a, b) => {
            let (a, b) = (evaluate(arena, *a, env, dialect)?, evaluate(arena, *b, env, dialect)?);
            binary(*op, a, b, dialect)?
        }
        Node::Exists(name) => f64::from(u8::from(env.exists(name))),
    };
    if value.is_infinite() || value.is_nan() && dialect == Dialect::LinuxCnc {
        return Err(format!("the calculation gives {}", if value.is_nan() { "not a number" } else { "infinity" }));
    }
    Ok(value)
}

/// A vacant value counts as 0 in arithmetic.
fn number(v: f64) -> f64 {
    if v.is_nan() {
        0.0
    } else {
        v
    }
}

/// A parameter number from a computed value: an integer (within 1e-4, as LinuxCNC reads integers).
pub(crate) fn parameter_number(v: f64) -> Result<u32, String> {
    let r = v.round();
    if (v - r).abs() > 1e-4 || !(0.0..=1e6).contains(&r) {
        return Err(format!("parameter number {v} is not a non-negative integer"));
    }
    Ok(r as u32)
}

fn power(a: f64, b: f64) -> Result<f64, String> {
    if a < 0.0 && b.floor() != b {
        return Err(format!("{a} raised to the non-integer power {b}"));
    }
    Ok(a.powf(b))
}

fn truth(v: f64) -> bool {
    number(v) != 0.0
}

fn binary(op: Op, a: f64, b: f64, dialect: Dialect) -> Result<f64, String> {
    let flag = |c: bool| f64::from(u8::from(c));
    let vacant = |v: f64| v.is_nan();
    Ok(match op {
        Op::Eq | Op::Ne if dialect == Dialect::Fanuc && (vacant(a) || vacant(b)) => flag((vacant(a) && vacant(b)) == (op == Op::Eq)),
        _ => {
            let (a, b) = (number(a), number(b));
            match op {
                Op::Power => power(a, b)?,
                Op::Times => a * b,
                Op::Divide => {
                    if b == 0.0 {
                        return Err("division by zero".into());
                    }
                    a / b
                }
                Op::Modulo => {
                    let m = a % b;
                    if dialect == Dialect::LinuxCnc && m < 0.0 {
                        m + b.abs()
                    } else {
                        m
                    }
                }
                Op::Plus => a + b,
                Op::Minus => a - b,
                Op::Eq => flag(equal(a, b, dialect)),
                Op::Ne => flag(!equal(a, b, dialect)),
                Op::Gt => flag(a > b),
                Op::Ge => flag(a >= b),
                Op::Lt => flag(a < b),
                Op::Le => flag(a <= b),
                Op::And | Op::Or | Op::Xor if dialect == Dialect::Fanuc => {
                    let (x, y) = (a.round() as i64, b.round() as i64);
                    (match op {
                        Op::And => x & y,
                        Op::Or => x | y,
                        _ => x ^ y,
                    }) as f64
                }
                Op::And => flag(truth(a) && truth(b)),
                Op::Or => flag(truth(a) || truth(b)),
                Op::Xor => flag(truth(a) != truth(b)),
            }
        }
    })
}

/// `EQ`: within 1e-4 in LinuxCNC; equal to the last bits in a Fanuc (its macro variables are
/// binary floating point too).
fn equal(a: f64, b: f64, dialect: Dialect) -> bool {
    match dialect {
        Dialect::LinuxCnc => (a - b).abs() < TOLERANCE_EQUAL,
        Dialect::Fanuc => (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs())),
    }
}

fn function(f: Func, v: f64, dialect: Dialect) -> Result<f64, String> {
    let in_unit = |name: &str| {
        if (-1.0..=1.0).contains(&v) {
            Ok(())
        } else {
            Err(format!("the argument of {name} is {v}, outside [-1, 1]"))
        }
    };
    Ok(match f {
        Func::Abs => v.abs(),
        Func::Acos => {
            in_unit("ACOS")?;
            v.acos().to_degrees()
        }
        Func::Asin => {
            in_unit("ASIN")?;
            v.asin().to_degrees()
        }
        Func::Atan => {
            let a = v.atan().to_degrees();
            if dialect == Dialect::Fanuc && a < 0.0 {
                a + 360.0
            } else {
                a
            }
        }
        Func::Cos => v.to_radians().cos(),
        Func::Exp => v.exp(),
        Func::Fix if dialect == Dialect::Fanuc => v.trunc(),
        Func::Fix => v.floor(),
        Func::Fup if dialect == Dialect::Fanuc => {
            if v >= 0.0 {
                v.ceil()
            } else {
                v.floor()
            }
        }
        Func::Fup => v.ceil(),
        Func::Ln => {
            if v <= 0.0 {
                return Err(format!("LN of {v}, not positive"));
            }
            v.ln()
        }
        Func::Round => v.round(),
        Func::Sin => v.to_radians().sin(),
        Func::Sqrt => {
            if v < 0.0 {
                return Err(format!("SQRT of the negative number {v}"));
            }
            v.sqrt()
        }
        Func::Tan => v.to_radians().tan(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    struct NoParams;
    impl Environment for NoParams {
        fn read(&mut self, _: &ParamRef, _: Option<u32>) -> Result<f64, String> {
            Ok(f64::NAN)
        }
        fn exists(&self, _: &str) -> bool {
            false
        }
    }

    fn eval(nodes: &[Node], dialect: Dialect) -> Result<f64, String> {
        evaluate(nodes, nodes.len() as u32 - 1, &mut NoParams, dialect)
    }

    #[test]
    fn operators_and_functions_of_both_dialects() {
        use Node::*;
        // -7 MOD 3 = 2 in LinuxCNC (never negative), -1 in Fanuc (sign of the dividend)
        let m = [Const(-7.0), Const(3.0), Binary(Op::Modulo, 0, 1)];
        assert_eq!(eval(&m, Dialect::LinuxCnc), Ok(2.0));
        assert_eq!(eval(&m, Dialect::Fanuc), Ok(-1.0));
        // 1 EQ 1.00005 within LinuxCNC's tolerance
        let e = [Const(1.0), Const(1.00005), Binary(Op::Eq, 0, 1)];
        assert_eq!(eval(&e, Dialect::LinuxCnc), Ok(1.0));
        assert_eq!(eval(&e, Dialect::Fanuc), Ok(0.0));
        // FIX / FUP of -1.2
        assert_eq!(eval(&[Const(-1.2), Func(super::Func::Fix, 0)], Dialect::LinuxCnc), Ok(-2.0));
        assert_eq!(eval(&[Const(-1.2), Func(super::Func::Fix, 0)], Dialect::Fanuc), Ok(-1.0));
        assert_eq!(eval(&[Const(-1.2), Func(super::Func::Fup, 0)], Dialect::Fanuc), Ok(-2.0));
        assert_eq!(eval(&[Const(-2.5), Func(super::Func::Round, 0)], Dialect::LinuxCnc), Ok(-3.0));
        // ATAN[-1]/[-1]: -135 deg, 225 deg on a Fanuc
        let a = [Const(-1.0), Const(-1.0), Atan2(0, 1)];
        assert!((eval(&a, Dialect::LinuxCnc).unwrap() + 135.0).abs() < 1e-12);
        assert!((eval(&a, Dialect::Fanuc).unwrap() - 225.0).abs() < 1e-12);
        // vacant: 0 in arithmetic, equal only to vacant
        assert_eq!(eval(&[Vacant, Const(2.0), Binary(Op::Plus, 0, 1)], Dialect::Fanuc), Ok(2.0));
        assert_eq!(eval(&[Vacant, Const(0.0), Binary(Op::Eq, 0, 1)], Dialect::Fanuc), Ok(0.0));
        assert_eq!(eval(&[Vacant, Vacant, Binary(Op::Eq, 0, 1)], Dialect::Fanuc), Ok(1.0));
        assert_eq!(eval(&[Vacant, Const(0.0), Binary(Op::Ge, 0, 1)], Dialect::Fanuc), Ok(1.0));
        // bitwise on a Fanuc, logic in LinuxCNC
        let and = [Const(6.0), Const(3.0), Binary(Op::And, 0, 1)];
        assert_eq!(eval(&and, Dialect::Fanuc), Ok(2.0));
        assert_eq!(eval(&and, Dialect::LinuxCnc), Ok(1.0));
        assert!(eval(&[Const(1.0), Const(0.0), Binary(Op::Divide, 0, 1)], Dialect::LinuxCnc).unwrap_err().contains("division by zero"));
        assert!(eval(&[Const(-1.0), Func(super::Func::Sqrt, 0)], Dialect::LinuxCnc).is_err());
        assert!(eval(&[Const(-8.0), Const(0.5), Binary(Op::Power, 0, 1)], Dialect::LinuxCnc).is_err());
        assert!((eval(&[Const(30.0), Func(super::Func::Sin, 0)], Dialect::LinuxCnc).unwrap() - 0.5).abs() < 1e-15);
    }
}
