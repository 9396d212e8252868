//! The two NC dialects: RS274/NGC as LinuxCNC 2.9 runs it, and the Fanuc dialect (Fanuc 0i/30i
//! series with Custom Macro B) as CAM post-processors write it; automatic detection, and the number
//! formats each controller reads.

use std::fmt;

/// An NC dialect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialect {
    /// RS274/NGC as LinuxCNC 2.9 runs it: O-word subroutines and control flow, numbered and named
    /// parameters, `;` comments.
    LinuxCnc,
    /// Fanuc: `%` tape delimiters, `O` program numbers, `M98`/`M99` subprograms, `G65` macro calls,
    /// Custom Macro B variables (`#1`-`#33`, `#100`+, `#500`+), `IF [...] GOTO`, `WHILE [...] DO`;
    /// a dimension word without a decimal point counts in least input increments.
    Fanuc,
}

impl Dialect {
    /// `linuxcnc` or `fanuc` (case-insensitive).
    pub fn parse(name: &str) -> Option<Dialect> {
        match name.to_ascii_lowercase().as_str() {
            "linuxcnc" | "rs274ngc" | "ngc" => Some(Dialect::LinuxCnc),
            "fanuc" => Some(Dialect::Fanuc),
            _ => None,
        }
    }

    /// The dialect a program is written in, from constructs only one of them has: a program
    /// number `O1234` on a line of its own, `M98`/`M99`/`G65` calls, `IF [...] GOTO`/`WHILE [...] DO`,
    /// `G28 G91`-style reference returns with `#500`-range variables, the ISO program number `:1234`,
    /// Haas's `G103`/`G154`/`G187` and `POPEN`/`DPRNT[...]` are Fanuc; O-words with
    /// `sub`/`call`/`if`..., named parameters `#<...>` and `;` comments are LinuxCNC. Without a sign
    /// of either, LinuxCNC (a plain G-code program means the same in both, apart from dimension
    /// words without a decimal point, which a Fanuc post never writes).
    pub fn detect(text: &str) -> Dialect {
        let (mut fanuc, mut linuxcnc) = (0usize, 0usize);
        for raw in text.lines().take(20_000) {
            // `;` followed by text is a LinuxCNC comment (on a line of its own too: `; Basic example`);
            // at the end of the line, a Fanuc end of block
            if text_after_semicolon(raw) {
                linuxcnc += 1;
            }
            let line = strip_comments(raw).to_ascii_uppercase();
            let compact: String = line.chars().filter(|c| !c.is_whitespace()).collect();
            if compact.is_empty() {
                continue;
            }
            if compact.contains("#<") {
                linuxcnc += 1;
            }
            let after_n = skip_sequence_number(&compact);
            if after_n.starts_with(':') || ["POPEN", "PCLOS", "DPRNT[", "BPRNT["].iter().any(|k| after_n.starts_with(k)) {
                fanuc += 1;
            }
            if let Some(rest) = after_n.strip_prefix('O') {
                let keyword = rest.trim_start_matches(|c: char| c.is_ascii_digit());
                if rest.starts_with('<') || O_KEYWORDS.iter().any(|k| keyword.starts_with(k)) {
                    linuxcnc += 1;
                } else if keyword.is_empty() && !rest.is_empty() {
                    fanuc += 1;
                }
            }
            if after_n.starts_with("IF[") && compact.contains("GOTO")
                || after_n.starts_with("GOTO")
                || after_n.starts_with("WHILE[") && compact.contains("DO")
                || after_n.starts_with("END") && after_n[3..].chars().next().is_some_and(|c| c.is_ascii_digit())
                || has_code(&compact, 'M', &[97, 98, 99])
                || has_code(&compact, 'G', &[65, 66, 103, 154, 187])
            {
                fanuc += 1;
            }
        }
        if fanuc > linuxcnc {
            Dialect::Fanuc
        } else {
            Dialect::LinuxCnc
        }
    }
}

impl fmt::Display for Dialect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Dialect::LinuxCnc => "linuxcnc",
            Dialect::Fanuc => "fanuc",
        })
    }
}

/// The keywords of LinuxCNC O-word statements.
const O_KEYWORDS: [&str; 15] = [
    "SUB",
    "ENDSUB",
    "CALL",
    "IF",
    "ELSEIF",
    "ELSE",
    "ENDIF",
    "WHILE",
    "ENDWHILE",
    "DO",
    "REPEAT",
    "ENDREPEAT",
    "BREAK",
    "CONTINUE",
    "RETURN",
];

