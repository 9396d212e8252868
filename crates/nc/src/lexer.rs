//! Reading one NC line: words (a letter and a value: a number, a parameter, an expression), parameter
//! assignments, comments, O-word statements (LinuxCNC) and the Fanuc macro statements.
//!
//! As LinuxCNC 2.9 reads a line (`interp_read.cc`): blanks are ignored everywhere outside comments
//! (`X 1 0` is `X10`), letters are case-insensitive, a comment is `( ... )` or runs from `;` to the end
//! of the line, a value is a number, `#n`, `#<name>`, `[expression]`, a unary function (`SIN[...]`,
//! `ATAN[y]/[x]`) or a sign before one of those. A Fanuc line has the same words and `[ ]`
//! expressions; `;` ends the block, `O1234` is a program number, and `IF`, `GOTO`, `WHILE ... DO`,
//! `END` are statements. Every word keeps the byte span of its value text, so that a writer can
//! replace a value and leave the rest of the line as it was.

use crate::dialect::Dialect;
use crate::expr::{ExprId, Func, Node, Op, ParamRef};
use std::ops::Range;

/// A word's value as written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Operand {
    Number(f64),
    Expr(ExprId),
}

/// One word, e.g. `X-12.5` or `Z[#1 - 2]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Word {
    /// Upper-case letter, or `@`, `^` (LinuxCNC polar coordinates), `$` (spindle).
    pub letter: u8,
    pub value: Operand,
    /// Byte range of the value text in the line.
    pub span: Range<usize>,
    /// The value is a number written with a decimal point (a Fanuc dimension word without one
    /// counts in least input increments).
    pub decimal_point: bool,
}

/// `#n = value`.
#[derive(Clone, Debug, PartialEq)]
pub struct Assignment {
    pub target: ParamRef,
    pub value: ExprId,
}

/// The label of an O-word: `o100` or `o<name>`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Label {
    Number(u32),
    Name(Box<str>),
}

impl std::fmt::Display for Label {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Label::Number(n) => write!(f, "o{n}"),
            Label::Name(s) => write!(f, "o<{s}>"),
        }
    }
}

/// A LinuxCNC O-word statement.
#[derive(Clone, Debug, PartialEq)]
pub enum OKind {
    Sub,
    EndSub(Option<ExprId>),
    Call(Vec<ExprId>),
    Return(Option<ExprId>),
    If(ExprId),
    ElseIf(ExprId),
    Else,
    EndIf,
    /// `while [cond]`: the start of a while loop or the end of a do loop (told apart when the
    /// program is indexed).
    While(ExprId),
    EndWhile,
    Do,
    Repeat(ExprId),
    EndRepeat,
    Break,
    Continue,
}

/// A control statement.
#[derive(Clone, Debug, PartialEq)]
pub enum Statement {
    /// LinuxCNC `o<label> <kind>`.
    O(Label, OKind),
    /// Fanuc `GOTO n` (the target is computed).
    Goto(ExprId),
    /// Fanuc `IF [cond] GOTO n`.
    IfGoto(ExprId, ExprId),
    /// Fanuc `IF [cond] THEN #i = ...`.
    IfThen(ExprId, Vec<Assignment>),
    /// Fanuc `WHILE [cond] DO m`.
    While(ExprId, u32),
    /// Fanuc `DO m` (an endless loop until a `GOTO` leaves it).
    Do(u32),
    /// Fanuc `END m`.
    End(u32),
    /// Fanuc/Haas external output (`POPEN`, `PCLOS`, `DPRNT[...]`, `BPRNT[...]`): data sent to a
    /// serial port, no effect on motion.
    Output,
    /// A SINUMERIK jump or control structure ([`crate::siemens::flow`]).
    Siemens(crate::siemens::flow::Control),
}

/// One line of a program.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Line {
    /// 1-based line number in its file.
    pub number: usize,
    /// Block delete `/` at the start.
    pub delete: bool,
    /// The `N` sequence number.
    pub sequence: Option<u32>,
    pub words: Vec<Word>,
    pub assignments: Vec<Assignment>,
    /// Byte ranges of the comment texts (inside the parentheses, or after `;`).
    pub comments: Vec<Range<usize>>,
    pub statement: Option<Statement>,
    /// A `%` line.
    pub percent: bool,
    /// Fanuc `O1234`.
    pub program_number: Option<u32>,
    /// Byte offset after the last item (before a trailing comment): where new words go.
    pub end_of_items: usize,
    /// A grbl system command (`$H`, `$J=G91 X10 F500`, `$32=1`): the byte range of its text, to
    /// the end of the line, or of `$J=` before the words of a jog (read in `grbl_system.rs`).
    pub system: Option<Range<usize>>,
    /// A SINUMERIK cycle call or `MCALL` ([`crate::siemens`]).
    pub siemens_call: Option<Box<crate::siemens::Call>>,
    /// A SINUMERIK jump label `NAME:` at the start of the block ([`crate::siemens::flow`]).
    pub siemens_label: Option<Box<str>>,
    /// A SINUMERIK `DEF` ([`crate::siemens::variables`]).
    pub siemens_def: bool,
}

