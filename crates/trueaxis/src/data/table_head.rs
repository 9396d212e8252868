//! The head of a forgiving table (`CsvTable`'s module documentation) and the splitting of its data
//! lines, shared by the table read whole ([`super::CsvTable`]) and the table read as a stream
//! ([`super::pose_stream`]): which line is the header (the first line of at least two fields that
//! the next content line repeats), the `Key: value` preamble, the separator and the decimal
//! comma, the header's names and units, and a data line's fields (quoted fields, trailing empty
//! fields, the field count against the header's).

use super::DataError;
use crate::io::header::{normalised, synonyms, Header};
use crate::io::metadata::Metadata;
use crate::io::text::{key_value, separator_of};

/// The header of a table and what was learned with it.
#[derive(Clone, Debug)]
pub(crate) struct TableHead {
    pub(crate) origin: String,
    pub(crate) headers: Vec<Header>,
    pub(crate) header_line: u64,
    pub(crate) separator: u8,
    /// True when numbers may have a decimal comma (the separator is not a comma).
    pub(crate) decimal_comma: bool,
    pub(crate) metadata: Metadata,
}

impl TableHead {
    /// The head from the lines up to and including the header line (the last of `lines`).
    pub(crate) fn parse(lines: &[(u64, &str)], origin: &str) -> Result<TableHead, DataError> {
        let invalid = |message: String| DataError::Invalid { origin: origin.to_string(), message };
        let ((header_line, header_text), preamble) = lines.split_last().ok_or_else(|| invalid("no data: the file is empty".into()))?;
        // before the header: `Key: value` lines, and `# Key: value` comments whose key is one of the
        // file's metadata or test parameters or a plain name (other comments and lines are prose)
        let mut pairs: Vec<(String, String)> = Vec::new();
        for (_, line) in preamble {
            if let Some((key, value)) = key_value(line.trim_start().trim_start_matches("//")) {
                if !is_comment(line) || crate::io::metadata::is_known_key(key) || is_simple_key(key) {
                    pairs.push((key.to_string(), value.to_string()));
                }
            }
        }
        let separator = separator_of(header_text);
        let mut fields = split_fields(header_text, separator);
        while fields.len() > 1 && fields.last().is_some_and(String::is_empty) {
            fields.pop();
        }
        if let Some(k) = fields.iter().position(String::is_empty) {
            return Err(invalid(format!("line {header_line}: column {} of the header has no name", k + 1)));
        }
        let headers: Vec<Header> = fields.iter().map(|f| Header::parse(f)).collect();
        for (i, h) in headers.iter().enumerate() {
            if let Some(j) = headers[..i].iter().position(|g| normalised(&g.name) == normalised(&h.name)) {
                return Err(invalid(format!(
                    "line {header_line}: columns {} (`{}`) and {} (`{}`) are the same column `{}`; a table names each column once: \
                     rename or remove one",
                    j + 1,
                    headers[j].text,
                    i + 1,
                    h.text,
                    h.name
                )));
            }
        }
        let metadata = Metadata::from_pairs(pairs.iter().map(|(k, v)| (k.as_str(), v.as_str())));
        Ok(TableHead {
            origin: origin.to_string(),
            headers,
            header_line: *header_line,
            separator,
            decimal_comma: separator != b',',
            metadata,
        })
    }

    pub(crate) fn invalid(&self, message: String) -> DataError {
        DataError::Invalid { origin: self.origin.clone(), message }
    }

    /// The fields of data line `number`; `None` for a blank or comment line. A line with another
    /// number of fields than the header is refused.
    pub(crate) fn fields(&self, number: u64, line: &str) -> Result<Option<Vec<String>>, DataError> {
        if line.trim().is_empty() || is_comment(line) {
            return Ok(None);
        }
        let mut row = split_fields(line, self.separator);
        while row.len() > self.headers.len() && row.last().is_some_and(String::is_empty) {
            row.pop();
        }
        if row.len() != self.headers.len() {
            let hint = if self.separator == b',' && row.len() > self.headers.len() && line.contains(|c: char| c.is_ascii_digit()) {
                " (decimal commas in a comma-separated file? separate the fields with `;`)"
            } else {
                ""
            };
            return Err(self.invalid(format!(
                "line {number}: {} fields, but the header (line {}) has {}{hint}",
                row.len(),
                self.header_line,
                self.headers.len()
            )));
        }
        Ok(Some(row))
    }
}

