//! A SINUMERIK 840D program in its own language rewritten as the RS274/NGC program with the same
//! moves, so that LinuxCNC's rs274 is the independent reader of the landing check for the 840D
//! too. Written construct by construct from the SINUMERIK 840D sl Programming Manual
//! Fundamentals (and the Programming Guide Cycles for CYCLE81/CYCLE82) and the LinuxCNC 2.9
//! G-code manual, without the library's reader or lexer:
//!
//! - `N` numbers are dropped, `;` comments and the archive header `%_N_.._MPF` become `( )`
//!   comments (ASCII, opened by `;` so that rs274 never reads them as its own `MSG,`/`ABORT,`);
//! - R parameters `R0`-`R999` are the numbered parameters `#1000`-`#1999` (global in both
//!   languages); each assignment of a block is a line of its own, before the block's other words,
//!   so that a later one sees an earlier one as the 840D reads a block, left to right;
//! - `X=expr` is `X[expr]`: `( )` become `[ ]`, `SIN COS TAN ASIN ACOS SQRT ABS EXP LN ROUND`
//!   keep their names (degrees in both; ROUND half away from zero in both), `ATAN2(a,b)` is
//!   `ATAN[a]/[b]`, `POT(x)` (the square) is `[x]*[x]`, `TRUNC(x)` (towards zero) is `FIX` of a
//!   positive and `FUP` of a negative value, a unary minus is `0-`;
//! - `CR=r` is rs274's `R` word: both take a positive radius for an arc up to 180 degrees and a
//!   negative one for an arc over 180 degrees; `I J K` are incremental in both by default
//!   (G91.1); a block with `I=AC(..)` runs in G90.1 (its incremental centre words written as
//!   `#5420`/`#5421`/`#5422`, the position where the block starts, plus the value), G91.1 after it;
//! - `X=IC(v)` in G90 is `X[#5420+v]`, `X=AC(v)` in G91 is `X[v-#5420]`;
//! - `TRANS X Y Z` (the programmable frame replaced, an axis not named shifted by 0) and `ATRANS`
//!   (added to it) are LinuxCNC's `G52`, its three values kept in `#2001`-`#2003`;
//! - `SUPA`, `G53`, `G153` are LinuxCNC's `G53`, taken only without a tool length offset in force
//!   (with the 840D's default `$MN_G53_TOOLCORR = 0` the offset stays active; LinuxCNC's G53 drops it);
//! - `T1` selects, `M6` changes and turns on the new tool's length (the 840D's default cutting
//!   edge D1): `T1 M6`, then `G43 H1` (`G49` with `D0` on that block) on a line of its own, where
//!   rs274 keeps the machine where it is as the 840D does (the length on the line of `M6`, it
//!   re-reads the position as if the machine had moved by the change of length); `D1` alone is
//!   `G43` of the tool in the spindle, `D0` is `G49`;
//! - `G4 F2` (seconds) is `G4 P2`; `G70`/`G700` are `G20`, `G71`/`G710` `G21`;
//! - `CYCLE81(RTP, RFP, SDIS, DP, DPR)`, `CYCLE82(.., DTB)`: `G0` to RFP + |SDIS|, `G1` to DP (or
//!   RFP - |DPR| when DPR is given), the dwell DTB, `G0` to RTP. Called directly (at the current
//!   position) they are written as those moves; under `MCALL` each position block is LinuxCNC's
//!   `G98 G81`/`G82` with `R` = RFP + |SDIS|, `Z` the depth, `P` = DTB when the hole starts at RTP
//!   (G98 retracts to the level the hole starts from; RTP not below R), else (after a tool change
//!   that moved the program zero...) the position move and those moves, chosen by `o<..> if` at
//!   run time. `MCALL` alone is `G80`;
//! - `L10 P3`, a call by name and `CALL "NAME"` run the file `NAME.SPF` or `_N_NAME_SPF` given to
//!   the rewriting: an O-word subroutine defined at the top (`o<name> sub` .. `o<name> endsub`,
//!   its header and `PROC NAME` dropped, its end at `M17`, `RET`, `M2` or `M30`), called inside
//!   `o<..> repeat [P]`;
//! - the motion mode (G0-G3) is written on every line that moves: LinuxCNC's G81 and G80 leave no
//!   motion mode, where the 840D keeps its own.
//!
//! A program with what it does not rewrite gives `None`: anything else (`AR=`, `DEF`, jumps and
//! loops, `PROC` with parameters, `CYCLE83`, `G41`/`G42`, `D2`, `T="name"`, an `R` assigned and used
//! on one block ...), cycles outside G17 or in G91, `IC`/`AC` with `SUPA`, a unit change after a
//! frame, a position block under `MCALL` with `Z` or not in G0.

