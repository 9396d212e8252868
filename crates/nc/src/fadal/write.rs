//! Lines the writer makes or edits, in a Fadal's spelling: the macro variables an expanded part
//! leaves set (`#301=3`, the interpreter's store of `V1`) are the macro statements `# V1 = 3`, one
//! a line; the R plane of a canned cycle is the R0 word with a signed value, `R0+5.003` (as the
//! Autodesk post for Fadal writes it), never a bare `R5.003`, which a Fadal may take for its R
//! parameter `R5`. A line with `G2`/`G3` (an R word there is the arc's radius) or `G10` keeps its
//! R word.

use super::{R_BASE, R_COUNT, V_BASE, V_COUNT};

/// `line` as Fadal blocks (more than one when macro statements are made of it).
pub fn spell(line: &str) -> Vec<String> {
    let (code, comment) = line.split_at(line.find('(').unwrap_or(line.len()));
    let mut words = Vec::new();
    let mut statements = Vec::new();
    let arc_or_setting = code.split(' ').any(|w| matches!(w, "G2" | "G3" | "G02" | "G03" | "G10"));
    for w in code.split(' ') {
        if let Some((n, v)) = w.strip_prefix('#').and_then(|a| a.split_once('=')) {
            if let Some(name) = n.parse::<u32>().ok().and_then(variable_name) {
                statements.push(format!("# {name} = {v}"));
                continue;
            }
        }
        match w.strip_prefix('R') {
            Some(v) if !arc_or_setting && !v.is_empty() => words.push(format!("R0{}", signed(v))),
            _ => words.push(w.to_string()),
        }
    }
    let block = words.join(" ") + comment;
    let mut out = Vec::new();
    if !block.trim().is_empty() {
        out.push(block);
    }
    out.extend(statements);
    out
}

/// The Fadal name of the interpreter's variable `n` (`#301` is `V1`, `#290` is `R0`).
fn variable_name(n: u32) -> Option<String> {
    if (V_BASE + 1..=V_BASE + V_COUNT).contains(&n) {
        Some(format!("V{}", n - V_BASE))
    } else if (R_BASE..R_BASE + R_COUNT).contains(&n) {
        Some(format!("R{}", n - R_BASE))
    } else {
        None
    }
}

/// The signed value of an R plane after `R0`: `v` as the value text of an R word (`5.003`,
/// `-2.`), or what an edit of `R0+5.000` left after the `R` (`05.003`: the `0` of `R0` and the new
/// value), or a value already signed after `R0` (`0+5.003`).
fn signed(v: &str) -> String {
    let b = v.as_bytes();
    let value = match b {
        [b'0', b'+' | b'-', ..] => return v[1..].to_string(),
        [b'0', d, ..] if d.is_ascii_digit() => &v[1..],
        _ => v,
    };
    if value.starts_with(['+', '-']) {
        value.to_string()
    } else {
        format!("+{value}")
    }
}

#[cfg(test)]
mod tests {
    use super::spell;

    #[test]
    fn variables_and_r_plane() {
        assert_eq!(spell("#301=3 #290=-0.5"), vec!["# V1 = 3", "# R0 = -0.5"]);
        assert_eq!(spell("G0 X1. #302=2"), vec!["G0 X1.", "# V2 = 2"]);
        assert_eq!(spell("N60 G98 G90 G81 X10.001 Y5. Z-3.002 R05.003 F200."), vec!["N60 G98 G90 G81 X10.001 Y5. Z-3.002 R0+5.003 F200."]);
        assert_eq!(spell("G81 X1. R0-2.003"), vec!["G81 X1. R0-2.003"]);
        assert_eq!(spell("X40. Y40. R5.003"), vec!["X40. Y40. R0+5.003"]);
        assert_eq!(spell("X40. R-0.002"), vec!["X40. R0-0.002"]);
        assert_eq!(spell("X40. R0.002"), vec!["X40. R0+0.002"]);
        assert_eq!(spell("G2 X1. Y1. R5. (R5 ARC)"), vec!["G2 X1. Y1. R5. (R5 ARC)"]);
        assert_eq!(spell("G0 X1. (R5 IS A COMMENT)"), vec!["G0 X1. (R5 IS A COMMENT)"]);
    }
}