impl Line {
    /// The word with `letter`, if any.
    pub fn word(&self, letter: u8) -> Option<&Word> {
        self.words.iter().find(|w| w.letter == letter)
    }

    /// Whether the line has nothing to execute (blank, comments only, `%`).
    pub fn is_empty(&self) -> bool {
        self.words.is_empty()
            && self.assignments.is_empty()
            && self.statement.is_none()
            && self.program_number.is_none()
            && self.system.is_none()
            && self.siemens_call.is_none()
    }
}

/// Longest line LinuxCNC reads (bytes without the line end): rs274 refuses a longer one as
/// "Command too long" (`LINELEN` of the interpreter, less the line end and the terminating NUL;
/// measured on rs274 2.9: 252 read, 253 refused). It also bounds the nesting of expressions.
pub const LINUXCNC_MAX_LINE: usize = 252;

/// Deepest nesting of brackets a Fanuc Custom Macro B control reads (five levels, the brackets of
/// functions included; deeper raises alarm 118).
pub const FANUC_MAX_BRACKETS: usize = 5;

/// Most expression nodes on one line and deepest nesting of values (brackets, functions, signs,
/// `#` indirections): bounds that keep the reading and the evaluation of any line within a small
/// stack, far beyond what a controller reads.
pub const MAX_NODES_PER_LINE: usize = 1000;
pub const MAX_NESTING: usize = 64;

/// Reads one line; `arena` receives its expression nodes. An error says what is wrong (the caller
/// adds file and line). `bytewise`: the line was read byte for byte (not UTF-8), its characters
/// above U+007F are bytes.
pub(crate) fn parse_line(text: &str, number: usize, dialect: Dialect, arena: &mut Vec<Node>, bytewise: bool) -> Result<Line, String> {
    let length = if bytewise { text.chars().count() } else { text.len() };
    if dialect == Dialect::LinuxCnc && length > LINUXCNC_MAX_LINE {
        return Err(format!("a line of {length} characters: LinuxCNC reads at most {LINUXCNC_MAX_LINE} (rs274: Command too long)"));
    }
    let first_node = arena.len();
    let line = parse_items(text, number, dialect, arena, bytewise)?;
    if arena.len() - first_node > MAX_NODES_PER_LINE {
        return Err(format!("more than {MAX_NODES_PER_LINE} terms in the expressions of one line"));
    }
    Ok(line)
}

