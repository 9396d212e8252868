//! Text-level forgiveness of instrument files: a UTF-8 byte-order mark, CRLF line ends, `,` `;` or
//! tab separators, decimal commas (`0,0123` in a `;`-separated file, as spreadsheets write them in
//! Germany and France), a leading `+`, the Unicode minus sign.

/// The text of a file without a UTF-8 byte-order mark; invalid UTF-8 is refused by the caller.
pub fn strip_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// The lines of `text` with their 1-based numbers, without the line ends (`\n`, `\r\n` or a lone
/// `\r` as old Mac exports write it).
pub fn numbered_lines(text: &str) -> Vec<(u64, &str)> {
    let mut out = Vec::new();
    let mut start = 0;
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'\n' => {
                out.push((out.len() as u64 + 1, &text[start..i]));
                start = i + 1;
            }
            b'\r' => {
                out.push((out.len() as u64 + 1, &text[start..i]));
                if bytes.get(i + 1) == Some(&b'\n') {
                    i += 1;
                }
                start = i + 1;
            }
            _ => {}
        }
        i += 1;
    }
    if start < text.len() {
        out.push((out.len() as u64 + 1, &text[start..]));
    }
    out
}

/// The field separator of a header line: a tab if there is one, else `;`, else `,`.
pub fn separator_of(header: &str) -> u8 {
    if header.contains('\t') {
        b'\t'
    } else if header.contains(';') {
        b';'
    } else {
        b','
    }
}

/// Parses a number as instrument software writes it: surrounding spaces, a leading `+`, the
/// Unicode minus `−`, and with `decimal_comma` a comma as the decimal mark (`-0,0123`) or
/// thousands dots before it (`1.234,5`). Not-a-number texts (`nan`, `inf`) parse; the caller
/// refuses values that are not finite. `None` when the text is not a number.
pub fn parse_number(text: &str, decimal_comma: bool) -> Option<f64> {
    let t = text.trim();
    if t.is_empty() || t.len() > 1000 {
        return None;
    }
    let mut s: String = t.chars().map(|c| if c == '−' { '-' } else { c }).collect();
    if decimal_comma && s.contains(',') {
        let commas = s.matches(',').count();
        let last_comma = s.rfind(',').unwrap_or(0);
        let dots_before_comma = s.rfind('.').is_none_or(|d| d < last_comma);
        if commas != 1 || !dots_before_comma {
            return None;
        }
        s = s.replace('.', "").replace(',', ".");
    }
    let s = s.strip_prefix('+').unwrap_or(&s);
    // Rust also parses `infinity`, `nan`: keep them (refused as not finite by the callers) but not
    // other words
    if s.chars().any(|c| c.is_ascii_alphabetic()) {
        let lower = s.to_ascii_lowercase();
        let lower = lower.trim_start_matches('-');
        let word_ok = matches!(lower, "nan" | "inf" | "infinity");
        let exponent_ok = !word_ok && lower.chars().filter(|c| c.is_ascii_alphabetic()).all(|c| c == 'e');
        if !(word_ok || exponent_ok) {
            return None;
        }
    }
    s.parse::<f64>().ok()
}

/// Whether the number `text`, read as `value`, underflowed: it is not zero as written (a digit 1-9
/// before its exponent) but reads as zero, being below the smallest positive double (about
/// 4.9e-324; `1e-400`). Such a value is refused rather than silently read as 0.
pub fn underflows(text: &str, value: f64) -> bool {
    value == 0.0 && text.split(['e', 'E']).next().is_some_and(|mantissa| mantissa.chars().any(|c| ('1'..='9').contains(&c)))
}

/// A `Key: value` line of a header block (`Machine: DMU 50`, `# Operator: J. Smith`): the key
/// (trimmed, at most 60 characters, starting with a letter) and the value (trimmed). `None` for
/// other lines.
pub fn key_value(line: &str) -> Option<(&str, &str)> {
    let line = line.trim().trim_start_matches('#').trim();
    let (key, value) = line.split_once(':').or_else(|| line.split_once('='))?;
    let key = key.trim();
    if key.is_empty() || key.len() > 60 || !key.chars().next().is_some_and(char::is_alphabetic) {
        return None;
    }
    Some((key, value.trim()))
}

/// The first 40 characters of a line, for messages (`...` when cut).
pub fn clip(line: &str) -> String {
    let s: String = line.chars().take(40).collect();
    if s.len() < line.len() {
        format!("{s}...")
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_the_forms_instrument_software_writes() {
        assert_eq!(parse_number(" +1.5 ", false), Some(1.5));
        assert_eq!(parse_number("−0.25", false), Some(-0.25));
        assert_eq!(parse_number("-0,0123", true), Some(-0.0123));
        assert_eq!(parse_number("1.234,5", true), Some(1234.5));
        assert_eq!(parse_number("1,2,3", true), None);
        assert_eq!(parse_number("1,5", false), None);
        assert_eq!(parse_number("2.5e-3", true), Some(2.5e-3));
        assert_eq!(parse_number("abc", false), None);
        assert!(parse_number("NaN", false).is_some_and(f64::is_nan));
    }

    #[test]
    fn lines_with_any_line_end() {
        let lines: Vec<&str> = numbered_lines("a\r\nb\rc\nd").iter().map(|l| l.1).collect();
        assert_eq!(lines, ["a", "b", "c", "d"]);
    }

    #[test]
    fn separators_and_key_values() {
        assert_eq!(separator_of("a;b,c"), b';');
        assert_eq!(separator_of("a\tb;c"), b'\t');
        assert_eq!(separator_of("a,b"), b',');
        assert_eq!(key_value("# Machine: DMU 50"), Some(("Machine", "DMU 50")));
        assert_eq!(key_value("Radius (mm) = 100"), Some(("Radius (mm)", "100")));
        assert_eq!(key_value("12:30"), None);
    }
}
