//! A program of the Fanuc family (Fanuc 0i/30i, Haas, Fadal format 2) rewritten as the RS274/NGC
//! program with the same moves, so that LinuxCNC's rs274 is the independent reader of the landing
//! check for these dialects too. Written from the Fanuc 0i-MF operator's manual (B-64604EN: program
//! format, G code groups, canned cycles, Custom Macro B) and the Haas mill operator's manual (NGC:
//! G103, G154, G187, `DPRNT`), construct by construct, without the library's reader:
//!
//! - `%` lines stay; the program number (`O1234`, ISO `:1234`) becomes a comment; the end of block
//!   `;` is dropped;
//! - a dimension word without a decimal point counts in least input increments (IS-B: 0.001 mm,
//!   0.0001 inch): written out as its value;
//! - a Fanuc starts in G00 and in G98 (rs274: no motion mode, G99): `G98` is put first;
//! - canned cycles are group 09, G00-G03 group 01: axis words after `G80` (or before any motion
//!   code) move in the group-01 mode, written out on such a line;
//! - a G00-G03 on a line without axis words (or beside `G28`) only sets the mode (rs274 would move
//!   to where it is): it is written on the next line with axis words, as every line with axis words
//!   and no motion code outside a cycle gets it;
//! - `G80` beside a G00-G03 is dropped (rs274 would run that code as a move without axis words);
//! - Haas's `G103` (look-ahead), `G187` (smoothness), `POPEN`, `PCLOS`, `DPRNT[...]` move nothing:
//!   comments; `M29` (rigid tapping mode) is dropped (rs274's `G84` makes the same moves);
//!   `G154 P1` becomes `G59.3` (the tests give no work offsets: both zero);
//! - a Fanuc applies a tool length offset by moving (`G43`, `G44`, `G49` without a Z word): its
//!   program Z stays until the next move, which goes there with the new offset, where LinuxCNC
//!   keeps the machine where it is and counts the program Z anew: the program Z is saved around
//!   such a line (`#<_fanuc_z>=#5422`, then the shift `#<_fanuc_dz>=[#<_fanuc_z>-#5422]`) and the
//!   next move gets it back (`Z[#5422+#<_fanuc_dz>]` in G90, its Z increment plus
//!   `#<_fanuc_dz>` in G91); such a line that moves itself is not rewritten;
//! - `WHILE [...] DOn` / `ENDn` become `o(100+n) while [...]` / `o(100+n) endwhile`; `#i = ...`,
//!   `[ ]` expressions, `SIN`/`COS` in degrees and `LT`/`GE` mean the same in both languages (an
//!   assigned expression is bracketed, as RS274/NGC asks).
//!
//! A program with what it does not rewrite (`M98`, Haas `M97`, `G65`, `IF`, `GOTO`, `M99`) gives `None`, and
//! so does tapping (`G74`, `G84`): a Fanuc feeds out to R and then, in G98, rapids up to the
//! initial level, where LinuxCNC's G84 feeds out to the clear level in one move.