mod expr;
mod words;

use expr::{expr, plain};
use words::{arguments, closing, comment_line, split_comment, strip_number, words, Word};

/// The RS274/NGC text of a SINUMERIK program whose subprogram files are `files` (name, text), or
/// `None`.
pub fn siemens_to_ngc(text: &str, files: &[(&str, String)]) -> Option<String> {
    let mut r = Rewriter { files, modes: Modes::default(), subs: Vec::new(), labels: 0, depth: 0 };
    let (body, _) = r.program(text, false)?;
    let mut out = String::from("(; a SINUMERIK 840D program rewritten as RS274/NGC)\n#2001=0\n#2002=0\n#2003=0\n");
    for s in &r.subs {
        out.push_str(&s.text);
    }
    Some(out + &body)
}

/// What the 840D holds between blocks that the rewriting needs.
#[derive(Clone, Debug, PartialEq)]
struct Modes {
    /// G0-G3.
    motion: u8,
    absolute: bool,
    xy_plane: bool,
    /// Tool selected by `T`, tool in the spindle, its length offset on.
    selected: Option<u32>,
    spindle: Option<u32>,
    offset: bool,
    /// The modal drilling cycle (81, 82) after `MCALL CYCLEnn(..)`.
    mcall: Option<u8>,
    /// A `TRANS`/`ATRANS` has been written (its values are in the units then in force).
    framed: bool,
}

impl Default for Modes {
    fn default() -> Self {
        Modes { motion: 0, absolute: true, xy_plane: true, selected: None, spindle: None, offset: false, mcall: None, framed: false }
    }
}

/// A subroutine written: its 840D name, the modes it was entered and left with, its label and text.
struct Sub {
    name: String,
    entry: Modes,
    exit: Modes,
    label: String,
    text: String,
}

struct Rewriter<'a> {
    files: &'a [(&'a str, String)],
    modes: Modes,
    subs: Vec<Sub>,
    labels: usize,
    depth: usize,
}

/// Settings and texts that move nothing: written as comments.
const INERT: &[&str] = &[
    "SOFT",
    "BRISK",
    "FFWON",
    "FFWOF",
    "CFTCP",
    "CFC",
    "COMPON",
    "COMPCAD",
    "COMPOF",
    "UPATH",
    "STOPRE",
    "ORIWKS",
    "TRAFOOF",
    "MSG",
    "WORKPIECE",
    "CYCLE832",
    "ADIS",
];

fn name_of(w: &Word) -> Option<&str> {
    match w {
        Word::Name(n) => Some(n.as_str()),
        _ => None,
    }
}

/// The moves of a drilling cycle at the current position (its values in #2011-#2014).
fn drill_moves(cycle: u8) -> String {
    let dwell = if cycle == 82 { "G4 P#2014\n" } else { "" };
    format!("G0 Z#2012\nG1 Z#2013\n{dwell}G0 Z#2011\n")
}

/// Whether a word moves nothing (`CYCLE800()` without parameters among them).
fn inert(w: &Word) -> bool {
    match w {
        Word::Call(n, a) if n == "CYCLE800" => a.trim().is_empty(),
        Word::Call(n, _) | Word::Name(n) | Word::Assign(n, _) => INERT.contains(&n.as_str()),
        _ => false,
    }
}

/// Names of the language that are not subprograms.
const KEYWORDS: &[&str] = &["TRANS", "ATRANS", "SUPA", "MCALL", "CALL", "RET", "PROC"];

