//! Lexer of RS274/NGC blocks (NIST RS274NGC interpreter version 3, the dialect of LinuxCNC): words
//! (a letter and a number), comments `( ... )` and `; ...`, line numbers `N`, the block-delete `/`
//! and the `%` program delimiters. Every word keeps the byte span of its number, so that a writer can
//! replace a value and leave the rest of the line untouched.

use std::ops::Range;

/// One word, e.g. `X-12.5`: the letter (upper case), its value and the span of the number text.
#[derive(Clone, Debug, PartialEq)]
pub struct Word {
    pub letter: char,
    pub value: f64,
    /// Byte range of the number in the line (the letter is at `number.start - 1` or before).
    pub number: Range<usize>,
}

/// One line of the program.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// 1-based line number in the file.
    pub line: usize,
    pub text: String,
    pub words: Vec<Word>,
}

impl Block {
    /// The words with `letter`.
    pub fn words_of(&self, letter: char) -> impl Iterator<Item = &Word> {
        self.words.iter().filter(move |w| w.letter == letter)
    }

    /// The value of the single word `letter`, if present.
    pub fn value(&self, letter: char) -> Option<f64> {
        self.words_of(letter).next().map(|w| w.value)
    }

    /// Byte offset where new words may be appended: before a trailing comment, after the last word.
    pub fn insertion_point(&self) -> usize {
        self.words.iter().map(|w| w.number.end).max().unwrap_or_else(|| self.text.trim_end().len())
    }
}

/// Splits a program into blocks; an error names the line and what cannot be read.
pub fn parse_program(text: &str) -> Result<Vec<Block>, String> {
    text.lines().enumerate().map(|(i, line)| parse_block(line, i + 1)).collect()
}

fn parse_block(text: &str, line: usize) -> Result<Block, String> {
    let bytes = text.as_bytes();
    let mut words = Vec::new();
    let mut i = 0;
    let err = |msg: String| Err(format!("line {line}: {msg}"));
    let trimmed = text.trim();
    if trimmed.starts_with('%') {
        return Ok(Block { line, text: text.to_string(), words });
    }
    while i < bytes.len() {
        let c = bytes[i] as char;
        match c {
            ' ' | '\t' | '\r' => i += 1,
            '/' if text[..i].trim().is_empty() => i += 1,
            '(' => match text[i..].find(')') {
                Some(end) => i += end + 1,
                None => return err("comment `(` without closing `)`".into()),
            },
            ';' => break,
            '#' | '[' => return err(format!("parameters and expressions (`{c}`) are not supported; expand them first")),
            c if c.is_ascii_alphabetic() => {
                let letter = c.to_ascii_uppercase();
                if letter == 'O' {
                    return err("subroutines and control flow (O-words) are not supported; expand them first".into());
                }
                let start = i + 1;
                let mut end = start;
                while end < bytes.len() && (bytes[end].is_ascii_digit() || matches!(bytes[end], b'.' | b'+' | b'-')) {
                    end += 1;
                }
                let number = &text[start..end];
                let value: f64 = match number.parse() {
                    Ok(v) if f64::is_finite(v) => v,
                    _ if number.is_empty() && bytes.get(end) == Some(&b'#') => {
                        return err(format!("parameters (`{letter}#...`) are not supported; expand them first"))
                    }
                    _ => return err(format!("`{letter}` must be followed by a number, found `{number}`")),
                };
                words.push(Word { letter, value, number: start..end });
                i = end;
            }
            _ => return err(format!("unexpected character `{c}`")),
        }
    }
    Ok(Block { line, text: text.to_string(), words })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_comments_and_spans() {
        let b = parse_block("N10 g1 X-1.5 y2 (move; here) Z.5 ; tail X9", 3).unwrap();
        let letters: String = b.words.iter().map(|w| w.letter).collect();
        assert_eq!(letters, "NGXYZ");
        assert_eq!(b.value('X'), Some(-1.5));
        assert_eq!(b.value('Z'), Some(0.5));
        let x = &b.words[2];
        assert_eq!(&b.text[x.number.clone()], "-1.5");
        assert!(parse_block("G1 X#1", 7).unwrap_err().contains("line 7"));
        assert!(parse_block("o100 sub", 2).unwrap_err().contains("O-words"));
        assert!(parse_block("G1 X1 (open", 4).unwrap_err().contains("without closing"));
    }
}
