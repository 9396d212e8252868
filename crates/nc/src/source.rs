//! The byte reader: a program file as a controller takes it, into lines of text, and back.
//!
//! - A UTF-8 byte-order mark (`EF BB BF`) at the start is accepted and written back.
//! - Lines end at LF, CR LF or a CR alone (old Mac and some DNC senders); each line keeps its own
//!   ending, and the last line its missing one, so that an unchanged program is written back byte
//!   for byte.
//! - A line that is not valid UTF-8 (Latin-1 or Windows-1252 comments of European posts) is read
//!   byte for byte as the characters U+0000-U+00FF and written back as the same bytes; the lexer
//!   accepts such bytes in comments only and names them as bytes (`byte 0xD9`) elsewhere.
//! - NUL and the other control bytes (below 0x20, and DEL) other than TAB are refused with the line:
//!   a controller stops at them or drops them, and a NUL cut a line short where it stood (a damaged
//!   or binary file).

use std::fmt::Write as _;

/// How a line ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ending {
    Lf,
    CrLf,
    Cr,
    /// The last line of a file without a final line end.
    None,
}

impl Ending {
    pub fn bytes(self) -> &'static [u8] {
        match self {
            Ending::Lf => b"\n",
            Ending::CrLf => b"\r\n",
            Ending::Cr => b"\r",
            Ending::None => b"",
        }
    }
}

/// A program file read into lines: `text` holds them joined by `\n`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SourceText {
    pub text: String,
    /// The file started with a UTF-8 byte-order mark.
    pub bom: bool,
    /// The ending of each line.
    pub endings: Vec<Ending>,
    /// Lines (0-based, ascending) read byte for byte because they are not UTF-8.
    pub bytewise: Vec<usize>,
}

/// Reads program bytes; an error gives the 0-based line and the reason.
pub fn decode(bytes: &[u8]) -> Result<SourceText, (usize, String)> {
    decode_part(bytes, true)
}

/// Reads a part of a program's bytes that starts at a line (`first`: the start of the file, where
/// a byte-order mark may stand) and ends after a line end (or at the end of the file).
pub fn decode_part(bytes: &[u8], first: bool) -> Result<SourceText, (usize, String)> {
    let (bom, bytes) = match bytes.strip_prefix(b"\xEF\xBB\xBF") {
        Some(rest) if first => (true, rest),
        _ => (false, bytes),
    };
    let mut out = SourceText { text: String::with_capacity(bytes.len()), bom, ..SourceText::default() };
    let mut start = 0;
    let mut i = 0;
    while start < bytes.len() {
        while i < bytes.len() && bytes[i] != b'\n' && bytes[i] != b'\r' {
            i += 1;
        }
        let (content, ending, next) = match bytes.get(i) {
            None => (&bytes[start..], Ending::None, i),
            Some(b'\n') => (&bytes[start..i], Ending::Lf, i + 1),
            Some(_) if bytes.get(i + 1) == Some(&b'\n') => (&bytes[start..i], Ending::CrLf, i + 2),
            Some(_) => (&bytes[start..i], Ending::Cr, i + 1),
        };
        let line = out.endings.len();
        check_controls(content).map_err(|m| (line, m))?;
        if line > 0 {
            out.text.push('\n');
        }
        match std::str::from_utf8(content) {
            Ok(s) => out.text.push_str(s),
            Err(_) => {
                out.bytewise.push(line);
                out.text.extend(content.iter().map(|&b| char::from(b)));
            }
        }
        out.endings.push(ending);
        start = next;
        i = next;
    }
    Ok(out)
}

/// Refuses control bytes other than TAB, naming the first with its column (1-based).
fn check_controls(line: &[u8]) -> Result<(), String> {
    match line.iter().position(|&b| (b < 0x20 && b != b'\t') || b == 0x7F) {
        None => Ok(()),
        Some(at) => {
            Err(format!("control byte {} at column {}: program text holds none (a damaged or binary file?)", byte_name(line[at]), at + 1))
        }
    }
}

