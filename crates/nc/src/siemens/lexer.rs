//! One block of a SINUMERIK 840D sl program (Programming Manual Fundamentals, "Fundamentals of
//! NC programming": block structure, addresses with a value or `=` and an expression, `;`
//! comments; "Arithmetic parameters (R)"; "Circular interpolation with radius" (`CR=`); "Frames"
//! (`TRANS`/`ATRANS`, `SUPA`); "Tool offsets" (`D`)), read into the interpreter's [`Line`]: every
//! word keeps the byte span of its value text (after the `=` when there is one), so that the
//! writer replaces a value and leaves the rest of the block, its text calls (`MSG("...")`,
//! `WORKPIECE(...)`, `CYCLE832(...)`) and its comments as they were. What the block means in the
//! interpreter's terms (the `G52` of a `TRANS`, the `G43` of a `D1`) is added as words with an
//! empty span, which the writer never changes.
//!
//! A file header `%_N_NAME_MPF` or `;$PATH=...` is read as an empty line (the writer keeps the
//! main file's). What is not read yet, or never (rotated,
//! scaled and mirrored frames, 5-axis transformations, probing, cycles, subprograms with
//! parameters, control flow), is refused with its line and the reason. A subprogram call (`L10 P3`,
//! `NAME`, `CALL "NAME"`) and `RET` are read as a [`Call`] ([`super::subprograms`]).

use super::cycles::Call;
use super::expr::Parser;
use super::{R_BASE, R_COUNT};
use crate::dialect::Dialect;
use crate::expr::{ExprId, Node, Op, ParamRef};
use crate::lexer::{push, Assignment, Line, Operand, Word};

/// Addresses that take a value: `X10`, `X=R1+2`, `F=200`.
const ADDRESSES: &[u8] = b"XYZABCIJKFSGMTDP";

/// Commands that move nothing and change no position, passed through (with their parenthesised
/// arguments when they have some): messages, the blank description of the simulation, the
/// high-speed settings, acceleration and feed-forward modes, feed correction modes.
const PASSED: &[&str] = &[
    "MSG",
    "WORKPIECE",
    "CYCLE832",
    "SOFT",
    "BRISK",
    "FFWON",
    "FFWOF",
    "CFTCP",
    "CFC",
    "CFIN",
    "COMPOF",
    "COMPON",
    "COMPCAD",
    "COMPCURV",
    "UPATH",
    "SPATH",
    "STOPRE",
    "ORIWKS",
    "ORIAXES",
    "TRAFOOF",
    "DIAMOF",
    "SPOS",
    "ADIS",
    "ADISPOS",
    "SETMS",
];

/// Commands refused, and why.
const REFUSED: &[(&str, &str)] = &[
    ("ROT", "(programmable rotation) is not supported: 3-axis frames are TRANS and ATRANS"),
    ("AROT", "(additive programmable rotation) is not supported: 3-axis frames are TRANS and ATRANS"),
    ("SCALE", "(programmable scaling) is not supported"),
    ("ASCALE", "(additive programmable scaling) is not supported"),
    ("MIRROR", "(programmable mirroring) is not supported"),
    ("AMIRROR", "(additive programmable mirroring) is not supported"),
    ("TRAORI", "(5-axis transformation, tool centre point) is not supported: correct the program in machine axes"),
    ("TRANSMIT", "(face-end transformation) is not supported"),
    ("TRACYL", "(cylinder surface transformation) is not supported"),
    ("CYCLE800", "(swivel plane) with parameters is not supported: correct the program in machine axes"),
    ("CIP", "(circle through an intermediate point) is not read yet: write G2/G3 with I J or CR="),
    ("CT", "(tangential circle) is not read yet: write G2/G3 with I J or CR="),
    ("MEAS", "(measuring) stops where the probe touches: the moves after it are not known beforehand"),
];

/// Reads one block (same contract as [`crate::lexer::parse_line`]; `_dialect` is the family).
pub(crate) fn parse_line(text: &str, number: usize, _dialect: Dialect, arena: &mut Vec<Node>, _bytewise: bool) -> Result<Line, String> {
    let mut line = Line { number, ..Line::default() };
    let s = text.as_bytes();
    let mut p = Parser::new(s, 0);
    if is_file_header(text) {
        // read as nothing: a subprogram file's header does not go into the expanded call
        return Ok(line);
    }
    if p.peek_raw() == b'/' {
        p.i += 1;
        line.delete = true;
    }
    if p.peek_raw() == b'N' && s.get(p.i + 1).is_some_and(u8::is_ascii_digit) {
        p.i += 1;
        line.sequence = Some(p.number()? as u32);
    }
    super::statements::label(&mut p, &mut line);
    let keyword = p.upcoming_identifier();
    if keyword == "DEF" || super::statements::KEYWORDS.contains(&keyword.as_str()) {
        p.name();
        if keyword == "DEF" {
            super::variables::definition(&mut p, &mut line, arena)?;
        } else {
            let c = super::statements::statement(&keyword, &mut p, arena)?;
            line.statement = Some(crate::lexer::Statement::Siemens(c));
        }
        if let Some(c) = text.find(';') {
            line.comments.push(c + 1..text.len());
        }
        line.end_of_items = text[..line.comments.first().map_or(text.len(), |c| c.start - 1)].trim_end().len();
        return Ok(line);
    }
    let mut block = Block::default();
    loop {
        let c = p.peek_raw();
        match c {
            0 => break,
            b';' => {
                line.comments.push(p.i + 1..text.len());
                break;
            }
            c if c.is_ascii_alphabetic() || c == b'_' || c == b'$' => {
                block.item(&mut p, &mut line, arena)?;
                line.end_of_items = s[..p.i].iter().rposition(|c| !matches!(c, b' ' | b'\t' | b'\r')).map_or(0, |k| k + 1);
            }
            _ => return Err(format!("unexpected `{}` at column {}", text[p.i..].chars().next().unwrap_or(' '), p.i + 1)),
        }
    }
    let at = line.end_of_items;
    block.finish(&mut line, at, arena)?;
    if line.words.is_empty() && line.assignments.is_empty() && line.end_of_items == 0 {
        line.end_of_items = line.comments.first().map_or(text.trim_end().len(), |c| c.start.saturating_sub(1));
    }
    Ok(line)
}