fn parse_items(text: &str, number: usize, dialect: Dialect, arena: &mut Vec<Node>, bytewise: bool) -> Result<Line, String> {
    let mut line = Line { number, ..Line::default() };
    let mut cur = Cursor { s: text.as_bytes(), text, i: 0, last: 0, dialect, bytewise, nesting: 0, brackets: 0 };
    match cur.peek() {
        b'%' => {
            line.percent = true;
            return Ok(line);
        }
        b'/' => {
            cur.bump();
            line.delete = true;
        }
        _ => {}
    }
    if cur.peek() == b'n' {
        cur.bump();
        let (v, _, _) = cur.number()?;
        if v < 0.0 || v.fract() != 0.0 {
            return Err(format!("the line number N{v} is not a whole number"));
        }
        line.sequence = Some(v as u32);
    }
    // `:` is the ISO program-number letter a Fanuc reads like `O`
    if cur.peek() == b'o' || cur.peek() == b':' && dialect == Dialect::Fanuc {
        cur.bump();
        match dialect {
            Dialect::LinuxCnc => match cur.program_number_alone() {
                Some(n) => line.program_number = Some(n),
                None => line.statement = Some(cur.o_statement(arena)?),
            },
            Dialect::Fanuc => {
                let (v, _, _) = cur.number()?;
                line.program_number = Some(v as u32);
            }
        }
        line.end_of_items = cur.last;
        cur.comments_only(&mut line.comments)?;
        return Ok(line);
    }
    if dialect == Dialect::LinuxCnc && matches!(cur.peek(), b'$' | b'?' | b'~' | b'!') {
        if let Some(system) = grbl_system_command(text, cur.i) {
            let jog = text[system.clone()].to_ascii_uppercase().starts_with("$J=");
            line.end_of_items = system.end;
            cur.i = system.end;
            line.system = Some(system);
            if !jog {
                cur.comments_only(&mut line.comments)?;
                return Ok(line);
            }
        }
    }
    if dialect == Dialect::Fanuc {
        if let Some(s) = cur.fanuc_statement(arena)? {
            line.statement = Some(s);
            line.end_of_items = cur.last;
            cur.comments_only(&mut line.comments)?;
            return Ok(line);
        }
    }
    loop {
        match cur.peek() {
            0 => break,
            b'(' => line.comments.push(cur.comment()?),
            b';' => {
                cur.bump();
                match dialect {
                    Dialect::LinuxCnc => {
                        line.comments.push(cur.i..text.len());
                        break;
                    }
                    Dialect::Fanuc => {
                        cur.comments_only(&mut line.comments)?;
                        break;
                    }
                }
            }
            b'#' => {
                line.assignments.push(cur.assignment(arena)?);
                line.end_of_items = cur.last;
            }
            c if c.is_ascii_lowercase() || matches!(c, b'@' | b'^' | b'$') => {
                let letter = c.to_ascii_uppercase();
                if letter == b'O' || letter == b'N' {
                    return Err(format!("{} may only start a line", letter as char));
                }
                cur.bump();
                let (value, span, decimal_point) = cur.value(arena)?;
                line.words.push(Word { letter, value, span, decimal_point });
                line.end_of_items = cur.last;
            }
            b',' if dialect == Dialect::Fanuc => return Err("optional chamfer and corner rounding (`,C` `,R`) are not supported".into()),
            _ => return Err(format!("unexpected {}", cur.here())),
        }
    }
    if line.words.is_empty() && line.assignments.is_empty() {
        line.end_of_items = text.trim_end().len().min(line.comments.first().map_or(usize::MAX, |c| c.start.saturating_sub(1)));
    }
    Ok(line)
}

/// A grbl system command starting at `at` (a `$`, or a real-time `?`, `~`, `!` alone on its
/// line): `$` and a letter, `$`, or `#`, or `$` and
/// digits followed by `=` (a setting); not LinuxCNC's spindle word `$1`. Its text to the end of
/// the line or to a comment (`$I ; build info`: grbl takes the comments out of a line before it
/// reads the command), or `$J=` alone (the words of the jog follow).
fn grbl_system_command(text: &str, at: usize) -> Option<Range<usize>> {
    if text.as_bytes()[at] != b'$' {
        // a real-time command on a line of its own (`?` status, `~` resume, `!` feed hold)
        let end = text[at + 1..].find([';', '(']).map_or(text.len(), |i| at + 1 + i);
        return text[at + 1..end].trim().is_empty().then_some(at..at + 1);
    }
    let rest = &text.as_bytes()[at + 1..];
    let digits = rest.iter().take_while(|c| c.is_ascii_digit()).count();
    let command = match rest.first() {
        Some(c) if c.is_ascii_alphabetic() || matches!(c, b'$' | b'#') => true,
        Some(c) if c.is_ascii_digit() => rest.get(digits) == Some(&b'='),
        _ => false,
    };
    if !command {
        return None;
    }
    if rest.len() >= 2 && rest[..2].eq_ignore_ascii_case(b"J=") {
        return Some(at..at + 3);
    }
    let end = text[at..].find([';', '(']).map_or(text.len(), |i| at + i);
    Some(at..at + text[at..end].trim_end().len())
}

/// The refusal of an O-word without its keyword (`o100` alone: LinuxCNC's rs274 refuses it too).
pub(crate) fn o_word_without_keyword(label: &Label) -> String {
    format!("`{label}` is not followed by sub, endsub, call, return, if, elseif, else, endif, while, endwhile, do, repeat, endrepeat, break or continue")
}

struct Cursor<'a> {
    s: &'a [u8],
    text: &'a str,
    i: usize,
    /// Just after the last character consumed (blanks skipped before it are not counted).
    last: usize,
    dialect: Dialect,
    bytewise: bool,
    /// Values being read inside one another, and open brackets.
    nesting: usize,
    brackets: usize,
}

