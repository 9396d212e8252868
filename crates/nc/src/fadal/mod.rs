//! Fadal format 2 (Fadal VMC programming manual, "Section 1: Summary", NC word summary; the
//! Autodesk post configuration `fadal.cps` for what a CAM post writes): Fanuc-compatible blocks,
//! read by the Fanuc lexer, with what a Fadal adds:
//!
//! - `E1`-`E48` select a fixture offset (`E1`-`E6` are the offsets `G54`-`G59` select), `E0`
//!   cancels it (machine coordinates): [`fixture`];
//! - the R plane of a canned cycle written `R0+5.000` / `R0-2.000` (the R0 word with a signed
//!   value), read as the Fanuc R level and written back so ([`write`]);
//! - macro statements, one a line after `#` ([`macros`]): `# V1 = ..`, `# R1 = ..`,
//!   `# IF .. THEN GOTO :LABEL`, `# GOTO :LABEL`, `#:LABEL`, `# PRINT`, `# CLEAR`, `# WAIT`.
//!
//! The macro variables are kept as numbered Fanuc variables: `V1`-`V100` as `#301`-`#400`, `R0`-`R9`
//! as `#290`-`#299` (a Fadal program has no `#` variables of its own); both start at 0. A label is
//! kept as the sequence number [`label_number`] of its line, so that `GOTO` runs on the Fanuc
//! machinery (a jump backwards expands the whole program, as a Fanuc `GOTO` does).

pub mod fixture;
pub mod macros;
pub mod write;

use crate::dialect::Dialect;
use crate::expr::Node;
use crate::lexer::Line;

/// The Fanuc variable that holds `V1` is `V_BASE + 1`.
pub const V_BASE: u32 = 300;
/// Macro variables read: `V1`-`V100`.
pub const V_COUNT: u32 = 100;
/// The Fanuc variable that holds `R0`.
pub const R_BASE: u32 = 290;
/// R parameters read: `R0`-`R9`.
pub const R_COUNT: u32 = 10;
/// Sequence numbers from here on stand for labels (a Fanuc `N` number has at most 5 digits).
pub const LABEL_BASE: u32 = 1 << 31;

/// The sequence number that stands for label `name` (upper case): a hash above [`LABEL_BASE`]
/// (two labels with the same number are told apart by their text when a jump is made).
pub fn label_number(name: &str) -> u32 {
    let mut h: u32 = 0x811c_9dc5;
    for b in name.bytes() {
        h = (h ^ u32::from(b.to_ascii_uppercase())).wrapping_mul(0x0100_0193);
    }
    LABEL_BASE | (h & (LABEL_BASE - 1))
}

/// The label a jump line names (`# IF .. THEN GOTO :LOOP` -> `LOOP`) or a label line defines
/// (`#:LOOP` -> `LOOP`), upper case.
pub fn label_of(text: &str) -> Option<String> {
    let code = text.split('(').next().unwrap_or("");
    let at = code.rfind(':')?;
    let name: String = code[at + 1..].trim().to_ascii_uppercase();
    (!name.is_empty() && name.bytes().all(|c| c.is_ascii_alphanumeric() || c == b'_')).then_some(name)
}

/// The macro variables at the start of a run: `V1`-`V100` and `R0`-`R9` at 0 (a Fadal has no vacant
/// value; what a program reads before it writes is the machine's and not known here).
pub(crate) fn start(params: &mut crate::params::Params) {
    for n in (V_BASE + 1..=V_BASE + V_COUNT).chain(R_BASE..R_BASE + R_COUNT) {
        params.set_numbered(n, 0.0).expect("a Fanuc common variable");
    }
}

/// The line a `GOTO :NAME` on line `k` of `file` jumps to, sequence number `n` standing for the
/// label: the line `#:NAME` of the same name.
pub(crate) fn jump(file: &crate::program::SourceFile, k: usize, n: u32) -> Result<usize, String> {
    let name = label_of(file.line_text(k)).unwrap_or_default();
    file.sequence
        .get(&n)
        .and_then(|lines| lines.iter().copied().find(|&t| label_of(file.line_text(t)).as_deref() == Some(name.as_str())))
        .ok_or_else(|| format!("GOTO :{name}: no label `#:{name}` in this program"))
}

/// Reads one Fadal line: a macro statement after `#`, else a Fanuc block with the `R0+` form of
/// the R plane and the refusals of what is not read.
pub(crate) fn parse_line(text: &str, number: usize, dialect: Dialect, arena: &mut Vec<Node>, bytewise: bool) -> Result<Line, String> {
    if let Some(at) = macro_start(text) {
        return macros::parse(text, at, number, arena);
    }
    check_block(text)?;
    let read = r0_as_word(text);
    crate::lexer::parse_line(&read, number, dialect, arena, bytewise)
}

/// Where a macro statement starts (its `#`), after blanks and an `N` number.
fn macro_start(text: &str) -> Option<usize> {
    let s = text.as_bytes();
    let mut i = 0;
    let skip = |i: &mut usize| {
        while *i < s.len() && matches!(s[*i], b' ' | b'\t') {
            *i += 1;
        }
    };
    skip(&mut i);
    if i < s.len() && s[i].eq_ignore_ascii_case(&b'N') {
        i += 1;
        while i < s.len() && s[i].is_ascii_digit() {
            i += 1;
        }
        skip(&mut i);
    }
    (s.get(i) == Some(&b'#')).then_some(i)
}