/// Whether a line is part of a file's header (`%_N_NAME_MPF`, `;$PATH=/_N_WKS_DIR/...`), which
/// stays first in the file.
pub fn is_file_header(text: &str) -> bool {
    let t = text.trim_start();
    t.starts_with('%') || t.starts_with(";$PATH")
}

/// What a block says beyond its words, known when it is read to its end.
#[derive(Default)]
struct Block {
    /// `TRANS` (false) or `ATRANS` (true), with the byte after the keyword.
    frame: Option<(bool, usize)>,
    /// `D0` (false), `D1`... (true).
    cutting_edge: Option<bool>,
    supa: bool,
    /// A value with `IC(...)` or `AC(...)`.
    one_value_mode: bool,
    /// R parameters and DEF variables assigned so far on the line.
    assigned: Vec<u32>,
    names: Vec<Box<str>>,
}

impl Parser<'_> {
    /// The next non-blank character, upper case; 0 at the end.
    fn peek_raw(&mut self) -> u8 {
        while self.i < self.s.len() && matches!(self.s[self.i], b' ' | b'\t' | b'\r') {
            self.i += 1;
        }
        self.s.get(self.i).map_or(0, |c| c.to_ascii_uppercase())
    }

    /// Skips a parenthesised argument list (strings in `"` may hold any character).
    fn skip_arguments(&mut self) -> Result<(), String> {
        if self.peek_raw() != b'(' {
            return Ok(());
        }
        let (mut depth, mut quoted) = (0usize, false);
        while self.i < self.s.len() {
            let c = self.s[self.i];
            self.i += 1;
            match c {
                b'"' => quoted = !quoted,
                b'(' if !quoted => depth += 1,
                b')' if !quoted => {
                    depth -= 1;
                    if depth == 0 {
                        return Ok(());
                    }
                }
                _ => {}
            }
        }
        Err("a `(` is never closed".into())
    }

    /// A word's value: `=` and an expression, or a signed number. The operand and its span.
    fn value(&mut self, letter: u8, arena: &mut Vec<Node>) -> Result<(Operand, std::ops::Range<usize>, Vec<u32>), String> {
        if self.peek_raw() == b'=' {
            self.i += 1;
            let start = {
                self.peek_raw();
                self.i
            };
            let mode = self.upcoming_name();
            if matches!(mode.as_str(), "IC" | "AC") && self.s.get(self.i + 2) == Some(&b'(') {
                self.i += 2;
                self.reads.clear();
                self.names.clear();
                let v = self.expression(arena)?;
                let e = one_value_mode(letter, mode == "IC", v, arena)?;
                let end = self.i;
                return Ok((Operand::Expr(e), start..end, std::mem::take(&mut self.reads)));
            }
            if matches!(mode.as_str(), "DC" | "ACP" | "ACN" | "CAC" | "CIC") {
                return Err(format!(
                    "`{}(...)` (a distance mode for one value) is not read yet: write the value in the block's mode (G90/G91)",
                    self.upcoming_name()
                ));
            }
            self.reads.clear();
            self.names.clear();
            let e = self.expression(arena)?;
            let end = start + self.s[start..self.i].iter().rposition(|c| !matches!(c, b' ' | b'\t' | b'\r')).map_or(0, |k| k + 1);
            let value = match arena[e as usize] {
                Node::Const(v) => Operand::Number(v),
                Node::Neg(c) => match arena[c as usize] {
                    Node::Const(v) => Operand::Number(-v),
                    _ => Operand::Expr(e),
                },
                _ => Operand::Expr(e),
            };
            return Ok((value, start..end, std::mem::take(&mut self.reads)));
        }
        let start = {
            self.peek_raw();
            self.i
        };
        let negative = match self.peek_raw() {
            b'-' => {
                self.i += 1;
                true
            }
            b'+' => {
                self.i += 1;
                false
            }
            _ => false,
        };
        let v = self.number()?;
        Ok((Operand::Number(if negative { -v } else { v }), start..self.i, Vec::new()))
    }

    /// The identifier (letters, digits, `_`) that starts at the cursor, upper case, not read.
    fn upcoming_identifier(&mut self) -> String {
        self.peek_raw();
        let end = (self.i..self.s.len()).find(|&j| !(self.s[j].is_ascii_alphanumeric() || self.s[j] == b'_')).unwrap_or(self.s.len());
        String::from_utf8_lossy(&self.s[self.i..end]).to_ascii_uppercase()
    }

    /// The name that starts at the cursor, without reading it.
    fn upcoming_name(&self) -> String {
        let mut j = self.i;
        while j < self.s.len() && self.s[j].is_ascii_alphabetic() {
            j += 1;
        }
        String::from_utf8_lossy(&self.s[self.i..j]).to_ascii_uppercase()
    }
}

