//! Lines the writer makes (the moves of expanded parts, the dwells of cycles) in the SINUMERIK's
//! spelling (Programming Manual Fundamentals, "Dwell time (G4)", "Exact stop (G60, G9)"): a dwell
//! `G4 P2` is `G4 F2` (F seconds), the exact-path mode `G61` of an expanded cycle is `G60`, and a
//! comment in parentheses runs from `;` instead.

/// `line` as a SINUMERIK block.
pub fn spell(line: &str) -> String {
    let t = line.trim_start();
    if t.starts_with('(') && t.ends_with(')') {
        return format!(";{}", &t[1..t.len() - 1]);
    }
    let mut words: Vec<String> = line.split(' ').map(str::to_string).collect();
    let dwell = words.iter().any(|w| w == "G4");
    for w in &mut words {
        if dwell && w.starts_with('P') {
            w.replace_range(..1, "F");
        } else if w == "G61" {
            *w = "G60".into();
        }
    }
    words.join(" ")
}

#[cfg(test)]
mod tests {
    use super::spell;

    #[test]
    fn dwell_exact_stop_and_comments() {
        assert_eq!(spell("G4 P0.5"), "G4 F0.5");
        assert_eq!(spell("G61"), "G60");
        assert_eq!(spell("G1 X1 P2"), "G1 X1 P2");
        assert_eq!(spell("(DRILL 8)"), ";DRILL 8");
        assert_eq!(spell("G0 X5.0001 Y2"), "G0 X5.0001 Y2");
    }
}