/// The line without `( ... )` comments and without what follows `;`.
fn strip_comments(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut depth = 0;
    for c in line.chars() {
        match c {
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            ';' if depth == 0 => break,
            _ if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out
}

/// Whether the line has a `;` outside `( )` comments with more than blanks after it, other than
/// `( )` comments (`G54; (WORK OFFSET)`: a Fanuc's end of block and a comment after it, as Haas
/// programs are written at the machine).
fn text_after_semicolon(line: &str) -> bool {
    let mut depth = 0;
    for (i, c) in line.char_indices() {
        match c {
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            ';' if depth == 0 => return !strip_comments(&line[i + 1..]).trim().is_empty(),
            _ => {}
        }
    }
    false
}

fn skip_sequence_number(compact: &str) -> &str {
    let s = compact.trim_start_matches('/');
    match s.strip_prefix('N') {
        Some(rest) => rest.trim_start_matches(|c: char| c.is_ascii_digit() || c == '.'),
        None => s,
    }
}

/// Whether the upper-case, space-free line has the word `letter` with one of `codes` (`M98`,
/// `M098`), not inside a longer number.
fn has_code(compact: &str, letter: char, codes: &[u32]) -> bool {
    let bytes = compact.as_bytes();
    for (i, &b) in bytes.iter().enumerate() {
        if b as char != letter || i > 0 && bytes[i - 1].is_ascii_alphabetic() {
            continue;
        }
        let digits: String = compact[i + 1..].chars().take_while(|c| c.is_ascii_digit()).collect();
        if compact[i + 1 + digits.len()..].starts_with('.') {
            continue;
        }
        if let Ok(v) = digits.parse::<u32>() {
            if codes.contains(&v) {
                return true;
            }
        }
    }
    false
}

/// How numbers are written for a dialect: `decimals` digits after the point, trailing zeros
/// removed; Fanuc always keeps the decimal point of a dimension word (`X10.`), since without it the
/// control reads least input increments.
pub fn format_number(value: f64, decimals: usize, dialect: Dialect) -> String {
    let mut s = format!("{value:.decimals$}");
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') && dialect == Dialect::LinuxCnc {
            s.pop();
        }
    } else if dialect == Dialect::Fanuc {
        s.push('.');
    }
    if s == "-0" || s == "-0." {
        s.remove(0);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detection_and_number_formats() {
        let fanuc = "%\nO1001 (PART)\nN10 G90 G17 G40 G49 G80\nN20 T1 M06\nN30 G43 H1 Z50.\nM98 P2000\nM30\n%\n";
        assert_eq!(Dialect::detect(fanuc), Dialect::Fanuc);
        let macro_b = "O0001\n#1=0\nWHILE [#1 LT 3] DO 1\nG91 X10.\n#1=#1+1\nEND 1\nM30\n";
        assert_eq!(Dialect::detect(macro_b), Dialect::Fanuc);
        let ngc = "o100 sub\nG0 X#1\no100 endsub\no100 call [2]\nM2\n";
        assert_eq!(Dialect::detect(ngc), Dialect::LinuxCnc);
        assert_eq!(Dialect::detect("#<depth> = 2\nG1 Z-#<depth>\nM2\n"), Dialect::LinuxCnc);
        assert_eq!(Dialect::detect("G0 X1 Y2\nG1 Z-1 F100\nM2\n"), Dialect::LinuxCnc);
        assert_eq!(Dialect::detect("%\n:1001\nG187 P1\nG0 X1.\nM30\n%\n"), Dialect::Fanuc);
        // `;` ending every block (as a Fanuc punches them) is no LinuxCNC comment
        let eob = "%\nO6000 (SLOTS)\nG21 G90;\n#1 = 0;\nN10 IF [#1 GE 3] GOTO 20;\nG0 X1.;\nN20 M30;\n%\n";
        assert_eq!(Dialect::detect(eob), Dialect::Fanuc);
        assert_eq!(Dialect::detect("G21 ; mm\nG0 X1 ; rapid\nM2\n"), Dialect::LinuxCnc);
        // a Haas program typed at the machine: `;` ending each block, a comment after it
        let haas =
            "G20 G90 G17; (SAFE START)\nG54; (OFFSET)\nG00; (RAPID)\nX1. Y1.;\nM97 P1000 L2; (FACE)\nM30;\nN1000 G91 Z-0.1;\nG90 M99;\n";
        assert_eq!(Dialect::detect(haas), Dialect::Fanuc);
        assert_eq!(format_number(10.0, 4, Dialect::Fanuc), "10.");
        assert_eq!(format_number(10.0, 4, Dialect::LinuxCnc), "10");
        assert_eq!(format_number(-0.00001, 4, Dialect::Fanuc), "0.");
        assert_eq!(format_number(-1.23456, 3, Dialect::Fanuc), "-1.235");
        assert_eq!(format_number(0.5, 5, Dialect::LinuxCnc), "0.5");
    }
}