impl Rewriter<'_> {
    /// The rewritten blocks of a program (`sub`: a subprogram file, ending at M17/RET/M2/M30) and
    /// whether it ended.
    fn program(&mut self, text: &str, sub: bool) -> Option<(String, bool)> {
        let mut out = String::new();
        for raw in text.lines() {
            let (code, comment) = split_comment(raw.trim_end_matches('\r'));
            let code = code.trim().to_ascii_uppercase();
            if code.starts_with('%') || sub && code.starts_with("PROC") {
                if code.starts_with("PROC") && code.split_whitespace().count() != 2 || code.contains('(') {
                    return None;
                }
                out.push_str(&comment_line(raw.trim()));
                continue;
            }
            if code.starts_with('/') {
                return None;
            }
            let ended = self.block(&strip_number(&code), &mut out, sub)?;
            if !comment.is_empty() {
                out.push_str(&comment_line(&comment));
            }
            if ended {
                return Some((out, true));
            }
        }
        (!sub).then_some((out, false))
    }

    /// One block into `out`; whether it ends the program or subprogram.
    fn block(&mut self, code: &str, out: &mut String, sub: bool) -> Option<bool> {
        let words = words(code)?;
        if words.is_empty() {
            return Some(false);
        }
        if words.iter().all(inert) {
            out.push_str(&comment_line(code));
            return Some(false);
        }
        if let Some(cycle) = words.iter().find_map(|w| match w {
            Word::Call(n, args) if n.starts_with("CYCLE") => Some((n.clone(), args.clone())),
            _ => None,
        }) {
            let modal = words.len() == 2 && words[0] == Word::Name("MCALL".into());
            if !modal && words.len() != 1 {
                return None;
            }
            return self.cycle(&cycle.0, &cycle.1, modal, out).map(|()| false);
        }
        match words.first().and_then(name_of) {
            Some("MCALL") if words.len() == 1 => {
                if self.modes.mcall.take().is_some() {
                    out.push_str("G80\n");
                }
                return Some(false);
            }
            Some("TRANS" | "ATRANS") => return self.frame(&words, out).map(|()| false),
            Some("RET") if sub && words.len() == 1 => return Some(true),
            _ => {}
        }
        if let Some((file, passes)) = self.call_of(&words)? {
            return self.call(&file, passes, out).map(|()| false);
        }
        self.plain(&words, out, sub)
    }

    /// The subprogram a block calls (`L10 P2`, `CONTOUR P2`, `CALL "NAME"`) and its passes.
    fn call_of(&self, words: &[Word]) -> Option<Option<(String, u32)>> {
        let passes = |rest: &[Word]| match rest {
            [] => Some(1),
            [Word::Letter(b'P', p)] => p.parse::<u32>().ok().filter(|&p| p >= 1),
            _ => None,
        };
        let (target, rest) = match words {
            // the digits as written: L7 and L007 are two programs on the 840D
            [Word::Letter(b'L', n), rest @ ..] if n.bytes().all(|c| c.is_ascii_digit()) => (format!("L{n}"), rest),
            [Word::Name(c), Word::Quoted(n)] if c == "CALL" => (n.clone(), &[][..]),
            [Word::Name(n), rest @ ..] if !KEYWORDS.contains(&n.as_str()) && n.len() >= 2 && n.as_bytes()[1].is_ascii_alphabetic() => {
                (n.clone(), rest)
            }
            _ => return Some(None),
        };
        Some(Some((target, passes(rest)?)))
    }

    /// A subprogram call: its subroutine (rewritten for the modes it is entered with), run
    /// `passes` times; the modes it leaves.
    fn call(&mut self, name: &str, passes: u32, out: &mut String) -> Option<()> {
        if self.modes.mcall.is_some() || self.depth >= 10 {
            return None;
        }
        let label = self.subroutine(name, self.modes.clone())?;
        if passes > 1 {
            // the second pass starts where the first ended: it must be the same subroutine
            let exit = self.subs.iter().find(|s| s.label == label)?.exit.clone();
            if self.subroutine(name, exit)? != label {
                return None;
            }
        }
        self.modes = self.subs.iter().find(|s| s.label == label)?.exit.clone();
        self.labels += 1;
        let call = format!("o<{label}> call\n");
        out.push_str(&if passes == 1 { call } else { format!("o<rep{0}> repeat [{passes}]\n{call}o<rep{0}> endrepeat\n", self.labels) });
        Some(())
    }

    /// The label of subprogram `name` entered with `entry` (rewritten once for each such entry).
    fn subroutine(&mut self, name: &str, entry: Modes) -> Option<String> {
        if let Some(s) = self.subs.iter().find(|s| s.name == name && s.entry == entry) {
            return Some(s.label.clone());
        }
        let wanted = [format!("{name}.SPF"), format!("_N_{name}_SPF")];
        let (_, text) = self.files.iter().find(|(f, _)| wanted.iter().any(|w| w.eq_ignore_ascii_case(f)))?;
        let saved = std::mem::replace(&mut self.modes, entry.clone());
        self.depth += 1;
        let body = self.program(text, true);
        self.depth -= 1;
        let exit = std::mem::replace(&mut self.modes, saved);
        let (body, _) = body?;
        if let Some(s) = self.subs.iter().find(|s| s.name == name && s.exit == exit && s.text.contains(&body)) {
            // entered otherwise, rewritten the same
            return Some(s.label.clone());
        }
        let variants = self.subs.iter().filter(|s| s.name == name).count();
        let label = if variants == 0 { name.to_ascii_lowercase() } else { format!("{}_{variants}", name.to_ascii_lowercase()) };
        let text = format!("o<{label}> sub\n{body}o<{label}> endsub\n");
        self.subs.push(Sub { name: name.to_string(), entry, exit, label: label.clone(), text });
        Some(label)
    }

    /// `TRANS`/`ATRANS` with X Y Z values: `G52` of the frame kept in #2001-#2003.
    fn frame(&mut self, words: &[Word], out: &mut String) -> Option<()> {
        if !self.modes.absolute {
            return None;
        }
        let add = matches!(&words[0], Word::Name(n) if n == "ATRANS");
        let mut values: [Option<String>; 3] = Default::default();
        for w in &words[1..] {
            let (axis, v) = axis_value(w)?;
            let k = b"XYZ".iter().position(|&a| a == axis)?;
            values[k] = Some(plain(&v)?);
        }
        for (k, v) in values.iter().enumerate() {
            let p = 2001 + k;
            match (v, add) {
                (Some(v), true) => out.push_str(&format!("#{p}=[#{p}+{v}]\n")),
                (Some(v), false) => out.push_str(&format!("#{p}={v}\n")),
                (None, false) => out.push_str(&format!("#{p}=0\n")),
                (None, true) => {}
            }
        }
        out.push_str("G52 X#2001 Y#2002 Z#2003\n");
        self.modes.framed = true;
        Some(())
    }

    /// `CYCLE81(..)`/`CYCLE82(..)`: its values set, then its moves (direct) or the modal call.
    fn cycle(&mut self, name: &str, args: &str, modal: bool, out: &mut String) -> Option<()> {
        let number: u8 = match name {
            "CYCLE81" => 81,
            "CYCLE82" => 82,
            _ => return None,
        };
        if !self.modes.xy_plane || !self.modes.absolute {
            return None;
        }
        let v = arguments(args)?;
        let count = if number == 81 { 5 } else { 6 };
        if v.len() > count && v[count..].iter().any(|a| !a.is_empty() && a != "0") {
            return None;
        }
        let get = |k: usize| v.get(k).filter(|a| !a.is_empty()).map(|a| expr(a)).unwrap_or(Some("0".into()));
        let (rtp, rfp, sdis) = (get(0)?, get(1)?, get(2)?);
        let depth = match (v.get(3).filter(|a| !a.is_empty()), v.get(4).filter(|a| !a.is_empty() && *a != "0")) {
            (_, Some(dpr)) => format!("[{rfp}-ABS[{}]]", expr(dpr)?),
            (Some(dp), None) => expr(dp)?,
            (None, None) => return None,
        };
        let dwell = if number == 82 { get(5)? } else { "0".into() };
        out.push_str(&format!("#2011={rtp}\n#2012=[{rfp}+ABS[{sdis}]]\n#2013={depth}\n#2014={dwell}\n"));
        if modal {
            self.modes.mcall = Some(number);
        } else {
            out.push_str(&drill_moves(number));
        }
        Some(())
    }

    /// Any other block: assignments, tool words, then one line of codes and values.
    fn plain(&mut self, words: &[Word], out: &mut String, sub: bool) -> Option<bool> {
        let mut b = Plain { g4: words.contains(&Word::Letter(b'G', "4".into())), ..Plain::default() };
        for w in words {
            self.word(w, &mut b, sub)?;
        }
        let values = self.render(&b)?;
        // an R assigned on the block and read by a later word: the 840D's order is not kept
        if b.assignments.iter().any(|(p, _)| values.iter().any(|(_, v)| reads(v, *p))) {
            return None;
        }
        for (p, e) in &b.assignments {
            out.push_str(&format!("#{p}={e}\n"));
        }
        self.tools(&b, out)?;
        if b.g4 {
            if !values.is_empty() || b.motion.is_some() || !b.codes.is_empty() || b.supa {
                return None;
            }
            out.push_str(&format!("G4 P{}\n", b.dwell.as_ref()?));
            return Some(b.ended);
        }
        if let Some(m) = b.motion {
            self.modes.motion = m;
        }
        let moves = values.iter().any(|(l, _)| b"XYZIJKR".contains(l));
        if moves && self.modes.mcall.is_some() {
            return self.hole(&b, &values, out).map(|()| b.ended);
        }
        let mut line = b.codes.join(" ");
        if moves || b.supa {
            line = self.motion_codes(&b, &values, line)?;
        }
        for (l, v) in &values {
            line.push_str(&format!(" {}{v}", *l as char));
        }
        let line = line.trim();
        if !line.is_empty() {
            out.push_str(line);
            out.push('\n');
        }
        if b.absolute_centre() {
            out.push_str("G91.1\n");
        }
        Some(b.ended)
    }

    /// The values of a block as RS274/NGC words: `IC`/`AC` from the current position (`#5420`..),
    /// the centre of a block with `I=AC(..)` counted from the program zero.
    fn render(&self, b: &Plain) -> Option<Vec<(u8, String)>> {
        let absolute_centre = b.absolute_centre();
        let mut out = Vec::with_capacity(b.values.len());
        for (l, v) in &b.values {
            let axis = b"XYZ".iter().position(|a| a == l);
            let centre = b"IJK".iter().position(|a| a == l);
            let text = match (v, axis, centre) {
                (Value::Number(n), ..) => n.clone(),
                (Value::Expr(e), ..) => expr(e)?,
                (Value::Ic(e), Some(k), _) if self.modes.absolute => format!("[#{}+{}]", 5420 + k, expr(e)?),
                (Value::Ac(e), Some(k), _) if !self.modes.absolute => format!("[{}-#{}]", expr(e)?, 5420 + k),
                (Value::Ic(e) | Value::Ac(e), _, _) => expr(e)?,
            };
            let text = match (centre, v) {
                (Some(k), Value::Number(_) | Value::Expr(_) | Value::Ic(_)) if absolute_centre => format!("[#{}+{text}]", 5420 + k),
                _ => text,
            };
            out.push((*l, text));
        }
        Some(out)
    }

    /// The codes of a block that moves: G90.1 for an absolute centre, G53 for SUPA, the motion mode.
    fn motion_codes(&self, b: &Plain, values: &[(u8, String)], mut line: String) -> Option<String> {
        let m = self.modes.motion;
        let centre = values.iter().any(|(l, _)| b"IJKR".contains(l));
        let relative = b.values.iter().any(|(_, v)| matches!(v, Value::Ic(_) | Value::Ac(_)));
        if centre != (m >= 2) || b.supa && (m >= 2 || self.modes.offset || relative) {
            return None;
        }
        if b.absolute_centre() {
            line.push_str(" G90.1");
        }
        if b.supa {
            line.push_str(" G53");
        }
        line.push_str(&format!(" G{m}"));
        Some(line)
    }

    /// A position block under `MCALL`: the hole as LinuxCNC's G98 G81/G82 when it starts at RTP
    /// (G98 retracts to where the hole starts) and RTP is not below R, else the position move and
    /// the cycle's moves.
    fn hole(&mut self, b: &Plain, values: &[(u8, String)], out: &mut String) -> Option<()> {
        let cycle = self.modes.mcall?;
        let xy = values.iter().all(|(l, _)| matches!(l, b'X' | b'Y' | b'F' | b'S'));
        if self.modes.motion != 0 || !xy || b.supa || !b.codes.iter().all(|c| c.starts_with('M')) {
            return None;
        }
        let mut words = b.codes.join(" ");
        for (l, v) in values {
            words.push_str(&format!(" {}{v}", *l as char));
        }
        let words = words.trim();
        self.labels += 1;
        let k = self.labels;
        let dwell = if cycle == 82 { " P#2014" } else { "" };
        out.push_str(&format!(
            "o<hole{k}> if [[ABS[#5422-#2011] LT 0.000001] AND [#2011 GE #2012]]\n\
             G98 G{cycle} {words} R#2012 Z#2013{dwell}\n\
             o<hole{k}> else\n\
             G0 {words}\n{}\
             o<hole{k}> endif\n",
            drill_moves(cycle)
        ));
        Some(())
    }

    /// `T`, `M6`, `D` of a block: the line before its other words.
    fn tools(&mut self, b: &Plain, out: &mut String) -> Option<()> {
        if let Some(t) = b.tool {
            self.modes.selected = Some(t);
        }
        if b.change {
            let t = self.modes.selected?;
            self.modes.spindle = Some(t);
            self.modes.offset = b.edge != Some(0);
            // the length on a line of its own: rs274 then keeps the machine where it is, as the
            // 840D does (with `T1 M6 G43 H1` on one line it re-reads the position as if the
            // machine had moved by the change of length)
            let length = if self.modes.offset { format!("G43 H{t}") } else { "G49".into() };
            out.push_str(&format!("T{t} M6\n{length}\n"));
            return Some(());
        }
        if let Some(t) = b.tool {
            out.push_str(&format!("T{t}\n"));
        }
        match (b.edge, self.modes.spindle) {
            (Some(0), _) => {
                self.modes.offset = false;
                out.push_str("G49\n");
            }
            (Some(_), Some(t)) => {
                self.modes.offset = true;
                out.push_str(&format!("G43 H{t}\n"));
            }
            _ => {}
        }
        Some(())
    }

    /// One word of a plain block into `b`.
    fn word(&mut self, w: &Word, b: &mut Plain, sub: bool) -> Option<()> {
        match w {
            Word::Assign(r, e) if r.starts_with('R') && r.len() > 1 => {
                let n: u32 = r[1..].parse().ok().filter(|&n| n < 1000)?;
                b.assignments.push((1000 + n, expr(e)?));
            }
            Word::Name(n) if n == "SUPA" => b.supa = true,
            w if inert(w) => {}
            Word::Letter(b'G', c) => self.g(c, b)?,
            Word::Letter(b'M', c) => self.m(c, b, sub)?,
            Word::Letter(b'T', t) => b.tool = Some(t.parse().ok()?),
            Word::Letter(b'D', d) => b.edge = Some(d.parse::<u32>().ok().filter(|&d| d <= 1)?),
            Word::Letter(b'F', f) if b.g4 => b.dwell = Some(f.clone()),
            Word::Assign(a, e) if b.g4 && a == "F" => b.dwell = Some(expr(e)?),
            Word::Letter(l, v) if b"XYZIJKFS".contains(l) => b.values.push((*l, Value::Number(v.clone()))),
            Word::Assign(a, e) if a == "CR" => b.values.push((b'R', Value::Expr(e.clone()))),
            Word::Assign(a, e) if a.len() == 1 && b"XYZIJKFS".contains(&a.as_bytes()[0]) => {
                let v = value_kind(e)?;
                if matches!(v, Value::Ic(_) | Value::Ac(_)) && !b"XYZIJK".contains(&a.as_bytes()[0]) {
                    return None;
                }
                b.values.push((a.as_bytes()[0], v));
            }
            _ => return None,
        }
        Some(())
    }

    /// A G code of a plain block (the 840D's names of units written as LinuxCNC's).
    fn g(&mut self, code: &str, b: &mut Plain) -> Option<()> {
        let c: u32 = code.parse().ok()?;
        let written = match c {
            0..=3 => {
                b.motion = Some(c as u8);
                None
            }
            4 => None,
            53 | 153 => {
                b.supa = true;
                None
            }
            9 | 60 | 64 | 450 | 451 | 601..=603 | 641 | 642 => None,
            70 | 71 | 700 | 710 if self.modes.framed => return None,
            70 | 700 => Some(20),
            71 | 710 => Some(21),
            17..=19 => {
                self.modes.xy_plane = c == 17;
                Some(c)
            }
            90 | 91 => {
                self.modes.absolute = c == 90;
                Some(c)
            }
            40 | 54..=57 | 94 | 95 | 97 => Some(c),
            _ => return None,
        };
        b.codes.extend(written.map(|c| format!("G{c}")));
        Some(())
    }

    fn m(&mut self, code: &str, b: &mut Plain, sub: bool) -> Option<()> {
        let c: u32 = code.parse().ok()?;
        match c {
            6 => b.change = true,
            0 | 1 | 3 | 4 | 5 | 7 | 8 | 9 => b.codes.push(format!("M{c}")),
            2 | 30 | 17 if sub => b.ended = true,
            2 | 30 => {
                b.codes.push(format!("M{c}"));
                b.ended = true;
            }
            _ => return None,
        }
        Some(())
    }
}