impl Cursor<'_> {
    /// The character at the cursor, readably (bytes of a line read byte for byte by their code).
    fn here(&self) -> String {
        match self.text.get(self.i..).and_then(|s| s.chars().next()) {
            Some(c) => crate::source::describe_char(c, self.bytewise),
            None => "end of the line".into(),
        }
    }

    /// Enters a nested value; refused beyond [`MAX_NESTING`].
    fn enter(&mut self) -> Result<(), String> {
        self.nesting += 1;
        if self.nesting > MAX_NESTING {
            return Err(format!("an expression nested more than {MAX_NESTING} levels deep"));
        }
        Ok(())
    }

    fn skip_blank(&mut self) {
        while self.i < self.s.len() && matches!(self.s[self.i], b' ' | b'\t' | b'\r') {
            self.i += 1;
        }
    }

    /// The next non-blank character, lower case; 0 at the end.
    fn peek(&mut self) -> u8 {
        self.skip_blank();
        self.s.get(self.i).map_or(0, |c| c.to_ascii_lowercase())
    }

    /// The character after the next non-blank one.
    fn peek_second(&mut self) -> u8 {
        self.skip_blank();
        let mut j = self.i + 1;
        while j < self.s.len() && matches!(self.s[j], b' ' | b'\t' | b'\r') {
            j += 1;
        }
        self.s.get(j).map_or(0, |c| c.to_ascii_lowercase())
    }

    fn bump(&mut self) {
        self.i += 1;
        self.last = self.i;
    }

    fn expect(&mut self, c: u8, what: &str) -> Result<(), String> {
        if self.peek() == c {
            self.bump();
            Ok(())
        } else {
            Err(format!("expected `{}` {what}", c as char))
        }
    }

    /// Consumes `keyword` (lower case letters, blanks allowed between them) if it comes next.
    fn keyword(&mut self, keyword: &str) -> bool {
        let (start, last) = (self.i, self.last);
        for k in keyword.bytes() {
            if self.peek() != k {
                (self.i, self.last) = (start, last);
                return false;
            }
            self.bump();
        }
        true
    }

    /// A number: signs, digits and one decimal point (blanks between them ignored).
    fn number(&mut self) -> Result<(f64, Range<usize>, bool), String> {
        let start = {
            self.skip_blank();
            self.i
        };
        let mut text = String::new();
        while matches!(self.peek(), b'+' | b'-') && text.chars().all(|c| c == '+' || c == '-') {
            text.push(self.s[self.i] as char);
            self.bump();
        }
        while matches!(self.peek(), b'0'..=b'9' | b'.') {
            text.push(self.s[self.i] as char);
            self.bump();
        }
        let end = self.last.max(start);
        let point = text.contains('.');
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() && text.chars().any(|c| c.is_ascii_digit()) => Ok((v, start..end, point)),
            _ if text.is_empty() => Err(match self.peek() {
                0 => "a value is missing at the end of the line".into(),
                _ => format!("a number is expected, found {}", self.here()),
            }),
            _ => Err(format!("`{text}` is not a number")),
        }
    }

    /// A value: number, parameter, bracketed expression, unary function, or a sign before one.
    fn value(&mut self, arena: &mut Vec<Node>) -> Result<(Operand, Range<usize>, bool), String> {
        self.enter()?;
        let v = self.value_inner(arena);
        self.nesting -= 1;
        v
    }

    fn value_inner(&mut self, arena: &mut Vec<Node>) -> Result<(Operand, Range<usize>, bool), String> {
        self.skip_blank();
        let start = self.i;
        let c = self.peek();
        // a Fanuc reads one sign before a value (`X+-5` raises an alarm; LinuxCNC's rs274 reads
        // it as -5, and so does its dialect here)
        if self.dialect == Dialect::Fanuc && matches!(c, b'+' | b'-') && matches!(self.peek_second(), b'+' | b'-') {
            return Err(format!("two signs `{}{}` before a value", c as char, self.peek_second() as char));
        }
        let operand = match c {
            b'[' => Operand::Expr(self.bracketed(arena)?),
            b'#' => {
                self.bump();
                let p = self.parameter(arena)?;
                Operand::Expr(push(arena, p))
            }
            b'+' | b'-' if !matches!(self.peek_second(), b'0'..=b'9' | b'.') => {
                self.bump();
                let (inner, _, _) = self.value(arena)?;
                match (c, inner) {
                    (b'+', v) => v,
                    (_, Operand::Number(v)) => Operand::Number(-v),
                    (_, Operand::Expr(e)) => Operand::Expr(push(arena, Node::Neg(e))),
                }
            }
            b'a'..=b'z' => Operand::Expr(self.function(arena)?),
            _ => {
                let (v, span, point) = self.number()?;
                return Ok((Operand::Number(v), span, point));
            }
        };
        Ok((operand, start..self.last, false))
    }

    /// The node of a value.
    fn operand_node(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        Ok(match self.value(arena)?.0 {
            Operand::Number(v) => push(arena, Node::Const(v)),
            Operand::Expr(e) => e,
        })
    }

    /// After `#`: `<name>`, a number, or a value giving the number.
    fn parameter(&mut self, arena: &mut Vec<Node>) -> Result<Node, String> {
        if self.peek() == b'<' {
            self.bump();
            let mut name = String::new();
            loop {
                match self.s.get(self.i) {
                    None => return Err("a parameter name `#<...` without `>`".into()),
                    Some(b'>') => {
                        self.bump();
                        break;
                    }
                    Some(c) if c.is_ascii_whitespace() => self.bump(),
                    Some(c) => {
                        name.push(c.to_ascii_lowercase() as char);
                        self.bump();
                    }
                }
            }
            if name.is_empty() {
                return Err("an empty parameter name `#<>`".into());
            }
            return Ok(Node::Param(ParamRef::Named(name.into())));
        }
        match self.value(arena)?.0 {
            Operand::Number(v) => {
                let n = crate::expr::parameter_number(v)?;
                Ok(if n == 0 && self.dialect == Dialect::Fanuc { Node::Vacant } else { Node::Param(ParamRef::Numbered(n)) })
            }
            Operand::Expr(e) => Ok(Node::Param(ParamRef::Indirect(e))),
        }
    }

    /// `#... = value`.
    fn assignment(&mut self, arena: &mut Vec<Node>) -> Result<Assignment, String> {
        self.bump();
        let target = match self.parameter(arena)? {
            Node::Param(p) => p,
            _ => return Err("#0 cannot be assigned".into()),
        };
        self.expect(b'=', "after the parameter of an assignment")?;
        let value = match self.dialect {
            Dialect::LinuxCnc => self.operand_node(arena)?,
            // Fanuc: `#i = <expression>` without brackets, to the end of the block
            Dialect::Fanuc => self.top_expression(arena)?,
        };
        Ok(Assignment { target, value })
    }

    /// `[ ... ]`.
    fn bracketed(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        self.expect(b'[', "")?;
        let (e, end) = self.inner(arena, false)?;
        if end != b']' {
            return Err("`,` outside a function argument list".into());
        }
        Ok(e)
    }

    /// The inside of brackets up to and including `]` (or `,` when `comma`), operators by
    /// precedence, left to right within one level; the node and the closing character.
    fn inner(&mut self, arena: &mut Vec<Node>, comma: bool) -> Result<(ExprId, u8), String> {
        self.brackets += 1;
        if self.dialect == Dialect::Fanuc && self.brackets > FANUC_MAX_BRACKETS {
            return Err(format!("brackets nested more than {FANUC_MAX_BRACKETS} levels (a Fanuc raises alarm 118)"));
        }
        self.enter()?;
        let e = self.operations(arena, &|c| c == b']' || comma && c == b',')?;
        self.nesting -= 1;
        self.brackets -= 1;
        let end = self.peek();
        self.bump();
        Ok((e, end))
    }

    /// An expression without brackets, up to the end of the line, a comment or `;` (Fanuc).
    fn top_expression(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        self.operations(arena, &|c| matches!(c, 0 | b'(' | b';' | b'#'))
    }

    /// Operands and binary operators up to (not including) a character for which `stop` holds:
    /// a stack of operators by precedence, reduced left to right within a level
    /// (LinuxCNC `read_real_expression`).
    fn operations(&mut self, arena: &mut Vec<Node>, stop: &dyn Fn(u8) -> bool) -> Result<ExprId, String> {
        let mut values = vec![self.operand_node(arena)?];
        let mut ops: Vec<Op> = Vec::new();
        let dialect = self.dialect;
        let reduce = |values: &mut Vec<ExprId>, ops: &mut Vec<Op>, arena: &mut Vec<Node>| {
            let op = ops.pop().expect("operator");
            let b = values.pop().expect("operand");
            let a = values.pop().expect("operand");
            values.push(push(arena, Node::Binary(op, a, b)));
        };
        while !stop(self.peek()) {
            let op = self.operator()?;
            while ops.last().is_some_and(|top| top.precedence(dialect) >= op.precedence(dialect)) {
                reduce(&mut values, &mut ops, arena);
            }
            ops.push(op);
            values.push(self.operand_node(arena)?);
        }
        while !ops.is_empty() {
            reduce(&mut values, &mut ops, arena);
        }
        Ok(values[0])
    }

    fn operator(&mut self) -> Result<Op, String> {
        let c = self.peek();
        let single = match c {
            b'+' => Some(Op::Plus),
            b'-' => Some(Op::Minus),
            b'/' => Some(Op::Divide),
            b'*' => {
                self.bump();
                if self.peek() == b'*' {
                    self.bump();
                    return Ok(Op::Power);
                }
                return Ok(Op::Times);
            }
            _ => None,
        };
        if let Some(op) = single {
            self.bump();
            return Ok(op);
        }
        for (word, op) in [
            ("and", Op::And),
            ("mod", Op::Modulo),
            ("or", Op::Or),
            ("xor", Op::Xor),
            ("eq", Op::Eq),
            ("ne", Op::Ne),
            ("gt", Op::Gt),
            ("ge", Op::Ge),
            ("lt", Op::Lt),
            ("le", Op::Le),
        ] {
            if self.keyword(word) {
                return Ok(op);
            }
        }
        Err(match c {
            0 => "an expression without its closing `]`".into(),
            _ => format!("unknown operator at {}", self.here()),
        })
    }

    /// A unary function: `ABS[...]`, `ATAN[y]/[x]`, `EXISTS[#<name>]`, Fanuc `ATAN[y,x]`, `POW[a,b]`.
    fn function(&mut self, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        let mut name = String::new();
        while self.peek().is_ascii_lowercase() {
            name.push(self.peek() as char);
            self.bump();
        }
        if name == "exists" && self.dialect == Dialect::LinuxCnc {
            self.expect(b'[', "after EXISTS")?;
            self.expect(b'#', "in EXISTS[#<name>]")?;
            let p = self.parameter(arena)?;
            self.expect(b']', "after EXISTS[#<name>")?;
            return match p {
                Node::Param(ParamRef::Named(n)) => Ok(push(arena, Node::Exists(n))),
                _ => Err("EXISTS takes a named parameter, EXISTS[#<name>]".into()),
            };
        }
        if (name == "atan" || name == "pow") && self.peek() == b'[' {
            self.bump();
            let (first, end) = self.inner(arena, self.dialect == Dialect::Fanuc)?;
            if end == b',' {
                let (second, end) = self.inner(arena, false)?;
                debug_assert_eq!(end, b']');
                return Ok(push(arena, if name == "pow" { Node::Pow(first, second) } else { Node::Atan2(first, second) }));
            }
            if name == "atan" && self.peek() == b'/' && self.peek_second() == b'[' {
                self.bump();
                let second = self.bracketed(arena)?;
                return Ok(push(arena, Node::Atan2(first, second)));
            }
            if name == "atan" && self.dialect == Dialect::Fanuc {
                return Ok(push(arena, Node::Func(Func::Atan, first)));
            }
            return Err(format!("{} needs two arguments: {}", name.to_uppercase(), if name == "pow" { "POW[a,b]" } else { "ATAN[y]/[x]" }));
        }
        let func = Func::named(&name).ok_or_else(|| match name.as_str() {
            "" => "a value is expected".to_string(),
            n => format!("unknown function or word `{}`", n.to_uppercase()),
        })?;
        let arg = self.bracketed(arena)?;
        Ok(push(arena, Node::Func(func, arg)))
    }

    /// `( ... )`: the range of its text.
    fn comment(&mut self) -> Result<Range<usize>, String> {
        self.bump();
        let start = self.i;
        while self.i < self.s.len() {
            match self.s[self.i] {
                b')' => {
                    self.bump();
                    return Ok(start..self.i - 1);
                }
                b'(' if self.dialect == Dialect::LinuxCnc => return Err("a comment inside a comment".into()),
                _ => self.bump(),
            }
        }
        Err("a comment `(` without its closing `)`".into())
    }

    /// Only comments (or nothing) may follow.
    fn comments_only(&mut self, comments: &mut Vec<Range<usize>>) -> Result<(), String> {
        loop {
            match self.peek() {
                0 => return Ok(()),
                b'(' => comments.push(self.comment()?),
                b';' if self.dialect == Dialect::LinuxCnc => {
                    comments.push(self.i + 1..self.s.len());
                    return Ok(());
                }
                b';' => self.bump(),
                _ => return Err(format!("unexpected {} after the statement", self.here())),
            }
        }
    }

    /// After `o`: a whole number alone on its line (comments aside), `O1234` as Mach3 and Mach4
    /// number a subprogram, which is no O-word statement; else nothing is consumed.
    fn program_number_alone(&mut self) -> Option<u32> {
        let (start, last) = (self.i, self.last);
        match self.number() {
            Ok((v, _, false)) if v >= 0.0 && v <= f64::from(u32::MAX) && matches!(self.peek(), 0 | b'(' | b';') => Some(v as u32),
            _ => {
                (self.i, self.last) = (start, last);
                None
            }
        }
    }

    /// After `o`: the label, the keyword and its arguments.
    fn o_statement(&mut self, arena: &mut Vec<Node>) -> Result<Statement, String> {
        let label = if self.peek() == b'<' {
            match self.parameter(arena)? {
                Node::Param(ParamRef::Named(n)) => Label::Name(n),
                _ => unreachable!("a name"),
            }
        } else {
            let (v, _, _) = self.number()?;
            if v < 0.0 || v.fract() != 0.0 {
                return Err(format!("the O-word number {v} is not a whole number"));
            }
            Label::Number(v as u32)
        };
        let optional = |c: &mut Self, arena: &mut Vec<Node>| -> Result<Option<ExprId>, String> {
            if c.peek() == b'[' {
                Ok(Some(c.bracketed(arena)?))
            } else {
                Ok(None)
            }
        };
        let required = |c: &mut Self, arena: &mut Vec<Node>, what: &str| -> Result<ExprId, String> {
            if c.peek() == b'[' {
                c.bracketed(arena)
            } else {
                Err(format!("`{label} {what}` needs a condition or count in brackets"))
            }
        };
        let kind = if self.keyword("sub") {
            OKind::Sub
        } else if self.keyword("endsub") {
            OKind::EndSub(optional(self, arena)?)
        } else if self.keyword("call") {
            let mut args = Vec::new();
            while self.peek() == b'[' {
                args.push(self.bracketed(arena)?);
            }
            OKind::Call(args)
        } else if self.keyword("return") {
            OKind::Return(optional(self, arena)?)
        } else if self.keyword("elseif") {
            OKind::ElseIf(required(self, arena, "elseif")?)
        } else if self.keyword("else") {
            OKind::Else
        } else if self.keyword("endif") {
            OKind::EndIf
        } else if self.keyword("if") {
            OKind::If(required(self, arena, "if")?)
        } else if self.keyword("endwhile") {
            OKind::EndWhile
        } else if self.keyword("while") {
            OKind::While(required(self, arena, "while")?)
        } else if self.keyword("do") {
            OKind::Do
        } else if self.keyword("endrepeat") {
            OKind::EndRepeat
        } else if self.keyword("repeat") {
            OKind::Repeat(required(self, arena, "repeat")?)
        } else if self.keyword("break") {
            OKind::Break
        } else if self.keyword("continue") {
            OKind::Continue
        } else {
            return Err(o_word_without_keyword(&label));
        };
        Ok(Statement::O(label, kind))
    }

    /// A Fanuc statement at the start of a line, if there is one.
    fn fanuc_statement(&mut self, arena: &mut Vec<Node>) -> Result<Option<Statement>, String> {
        let start = self.i;
        if self.keyword("if") && self.peek() == b'[' {
            let cond = self.bracketed(arena)?;
            if self.keyword("goto") {
                let target = self.operand_node(arena)?;
                return Ok(Some(Statement::IfGoto(cond, target)));
            }
            if self.keyword("then") {
                let mut assignments = Vec::new();
                while self.peek() == b'#' {
                    assignments.push(self.assignment(arena)?);
                }
                if assignments.is_empty() {
                    return Err("IF [...] THEN must be followed by an assignment `#i = ...`".into());
                }
                return Ok(Some(Statement::IfThen(cond, assignments)));
            }
            return Err("IF [...] must be followed by GOTO n or THEN #i = ...".into());
        }
        self.i = start;
        if self.keyword("goto") {
            let target = self.operand_node(arena)?;
            return Ok(Some(Statement::Goto(target)));
        }
        self.i = start;
        if self.keyword("while") && self.peek() == b'[' {
            let cond = self.bracketed(arena)?;
            if !self.keyword("do") {
                return Err("WHILE [...] must be followed by DO m".into());
            }
            let m = self.loop_number()?;
            return Ok(Some(Statement::While(cond, m)));
        }
        self.i = start;
        if self.keyword("end") && self.peek().is_ascii_digit() {
            return Ok(Some(Statement::End(self.loop_number()?)));
        }
        self.i = start;
        for word in ["popen", "pclos", "dprnt", "bprnt"] {
            if self.keyword(word) {
                if word.ends_with("prnt") {
                    self.print_format()?;
                }
                return Ok(Some(Statement::Output));
            }
            self.i = start;
        }
        if self.keyword("do") && self.peek().is_ascii_digit() {
            return Ok(Some(Statement::Do(self.loop_number()?)));
        }
        self.i = start;
        Ok(None)
    }

    /// The `[...]` of `DPRNT`/`BPRNT`: text and `#` variables with their formats, brackets nested.
    fn print_format(&mut self) -> Result<(), String> {
        self.expect(b'[', "after DPRNT or BPRNT")?;
        let mut depth = 1;
        while depth > 0 {
            match self.s.get(self.i) {
                None => return Err("DPRNT[ or BPRNT[ without its closing `]`".into()),
                Some(b'[') => depth += 1,
                Some(b']') => depth -= 1,
                _ => {}
            }
            self.bump();
        }
        Ok(())
    }

    fn loop_number(&mut self) -> Result<u32, String> {
        let (v, _, _) = self.number()?;
        if !(1.0..=3.0).contains(&v) || v.fract() != 0.0 {
            return Err(format!("loop number {v}: DO and END take 1, 2 or 3"));
        }
        Ok(v as u32)
    }
}

