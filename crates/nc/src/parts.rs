//! A program file read in parts, so that a program of any length is run and written with memory
//! that does not grow with it: each part holds whole lines (ends LF, CR LF or a CR alone, as
//! [`crate::source`] reads them), at least a given number of them or up to the end of the file. A
//! CR at the end of the bytes read so far waits for the next byte (it may be the CR of a CR LF).

use std::io::Read;

/// The bytes of one part, and whether it ends the file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Part {
    pub bytes: Vec<u8>,
    pub last: bool,
}

/// Reads parts of a program from a byte stream.
pub struct PartReader<R> {
    reader: R,
    pending: Vec<u8>,
    /// Bytes of `pending` scanned for line ends, the line ends found, and the end of the last one.
    scanned: usize,
    ends: usize,
    cut: usize,
    eof: bool,
    done: bool,
}

/// Bytes asked of the reader at a time.
const BLOCK: usize = 1 << 16;

impl<R: Read> PartReader<R> {
    pub fn new(reader: R) -> Self {
        PartReader { reader, pending: Vec::new(), scanned: 0, ends: 0, cut: 0, eof: false, done: false }
    }

    /// The next part: its first `lines` lines (at least one), or the rest of the file; `None` after
    /// the last part.
    pub fn next_part(&mut self, lines: usize) -> std::io::Result<Option<Part>> {
        if self.done {
            return Ok(None);
        }
        let lines = lines.max(1);
        self.fill(lines)?;
        if self.ends >= lines {
            let rest = self.pending.split_off(self.cut);
            let bytes = std::mem::replace(&mut self.pending, rest);
            self.scanned -= self.cut;
            (self.ends, self.cut) = (0, 0);
            return Ok(Some(Part { bytes, last: false }));
        }
        self.done = true;
        Ok(Some(Part { bytes: std::mem::take(&mut self.pending), last: true }))
    }

    /// The next `lines` lines (or the rest of the file) without taking them: what the next parts
    /// will hold, and whether that is the rest of the file.
    pub fn peek(&mut self, lines: usize) -> std::io::Result<(&[u8], bool)> {
        self.fill(lines)?;
        let end = if self.ends >= lines { self.cut } else { self.pending.len() };
        (self.scanned, self.ends, self.cut) = (0, 0, 0);
        Ok((&self.pending[..end], self.eof && end == self.pending.len()))
    }

    /// Reads until `lines` line ends are counted or the input ends.
    fn fill(&mut self, lines: usize) -> std::io::Result<()> {
        loop {
            self.scan(lines);
            if self.ends >= lines || self.eof {
                return Ok(());
            }
            let old = self.pending.len();
            self.pending.resize(old + BLOCK, 0);
            let read = loop {
                match self.reader.read(&mut self.pending[old..]) {
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                    r => break r,
                }
            };
            self.pending.truncate(old + *read.as_ref().unwrap_or(&0));
            self.eof = read? == 0;
        }
    }

    /// Counts line ends in the unscanned bytes up to the `lines`-th.
    fn scan(&mut self, lines: usize) {
        let p = &self.pending;
        while self.scanned < p.len() && self.ends < lines {
            let i = self.scanned;
            match p[i] {
                b'\n' => {
                    self.ends += 1;
                    self.cut = i + 1;
                }
                b'\r' => match p.get(i + 1) {
                    None if !self.eof => return,
                    Some(b'\n') => {}
                    _ => {
                        self.ends += 1;
                        self.cut = i + 1;
                    }
                },
                _ => {}
            }
            self.scanned += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reads `bytes` in parts of `lines` lines through a reader that gives `chunk` bytes at a time.
    fn parts(bytes: &[u8], lines: usize, chunk: usize) -> Vec<Part> {
        struct Dribble<'a>(&'a [u8], usize);
        impl Read for Dribble<'_> {
            fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
                let n = self.1.min(buf.len()).min(self.0.len());
                buf[..n].copy_from_slice(&self.0[..n]);
                self.0 = &self.0[n..];
                Ok(n)
            }
        }
        let mut r = PartReader::new(Dribble(bytes, chunk));
        assert_eq!(r.peek(lines + 1).unwrap().0.len(), r.peek(lines + 1).unwrap().0.len());
        std::iter::from_fn(|| r.next_part(lines).unwrap()).collect()
    }

    #[test]
    fn parts_hold_whole_lines_of_every_ending() {
        let text = b"G0 X1\r\nG1 Y2\rG1 Z3\nM2\r\n(end)";
        for chunk in [1, 2, 3, 7, 1000] {
            let p = parts(text, 2, chunk);
            let cut: Vec<&[u8]> = p.iter().map(|p| &p.bytes[..]).collect();
            assert_eq!(cut, [&b"G0 X1\r\nG1 Y2\r"[..], b"G1 Z3\nM2\r\n", b"(end)"], "chunk {chunk}");
            assert_eq!(p.iter().map(|p| p.last).collect::<Vec<_>>(), [false, false, true]);
        }
        // a CR at the end of the file ends its last line
        let p = parts(b"G0 X1\rM2\r", 1, 1);
        assert_eq!(p.iter().map(|p| p.bytes.len()).collect::<Vec<_>>(), [6, 3, 0]);
        assert_eq!(parts(b"", 5, 4), [Part { bytes: vec![], last: true }]);
        let mut r = PartReader::new(&text[..]);
        assert_eq!(r.peek(3).unwrap(), (&b"G0 X1\r\nG1 Y2\rG1 Z3\n"[..], false));
        assert_eq!(r.peek(9).unwrap(), (&text[..], true));
        assert_eq!(r.next_part(1).unwrap().unwrap().bytes, b"G0 X1\r\n");
    }
}
