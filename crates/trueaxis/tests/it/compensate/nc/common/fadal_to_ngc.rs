//! A Fadal format 2 program rewritten as the RS274/NGC program with the same moves, so that
//! LinuxCNC's rs274 reads Fadal programs too. Written from the Fadal VMC programming manual (NC
//! word summary: `E` fixture offsets, the R0 plane of the fixed cycles, `V`/`R` macro variables)
//! and the Autodesk post configuration for Fadal (`fadal.cps`: `E` numbers, `R0+5.000`), construct
//! by construct, without the library's reader; what is Fanuc in it is then rewritten by
//! [`super::fanuc_to_ngc::translate`]:
//!
//! - `E1`-`E6` become `G54`-`G59`, `E7`/`E8` `G59.1`/`G59.2` (the test gives their values to rs274
//!   at #5341.../#5361...), `E0` (none) `G59.3` (the tests leave #5381... at 0);
//! - the R plane `R0+5.000` / `R0-2.` becomes `R+5.000` / `R-2.`;
//! - `G94` (feed per minute, a Fadal's and LinuxCNC's default) is dropped: rs274 sets the feed to 0
//!   at every `G94` until the next `F` (a Fadal keeps it); `G93` (inverse time) is not rewritten;
//! - macro statements: `# V1 = ..` / `# R1 = ..` become `#301=[..]` / `#291=[..]` (`V`n is #(300+n),
//!   `R`n #(290+n), `( )` are `[ ]`, `SQR` is `SQRT`; EQ NE GT GE LT LE AND OR and ABS mean the same);
//!   a label `#:NAME` and the one `# IF c THEN GOTO :NAME` after it that jumps back to it become
//!   `o.. do` ... `o.. while [c]`; a `# IF c THEN GOTO :NAME` (or `# GOTO :NAME`) jumping forward
//!   to its label becomes `o.. if [[c] EQ 0]` ... `o.. endif`; `# PRINT`, `# CLEAR`, `# WAIT`
//!   become comments.
//!
//! `None` for what it does not rewrite: a label with more than one jump, jumps that cross, a
//! `GOTO` back without a condition (endless), other `E` numbers or macro statements.

use std::collections::HashMap;

/// The RS274/NGC text of a Fadal program, or `None`.
pub fn translate(text: &str) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out: Vec<String> = Vec::with_capacity(lines.len());
    // label -> line; jumps: (line, label, condition)
    let mut labels: HashMap<String, usize> = HashMap::new();
    let mut jumps: Vec<(usize, String, Option<String>)> = Vec::new();
    for (k, raw) in lines.iter().enumerate() {
        let code = raw.trim();
        let Some(statement) = code.strip_prefix('#') else {
            out.push(block(raw)?);
            continue;
        };
        let s = statement.trim().to_ascii_uppercase();
        if let Some(name) = s.strip_prefix(':') {
            if labels.insert(name.trim().to_string(), k).is_some() {
                return None;
            }
            out.push(String::new());
        } else if let Some(rest) = s.strip_prefix("IF") {
            let (cond, target) = rest.split_once("THEN")?;
            let label = target.trim().strip_prefix("GOTO")?.trim().strip_prefix(':')?.trim().to_string();
            jumps.push((k, label, Some(expression(cond)?)));
            out.push(String::new());
        } else if let Some(target) = s.strip_prefix("GOTO") {
            jumps.push((k, target.trim().strip_prefix(':')?.trim().to_string(), None));
            out.push(String::new());
        } else if ["PRINT", "CLEAR", "WAIT"].iter().any(|w| s.starts_with(w)) {
            out.push(format!("(FADAL {})", s.replace(['(', ')'], " ")));
        } else {
            let (target, value) = s.split_once('=')?;
            out.push(format!("#{}={}", variable(target.trim())?, expression(value)?));
        }
    }
    structure(&mut out, &labels, &jumps)?;
    // the Fanuc part; the O-word lines pass through it as comments
    let fanuc: String = out.iter().map(|l| format!("{l}\n")).collect();
    let ngc = super::fanuc_to_ngc::translate(&fanuc)?;
    Some(
        ngc.lines()
            .map(|l| match l.trim().strip_prefix("(OWORD ").and_then(|o| o.strip_suffix(')')) {
                Some(o) => format!("{o}\n"),
                None => format!("{l}\n"),
            })
            .collect(),
    )
}

/// Jumps and their labels as O-word loops and branches, written (as comments `(OWORD ..)`) on
/// the lines of the labels and jumps; `None` when they do not nest.
fn structure(out: &mut [String], labels: &HashMap<String, usize>, jumps: &[(usize, String, Option<String>)]) -> Option<()> {
    let mut spans: Vec<(usize, usize)> = Vec::new();
    let mut used = std::collections::HashSet::new();
    for (n, (at, label, cond)) in jumps.iter().enumerate() {
        let target = *labels.get(label)?;
        if !used.insert(target) {
            return None;
        }
        let o = 100 + n;
        let (first, last) = if target < *at {
            // back to the label: a do-while loop
            let cond = cond.clone()?;
            out[target] = format!("(OWORD o{o} do)");
            out[*at] = format!("(OWORD o{o} while {cond})");
            (target, *at)
        } else {
            let cond = cond.clone().unwrap_or_else(|| "[1]".into());
            out[*at] = format!("(OWORD o{o} if [{cond} EQ 0])");
            out[target] = format!("(OWORD o{o} endif)");
            (*at, target)
        };
        if spans.iter().any(|&(a, b)| (a < first && first < b && b < last) || (first < a && a < last && last < b)) {
            return None;
        }
        spans.push((first, last));
    }
    Some(())
}