/// Appends a node; its index.
pub fn push(arena: &mut Vec<Node>, node: Node) -> ExprId {
    arena.push(node);
    (arena.len() - 1) as ExprId
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str, dialect: Dialect) -> (Line, Vec<Node>) {
        let mut arena = Vec::new();
        let line = parse_line(text, 1, dialect, &mut arena, false).unwrap_or_else(|e| panic!("{text}: {e}"));
        (line, arena)
    }

    #[test]
    fn words_spans_comments_and_blanks() {
        let (l, _) = parse("N10 g1 X-1.5 y 2 (move; here) Z.5 ; tail X9", Dialect::LinuxCnc);
        let letters: String = l.words.iter().map(|w| w.letter as char).collect();
        assert_eq!(letters, "GXYZ");
        assert_eq!(l.sequence, Some(10));
        assert_eq!(l.word(b'X').unwrap().value, Operand::Number(-1.5));
        assert_eq!(l.word(b'Y').unwrap().value, Operand::Number(2.0));
        let text = "N10 g1 X-1.5 y 2 (move; here) Z.5 ; tail X9";
        assert_eq!(&text[l.word(b'X').unwrap().span.clone()], "-1.5");
        assert_eq!(&text[l.comments[0].clone()], "move; here");
        assert_eq!(&text[l.comments[1].clone()], " tail X9");
        assert_eq!(&text[..l.end_of_items], "N10 g1 X-1.5 y 2 (move; here) Z.5");
        // blanks inside a number, as LinuxCNC reads them
        assert_eq!(parse("X1 0.5", Dialect::LinuxCnc).0.word(b'X').unwrap().value, Operand::Number(10.5));
    }

    #[test]
    fn expressions_parameters_and_statements() {
        let (l, a) = parse("#1 = [2 + 3 * 4 ** 2] #<depth>=-#1 X[ATAN[1]/[1]]", Dialect::LinuxCnc);
        assert_eq!(l.assignments.len(), 2);
        assert!(matches!(a[l.assignments[0].value as usize], Node::Binary(Op::Plus, _, _)));
        assert_eq!(l.assignments[1].target, ParamRef::Named("depth".into()));
        assert!(matches!(l.word(b'X').unwrap().value, Operand::Expr(_)));
        let (l, _) = parse("o<my sub> call [1] [#2 + 1]", Dialect::LinuxCnc);
        assert!(matches!(l.statement, Some(Statement::O(Label::Name(ref n), OKind::Call(ref args))) if &**n == "mysub" && args.len() == 2));
        let (l, _) = parse("o100 while [#1 LT 10] (loop)", Dialect::LinuxCnc);
        assert!(matches!(l.statement, Some(Statement::O(Label::Number(100), OKind::While(_)))));
        let (l, _) = parse("N20 IF [#1 GE 3.] GOTO 50", Dialect::Fanuc);
        assert!(matches!(l.statement, Some(Statement::IfGoto(_, _))));
        let (l, _) = parse("WHILE [#2 LE #3] DO 1", Dialect::Fanuc);
        assert!(matches!(l.statement, Some(Statement::While(_, 1))));
        let (l, _) = parse("O1234 (PART 7)", Dialect::Fanuc);
        assert_eq!(l.program_number, Some(1234));
        let (l, _) = parse("G01 X10. Y5 F#100;", Dialect::Fanuc);
        assert!(l.word(b'X').unwrap().decimal_point && !l.word(b'Y').unwrap().decimal_point);
        for bad in ["G1 X", "G1 X[1 + ]", "o100 foo", "#1 5", "G1 (open", "X[1,2]", "G1 O5"] {
            assert!(parse_line(bad, 1, Dialect::LinuxCnc, &mut Vec::new(), false).is_err(), "{bad}");
        }
    }
}
