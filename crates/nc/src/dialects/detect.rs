//! Which controller a program was written for: its family from [`Dialect::detect`], then codes
//! only one controller of that family has, then a controller named in a comment (a post's
//! header, `(POST: HAAS VF2)`). Siemens's native language is told by its own constructs first.
//!
//! - Siemens 840D: `CYCLE81(`...`CYCLE83(`, `CYCLE800(`, `CYCLE832(`, `MCALL`, `CR=`, `AR=`, a
//!   line starting `TRANS`/`ATRANS`/`MSG(`, `R1=` assignments, `DEF REAL`/`DEF INT`;
//! - Haas: `G103`, `G154`, `G187`, `M97`, `POPEN`, `PCLOS`, `DPRNT[`, `BPRNT[`;
//! - Fadal: its macro statements, a line starting `#` and a blank or a keyword (`# V1 = 2`,
//!   `#:LOOP`, `# IF`, `# CLEAR`, `# PRINT`), a fixture offset `E1`-`E48`, the R plane `R0+5.`;
//! - grbl: its system commands, a line starting `$` (`$H` homing, `$X` unlock, `$J=` jogging,
//!   `$32=1` a setting);
//! - Mach3 (Mach4 when a comment names it): a program read as a Fanuc's for its `M98` calls of `O`
//!   subprograms, but without a program number before its first block and with a dimension word
//!   without a decimal point (see [`mach_subprograms`]); and a program read as RS274/NGC (`;`
//!   comments after its blocks, as `N1 G21; mm mode`) whose first block is a program number
//!   (`O0000(MY GCODE)`): LinuxCNC and grbl refuse such a line, Mach3 takes it as the program's
//!   number ("Using Mach3Mill", the O word), and a Fanuc would read the text after `;` as the next
//!   block (see [`numbered_first`]);
//! - a comment naming HAAS, FADAL, GRBL, MACH3/MACH 3, MACH4/MACH 4, or SINUMERIK/840D.

use super::Controller;
use crate::dialect::Dialect;

pub(super) fn controller(text: &str) -> Controller {
    // a UTF-8 byte-order mark is no code (Windows editors write one)
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let family = Dialect::detect(text);
    let mut marks = [0usize; 8];
    let mut named = [0usize; 8];
    let index = |c: Controller| Controller::ALL.iter().position(|&x| x == c).expect("every controller is in ALL");
    for raw in text.lines().take(20_000) {
        let upper = raw.trim().to_ascii_uppercase();
        let (code, comment) = split_comment(&upper);
        if let Some(c) = marker(&code) {
            marks[index(c)] += 1;
        }
        if let Some(c) = named_in(&comment) {
            named[index(c)] += 1;
        }
    }
    if marks[index(Controller::Siemens)] > 0 {
        return Controller::Siemens;
    }
    let of_family: Vec<Controller> = Controller::ALL.into_iter().filter(|c| c.family() == family).collect();
    let best = |counts: &[usize; 8]| of_family.iter().copied().filter(|&c| counts[index(c)] > 0).max_by_key(|&c| counts[index(c)]);
    let mach_sign = match family {
        Dialect::Fanuc => mach_subprograms(text),
        Dialect::LinuxCnc => numbered_first(text),
    };
    if best(&marks).is_none() && mach_sign {
        return if named[index(Controller::Mach4)] > named[index(Controller::Mach3)] { Controller::Mach4 } else { Controller::Mach3 };
    }
    best(&marks).or_else(|| best(&named)).unwrap_or(Controller::of_family(family))
}

/// The code lines of a program (upper case, comments and `%` lines left out), as read for detection.
fn code_lines(text: &str) -> impl Iterator<Item = String> + '_ {
    text.lines().take(20_000).map(|raw| split_comment(&raw.trim().to_ascii_uppercase()).0).filter(|c| {
        let c = c.trim();
        !c.is_empty() && c != "%"
    })
}