/// The words of a plain block as they are read.
#[derive(Default)]
struct Plain {
    assignments: Vec<(u32, String)>,
    /// G and M codes written as they are (units as G20/G21).
    codes: Vec<String>,
    motion: Option<u8>,
    values: Vec<(u8, Value)>,
    g4: bool,
    dwell: Option<String>,
    supa: bool,
    tool: Option<u32>,
    change: bool,
    edge: Option<u32>,
    ended: bool,
}

impl Plain {
    fn absolute_centre(&self) -> bool {
        self.values.iter().any(|(l, v)| b"IJK".contains(l) && matches!(v, Value::Ac(_)))
    }
}

/// A value as written: a number, `=expr`, `=IC(expr)`, `=AC(expr)`.
#[derive(Clone, Debug, PartialEq)]
enum Value {
    Number(String),
    Expr(String),
    Ic(String),
    Ac(String),
}

fn value_kind(e: &str) -> Option<Value> {
    for (name, kind) in [("IC(", Value::Ic as fn(String) -> Value), ("AC(", Value::Ac)] {
        if let Some(inner) = e.strip_prefix(name).and_then(|r| r.strip_suffix(')')) {
            // the parentheses must be the function's own: `IC(1)+(2)` is not one value
            return (closing(e, name.len() - 1)? == e.len() - 1).then(|| kind(inner.to_string()));
        }
    }
    Some(Value::Expr(e.to_string()))
}

/// Whether RS274/NGC text `v` reads parameter `#p`.
fn reads(v: &str, p: u32) -> bool {
    let key = format!("#{p}");
    v.match_indices(&key).any(|(i, _)| !v[i + key.len()..].starts_with(|c: char| c.is_ascii_digit()))
}

/// A value of `TRANS`/`ATRANS`: its axis and text (number or expression, no `IC`/`AC`).
fn axis_value(w: &Word) -> Option<(u8, String)> {
    match w {
        Word::Letter(l, v) => Some((*l, v.clone())),
        Word::Assign(a, e) if a.len() == 1 && matches!(value_kind(e)?, Value::Expr(_)) => Some((a.as_bytes()[0], e.clone())),
        _ => None,
    }
}

#[cfg(test)]
mod tests;