impl Block {
    /// One item from a letter on: a word, an R assignment, a command.
    fn item(&mut self, p: &mut Parser, line: &mut Line, arena: &mut Vec<Node>) -> Result<(), String> {
        let start = p.i;
        let letters = p.upcoming_name();
        let next = p.s.get(start + letters.len()).copied().unwrap_or(0);
        if letters == "T" && p.s[start + 1..].iter().find(|c| !matches!(c, b' ' | b'=')) == Some(&b'"') {
            return Err("T=\"name\": a tool by its name is not read yet: write T with its number (T1)".into());
        }
        // an address letter and its value
        if letters.len() == 1
            && ADDRESSES.contains(&letters.as_bytes()[0])
            && (next.is_ascii_digit() || matches!(next, b'.' | b'-' | b'+' | b'=' | b' '))
        {
            p.i += 1;
            return self.word(letters.as_bytes()[0], p, line, arena);
        }
        if (letters == "CR" || letters == "AR") && p.s[start + 2..].iter().find(|c| !matches!(c, b' ' | b'\t')) == Some(&b'=') {
            // CR= is LinuxCNC's R; AR= the opening angle ([`super::arcs`])
            let letter = if letters == "AR" { super::arcs::AR } else { b'R' };
            if line.words.iter().any(|w| w.letter == letter) {
                return Err(format!("two {letters}= words on one block"));
            }
            p.i += 2;
            let (value, span, _) = p.value(b'R', arena)?;
            line.words.push(Word { letter, value, span, decimal_point: true });
            return Ok(());
        }
        let name = p.name();
        if let Some(n) = name.strip_prefix('R').and_then(|d| d.parse::<u32>().ok()) {
            return self.assignment(n, p, line, arena);
        }
        match name.as_str() {
            "TRANS" | "ATRANS" => {
                self.frame = Some((name == "ATRANS", p.i));
                Ok(())
            }
            "SUPA" => {
                self.supa = true;
                Ok(())
            }
            "CYCLE800" => {
                let at = p.i;
                p.skip_arguments()?;
                if p.s[at..p.i].iter().any(|c| !matches!(c, b'(' | b')' | b' ')) {
                    return Err(format!("CYCLE800 {}", refusal("CYCLE800")));
                }
                Ok(())
            }
            n if PASSED.contains(&n) => {
                if p.peek_raw() == b'=' {
                    p.i += 1;
                    p.expression(&mut Vec::new())?;
                }
                p.skip_arguments()
            }
            "MCALL" => {
                let call = match p.peek_raw() {
                    0 | b';' => Call::ModalOff,
                    _ => match p.name().as_str() {
                        c @ ("CYCLE81" | "CYCLE82" | "CYCLE83") => cycle_call(c, true, p, arena)?,
                        other => return Err(format!("MCALL {other}: a modal call of CYCLE81, CYCLE82 or CYCLE83 is read")),
                    },
                };
                set_call(line, call)
            }
            c @ ("CYCLE81" | "CYCLE82" | "CYCLE83") => {
                let call = cycle_call(c, false, p, arena)?;
                set_call(line, call)
            }
            n if n.starts_with("CYCLE") => {
                Err(format!("{n} is not read: of the cycles, CYCLE81, CYCLE82 and CYCLE83 are read; others make moves of their own"))
            }
            "RET" => set_call(line, Call::Return),
            "PROC" => {
                let sub = p.name();
                match p.peek_raw() {
                    0 | b';' => Ok(()),
                    b'(' => Err(format!("PROC {sub}(...): a subprogram with parameters is not read yet")),
                    _ => Err(format!("PROC {sub} {}: only PROC and the name are read (SAVE, DISPLOF... are not)", p.name())),
                }
            }
            "CALL" => {
                if p.peek_raw() != b'"' {
                    return Err("CALL with a variable is not read: CALL \"NAME\" with the name in quotes is".into());
                }
                let start = p.i + 1;
                let end = start + p.s[start..].iter().position(|&c| c == b'"').ok_or("a `\"` is never closed")?;
                p.i = end + 1;
                let name = String::from_utf8_lossy(&p.s[start..end]).trim().to_ascii_uppercase();
                if !super::subprograms::is_name(&name) {
                    return Err(format!("CALL \"{name}\": not a subprogram name"));
                }
                set_call(line, Call::Sub { name, passes: 1 })
            }
            n if REFUSED.iter().any(|(k, _)| *k == n) => Err(format!("{n} {}", refusal(n))),
            n if p.peek_raw() == b'=' && super::variables::is_variable_name(n) => self.variable(n, p, line, arena),
            n if super::subprograms::is_name(n) => {
                if p.peek_raw() == b'(' {
                    return Err(format!("{n}(...): a subprogram call with parameters is not read yet"));
                }
                set_call(line, Call::Sub { name: n.to_string(), passes: 1 })
            }
            n => Err(format!("`{n}` is not read: not a SINUMERIK address, command or subprogram name")),
        }
    }