/// A Fadal block with its `E` word and `R0` plane in Fanuc's words.
fn block(raw: &str) -> Option<String> {
    let b = raw.as_bytes();
    let mut out = String::new();
    let mut depth = 0;
    let mut i = 0;
    while i < b.len() {
        let c = b[i].to_ascii_uppercase();
        let word_start = i == 0 || !b[i - 1].is_ascii_alphabetic();
        match c {
            b'(' => depth += 1,
            b')' => depth -= 1,
            _ => {}
        }
        if depth == 0 && word_start && c == b'E' {
            let digits: String = raw[i + 1..].chars().take_while(char::is_ascii_digit).collect();
            let systems = ["G59.3", "G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2"];
            out.push_str(systems.get(digits.parse::<usize>().ok()?)?);
            i += 1 + digits.len();
            continue;
        }
        if depth == 0 && word_start && c == b'G' && raw[i + 1..].starts_with("94") && !raw[i + 1..].starts_with("94.") {
            // feed per minute, the only feed mode these programs use (G93 is refused below)
            i += 3;
            continue;
        }
        if depth == 0 && word_start && c == b'G' && raw[i + 1..].starts_with("93") {
            return None;
        }
        if depth == 0 && word_start && c == b'R' && b.get(i + 1) == Some(&b'0') && matches!(b.get(i + 2), Some(b'+' | b'-')) {
            out.push('R');
            i += 2;
            continue;
        }
        out.push(b[i] as char);
        i += 1;
    }
    Some(out)
}

/// The parameter of a Fadal variable name (`V1` -> 301, `R1` -> 291).
fn variable(name: &str) -> Option<u32> {
    let n: u32 = name.get(1..)?.parse().ok()?;
    match name.as_bytes().first()? {
        b'V' if (1..=100).contains(&n) => Some(300 + n),
        b'R' if n < 10 => Some(290 + n),
        _ => None,
    }
}

/// A Fadal expression (upper case) in RS274/NGC, bracketed.
fn expression(text: &str) -> Option<String> {
    let b = text.trim().as_bytes();
    let mut out = String::from("[");
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_alphabetic() {
            let start = i;
            while i < b.len() && b[i].is_ascii_alphanumeric() {
                i += 1;
            }
            let name = std::str::from_utf8(&b[start..i]).ok()?;
            match name {
                "EQ" | "NE" | "GT" | "GE" | "LT" | "LE" | "AND" | "OR" | "ABS" => out.push_str(name),
                "SQR" => out.push_str("SQRT"),
                v => out.push_str(&format!("#{}", variable(v)?)),
            }
            continue;
        }
        out.push(match c {
            b'(' => '[',
            b')' => ']',
            c => c as char,
        });
        i += 1;
    }
    out.push(']');
    Some(out)
}

#[test]
fn fadal_constructs_in_rs274ngc() {
    let text = "%\nO1 (T)\nG90 G0 E1 X1.\nE7\nE0 G0 Z-5.\nG81 Z-3. R0+2.5 F100. (R0+1 IN A COMMENT)\n# V1 = (2 + V1) * 3\n#:LOOP\n# V2 = SQR(V1) + R1\n# IF V2 LT 10 AND V1 GT 0 THEN GOTO :LOOP\n# IF V1 EQ 0 THEN GOTO :SKIP\n# PRINT \"HI (X)\"\n#:SKIP\nM30\n%\n";
    let ngc = translate(text).unwrap();
    for expected in [
        "G54 X1.",
        "G59.1",
        "G59.3 G0 Z-5.",
        "R+2.5 F100. (R0+1 IN A COMMENT)",
        "#301=[[[2+#301]*3]]",
        "o100 do",
        "#302=[[SQRT[#301]+#291]]",
        "o100 while [#302 LT 10 AND #301 GT 0]",
        "o101 if [[#301 EQ 0] EQ 0]",
        "(FADAL PRINT \"HI  X \")",
        "o101 endif",
    ] {
        assert!(ngc.contains(expected), "`{expected}` in\n{ngc}");
    }
    // jumps that cross, a label with two jumps, an endless loop, an unknown E number
    assert!(translate("#:A\n# IF V1 GT 0 THEN GOTO :B\n# IF V1 GT 0 THEN GOTO :A\n#:B\nM30\n").is_none());
    assert!(translate("#:A\n# IF V1 GT 0 THEN GOTO :A\n# IF V1 GT 1 THEN GOTO :A\nM30\n").is_none());
    assert!(translate("#:A\nG0 X1.\n# GOTO :A\nM30\n").is_none());
    assert!(translate("G0 E9 X1.\nM30\n").is_none());
    assert!(translate("G93 G1 X1. F2.\nM30\n").is_none());
    assert_eq!(translate("G17 G94 G3 X1. Y1. I1. J0.\n").unwrap(), "G98 (a Fanuc starts in G98)\nG17 G3 X1. Y1. I1. J0.\n");
}