/// The code of a line: its text with comments blanked (same length).
fn code_of(text: &str) -> Vec<u8> {
    let mut depth = 0;
    text.bytes()
        .map(|c| match c {
            b'(' => {
                depth += 1;
                b' '
            }
            b')' if depth > 0 => {
                depth -= 1;
                b' '
            }
            _ if depth > 0 => b' ',
            c => c.to_ascii_uppercase(),
        })
        .collect()
}

/// Refuses, with the reason, what a Fadal reads and this reader does not: R parameters in words
/// (`X+R1`, `R1+1.`) and subroutines (`L0100` ... `M17`, called `L0102`).
fn check_block(text: &str) -> Result<(), String> {
    let code = code_of(text);
    for (i, &c) in code.iter().enumerate() {
        let next = |k: usize| code.get(i + k).copied().unwrap_or(0);
        let signed = matches!(next(1), b'+' | b'-');
        let r_at = if signed { 2 } else { 1 };
        if c.is_ascii_uppercase() && c != b'R' && next(r_at) == b'R' && next(r_at + 1).is_ascii_digit() {
            let word: String = code[i..(i + r_at + 2).min(code.len())].iter().map(|&b| b as char).collect();
            return Err(format!(
                "`{word}`: R parameters in words are not read yet (their form is not confirmed here): set the value with a macro statement"
            ));
        }
    }
    // `R1+1.` (a fixed subroutine's parameter, `L9101 R1+1.`): R1 set to +1
    if let Some(i) = (0..code.len().saturating_sub(2)).find(|&i| {
        (i == 0 || !code[i - 1].is_ascii_uppercase())
            && code[i] == b'R'
            && (b'1'..=b'9').contains(&code[i + 1])
            && matches!(code[i + 2], b'+' | b'-')
    }) {
        let word: String = code[i..].iter().take_while(|c| !matches!(c, b' ')).map(|&b| b as char).collect();
        return Err(format!(
            "`{word}` sets the R parameter R{} (a Fadal subroutine's parameter): not read yet; write it as `# R{} = ..`",
            code[i + 1] as char,
            code[i + 1] as char
        ));
    }
    let has = |letter: u8| code.iter().enumerate().any(|(i, &c)| c == letter && (i == 0 || !code[i - 1].is_ascii_uppercase()));
    if has(b'L') && !has(b'G') && !has(b'M') {
        return Err("L words alone (Fadal subroutines: a definition `L0100` ... `M17`, a call `L0102`) are not read yet: write the subroutine as an O program called by M98".into());
    }
    Ok(())
}

/// `text` with the R plane's `R0+5.000` written `R +5.000` (same length), which the Fanuc lexer
/// reads as the R word `+5.000`.
fn r0_as_word(text: &str) -> String {
    let code = code_of(text);
    let mut out = text.as_bytes().to_vec();
    for i in 0..code.len().saturating_sub(2) {
        let word_start = i == 0 || !code[i - 1].is_ascii_uppercase();
        if word_start && code[i] == b'R' && code[i + 1] == b'0' && matches!(code[i + 2], b'+' | b'-') {
            out[i + 1] = b' ';
        }
    }
    String::from_utf8(out).expect("an ASCII digit replaced by a blank")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Line, String> {
        parse_line(text, 1, Dialect::Fanuc, &mut Vec::new(), false)
    }

    #[test]
    fn r0_plane_and_refusals() {
        let l = read("N60 G98 G90 G81 X10. Y5. Z-3. R0+5.000 F200.").unwrap();
        let r = l.word(b'R').unwrap();
        assert_eq!(r.value, crate::lexer::Operand::Number(5.0));
        assert_eq!(&"N60 G98 G90 G81 X10. Y5. Z-3. R0+5.000 F200."[r.span.clone()], "+5.000");
        assert_eq!(read("G81 Z-3. R0-2.5").unwrap().word(b'R').unwrap().value, crate::lexer::Operand::Number(-2.5));
        assert_eq!(read("G2 X1. Y1. R5.").unwrap().word(b'R').unwrap().value, crate::lexer::Operand::Number(5.0));
        assert!(read("G1 X+R1 F100.").unwrap_err().contains("`X+R1`: R parameters in words"));
        assert!(read("L0102").unwrap_err().contains("Fadal subroutines"));
        assert!(read("L9101 R1+1.").unwrap_err().contains("`R1+1.` sets the R parameter R1"));
        assert!(read("G0 X1. (R1 L0100 IN A COMMENT)").is_ok());
        assert_eq!(label_of("# IF V1 GT 3 THEN GOTO :LOOP2"), Some("LOOP2".into()));
        assert_eq!(label_of("#:LOOP2"), Some("LOOP2".into()));
        assert_ne!(label_number("A"), label_number("B"));
        assert!(label_number("LOOP") >= LABEL_BASE);
        assert_eq!(label_number("loop"), label_number("LOOP"));
    }
}