    fn word(&mut self, letter: u8, p: &mut Parser, line: &mut Line, arena: &mut Vec<Node>) -> Result<(), String> {
        let (value, span, reads) = p.value(letter, arena)?;
        let mode = p.s[span.clone()].get(..3).map(|m| m.to_ascii_uppercase());
        self.one_value_mode |= matches!(mode.as_deref(), Some(b"IC(" | b"AC("));
        if let Some(r) = reads.iter().find(|r| self.assigned.contains(r)) {
            return Err(format!("R{r} is assigned and read on one block: assign it on a block of its own"));
        }
        self.check_names(p)?;
        if letter != b'G' && letter != b'M' && line.words.iter().any(|w| w.letter == letter) {
            return Err(format!("two {} words on one block", letter as char));
        }
        match letter {
            b'D' => {
                let Operand::Number(v) = value else { return Err("D takes a number".into()) };
                if v != 0.0 && v != 1.0 {
                    return Err(format!("D{v}: cutting edges other than D1 are not read yet (one length per tool, from the tool table)"));
                }
                self.cutting_edge = Some(v != 0.0);
                return Ok(());
            }
            b'G' => {
                let Operand::Number(v) = value else { return Err("G takes a number".into()) };
                if matches!(v as u32, 43 | 44 | 49 | 52 | 92) && v.fract() == 0.0 {
                    return Err(format!("G{v} is not a SINUMERIK G function (tool offsets come with D, shifts with TRANS)"));
                }
            }
            _ => {}
        }
        line.words.push(Word { letter, value, span, decimal_point: true });
        Ok(())
    }

    fn assignment(&mut self, n: u32, p: &mut Parser, line: &mut Line, arena: &mut Vec<Node>) -> Result<(), String> {
        if n >= R_COUNT {
            return Err(format!("R{n}: R parameters R0-R{} are read", R_COUNT - 1));
        }
        if p.peek_raw() != b'=' {
            return Err(format!("R{n} without `=`: an R parameter is assigned with R{n}=..."));
        }
        p.i += 1;
        let value = self.assigned_value(p, arena)?;
        self.assigned.push(n);
        line.assignments.push(Assignment { target: ParamRef::Numbered(R_BASE + n), value });
        Ok(())
    }

    /// The expression after the `=` of an assignment; refused when it reads an R parameter or a
    /// variable the same block assigns before it (the 840D reads the block's values first).
    fn assigned_value(&mut self, p: &mut Parser, arena: &mut Vec<Node>) -> Result<ExprId, String> {
        p.reads.clear();
        p.names.clear();
        let value = p.expression(arena)?;
        if let Some(r) = p.reads.iter().find(|r| self.assigned.contains(r)) {
            return Err(format!("R{r} is assigned and read on one block: assign it on a block of its own"));
        }
        self.check_names(p)?;
        Ok(value)
    }

    /// A DEF variable given a value on the block: `NAME=expression`.
    fn variable(&mut self, name: &str, p: &mut Parser, line: &mut Line, arena: &mut Vec<Node>) -> Result<(), String> {
        p.i += 1;
        let value = self.assigned_value(p, arena)?;
        self.names.push(name.into());
        line.assignments.push(Assignment { target: ParamRef::Named(name.into()), value });
        Ok(())
    }

    /// A variable read by the expression just read is not given a value earlier on the block.
    fn check_names(&self, p: &Parser) -> Result<(), String> {
        match p.names.iter().find(|n| self.names.contains(n)) {
            Some(n) => Err(format!("{n} is assigned and read on one block: assign it on a block of its own")),
            None => Ok(()),
        }
    }