/// A control byte by its code and name: `0x00 (NUL)`.
fn byte_name(b: u8) -> String {
    const NAMES: [&str; 32] = [
        "NUL", "SOH", "STX", "ETX", "EOT", "ENQ", "ACK", "BEL", "BS", "TAB", "LF", "VT", "FF", "CR", "SO", "SI", "DLE", "DC1", "DC2",
        "DC3", "DC4", "NAK", "SYN", "ETB", "CAN", "EM", "SUB", "ESC", "FS", "GS", "RS", "US",
    ];
    let name = NAMES.get(b as usize).copied().unwrap_or("DEL");
    format!("0x{b:02X} ({name})")
}

impl SourceText {
    /// Whether line `k` was read byte for byte.
    pub fn is_bytewise(&self, k: usize) -> bool {
        self.bytewise.binary_search(&k).is_ok()
    }

    /// The ending of line `k` (LF past the last line).
    pub fn ending(&self, k: usize) -> Ending {
        self.endings.get(k).copied().unwrap_or(Ending::Lf)
    }
}

/// Appends the text of a line to `out` as bytes: a line read byte for byte goes back byte for
/// byte (every character of its text is below U+0100: the reader's and the ASCII the writer adds).
pub fn encode_line(line: &str, bytewise: bool, out: &mut Vec<u8>) {
    if bytewise {
        out.extend(line.chars().map(|c| u8::try_from(u32::from(c)).unwrap_or(b'?')));
    } else {
        out.extend_from_slice(line.as_bytes());
    }
}

/// A character found where it does not belong, readably: printable ASCII as itself, a byte of a
/// line read byte for byte as its code (`byte 0xD9`), any other character with its code point
/// (`` `٣` (U+0663) ``).
pub fn describe_char(c: char, bytewise: bool) -> String {
    let mut s = String::new();
    if c.is_ascii_graphic() {
        let _ = write!(s, "`{c}`");
    } else if bytewise && u32::from(c) < 0x100 {
        let _ = write!(s, "byte 0x{:02X}", u32::from(c));
    } else if c.is_control() || c.is_whitespace() {
        let _ = write!(s, "U+{:04X}", u32::from(c));
    } else {
        let _ = write!(s, "`{c}` (U+{:04X})", u32::from(c));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip(bytes: &[u8]) -> Vec<u8> {
        let s = decode(bytes).unwrap();
        let mut out = Vec::new();
        if s.bom {
            out.extend_from_slice(b"\xEF\xBB\xBF");
        }
        for (k, line) in s.text.split('\n').take(s.endings.len()).enumerate() {
            encode_line(line, s.is_bytewise(k), &mut out);
            out.extend_from_slice(s.ending(k).bytes());
        }
        out
    }

    #[test]
    fn line_ends_bom_and_bytes_round_trip() {
        for bytes in
            [&b"%\rO1000\rG0 X1\r%\r"[..], b"G0 X1\r\nG1 Y2\nM2", b"\xEF\xBB\xBFG0 X1 (Stra\xDFe)\n(caf\xC3\xA9)\nM2\n", b"", b"\n\n"]
        {
            assert_eq!(round_trip(bytes), bytes);
        }
        let s = decode(b"%\rO1000\rG0 X1\r%\r").unwrap();
        assert_eq!(s.text, "%\nO1000\nG0 X1\n%");
        assert_eq!(s.endings, vec![Ending::Cr; 4]);
        let s = decode(b"\xEF\xBB\xBFG0 X1 (Stra\xDFe)\n(caf\xC3\xA9)\nM2").unwrap();
        assert!(s.bom);
        assert_eq!(s.bytewise, vec![0]);
        assert_eq!(s.text, "G0 X1 (Stra\u{DF}e)\n(caf\u{E9})\nM2");
        assert_eq!(s.endings.last(), Some(&Ending::None));
    }

    #[test]
    fn control_bytes_are_refused_with_line_and_column() {
        let e = decode(b"G0 X0\nG1 F500 X3\x0000 Y50\nM2\n").unwrap_err();
        assert_eq!(e, (1, "control byte 0x00 (NUL) at column 11: program text holds none (a damaged or binary file?)".to_string()));
        assert_eq!(decode(b"G0\x1BX1\n").unwrap_err().1[..21], *"control byte 0x1B (ES");
        assert!(decode(b"G0\tX1\n").is_ok());
        assert_eq!(describe_char('\u{0663}', false), "`\u{0663}` (U+0663)");
        assert_eq!(describe_char('\u{D9}', true), "byte 0xD9");
        assert_eq!(describe_char('!', false), "`!`");
    }
}
