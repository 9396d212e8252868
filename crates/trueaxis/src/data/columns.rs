//! Generic CSV tables with named columns (laser, level and other instrument data, DESIGN.md
//! section 3): `#` comments, trimmed fields, errors naming the file, line and column.

use super::DataError;

/// A CSV file held in memory, with accessors for named columns.
#[derive(Clone, Debug)]
pub struct CsvTable {
    origin: String,
    headers: Vec<String>,
    rows: Vec<Vec<String>>,
    lines: Vec<u64>,
}

impl CsvTable {
    /// Reads a CSV file.
    pub fn read(path: impl AsRef<std::path::Path>) -> Result<CsvTable, DataError> {
        let path = path.as_ref();
        let file = std::fs::File::open(path).map_err(|source| DataError::Read { path: path.display().to_string(), source })?;
        Self::from_reader(file, &path.display().to_string())
    }

    /// Reads CSV text from any reader; `origin` names it in messages.
    pub fn from_reader(reader: impl std::io::Read, origin: &str) -> Result<CsvTable, DataError> {
        let invalid = |message: String| DataError::Invalid { origin: origin.to_string(), message };
        let mut csv = csv::ReaderBuilder::new().trim(csv::Trim::All).comment(Some(b'#')).from_reader(reader);
        let headers = csv.headers().map_err(|e| invalid(format!("cannot read the header line: {e}")))?.iter().map(String::from).collect();
        let mut table = CsvTable { origin: origin.to_string(), headers, rows: Vec::new(), lines: Vec::new() };
        for record in csv.records() {
            let record = record.map_err(|e| invalid(e.to_string().replace('\n', " ")))?;
            table.lines.push(record.position().map_or(0, |p| p.line()));
            table.rows.push(record.iter().map(String::from).collect());
        }
        if table.rows.is_empty() {
            let empty = table.headers.iter().all(|h| h.is_empty());
            return Err(invalid(if empty { "no data: the file is empty" } else { "no data: the file has a header but no rows" }.into()));
        }
        Ok(table)
    }

    pub fn len(&self) -> usize {
        self.rows.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    pub fn has_column(&self, name: &str) -> bool {
        self.headers.iter().any(|h| h == name)
    }

    /// 1-based file line of each row.
    pub fn lines(&self) -> &[u64] {
        &self.lines
    }

    fn index(&self, name: &str) -> Result<usize, DataError> {
        self.headers.iter().position(|h| h == name).ok_or_else(|| DataError::Invalid {
            origin: self.origin.clone(),
            message: format!("missing column `{name}`; the header has: {}", self.headers.join(",")),
        })
    }

    /// A column of finite numbers.
    pub fn numbers(&self, name: &str) -> Result<Vec<f64>, DataError> {
        let i = self.index(name)?;
        self.rows
            .iter()
            .zip(&self.lines)
            .map(|(row, line)| {
                let text = &row[i];
                text.parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| DataError::Invalid {
                    origin: self.origin.clone(),
                    message: format!("line {line}: column {name}: `{text}` is not a finite number"),
                })
            })
            .collect()
    }

    /// A column of text.
    pub fn texts(&self, name: &str) -> Result<Vec<String>, DataError> {
        let i = self.index(name)?;
        Ok(self.rows.iter().map(|row| row[i].clone()).collect())
    }

    /// An error about row `row` of this table.
    pub fn row_error(&self, row: usize, message: &str) -> DataError {
        DataError::Invalid { origin: self.origin.clone(), message: format!("line {}: {message}", self.lines[row]) }
    }
}