/// A Mach3/Mach4 program with subprograms (its blocks RS274/NGC, its subprograms the Fanuc way:
/// "Using Mach3Mill", 10.7) rewritten with LinuxCNC O-word subroutines, as the LinuxCNC 2.9 manual
/// ("O Codes") writes them: each `O1234` ... `M99` after the main program's `M30` becomes `o1234
/// sub` ... `o1234 endsub`, moved before the main program (rs274 knows a subroutine once its
/// definition has been read); `M98 P1234` becomes `o1234 call`, and with `L n` a call inside `o<..>
/// repeat [n]`. A program without `M98` is given back as it is; `None` when a call has words
/// beside `P` and `L`, or `M99` has a `P`. (Mach3's subprograms share the parameters of the main
/// program and LinuxCNC's do not: the programs rewritten here use none.)
pub fn mach_to_ngc(text: &str) -> Option<String> {
    let upper = |l: &str| split(l).0.to_ascii_uppercase().replace([' ', '\t'], "");
    if !text.lines().any(|l| upper(l).contains("M98")) {
        return Some(text.to_string());
    }
    let (mut head, mut subs, mut main, mut tail) = (String::new(), String::new(), String::new(), String::new());
    let (mut ended, mut inside, mut repeats) = (false, false, 0);
    for (k, raw) in text.lines().enumerate() {
        let code = upper(raw);
        let number = code.strip_prefix('O').filter(|n| !n.is_empty() && n.bytes().all(|c| c.is_ascii_digit()));
        let out = if k == 0 && code == "%" {
            head.push_str("%\n");
            continue;
        } else if let Some(n) = number.filter(|_| ended) {
            inside = true;
            subs.push_str(&format!("o{} sub\n", n.parse::<u32>().ok()?));
            continue;
        } else if inside && code.contains("M99") {
            if code != "M99" {
                return None;
            }
            inside = false;
            let label = subs.lines().rev().find(|l| l.ends_with(" sub"))?.trim_end_matches(" sub").to_string();
            subs.push_str(&format!("{label} endsub\n"));
            continue;
        } else if inside {
            &mut subs
        } else if ended {
            &mut tail
        } else {
            &mut main
        };
        if let Some(call) = code.strip_prefix("M98") {
            let words = words(call)?;
            let value = |l: u8| words.iter().find(|(c, _)| *c == l).and_then(|(_, v)| v.parse::<f64>().ok());
            if words.iter().any(|(l, _)| !matches!(l, b'P' | b'L')) {
                return None;
            }
            let (p, l) = (value(b'P')? as u32, value(b'L').unwrap_or(1.0) as u32);
            repeats += 1;
            out.push_str(&format!("o<rep{repeats}> repeat [{l}]\no{p} call\no<rep{repeats}> endrepeat\n"));
        } else {
            out.push_str(raw);
            out.push('\n');
        }
        let program_end = |(l, v): &(u8, String)| *l == b'M' && matches!(v.parse::<f64>(), Ok(c) if c == 2.0 || c == 30.0);
        ended |= !inside && words(&code).is_some_and(|w| w.iter().any(program_end));
    }
    Some(head + &subs + &main + &tail)
}

/// A grbl stream with system commands (grbl wiki, "Grbl v1.1 Commands" and "Grbl v1.1 Jogging")
/// rewritten as RS274/NGC for a program in `G90 G21` (the corpus writes them so): a jog `$J=<words>`
/// becomes `G1 <words>` followed by `G90 G21` (a jog's distance mode and units hold for the jog
/// only; its feed does not change the positions); any other `$` line becomes a comment. `None`
/// when the program leaves `G90 G21`.
pub fn grbl_to_ngc(text: &str) -> Option<String> {
    let mut out = String::new();
    for raw in text.lines() {
        let code = raw.trim();
        let upper = code.to_ascii_uppercase();
        if ["G91", "G20"].iter().any(|k| upper.contains(k)) && !upper.starts_with("$J=") {
            return None;
        }
        if let Some(words) = upper.strip_prefix("$J=") {
            out.push_str(&format!("G1 {words}\nG90 G21\n"));
        } else if upper.starts_with('$') {
            out.push_str(&format!("(grbl {code})\n"));
        } else {
            out.push_str(raw);
            out.push('\n');
        }
    }
    Some(out)
}

/// The RS274/NGC text of a Fanuc-family program, or `None`.
pub fn translate(text: &str) -> Option<String> {
    let mut t = Translator { inch: false, group01: "G0", cycle: false, out: String::new(), first: true, incremental: false, held_z: false };
    for raw in text.lines() {
        t.line(raw)?;
    }
    Some(t.out)
}

struct Translator {
    inch: bool,
    /// The last of G0-G3, and whether a canned cycle is in force (axis words then make a hole).
    group01: &'static str,
    cycle: bool,
    out: String,
    first: bool,
    /// G91, and a tool length offset changed without a move (the program Z held since).
    incremental: bool,
    held_z: bool,
}

/// Letters of dimension words (counted in increments without a decimal point).
const DIMENSIONS: &[u8] = b"XYZIJKRQ";

impl Translator {
    fn line(&mut self, raw: &str) -> Option<()> {
        let line = raw.trim_end().trim_end_matches(';').trim_end();
        if line.trim() == "%" {
            self.out.push_str("%\n");
            return Some(());
        }
        if self.first {
            self.out.push_str("G98 (a Fanuc starts in G98)\n");
            self.first = false;
        }
        let (code, comments) = split(line);
        let upper = code.to_ascii_uppercase();
        let body = upper.trim_start_matches(|c: char| c == 'N' || c.is_ascii_digit() || c == ' ');
        let number = &upper[..upper.len() - body.len()];
        if body.starts_with('O') || body.starts_with(':') || ["POPEN", "PCLOS", "DPRNT", "BPRNT"].iter().any(|k| body.starts_with(k)) {
            return self.emit(&format!("{number}({})", body.replace(['(', ')'], " ")), &comments);
        }
        if let Some(rest) = body.strip_prefix("WHILE") {
            let (cond, n) = rest.rsplit_once("DO")?;
            return self.emit(&format!("o{} while {}", 100 + n.trim().parse::<u32>().ok()?, cond.trim()), &comments);
        }
        if let Some(n) = body.strip_prefix("END").and_then(|n| n.trim().parse::<u32>().ok()) {
            return self.emit(&format!("o{} endwhile", 100 + n), &comments);
        }
        if ["IF", "GOTO", "M97", "M98", "M99", "G65"].iter().any(|k| body.contains(k)) {
            return None;
        }
        let words = words(body)?;
        self.block(number, &words, &comments)
    }

