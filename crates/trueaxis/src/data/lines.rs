//! The lines of a text file read as a stream, in bounded memory, with the forgiveness of the whole
//! file's reader (`io::text_of`, `io::text::numbered_lines`): `\n`, `\r\n` or a lone `\r` ends a
//! line (numbered from 1), a UTF-8 byte-order mark at the start is dropped, a line that is not
//! UTF-8 is read as Latin-1 / Windows-1252 (older instrument software), and a NUL byte is refused
//! with its line (not a text file). A line longer than [`MAX_LINE`] bytes is refused: no table
//! trueaxis reads has one, and the bound keeps memory independent of the input.

use super::DataError;
use std::io::BufRead;

/// Longest line accepted (bytes).
pub const MAX_LINE: usize = 1 << 20;

/// The numbered lines of a reader.
pub struct Lines<R> {
    reader: R,
    origin: String,
    number: u64,
    /// The last line ended with `\r`: a `\n` that follows belongs to it.
    after_cr: bool,
    bytes: Vec<u8>,
}

impl<R: BufRead> Lines<R> {
    pub fn new(reader: R, origin: &str) -> Lines<R> {
        Lines { reader, origin: origin.to_string(), number: 0, after_cr: false, bytes: Vec::new() }
    }

    fn invalid(&self, message: String) -> DataError {
        DataError::Invalid { origin: self.origin.clone(), message }
    }

    /// The next line and its number, without its end; `None` at the end of the input.
    pub fn next_line(&mut self) -> Result<Option<(u64, String)>, DataError> {
        self.bytes.clear();
        let mut ended = false;
        loop {
            let buffer = self.reader.fill_buf().map_err(|source| DataError::Read { path: self.origin.clone(), source })?;
            if buffer.is_empty() {
                break;
            }
            let mut used = 0;
            if self.after_cr && buffer[0] == b'\n' {
                used = 1;
            }
            self.after_cr = false;
            match buffer[used..].iter().position(|b| *b == b'\n' || *b == b'\r') {
                Some(i) => {
                    self.bytes.extend_from_slice(&buffer[used..used + i]);
                    self.after_cr = buffer[used + i] == b'\r';
                    used += i + 1;
                    ended = true;
                }
                None => {
                    self.bytes.extend_from_slice(&buffer[used..]);
                    used = buffer.len();
                }
            }
            self.reader.consume(used);
            if self.bytes.len() > MAX_LINE {
                return Err(self.invalid(format!("line {}: longer than {} bytes: not a table", self.number + 1, MAX_LINE)));
            }
            if ended {
                break;
            }
        }
        if !ended && self.bytes.is_empty() {
            return Ok(None);
        }
        self.number += 1;
        if self.bytes.contains(&0) {
            return Err(self.invalid(format!("line {}: a NUL byte: this is not a text file (export the data as text or CSV)", self.number)));
        }
        let mut text = match std::str::from_utf8(&self.bytes) {
            Ok(s) => s.to_string(),
            Err(_) => self.bytes.iter().map(|&b| b as char).collect(),
        };
        if self.number == 1 {
            text = crate::io::text::strip_bom(&text).to_string();
        }
        Ok(Some((self.number, text)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(bytes: &[u8], capacity: usize) -> Vec<(u64, String)> {
        let mut l = Lines::new(std::io::BufReader::with_capacity(capacity, bytes), "f.csv");
        let mut out = Vec::new();
        while let Some(line) = l.next_line().unwrap() {
            out.push(line);
        }
        out
    }

    #[test]
    fn every_line_end_and_encoding_as_the_whole_file_reader() {
        let text = "\u{feff}X,Y\r\n1,2\r3,4\n\n5,6\r\n7,\u{b0}";
        let whole: Vec<(u64, String)> =
            crate::io::text::numbered_lines(crate::io::text::strip_bom(text)).into_iter().map(|(n, l)| (n, l.to_string())).collect();
        // buffers of every size down to one byte split the ends anywhere
        for capacity in [1, 2, 3, 7, 64] {
            assert_eq!(lines(text.as_bytes(), capacity), whole, "capacity {capacity}");
        }
        assert_eq!(lines(b"a\xb0b\n", 8), [(1, "a\u{b0}b".to_string())]);
        let mut l = Lines::new(&b"X\n1\x002\n"[..], "f.csv");
        l.next_line().unwrap();
        assert!(l.next_line().unwrap_err().to_string().contains("f.csv: line 2: a NUL byte"));
        let long = vec![b'1'; MAX_LINE + 10];
        assert!(Lines::new(&long[..], "f.csv").next_line().unwrap_err().to_string().contains("line 1: longer than"));
    }
}
