//! Matrix Market files (NIST format), to import the capacity and conductivity matrices (and a load
//! vector) of a model built in an external FE tool (Zhu 2008 used MSC/NASTRAN DMAP exports).
//!
//! Read: `%%MatrixMarket matrix coordinate real|integer general|symmetric` (symmetric files store one
//! triangle, mirrored here) and `%%MatrixMarket matrix array real general` (a dense column, for a
//! load vector). Indices are 1-based. Write: coordinate real symmetric (lower triangle).

use super::assembly::from_triplets;
use crate::error::Error;
use faer::sparse::{SparseColMat, Triplet};
use std::fmt::Write;

/// Reads a square sparse matrix from Matrix Market text; `origin` names the file in messages.
pub fn read_matrix(text: &str, origin: &str) -> Result<SparseColMat<usize, f64>, Error> {
    let (header, mut lines) = header(text, origin)?;
    let words: Vec<String> = header.split_whitespace().map(str::to_lowercase).collect();
    if words.len() < 5 || words[1] != "matrix" || words[2] != "coordinate" || !matches!(words[3].as_str(), "real" | "integer") {
        return Err(Error::input(format!("{origin}: line 1: expected `%%MatrixMarket matrix coordinate real general|symmetric`")));
    }
    let symmetric = match words[4].as_str() {
        "symmetric" => true,
        "general" => false,
        other => return Err(Error::input(format!("{origin}: line 1: symmetry `{other}` is not supported (general or symmetric)"))),
    };
    let (line_no, size) = lines.next().ok_or_else(|| Error::input(format!("{origin}: missing the size line")))?;
    let size = numbers::<usize>(size, 3, origin, line_no)?;
    let (rows, cols, nnz) = (size[0], size[1], size[2]);
    if rows != cols || rows == 0 {
        return Err(Error::input(format!("{origin}: line {line_no}: the matrix is {rows}x{cols}; C and K must be square")));
    }
    // no more entries than lines of at least `i j v` (6 bytes): an absurd count in the size line
    // must not reserve memory before the entries are counted (found by the matrix_market fuzz target)
    let room = nnz.min(text.len() / 6);
    let mut triplets = Vec::with_capacity(if symmetric { 2 * room } else { room });
    let mut count = 0;
    for (line_no, line) in lines {
        let parts: Vec<&str> = line.split_whitespace().collect();
        if parts.len() != 3 {
            return Err(Error::input(format!("{origin}: line {line_no}: expected `row column value`")));
        }
        let (i, j) = (index(parts[0], rows, origin, line_no)?, index(parts[1], cols, origin, line_no)?);
        let v: f64 = parts[2]
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| Error::input(format!("{origin}: line {line_no}: `{}` is not a finite number", parts[2])))?;
        triplets.push(Triplet::new(i, j, v));
        if symmetric && i != j {
            triplets.push(Triplet::new(j, i, v));
        }
        count += 1;
    }
    if count != nnz {
        return Err(Error::input(format!("{origin}: the size line announces {nnz} entries but the file has {count}")));
    }
    from_triplets(rows, &triplets)
}

/// Reads a dense vector (`array` format, one column) from Matrix Market text.
pub fn read_vector(text: &str, origin: &str) -> Result<Vec<f64>, Error> {
    let (header, mut lines) = header(text, origin)?;
    let words: Vec<String> = header.split_whitespace().map(str::to_lowercase).collect();
    if words.len() < 4 || words[1] != "matrix" || words[2] != "array" {
        return Err(Error::input(format!("{origin}: line 1: expected `%%MatrixMarket matrix array real general`")));
    }
    let (line_no, size) = lines.next().ok_or_else(|| Error::input(format!("{origin}: missing the size line")))?;
    let size = numbers::<usize>(size, 2, origin, line_no)?;
    if size[1] != 1 {
        return Err(Error::input(format!("{origin}: line {line_no}: a load vector has one column, not {}", size[1])));
    }
    let mut v = Vec::with_capacity(size[0]);
    for (line_no, line) in lines {
        v.push(numbers::<f64>(line, 1, origin, line_no)?[0]);
    }
    if v.len() != size[0] || v.iter().any(|x| !x.is_finite()) {
        return Err(Error::input(format!("{origin}: expected {} finite values, found {}", size[0], v.len())));
    }
    Ok(v)
}