    fn block(&mut self, number: &str, words: &[(u8, String)], comments: &str) -> Option<()> {
        let g: Vec<f64> = words.iter().filter(|(l, _)| *l == b'G').filter_map(|(_, v)| v.parse().ok()).collect();
        if g.iter().any(|&c| c == 103.0 || c == 187.0) {
            return self.emit(&format!("{number}(HAAS {})", join(words)), comments);
        }
        self.inch = if g.contains(&20.0) { true } else { self.inch && !g.contains(&21.0) };
        let moving_code = g.iter().any(|c| [0.0, 1.0, 2.0, 3.0].contains(c));
        let axis_words = words.iter().any(|(l, _)| b"XYZABC".contains(l));
        let mut out: Vec<(u8, String)> = Vec::new();
        let mut motion = None;
        for (l, v) in words {
            match (*l, v.as_str()) {
                (b'M', "29") => continue,
                (b'G', "154") => out.push((b'G', "59.3".into())),
                (b'P', _) if g.contains(&154.0) => continue,
                (b'G', c) => {
                    let c: f64 = c.parse().ok()?;
                    if [0.0, 1.0, 2.0, 3.0].contains(&c) {
                        motion = Some(["G0", "G1", "G2", "G3"][c as usize]);
                    } else if c == 80.0 {
                        self.cycle = false;
                    } else if c == 74.0 || c == 84.0 {
                        return None;
                    } else if c == 73.0 || c == 76.0 || (81.0..=89.0).contains(&c) {
                        self.cycle = true;
                        motion = None;
                    }
                    let mode_only = [0.0, 1.0, 2.0, 3.0].contains(&c) && (g.contains(&28.0) || !axis_words);
                    if !(mode_only || c == 80.0 && moving_code) {
                        out.push((b'G', v.clone()));
                    }
                }
                (l, v) if DIMENSIONS.contains(&l) && !v.contains('.') && v.parse::<i64>().is_ok() => {
                    let increment = if self.inch { 1e-4 } else { 1e-3 };
                    out.push((l, format!("{}", v.parse::<i64>().ok()? as f64 * increment)));
                }
                _ => out.push((*l, v.clone())),
            }
        }
        if let Some(m) = motion {
            self.group01 = m;
            self.cycle = false;
            if !axis_words || g.contains(&28.0) {
                motion = None;
            }
        }
        let axes = out.iter().any(|(l, _)| b"XYZABC".contains(l));
        let uses_axes = g.iter().any(|c| [10.0, 28.0, 30.0, 52.0, 92.0].contains(c));
        self.incremental = if g.contains(&91.0) { true } else { self.incremental && !g.contains(&90.0) };
        let moves = axes && !self.cycle && !uses_axes;
        let holds = self.holds_tool_z(&g, &out, moves)?;
        self.give_held_z(&mut out, moves);
        let mut text = String::from(number);
        // every such line, not only the first after G80: inside a loop the text's order is not
        // the order of execution (rs274 takes the repeated code as it is)
        if axes && motion.is_none() && !self.cycle && !uses_axes {
            text.push_str(self.group01);
            text.push(' ');
        }
        text.push_str(&join(&out));
        self.emit(&text, comments)?;
        if holds {
            self.held_z = true;
            self.out.push_str("#<_fanuc_dz>=[#<_fanuc_z>-#5422]\n");
        }
        Some(())
    }

    /// A Fanuc's tool length offset applied by moving: whether this line changes it without a Z
    /// word (in G91: with one), the program Z then saved before it; `None` when the line also moves.
    fn holds_tool_z(&mut self, g: &[f64], out: &[(u8, String)], moves: bool) -> Option<bool> {
        let z = out.iter().any(|(l, _)| *l == b'Z');
        // a `G28`/`G30` moves with the new offset at once
        let home = g.contains(&28.0) || g.contains(&30.0);
        self.held_z &= !home;
        let holds = g.iter().any(|c| [43.0, 44.0, 49.0].contains(c)) && (!z || self.incremental) && !home;
        if holds && moves {
            return None;
        }
        if holds && !self.held_z {
            self.out.push_str("#<_fanuc_z>=#5422 (a Fanuc keeps its program Z until the next move)\n");
        }
        Some(holds)
    }