/// The index of the column that answers to `name`: the same name, else the same name without
/// regard to case, spaces and underscores, else a synonym; two columns answering at the same level
/// are an error, and so is none (the message lists the header).
pub(crate) fn find_column(headers: &[Header], name: &str, origin: &str) -> Result<usize, DataError> {
    let invalid = |message: String| DataError::Invalid { origin: origin.to_string(), message };
    if let Some(i) = headers.iter().position(|h| h.name == name) {
        return Ok(i);
    }
    let wanted = std::iter::once(normalised(name)).chain(synonyms(name).iter().map(|s| normalised(s)));
    for want in wanted {
        let hits: Vec<usize> = (0..headers.len()).filter(|&i| normalised(&headers[i].name) == want).collect();
        match hits.as_slice() {
            [] => continue,
            [i] => return Ok(*i),
            [a, b, ..] => {
                return Err(invalid(format!(
                    "the columns `{}` and `{}` both answer to `{name}`; rename one",
                    headers[*a].text, headers[*b].text
                )))
            }
        }
    }
    let also = synonyms(name);
    let or = if also.is_empty() { String::new() } else { format!(" (or {})", also.iter().take(3).copied().collect::<Vec<_>>().join(", ")) };
    Err(invalid(format!(
        "missing column `{name}`{or}; the header has: {}",
        headers.iter().map(|h| h.text.as_str()).collect::<Vec<_>>().join(",")
    )))
}

/// Splits one line into fields at `sep`, honouring double quotes (`""` inside quotes is a quote);
/// fields trimmed.
pub(crate) fn split_fields(line: &str, sep: u8) -> Vec<String> {
    let sep = sep as char;
    let mut out = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        if quoted {
            if c == '"' {
                if chars.peek() == Some(&'"') {
                    field.push('"');
                    chars.next();
                } else {
                    quoted = false;
                }
            } else {
                field.push(c);
            }
        } else if c == '"' && field.trim().is_empty() {
            field.clear();
            quoted = true;
        } else if c == sep {
            out.push(field.trim().to_string());
            field.clear();
        } else {
            field.push(c);
        }
    }
    out.push(field.trim().to_string());
    out
}

pub(crate) fn is_comment(line: &str) -> bool {
    let t = line.trim_start();
    t.starts_with('#') || t.starts_with("//")
}

/// A key of a `# Key: value` comment that is a name, not prose: at most 30 characters and 4 words,
/// without punctuation other than `(`, `)`, `/`, `-` and `.` (`Air Humid`, `Mat temp 1 (degC)`).
fn is_simple_key(key: &str) -> bool {
    key.chars().count() <= 30
        && key.split_whitespace().count() <= 4
        && key.chars().all(|c| c.is_alphanumeric() || matches!(c, ' ' | '(' | ')' | '/' | '-' | '.' | '_'))
}

/// The number of fields of a line at `sep`, without trailing empty fields.
fn field_count(line: &str, sep: u8) -> usize {
    let fields = split_fields(line, sep);
    fields.len() - fields.iter().rev().take_while(|f| f.is_empty()).count().min(fields.len() - 1)
}

/// The index (into `lines`) of the header: the first line of at least two fields whose next line
/// (blank and comment lines skipped) has as many fields at the same separator; lines before it are
/// the file's preamble (a ballbar export's `Key: value` header, prose). Without such a pair, the
/// first line of at least two fields, else the first line.
pub(crate) fn header_index(lines: &[(u64, &str)]) -> Option<usize> {
    let content: Vec<usize> = (0..lines.len()).filter(|&k| is_content(lines[k].1)).collect();
    for w in content.windows(2) {
        if is_header_pair(lines[w[0]].1, lines[w[1]].1) {
            return Some(w[0]);
        }
    }
    content.iter().copied().find(|&k| field_count(lines[k].1, separator_of(lines[k].1)) >= 2).or(content.first().copied())
}

/// A line that is neither blank nor a comment.
pub(crate) fn is_content(line: &str) -> bool {
    !line.trim().is_empty() && !is_comment(line)
}

/// Whether the content line `first` is a header that the next content line `next` repeats: at
/// least two fields, as many in both at the header's separator.
pub(crate) fn is_header_pair(first: &str, next: &str) -> bool {
    let sep = separator_of(first);
    let n = field_count(first, sep);
    n >= 2 && field_count(next, sep) == n
}