    /// The words that say what the block's commands mean to the interpreter.
    fn finish(&mut self, line: &mut Line, at: usize, arena: &mut Vec<Node>) -> Result<(), String> {
        let virtual_word = |letter: u8, v: f64| Word { letter, value: Operand::Number(v), span: at..at, decimal_point: true };
        let mut gs = Vec::new();
        if let Some((additive, _)) = self.frame {
            if line.words.iter().any(|w| !matches!(w.letter, b'X' | b'Y' | b'Z')) {
                return Err("TRANS and ATRANS take X Y Z on a block of their own".into());
            }
            gs.push(virtual_word(b'G', 52.0));
            for (k, l) in [b'X', b'Y', b'Z'].into_iter().enumerate() {
                match line.words.iter_mut().find(|w| w.letter == l) {
                    Some(w) if additive => {
                        // ATRANS: the shift so far plus the value; LinuxCNC keeps the G52 shift in
                        // #5211... in machine units
                        let stored = push(arena, Node::Param(ParamRef::Numbered(5211 + k as u32)));
                        let shift = machine_to_program_units(arena, stored);
                        let value = match w.value {
                            Operand::Number(v) => push(arena, Node::Const(v)),
                            Operand::Expr(e) => e,
                        };
                        w.value = Operand::Expr(push(arena, Node::Binary(Op::Plus, shift, value)));
                    }
                    Some(_) => {}
                    None if additive => {}
                    None => line.words.push(virtual_word(l, 0.0)),
                }
            }
        }
        if self.supa {
            gs.push(virtual_word(b'G', 53.0));
        }
        if let Some(Call::Sub { name, passes }) = line.siemens_call.as_deref_mut() {
            if let Some(w) = line.words.iter().find(|w| w.letter != b'P') {
                return Err(format!("{name} is a subprogram call: write {} on a block of its own", w.letter as char));
            }
            if let Some(w) = line.words.pop() {
                *passes = match w.value {
                    Operand::Number(v) if (1.0..=9999.0).contains(&v) && v.fract() == 0.0 => v as u32,
                    _ => return Err(format!("{name} P: the number of passes is a whole number from 1 to 9999")),
                };
            }
        }
        let distance = line.words.iter().any(|w| w.letter == b'G' && matches!(w.value, Operand::Number(v) if v == 90.0 || v == 91.0));
        if self.one_value_mode && distance {
            return Err("IC(...)/AC(...) with G90 or G91 on the same block: set the mode on a block before".into());
        }
        let tool_change = line.words.iter().any(|w| w.letter == b'M' && w.value == Operand::Number(6.0));
        match self.cutting_edge {
            Some(false) => gs.push(virtual_word(b'G', 49.0)),
            Some(true) => gs.push(virtual_word(b'G', 43.0)),
            None if tool_change => gs.push(virtual_word(b'G', 43.0)),
            None => {}
        }
        if line.words.iter().any(|w| w.letter == b'G' && w.value == Operand::Number(4.0)) {
            // G4 F.. dwells F seconds (LinuxCNC's G4 P..)
            if let Some(f) = line.words.iter_mut().find(|w| w.letter == b'F') {
                f.letter = b'P';
            }
        }
        line.words.extend(gs);
        Ok(())
    }
}

/// `CYCLE8x(a, , c)`: the parameters, each an expression or left empty.
fn cycle_call(name: &str, modal: bool, p: &mut Parser, arena: &mut Vec<Node>) -> Result<Call, String> {
    let number = name[5..].parse().expect("CYCLE and digits");
    if p.peek_raw() != b'(' {
        return Err(format!("{name} without its parameters in ( )"));
    }
    p.i += 1;
    let mut args = Vec::new();
    loop {
        args.push(match p.peek_raw() {
            b',' | b')' => None,
            _ => Some(p.expression(arena)?),
        });
        match p.peek_raw() {
            b',' => p.i += 1,
            b')' => {
                p.i += 1;
                return Ok(Call::Cycle { number, args, modal });
            }
            _ => return Err(format!("`,` or `)` expected in the parameters of {name} at column {}", p.i + 1)),
        }
    }
}

/// `X=IC(v)`, `X=AC(v)` (Fundamentals, "Absolute dimensions (G90, AC)", "Incremental dimensions
/// (G91, IC)"): the value of one axis in the other distance mode, stated in the block's mode from
/// the current position in program coordinates (`#5420`...): IC in G90 is v + position, AC in G91
/// v - position. The centre `I=AC(v)` is absolute (v - position; I J K are incremental from the
/// start by default), `I=IC(v)` the default.
fn one_value_mode(letter: u8, incremental: bool, v: u32, arena: &mut Vec<Node>) -> Result<u32, String> {
    let (k, centre) = match letter {
        b'X' | b'Y' | b'Z' => ((letter - b'X') as u32, false),
        b'A' | b'B' | b'C' => ((letter - b'A') as u32 + 3, false),
        b'I' | b'J' | b'K' => ((letter - b'I') as u32, true),
        _ => return Err(format!("{}=IC(...)/AC(...) is read for axes and I J K", letter as char)),
    };
    if centre && incremental {
        return Ok(v);
    }
    let position = push(arena, Node::Param(ParamRef::Numbered(5420 + k)));
    let offset = match centre {
        true => position,
        false => {
            // the value counts from the position when the block's mode is the other one
            let mode = push(arena, Node::Param(ParamRef::Named(if incremental { "_absolute" } else { "_incremental" }.into())));
            push(arena, Node::Binary(Op::Times, mode, position))
        }
    };
    Ok(push(arena, Node::Binary(if incremental { Op::Plus } else { Op::Minus }, v, offset)))
}

/// A block holds one call.
fn set_call(line: &mut Line, call: Call) -> Result<(), String> {
    if line.siemens_call.is_some() {
        return Err("two calls on one block".into());
    }
    line.siemens_call = Some(Box::new(call));
    Ok(())
}

fn refusal(name: &str) -> &'static str {
    REFUSED.iter().find(|(k, _)| *k == name).map_or("is not read", |(_, why)| why)
}

