//! Damaged variants of the shipped example files, made in memory: each function takes the text
//! of a CSV file (comment lines `#` and the header kept) and returns the text with one damage, as
//! shop-floor data has it (a run or column in another unit, another axis's run, a stuck sensor,
//! repeated rows, gross outliers, a temperature step or gap, degF, a spike, a blank cell).
//! docs/screening.md lists them with the finding each must give.

use std::path::PathBuf;

/// The text of a shipped example (path relative to the repository).
pub fn example(path: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(path);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The path of a shipped example.
pub fn example_path(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(path)
}

/// A CSV text split into its leading lines (comments and header), the header's names and its rows.
pub struct Csv {
    pub head: Vec<String>,
    pub names: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Csv {
    pub fn parse(text: &str) -> Csv {
        let mut head = Vec::new();
        let mut rows = Vec::new();
        let mut names = Vec::new();
        for line in text.lines() {
            if names.is_empty() {
                head.push(line.to_string());
                if !line.starts_with('#') && !line.trim().is_empty() {
                    names = line.split(',').map(|s| s.trim().to_string()).collect();
                }
            } else if !line.trim().is_empty() {
                rows.push(line.split(',').map(str::to_string).collect());
            }
        }
        Csv { head, names, rows }
    }

    pub fn col(&self, name: &str) -> usize {
        self.names.iter().position(|n| n == name).unwrap_or_else(|| panic!("no column {name}"))
    }

    /// The 1-based file line of row `i`.
    pub fn line(&self, i: usize) -> u64 {
        (self.head.len() + i + 1) as u64
    }

    pub fn value(&self, i: usize, name: &str) -> f64 {
        self.rows[i][self.col(name)].parse().unwrap()
    }

    pub fn set(&mut self, i: usize, name: &str, v: f64) {
        let c = self.col(name);
        self.rows[i][c] = format!("{v}");
    }

    /// Applies `f` to column `name` of the rows `select` picks.
    pub fn map(mut self, name: &str, select: impl Fn(&Csv, usize) -> bool, f: impl Fn(f64) -> f64) -> Csv {
        for i in 0..self.rows.len() {
            if select(&self, i) {
                let v = f(self.value(i, name));
                self.set(i, name, v);
            }
        }
        self
    }

    /// Adds a column whose value is `f(row index)`.
    pub fn add_column(mut self, name: &str, f: impl Fn(usize) -> f64) -> Csv {
        let last = self.head.len() - 1;
        self.head[last] += &format!(",{name}");
        self.names.push(name.into());
        for (i, row) in self.rows.iter_mut().enumerate() {
            row.push(format!("{:.3}", f(i)));
        }
        self
    }

    pub fn text(&self) -> String {
        let mut out = self.head.join("\n") + "\n";
        for r in &self.rows {
            out += &(r.join(",") + "\n");
        }
        out
    }
}

/// Rows of run `run` (column `run`).
pub fn of_run(run: &str) -> impl Fn(&Csv, usize) -> bool + '_ {
    move |c: &Csv, i: usize| c.rows[i][c.col("run")] == run
}

/// Every row.
pub fn all(_: &Csv, _: usize) -> bool {
    true
}