/// Writes a symmetric matrix as coordinate real symmetric (its lower triangle).
pub fn write_symmetric(a: &SparseColMat<usize, f64>) -> String {
    let (cp, ri, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    let mut entries = Vec::new();
    for j in 0..a.ncols() {
        for p in cp[j]..cp[j + 1] {
            if ri[p] >= j {
                entries.push((ri[p] + 1, j + 1, val[p]));
            }
        }
    }
    let mut out = format!("%%MatrixMarket matrix coordinate real symmetric\n{} {} {}\n", a.nrows(), a.ncols(), entries.len());
    for (i, j, v) in entries {
        let _ = writeln!(out, "{i} {j} {v:e}");
    }
    out
}

/// Writes a vector in array format.
pub fn write_vector(v: &[f64]) -> String {
    let mut out = format!("%%MatrixMarket matrix array real general\n{} 1\n", v.len());
    for x in v {
        let _ = writeln!(out, "{x:e}");
    }
    out
}

type Lines<'a> = Box<dyn Iterator<Item = (usize, &'a str)> + 'a>;

fn header<'a>(text: &'a str, origin: &str) -> Result<(&'a str, Lines<'a>), Error> {
    let mut all = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim()));
    let (_, first) = all.next().ok_or_else(|| Error::input(format!("{origin}: the file is empty")))?;
    if !first.to_lowercase().starts_with("%%matrixmarket") {
        return Err(Error::input(format!("{origin}: line 1: not a Matrix Market file (it must start with %%MatrixMarket)")));
    }
    Ok((first, Box::new(all.filter(|(_, l)| !l.is_empty() && !l.starts_with('%')))))
}

fn numbers<T: std::str::FromStr>(line: &str, count: usize, origin: &str, line_no: usize) -> Result<Vec<T>, Error> {
    let v: Vec<T> = line
        .split_whitespace()
        .map(|w| w.parse::<T>())
        .collect::<Result<_, _>>()
        .map_err(|_| Error::input(format!("{origin}: line {line_no}: `{line}` is not {count} number(s)")))?;
    if v.len() != count {
        return Err(Error::input(format!("{origin}: line {line_no}: expected {count} number(s), found {}", v.len())));
    }
    Ok(v)
}

fn index(text: &str, size: usize, origin: &str, line_no: usize) -> Result<usize, Error> {
    match text.parse::<usize>() {
        Ok(i) if (1..=size).contains(&i) => Ok(i - 1),
        _ => Err(Error::input(format!("{origin}: line {line_no}: index `{text}` is not in 1..{size}"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::thermal::assembly::to_dense;

    #[test]
    fn symmetric_files_round_trip_and_mirror() {
        let text = "%%MatrixMarket matrix coordinate real symmetric\n% a comment\n3 3 4\n1 1 2.0\n2 1 -1\n2 2 2\n3 3 1.5e0\n";
        let a = read_matrix(text, "k.mtx").unwrap();
        let d = to_dense(&a);
        assert_eq!((d[(0, 1)], d[(1, 0)], d[(2, 2)], d[(0, 2)]), (-1.0, -1.0, 1.5, 0.0));
        let back = to_dense(&read_matrix(&write_symmetric(&a), "again").unwrap());
        assert_eq!(back, d);
        assert_eq!(read_vector(&write_vector(&[1.0, -2.5]), "q").unwrap(), vec![1.0, -2.5]);
        let e = read_matrix("%%MatrixMarket matrix coordinate real general\n2 2 1\n3 1 1.0\n", "bad.mtx").unwrap_err().to_string();
        assert!(e.contains("bad.mtx: line 3: index `3` is not in 1..2"), "{e}");
        assert!(read_matrix("%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1.0\n", "short.mtx")
            .unwrap_err()
            .to_string()
            .contains("announces 2"));
    }

    #[test]
    fn an_absurd_entry_count_is_refused_without_reserving_it() {
        // 4.7e9 entries announced (150 GB of triplets): once an abort, found by fuzzing
        let text = "%%MatrixMarket matrix coordinate real symmetric\n23 23 4698200222\n1 1 4\n";
        let e = read_matrix(text, "huge.mtx").unwrap_err().to_string();
        assert!(e.contains("huge.mtx: the size line announces 4698200222 entries but the file has 1"), "{e}");
    }
}