/// Whether a code line is a program number: `O1234` or ISO `:1234` (after a sequence number), alone.
fn program_number(code: &str) -> bool {
    // the name after the number, `O0000(MY GCODE)`, is a comment
    let c: String = code.split('(').next().unwrap_or("").chars().filter(|c| !c.is_whitespace()).collect();
    let after_n = c.strip_prefix('N').map_or(c.as_str(), |r| r.trim_start_matches(|d: char| d.is_ascii_digit()));
    after_n.strip_prefix(['O', ':']).is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

/// A program read as RS274/NGC whose first block is a program number alone (`O0000`): not a
/// LinuxCNC or grbl program, which refuse such a line.
fn numbered_first(text: &str) -> bool {
    code_lines(text).next().is_some_and(|first| program_number(&first))
}

/// A program that calls `O` subprograms the Fanuc way but is read as RS274/NGC: no program number
/// before its first block (a Fanuc stores a program under its `O` number) and a dimension word
/// without a decimal point (`Z0`, `X40`: a Fanuc counts it in least input increments, and a post
/// for a Fanuc always writes the point). Mach3's and Mach4's CAM posts write such programs.
fn mach_subprograms(text: &str) -> bool {
    let mut codes = code_lines(text);
    let numbered = |c: &str| {
        let c: String = c.chars().filter(|c| !c.is_whitespace()).collect();
        let after_n = c.strip_prefix('N').map_or(c.as_str(), |r| r.trim_start_matches(|d: char| d.is_ascii_digit()));
        after_n.starts_with(['O', ':'])
    };
    if codes.next().is_none_or(|first| numbered(&first)) {
        return false;
    }
    codes.any(|c| integer_dimension(&c))
}

/// Whether a code line has a dimension word (X Y Z I J K R) written without a decimal point.
fn integer_dimension(code: &str) -> bool {
    let compact: Vec<u8> = code.bytes().filter(|c| !c.is_ascii_whitespace()).collect();
    compact.iter().enumerate().any(|(i, &b)| {
        let word = b"XYZIJKR".contains(&b) && (i == 0 || !compact[i - 1].is_ascii_alphabetic());
        let value: Vec<u8> =
            compact[i + 1..].iter().copied().take_while(|c| c.is_ascii_digit() || matches!(c, b'.' | b'-' | b'+')).collect();
        word && value.iter().any(u8::is_ascii_digit) && !value.contains(&b'.')
    })
}

/// The code part of an upper-case line and its comments (`( )`, and what follows `;`).
fn split_comment(line: &str) -> (String, String) {
    let (mut code, mut comment) = (String::new(), String::new());
    let mut depth = 0;
    for (i, c) in line.char_indices() {
        match c {
            '(' if depth == 0 && !code.ends_with(|p: char| p.is_ascii_alphanumeric() || p == '=') => depth = 1,
            ')' if depth > 0 => depth = 0,
            ';' if depth == 0 => {
                comment.push_str(&line[i + 1..]);
                break;
            }
            _ if depth > 0 => comment.push(c),
            _ => code.push(c),
        }
    }
    (code, comment)
}

/// The controller only whose programs hold this code line.
fn marker(code: &str) -> Option<Controller> {
    let compact: String = code.chars().filter(|c| !c.is_whitespace()).collect();
    let after_n = compact.trim_start_matches('/');
    let after_n = match after_n.strip_prefix('N') {
        Some(rest) => rest.trim_start_matches(|c: char| c.is_ascii_digit()),
        None => after_n,
    };
    let siemens = ["CYCLE81(", "CYCLE82(", "CYCLE83(", "CYCLE800(", "CYCLE832(", "MCALL", "CR=", "AR=", "=IC(", "=AC("]
        .iter()
        .any(|k| compact.contains(k))
        || ["TRANS", "ATRANS", "MSG(", "DEFREAL", "DEFINT"].iter().any(|k| after_n.starts_with(k))
        || r_assignment(after_n);
    if siemens {
        return Some(Controller::Siemens);
    }
    if ["POPEN", "PCLOS", "DPRNT[", "BPRNT["].iter().any(|k| after_n.starts_with(k))
        || ["G103", "G154", "G187", "M97"].iter().any(|k| has_code(&compact, k))
    {
        return Some(Controller::Haas);
    }
    let fadal_macro = code.trim_start().strip_prefix('#').is_some_and(|rest| {
        rest.starts_with([' ', ':'])
            || ["IF", "CLEAR", "PRINT", "WAIT", "INPUT", "GOTO", "V", "R"]
                .iter()
                .any(|k| rest.starts_with(k) && !rest[k.len()..].starts_with('['))
                && !rest.starts_with(|c: char| c.is_ascii_digit())
    });
    if fadal_macro || fadal_words(&compact) {
        return Some(Controller::Fadal);
    }
    if code.trim_start().starts_with('$') || ["?", "~", "!"].contains(&code.trim()) {
        return Some(Controller::Grbl);
    }
    None
}

/// A Fadal's words in a compact code line: a fixture offset `E1`-`E48` (a whole number: Haas's
/// `G187 E0.01` has a point) or the R plane written `R0+5.` / `R0-2.`.
fn fadal_words(compact: &str) -> bool {
    let b = compact.as_bytes();
    (0..b.len()).any(|i| {
        let word_start = i == 0 || !b[i - 1].is_ascii_alphabetic();
        let digits: Vec<u8> = b[i + 1..].iter().copied().take_while(u8::is_ascii_digit).collect();
        let next = b.get(i + 1 + digits.len()).copied().unwrap_or(0);
        let e_word = b[i] == b'E' && !digits.is_empty() && next != b'.' && digits.len() <= 2;
        let r0 = b[i] == b'R' && digits == b"0" && matches!(next, b'+' | b'-');
        word_start && (e_word || r0)
    })
}

/// `R12=...`: a Siemens R parameter assignment (an `R` word is never followed by `=` elsewhere).
fn r_assignment(s: &str) -> bool {
    s.strip_prefix('R').is_some_and(|rest| {
        let digits = rest.chars().take_while(char::is_ascii_digit).count();
        digits > 0 && rest[digits..].starts_with('=')
    })
}

/// Whether `code` (`G103`) stands as a word in the compact line, not inside a longer number.
fn has_code(compact: &str, code: &str) -> bool {
    compact.match_indices(code).any(|(i, _)| {
        let before_ok = i == 0 || !compact.as_bytes()[i - 1].is_ascii_alphabetic();
        let after = &compact[i + code.len()..];
        before_ok && !after.starts_with(|c: char| c.is_ascii_digit() || c == '.')
    })
}

/// The controller a comment names.
fn named_in(comment: &str) -> Option<Controller> {
    let names: [(&[&str], Controller); 6] = [
        (&["SINUMERIK", "840D"], Controller::Siemens),
        (&["HAAS"], Controller::Haas),
        (&["FADAL"], Controller::Fadal),
        (&["GRBL"], Controller::Grbl),
        (&["MACH3", "MACH 3"], Controller::Mach3),
        (&["MACH4", "MACH 4"], Controller::Mach4),
    ];
    names.iter().find(|(keys, _)| keys.iter().any(|k| comment.contains(k))).map(|(_, c)| *c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn controllers_told_apart() {
        let haas = "%\nO1001 (PART)\nG00 G17 G40 G49 G80 G90\nG154 P1\nG187 P1 E0.01\nM30\n%\n";
        assert_eq!(controller(haas), Controller::Haas);
        assert_eq!(controller("%\nO1001\nG0 X1.\nM30\n%\n"), Controller::Fanuc);
        assert_eq!(controller("%\nO1001 (POST: FADAL 88HS)\nG0 X1.\nM30\n%\n"), Controller::Fadal);
        assert_eq!(controller("%\nO1\n# V1 = 2\n#:LOOP\nG0 X1.\nM30\n%\n"), Controller::Fadal);
        assert_eq!(controller("%\nO1\nG90 G0 E1 X1. Y1.\nM30\n%\n"), Controller::Fadal);
        assert_eq!(controller("%\nO1\nG98 G81 X1. Y1. Z-2. R0+1. F100.\nM30\n%\n"), Controller::Fadal);
        assert_eq!(controller("%\nO1\n#IF V1 GT 2 THEN GOTO :A\nM30\n%\n"), Controller::Fadal);
        assert_eq!(controller("$H\nG21 G90\nG0 X1 Y1\nM2\n"), Controller::Grbl);
        assert_eq!(controller("(Exported for GRBL)\nG21 G90\nG0 X1 Y1\nM2\n"), Controller::Grbl);
        assert_eq!(controller("(Mach3 post)\nG21 G90\nG0 X1 Y1\nM30\n"), Controller::Mach3);
        assert_eq!(controller("G21 G90\nG0 X1 Y1\nM2\n"), Controller::LinuxCnc);
        let siemens = "; SINUMERIK\nN10 G17 G90 G54\nR1=5\nN20 G2 X10 Y10 CR=5\nMCALL CYCLE81(10,0,2,-5)\nM30\n";
        assert_eq!(controller(siemens), Controller::Siemens);
        assert_eq!(controller("N10 G90\nN20 G1 X=IC(5) Y=AC(3)\nM30\n"), Controller::Siemens);
        assert_eq!(controller("N10 G0 X10 Y10\nN20 TRANS X5\nM30\n"), Controller::Siemens);
        // a Fanuc macro variable `#100 = 2` and a LinuxCNC `#<x>` are no Fadal macro statements
        assert_eq!(controller("%\nO1\n#100 = 2\nG0 X#100\nM30\n%\n"), Controller::Fanuc);
        assert_eq!(controller("#<x> = 2\nG0 X#<x>\nM2\n"), Controller::LinuxCnc);
        // Mach3 subprograms (`O` after `M30`, numbers without a point, no program number first);
        // a Fanuc program with its number first, or with decimal points, stays a Fanuc's
        let mach = "%\n(1001)\nG21 G90\nG0 X10 Y10 Z0\nM98 P1001 L2\nM30\nO1001\nG91 G1 Z-1 F300\nG90 M99\n%\n";
        assert_eq!(controller(mach), Controller::Mach3);
        assert_eq!(controller(&mach.replace("(1001)", "(MACH4 POST)")), Controller::Mach4);
        assert_eq!(controller(&mach.replace("(1001)", "O1000")), Controller::Fanuc);
        assert_eq!(controller(&mach.replace("X10 Y10 Z0\n", "X10. Y10. Z0.\n").replace("Z-1 ", "Z-1. ")), Controller::Fanuc);
        // a program number first, `;` comments after the blocks: read as RS274/NGC, which LinuxCNC
        // refuses with such a number and Mach3 takes (a hand-written program in this style)
        let numbered = "%\nO0000(MY GCODE)\nN1 G21; mm mode\nN2 G0 G17 G40 G49 G80 G90; rapid\nN3 X1 Y1\nN4 M30; end\n%\n";
        assert_eq!(controller(numbered), Controller::Mach3);
        assert_eq!(controller("; example\nO1000\nT1 M6\nG0 G90 G21\nG1 X-40 F100 ; a cut\nM30\n"), Controller::Mach3);
        assert_eq!(controller("\u{feff}; example\nO1000\nT1 M6\nG0 G90 G21\nG1 X-40 F100 ; a cut\nM30\n"), Controller::Mach3);
        // `;` comments on lines of their own only (a published beginner's example)
        assert_eq!(
            controller("; Basic example\n; taken from a web page\n\nO1000\nT1 M6\nG0 G90 G21\nG1 X-40 F100\nM30\n"),
            Controller::Mach3
        );
        assert_eq!(controller(&numbered.replace("O0000(MY GCODE)", "(MY GCODE)")), Controller::LinuxCnc);
        assert_eq!(controller(&numbered.replace("O0000(MY GCODE)", "o100 sub")), Controller::LinuxCnc);
        // a Haas code named in a comment only is no Haas code
        assert_eq!(controller("%\nO1 (NO G187 HERE)\nG0 X1.\nM30\n%\n"), Controller::Fanuc);
    }
}
