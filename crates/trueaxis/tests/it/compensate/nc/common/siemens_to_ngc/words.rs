//! The blocks of a SINUMERIK 840D program as words (SINUMERIK 840D sl Programming Manual
//! Fundamentals, "Block structure"): `N` numbers and `;` comments apart, addresses with a number
//! (`X10.5`, `G0X10` written together), addresses with `=` and an expression (`X=R1+5`,
//! `CR=-10`; blanks allowed inside parentheses only), names with their `( )` arguments
//! (`CYCLE81(15, 0, 2, -12)`, `MSG("..")`), quoted names (`CALL "L10"`) and names alone.

/// A word of a block: an address with a number (`X10.5`, `G0`), an address with `=` and an
/// expression (`X=R1+5`, `R1=40`, `CR=5`), a name with `( )` (`CYCLE81(..)`), a quoted string,
/// a name alone (`TRANS`, `MCALL`, a subprogram).
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Word {
    Letter(u8, String),
    Assign(String, String),
    Call(String, String),
    Quoted(String),
    Name(String),
}

/// The index of the `)` closing the `(` at `open`.
pub(super) fn closing(s: &str, open: usize) -> Option<usize> {
    let mut depth = 0;
    for (i, c) in s.char_indices().skip(open) {
        match c {
            '(' => depth += 1,
            ')' => {
                depth -= 1;
                if depth == 0 {
                    return Some(i);
                }
            }
            _ => {}
        }
    }
    None
}

/// The code of a line and its `;` comment (outside quotes).
pub(super) fn split_comment(line: &str) -> (String, String) {
    let mut quoted = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => quoted = !quoted,
            ';' if !quoted => return (line[..i].to_string(), line[i + 1..].trim().to_string()),
            _ => {}
        }
    }
    (line.to_string(), String::new())
}

/// A comment line rs274 reads as nothing: ASCII, without parentheses, opened by `;`.
pub(super) fn comment_line(text: &str) -> String {
    let clean: String = text
        .chars()
        .map(|c| match c {
            '(' => '[',
            ')' => ']',
            c if c.is_ascii_graphic() || c == ' ' => c,
            _ => '?',
        })
        .take(200)
        .collect();
    format!("(; {clean})\n")
}

/// A block without its `N` number.
pub(super) fn strip_number(code: &str) -> String {
    let rest = code.strip_prefix('N').filter(|r| r.starts_with(|c: char| c.is_ascii_digit()));
    rest.map_or(code, |r| r.trim_start_matches(|c: char| c.is_ascii_digit())).trim().to_string()
}

/// The words of an upper-case block (see [`Word`]); `None` for what is not one of them.
pub(super) fn words(code: &str) -> Option<Vec<Word>> {
    let b = code.as_bytes();
    let (mut out, mut i) = (Vec::new(), 0);
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
        } else if c == b'"' {
            let end = i + 1 + code[i + 1..].find('"')?;
            out.push(Word::Quoted(code[i + 1..end].to_string()));
            i = end + 1;
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < b.len() && (b[i].is_ascii_alphabetic() || b[i] == b'_') {
                i += 1;
            }
            let number = i - start == 1 && i < b.len() && (b[i].is_ascii_digit() || b"+-.".contains(&b[i]));
            if number {
                let n0 = i;
                i += 1;
                while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                    i += 1;
                }
                let n = &code[n0..i];
                if b.get(i) == Some(&b'=') {
                    // R1=...
                    let (e, next) = expression_at(code, i + 1)?;
                    out.push(Word::Assign(format!("{}{n}", c as char), e));
                    i = next;
                } else {
                    n.trim_start_matches('+').parse::<f64>().ok()?;
                    out.push(Word::Letter(c, n.trim_start_matches('+').to_string()));
                }
                continue;
            }
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            let name = code[start..i].to_string();
            match b.get(i) {
                Some(b'=') => {
                    let (e, next) = expression_at(code, i + 1)?;
                    out.push(Word::Assign(name, e));
                    i = next;
                }
                Some(b'(') => {
                    let end = closing(code, i)?;
                    out.push(Word::Call(name, code[i + 1..end].to_string()));
                    i = end + 1;
                }
                _ => out.push(Word::Name(name)),
            }
        } else {
            return None;
        }
    }
    Some(out)
}

/// The expression starting at byte `i` (to the next blank outside parentheses, blanks inside
/// dropped) and where it ends.
fn expression_at(code: &str, i: usize) -> Option<(String, usize)> {
    let (mut depth, mut e) = (0i32, String::new());
    for (k, c) in code[i..].char_indices() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            c if c.is_ascii_whitespace() && depth == 0 => return (!e.is_empty()).then_some((e, i + k)),
            c if c.is_ascii_whitespace() => continue,
            _ => {}
        }
        e.push(c);
    }
    (!e.is_empty() && depth == 0).then_some((e, code.len()))
}

/// The arguments of a call, split at the commas outside parentheses, blanks dropped.
pub(super) fn arguments(args: &str) -> Option<Vec<String>> {
    let (mut out, mut depth, mut one) = (Vec::new(), 0i32, String::new());
    for c in args.chars().filter(|c| !c.is_ascii_whitespace()) {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            ',' if depth == 0 => {
                out.push(std::mem::take(&mut one));
                continue;
            }
            _ => {}
        }
        one.push(c);
    }
    out.push(one);
    Some(out)
}
