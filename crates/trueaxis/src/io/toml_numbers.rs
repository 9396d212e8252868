//! Numbers of a TOML file that underflow: `1e-400` parses as 0 without a word (a TOML float is a
//! double), so an error value or a coefficient written in the wrong unit would vanish. Every TOML
//! reader of trueaxis checks its text with [`refuse_underflow`] before parsing it: the numbers
//! outside strings and comments are read, and one that is not zero as written but is 0 as a double
//! (`io::text::underflows`) is refused with its line.

use super::text::underflows;

/// The first number of `text` that underflows to zero, with its 1-based line.
pub fn first_underflow(text: &str) -> Option<(usize, String)> {
    let bytes = text.as_bytes();
    let (mut i, mut line) = (0, 1);
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            b'\n' => line += 1,
            b'#' => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'"' | b'\'' => {
                let (end, lines) = skip_string(bytes, i);
                line += lines;
                i = end;
                continue;
            }
            _ if c.is_ascii_digit() || ((c == b'+' || c == b'-') && bytes.get(i + 1).is_some_and(u8::is_ascii_digit)) => {
                // a bare word that starts with a digit or a sign: a number, a date or a key
                let before = i.checked_sub(1).map(|k| bytes[k]);
                let start = i;
                while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || matches!(bytes[i], b'_' | b'.' | b'+' | b'-')) {
                    i += 1;
                }
                let word = &text[start..i];
                let part_of_key = before.is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_');
                let plain: String = word.chars().filter(|c| *c != '_').collect();
                if !part_of_key {
                    if let Ok(v) = plain.parse::<f64>() {
                        if underflows(&plain, v) {
                            return Some((line, word.to_string()));
                        }
                    }
                }
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    None
}

/// The end of the string that starts at `at` (basic or literal, on one line or multi-line) and
/// the line ends inside it.
fn skip_string(bytes: &[u8], at: usize) -> (usize, usize) {
    let quote = bytes[at];
    let triple = bytes.len() >= at + 3 && bytes[at + 1] == quote && bytes[at + 2] == quote;
    let mut i = at + if triple { 3 } else { 1 };
    let mut lines = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' if quote == b'"' => i += 1,
            b'\n' => {
                lines += 1;
                if !triple {
                    return (i, lines - 1);
                }
            }
            b if b == quote && (!triple || bytes[i..].starts_with(&[quote; 3])) => return (i + if triple { 3 } else { 1 }, lines),
            _ => {}
        }
        i += 1;
    }
    (i, lines)
}

/// Refuses a TOML text with a number that underflows to zero: bad input at its line, for the
/// reader to name the file (`Error::in_file`).
pub fn refuse_underflow(text: &str) -> crate::error::Result<()> {
    match first_underflow(text) {
        None => Ok(()),
        Some((line, word)) => Err(crate::Error::input(format!(
            "`{word}` is below the smallest number a double holds (about 4.9e-324) and would be read as 0; write 0, or the value in \
             its unit"
        ))
        .at_line(line)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_that_vanish_are_found_and_others_left() {
        let text = "name = \"1e-400 in a string\" # and 1e-500 in a comment\n[constant]\nEC0X = 0.0\nEB0C = 1e-300\n\
                    EA0C = '''\nmulti 1e-999\n'''\n[table.EXX]\nposition = [-1e2, 0, 1_0.5]\nvalue = [0, 2.5e-400, 0e-999]\n";
        assert_eq!(first_underflow(text), Some((10, "2.5e-400".to_string())));
        assert!(refuse_underflow(text).unwrap_err().to_string().starts_with("line 10: `2.5e-400` is below"));
        for fine in ["a = 0\nb = -0.0e-400\nc = 1979-05-27T07:32:00Z\nd = 0x10\ne = 4.9e-324\n", "EX0C = 1\nx1e-400 = 2\n"] {
            assert_eq!(first_underflow(fine), None, "{fine}");
        }
        assert_eq!(first_underflow("a = -1E-330"), Some((1, "-1E-330".to_string())));
    }
}
