//! Lines the writer makes (the moves of expanded parts, the dwells of cycles) in the SINUMERIK's
//! spelling (Programming Manual Fundamentals, "Dwell time (G4)", "Exact stop (G60, G9)"): a dwell
//! `G4 P2` is `G4 F2` (F seconds), the exact-path mode `G61` of an expanded cycle is `G60`, a
//! comment in parentheses runs from `;` instead, and the R parameters an expanded subprogram call
//! leaves set (`#1001=40`) are `R1=40` ("Arithmetic parameters (R)"), the DEF variables
//! (`#<COUNT>=3`) `COUNT=3`; `G43`/`G49`/`G52`/`G53`
//! are `D1`/`D0`/`TRANS`/`SUPA` ("Tool offsets", "Frames").

use super::{R_BASE, R_COUNT};

/// The codes the reader states the 840D's commands as, written back as those commands: the
/// tool length offset `G43` is the cutting edge `D1` (the only one read), `G49` is `D0`, the
/// shift `G52 X Y Z` is `TRANS X Y Z`, `G53` is `SUPA`.
const SPELLED: [(&str, &str); 4] = [("G43", "D1"), ("G49", "D0"), ("G52", "TRANS"), ("G53", "SUPA")];

/// `line` as a SINUMERIK block.
pub fn spell(line: &str) -> String {
    let t = line.trim_start();
    if t.starts_with('(') && t.ends_with(')') {
        return format!(";{}", &t[1..t.len() - 1]);
    }
    // what follows a `;` (a comment, or text in quotes) stays as it is
    let (code, rest) = line.split_at(line.find(';').unwrap_or(line.len()));
    let mut words: Vec<String> = code.split(' ').map(str::to_string).collect();
    let dwell = words.iter().any(|w| w == "G4");
    for w in &mut words {
        if let Some((name, v)) = w.strip_prefix("#<").and_then(|a| a.split_once(">=")) {
            // a DEF variable an expanded part leaves set: #<COUNT>=3 is COUNT=3
            *w = format!("{name}={v}");
        } else if let Some((n, v)) = w.strip_prefix('#').and_then(|a| a.split_once('=')) {
            // the R parameters an expanded part leaves set: #1001=3 is R1=3
            if let Some(r) = n.parse::<u32>().ok().filter(|n| (R_BASE..R_BASE + R_COUNT).contains(n)) {
                *w = format!("R{}={v}", r - R_BASE);
            }
        } else if let Some(&(_, spelled)) = SPELLED.iter().find(|(g, _)| g == w) {
            // the interpreter's codes for what the reader read from the 840D's commands
            *w = spelled.into();
        } else if dwell && w.starts_with('P') {
            w.replace_range(..1, "F");
        } else if w == "G61" {
            *w = "G60".into();
        }
    }
    words.join(" ") + rest
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
        assert_eq!(spell("#1001=40 #1999=-2.5"), "R1=40 R999=-2.5");
        assert_eq!(spell("#1001=4 #<COUNT>=3"), "R1=4 COUNT=3");
        assert_eq!(spell("M6 G43 T1"), "M6 D1 T1");
        assert_eq!(spell("G0 X1 ; G43 G61 P2"), "G0 X1 ; G43 G61 P2");
        assert_eq!(spell("G4 P1;G43"), "G4 F1;G43");
        assert_eq!(spell("G52 X10 Y5 Z0"), "TRANS X10 Y5 Z0");
        assert_eq!(spell("G0 G53 Z0 G49"), "G0 SUPA Z0 D0");
    }
}