    /// The next move after the tool length offset changed without a move: its Z the one held.
    fn give_held_z(&mut self, out: &mut Vec<(u8, String)>, moves: bool) {
        if !(self.held_z && moves) {
            return;
        }
        self.held_z = false;
        let z = out.iter().position(|(l, _)| *l == b'Z');
        let value = match (z, self.incremental) {
            (Some(_), false) => return,
            (None, false) => "[#5422+#<_fanuc_dz>]".to_string(),
            (None, true) => "#<_fanuc_dz>".to_string(),
            (Some(i), true) => format!("[{}+#<_fanuc_dz>]", out[i].1),
        };
        match z {
            Some(i) => out[i].1 = value,
            None => out.push((b'Z', value)),
        }
    }

    fn emit(&mut self, code: &str, comments: &str) -> Option<()> {
        self.out.push_str(code.trim_end());
        if !comments.is_empty() {
            self.out.push(' ');
            self.out.push_str(comments);
        }
        self.out.push('\n');
        Some(())
    }
}

fn join(words: &[(u8, String)]) -> String {
    words.iter().map(|(l, v)| format!("{}{v}", *l as char)).collect::<Vec<_>>().join(" ")
}

/// The code of a line and its `( )` comments (kept in order at its end).
fn split(line: &str) -> (String, String) {
    let (mut code, mut comments, mut depth) = (String::new(), String::new(), 0);
    for c in line.chars() {
        match c {
            '(' => {
                depth += 1;
                comments.push(c);
            }
            ')' if depth > 0 => {
                depth -= 1;
                comments.push(c);
            }
            _ if depth > 0 => comments.push(c),
            _ => code.push(c),
        }
    }
    (code, comments)
}

/// The words of an upper-case block: a letter and its value text (a number, `#n`, `[...]`, with a
/// sign), or `#i = ...` assignments kept whole (under the letter `#`).
fn words(body: &str) -> Option<Vec<(u8, String)>> {
    let b: Vec<u8> = body.bytes().filter(|c| *c != b' ' && *c != b'\t').collect();
    if b.first() == Some(&b'#') {
        // RS274/NGC takes an expression as a value in brackets only; a line may hold several
        // assignments (`#1=2 #3=4`), each starting at a `#` outside brackets after a value
        let text = String::from_utf8(b[1..].to_vec()).ok()?;
        let mut out = Vec::new();
        for one in assignments(&text) {
            let (target, value) = one.split_once('=')?;
            out.push((b'#', format!("{target}=[{value}]")));
        }
        return Some(out);
    }
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let letter = b[i];
        if !letter.is_ascii_alphabetic() {
            return None;
        }
        i += 1;
        let start = i;
        let mut depth = 0;
        while i < b.len() && (depth > 0 || !b[i].is_ascii_alphabetic() || i == start) {
            match b[i] {
                b'[' => depth += 1,
                b']' => depth -= 1,
                c if c.is_ascii_alphabetic() && depth == 0 => break,
                _ => {}
            }
            i += 1;
        }
        out.push((letter, String::from_utf8(b[start..i].to_vec()).ok()?));
    }
    Some(out)
}

/// `1=2#3=[#1+4]` (after the first `#`) split into `1=2` and `3=[#1+4]`.
fn assignments(text: &str) -> Vec<&str> {
    let (mut parts, mut start, mut depth, mut seen_eq) = (Vec::new(), 0, 0, false);
    for (i, c) in text.char_indices() {
        match c {
            '[' => depth += 1,
            ']' => depth -= 1,
            '=' if depth == 0 => seen_eq = true,
            '#' if depth == 0 && seen_eq && text[start..i].ends_with(|p: char| p.is_ascii_digit() || p == '.' || p == ']') => {
                // `#` right after a value: the next assignment (a `#` read as a value follows `=` or an operator)
                let rest = &text[i + 1..];
                let digits = rest.chars().take_while(char::is_ascii_digit).count();
                if rest[digits..].starts_with('=') {
                    parts.push(&text[start..i]);
                    start = i + 1;
                    seen_eq = false;
                }
            }
            _ => {}
        }
    }
    parts.push(&text[start..]);
    parts
}