/// A length `value` kept in machine units as the program's units, by LinuxCNC's `#<_metric>` (the
/// program's G71/G70) and `#<_metric_machine>`: `value * a / b` with a = 25.4 for a program in mm
/// on an inch machine, b = 25.4 for a program in inch on a mm machine, else 1.
fn machine_to_program_units(arena: &mut Vec<Node>, value: ExprId) -> ExprId {
    let metric = push(arena, Node::Param(ParamRef::Named("_metric".into())));
    let metric_machine = push(arena, Node::Param(ParamRef::Named("_metric_machine".into())));
    let one = push(arena, Node::Const(1.0));
    let step = push(arena, Node::Const(crate::MM_PER_INCH - 1.0));
    // 1 + m (1 - n) (25.4 - 1) and 1 + (1 - m) n (25.4 - 1)
    let factor = |arena: &mut Vec<Node>, m: ExprId, n: ExprId| {
        let not_n = push(arena, Node::Binary(Op::Minus, one, n));
        let both = push(arena, Node::Binary(Op::Times, m, not_n));
        let more = push(arena, Node::Binary(Op::Times, both, step));
        push(arena, Node::Binary(Op::Plus, one, more))
    };
    let imperial = push(arena, Node::Binary(Op::Minus, one, metric));
    let imperial_machine = push(arena, Node::Binary(Op::Minus, one, metric_machine));
    let a = factor(arena, metric, metric_machine);
    let b = factor(arena, imperial, imperial_machine);
    let scaled = push(arena, Node::Binary(Op::Times, value, a));
    push(arena, Node::Binary(Op::Divide, scaled, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> (Line, Vec<Node>) {
        let mut arena = Vec::new();
        let line = parse_line(text, 1, Dialect::LinuxCnc, &mut arena, false).unwrap_or_else(|e| panic!("{text}: {e}"));
        (line, arena)
    }

    fn refused(text: &str) -> String {
        parse_line(text, 1, Dialect::LinuxCnc, &mut Vec::new(), false).expect_err(text)
    }

    #[test]
    fn words_equals_forms_spans_and_comments() {
        let text = "N30 G1 X10.5 Y=R1+5 Z=-R3 CR=-12.5 F=200 ; finish";
        let (l, _) = read(text);
        assert_eq!(l.sequence, Some(30));
        let letters: String = l.words.iter().map(|w| w.letter as char).collect();
        assert_eq!(letters, "GXYZRF");
        assert_eq!(&text[l.word(b'X').unwrap().span.clone()], "10.5");
        assert_eq!(&text[l.word(b'Y').unwrap().span.clone()], "R1+5");
        assert_eq!(&text[l.word(b'Z').unwrap().span.clone()], "-R3");
        assert_eq!(l.word(b'R').unwrap().value, Operand::Number(-12.5));
        assert_eq!(&text[l.comments[0].clone()], " finish");
        assert_eq!(&text[..l.end_of_items], "N30 G1 X10.5 Y=R1+5 Z=-R3 CR=-12.5 F=200");
        let (l, _) = read("%_N_PLATE_MPF");
        assert!(l.is_empty() && !l.percent);
        assert!(is_file_header(";$PATH=/_N_WKS_DIR/_N_PLATE_WPD") && !is_file_header("; $PATH is a comment"));
        let (l, _) = read("N20 MSG(\"DRILL; (8 mm)\") ; text call");
        assert!(l.words.is_empty() && l.comments.len() == 1);
        let (l, _) = read("WORKPIECE(,\"\",,\"BOX\",112,0,-10,80,0,0,100,60)");
        assert!(l.is_empty());
    }

    #[test]
    fn r_parameters_trans_atrans_and_tool_offsets() {
        let (l, _) = read("R1=5 R2=-2.5*R7");
        assert_eq!(l.assignments.len(), 2);
        assert_eq!(l.assignments[1].target, ParamRef::Numbered(R_BASE + 2));
        // TRANS: the G52 shift of every axis, named or not
        let (l, _) = read("TRANS X10 Y=R4");
        let g: Vec<_> = l.words.iter().map(|w| (w.letter as char, w.span.is_empty())).collect();
        assert_eq!(g, vec![('X', false), ('Y', false), ('Z', true), ('G', true)]);
        assert_eq!(l.word(b'Z').unwrap().value, Operand::Number(0.0));
        // ATRANS: the shift kept in #5211... plus the value
        let (l, a) = read("ATRANS Z-2");
        let Operand::Expr(e) = l.word(b'Z').unwrap().value else { panic!("an expression") };
        let Node::Binary(Op::Plus, shift, _) = &a[e as usize] else { panic!("a sum") };
        // (the kept shift x a) / b: converted from the machine's units (frame_units_tests below)
        let Node::Binary(Op::Divide, scaled, _) = &a[*shift as usize] else { panic!("a quotient") };
        assert!(matches!(&a[*scaled as usize], Node::Binary(Op::Times, s, _) if a[*s as usize] == Node::Param(ParamRef::Numbered(5213))));
        assert!(l.word(b'X').is_none());
        let g = |t: &str| read(t).0.words.iter().filter(|w| w.letter == b'G').map(|w| w.value).collect::<Vec<_>>();
        assert_eq!(g("T1 D1"), vec![Operand::Number(43.0)]);
        assert_eq!(g("M6"), vec![Operand::Number(43.0)]);
        assert_eq!(g("G0 SUPA Z0 D0"), vec![Operand::Number(0.0), Operand::Number(53.0), Operand::Number(49.0)]);
        // G4 F2: two seconds
        assert_eq!(read("G4 F2").0.word(b'P').unwrap().value, Operand::Number(2.0));
    }

    #[test]
    fn what_is_not_read_is_refused_saying_what() {
        for (text, says) in [
            ("AROT Z45", "AROT (additive programmable rotation)"),
            ("ROT Z30", "ROT (programmable rotation)"),
            ("TRAORI", "TRAORI (5-axis"),
            ("CYCLE800(0,\"TC1\",200000,57,0,0,0,0,45,0,0,0,0,1)", "CYCLE800 (swivel plane)"),
            ("CYCLE977(101,1,,1,50,,,3,1,1,,,1)", "CYCLE977 is not read"),
            ("MCALL CYCLE84(10,0,2,-12)", "MCALL CYCLE84: a modal call of CYCLE81, CYCLE82 or CYCLE83"),
            ("CYCLE81(10,0,2,-5", "`,` or `)` expected"),
            ("G1 X=DC(5)", "`DC(...)`"),
            ("G1 F=AC(5)", "F=IC(...)/AC(...) is read for axes"),
            ("G91 X=AC(5)", "with G90 or G91 on the same block"),
            ("T=\"FACE MILL 50\"", "T=\"name\""),
            ("G43 H1", "G43 is not a SINUMERIK G function"),
            ("R1=5 R2=R1", "R1 is assigned and read on one block"),
            ("X1 X2", "two X words"),
            ("T1 D2", "D2: cutting edges other than D1"),
            ("R1000=1", "R0-R999"),
            ("CIP X10 Y10 I1=5 J1=5", "CIP (circle through an intermediate point)"),
            ("IF R1>0 X10", "IF ... X10: a condition is followed by GOTOF"),
            ("IF R1>0 AND R2<5 GOTOF END", "two comparisons without parentheses"),
            ("ENDIF X1", "ENDIF is written on a block of its own"),
            ("REPEAT BEGIN END P=3", "program section repetition"),
            ("FOR X=1 TO 3", "the counter is an R parameter or a DEF variable"),
            ("FOR R1=1 TOO 3", "`TO` expected"),
            ("GOTOF \"LABEL\"", "a target in a variable is not read"),
            ("DEF STRING[8] NAME", "REAL, INT and BOOL are read"),
            ("DEF REAL AB[5]", "arrays are not read yet"),
            ("DEF INT AA=1, BB=AA+1", "AA is defined and read on one block"),
            ("COUNT=COUNT+1 X=COUNT", "COUNT is assigned and read on one block"),
            ("FOO(1, 2)", "FOO(...): a subprogram call with parameters"),
            ("L10 X5", "L10 is a subprogram call: write X on a block of its own"),
            ("L10 P0", "passes is a whole number from 1 to 9999"),
            ("PROC CONTOUR(REAL DEPTH)", "a subprogram with parameters"),
            ("CALL R10", "CALL with a variable"),
            ("L10 L20", "two calls on one block"),
            ("3X", "unexpected `3`"),
        ] {
            let message = refused(text);
            assert!(message.contains(says), "{text}: {message}");
        }
    }
}

#[cfg(test)]
mod flow_tests {
    use super::*;
    use crate::lexer::Statement;
    use crate::siemens::flow::{Control, JumpKind, Target};

    fn control(text: &str) -> (Line, Option<Control>) {
        let mut line = parse_line(text, 1, Dialect::LinuxCnc, &mut Vec::new(), false).unwrap_or_else(|e| panic!("{text}: {e}"));
        let c = match line.statement.take() {
            Some(Statement::Siemens(c)) => Some(c),
            _ => None,
        };
        (line, c)
    }

    #[test]
    fn labels_jumps_structures_and_definitions() {
        let (l, c) = control("N28 METKA1: ; the loop");
        assert_eq!((l.sequence, l.siemens_label.as_deref(), c), (Some(28), Some("METKA1"), None));
        assert_eq!(l.comments.len(), 1);
        let (l, _) = control("_MM0:R1=R2+1");
        assert_eq!((l.siemens_label.as_deref(), l.assignments.len()), (Some("_MM0"), 1));
        let Some(Control::Jump(j)) = control("N35 IF R20<90 GOTOB METKA1").1 else { panic!("a jump") };
        assert!(j.condition.is_some() && j.kind == JumpKind::Backward && j.target == Target::Label("METKA1".into()));
        let Some(Control::Jump(j)) = control("GOTOC N100 ; on").1 else { panic!("a jump") };
        assert!(j.condition.is_none() && j.kind == JumpKind::NoAlarm && j.target == Target::Block(100));
        assert!(matches!(control("IF (R1 > 0) AND (R2 < 5) ; both").1, Some(Control::If(_))));
        assert!(matches!(control("FOR R1 = 1 TO R5*2").1, Some(Control::For { counter: ParamRef::Numbered(1001), .. })));
        assert!(matches!(control("for count=0 to 3").1, Some(Control::For { counter: ParamRef::Named(_), .. })));
        for (text, want) in [("ELSE", Control::Else), ("ENDIF", Control::EndIf), ("LOOP", Control::Loop), ("ENDLOOP", Control::EndLoop)] {
            assert_eq!(control(text).1, Some(want));
        }
        assert!(matches!(control("UNTIL R1>=3").1, Some(Control::Until(_))));
        // DEF: the type mark, then the value, of each name
        let (l, _) = control("DEF REAL DEPTH=-2.5, WIDTH ; sizes");
        let targets: Vec<String> = l.assignments.iter().map(|a| format!("{:?}", a.target)).collect();
        assert_eq!(targets.len(), 4, "{targets:?}");
        assert!(l.siemens_def && targets[0].contains("DEPTH:REAL") && targets[3].contains("WIDTH"), "{targets:?}");
        let (l, _) = control("COUNT=COUNT+1 R1=R2*2");
        assert_eq!(l.assignments.len(), 2);
        assert_eq!(l.assignments[0].target, ParamRef::Named("COUNT".into()));
    }
}

#[cfg(test)]
mod cycle_tests {
    use super::*;

    #[test]
    fn cycle_calls_with_empty_parameters_and_mcall_on_and_off() {
        let mut arena = Vec::new();
        let l = parse_line("N50 MCALL CYCLE81(10, 0, 2, , R5*2) ; modal", 1, Dialect::LinuxCnc, &mut arena, false).unwrap();
        let Some(call) = l.siemens_call.as_deref() else { panic!("a call") };
        let Call::Cycle { number: 81, args, modal: true } = call else { panic!("{call:?}") };
        assert_eq!(args.iter().map(Option::is_some).collect::<Vec<_>>(), vec![true, true, true, false, true]);
        assert!(!l.is_empty());
        let l = parse_line("CYCLE82(15,0,1,-8,,0.5)", 1, Dialect::LinuxCnc, &mut arena, false).unwrap();
        assert!(matches!(l.siemens_call.as_deref(), Some(Call::Cycle { number: 82, modal: false, .. })));
        let l = parse_line("N90 MCALL", 1, Dialect::LinuxCnc, &mut arena, false).unwrap();
        assert_eq!(l.siemens_call.as_deref(), Some(&Call::ModalOff));
    }
}

#[cfg(test)]
mod subprogram_tests {
    use super::*;

    fn call(text: &str) -> Option<Call> {
        let line = parse_line(text, 1, Dialect::LinuxCnc, &mut Vec::new(), false).unwrap_or_else(|e| panic!("{text}: {e}"));
        line.siemens_call.map(|c| *c)
    }

    #[test]
    fn calls_by_number_name_and_call_with_passes() {
        let sub = |name: &str, passes| Some(Call::Sub { name: name.into(), passes });
        assert_eq!(call("N40 L10"), sub("L10", 1));
        assert_eq!(call("L10 P3 ; three passes"), sub("L10", 3));
        assert_eq!(call("POCKET1 P2"), sub("POCKET1", 2));
        assert_eq!(call("N50 CALL \"plate_2\""), sub("PLATE_2", 1));
        assert_eq!(call("RET"), Some(Call::Return));
        assert_eq!(call("PROC L10 ; header of the file"), None);
        assert_eq!(call("M17"), None);
    }
}

#[cfg(test)]
mod frame_units_tests {
    use crate::axes::{AxisSpec, MachineAxes};
    use crate::{Controller, ProgramSetup};

    /// `TRANS X10` then `ATRANS X5` shifts the program zero by 15 in the program's units, whatever
    /// the machine's units (LinuxCNC keeps the shift in machine units: an inch machine once counted
    /// it 25.4 times too small, as rs274 reading the corpus's rewriting showed).
    #[test]
    fn atrans_adds_in_the_programs_units_on_mm_and_inch_machines() {
        let axis = |letter| AxisSpec { letter, rotary: false, range: None };
        let axes = MachineAxes { name: "mill".into(), axes: vec![axis('X'), axis('Y'), axis('Z')] };
        for machine_inch in [false, true] {
            for (units, mm_per_unit) in [("G71", 1.0), ("G70", 25.4)] {
                let mut setup = ProgramSetup::zero(&axes);
                setup.machine_inch = machine_inch;
                let text = format!("N10 {units} G90\nN20 TRANS X10\nN30 ATRANS X5\nN40 G0 X1 Y0 Z0\nN50 M30\n");
                let (trace, _) = crate::run(&axes, text.as_bytes(), "p.mpf", Some(Controller::Siemens), &setup).unwrap();
                // the move's end in mm (the trace keeps machine positions in mm)
                let x = trace.moves.last().unwrap().end[0];
                let want = 16.0 * mm_per_unit;
                assert!((x - want).abs() < 1e-9, "machine inch {machine_inch}, {units}: X {x} mm, want {want}");
            }
        }
    }
}
