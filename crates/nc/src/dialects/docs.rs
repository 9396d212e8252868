//! The tables of docs/nc.md, written from the dialects' data: for each dialect its family, its G
//! codes by modal group, the codes it passes through and refuses, its M codes, the codes that take
//! axis words, its numbers, comments and unknown codes.

use super::{Comments, Controller, DialectTable, Group, Meaning, Unknown};
use crate::dialects::gcode_text;

/// The groups in the order of the tables, with their names.
const GROUPS: [(Group, &str); 15] = [
    (Group::Motion, "motion (G0-G3, canned cycles, G80)"),
    (Group::Plane, "plane"),
    (Group::Distance, "distance mode"),
    (Group::ArcDistance, "arc centre mode"),
    (Group::FeedMode, "feed mode"),
    (Group::Units, "units"),
    (Group::CutterComp, "cutter radius compensation"),
    (Group::ToolLength, "tool length offset"),
    (Group::Retract, "cycle return level"),
    (Group::System, "work coordinate systems"),
    (Group::Path, "path control"),
    (Group::SpindleMode, "spindle speed mode"),
    (Group::Lathe, "lathe diameter mode"),
    (Group::NonModal, "non-modal (their block only)"),
    (Group::Other, "passed through unchanged (no effect on positions)"),
];

/// The markdown table of one dialect (a heading, then a two-column table).
pub fn markdown(controller: Controller) -> String {
    let t = controller.table();
    let mut rows: Vec<(String, String)> = vec![("read as".into(), family_text(t)), ("from".into(), t.source.into())];
    for (group, name) in GROUPS {
        let codes = codes_where(t, |m| m == Meaning::In(group));
        if !codes.is_empty() {
            rows.push((name.into(), codes));
        }
    }
    rows.push((
        "take axis words".into(),
        format!("the motion codes, {}", list(t.axis_codes.iter().copied().filter(|&c| !matches!(t.group(c), Ok(Group::Unknown) | Err(_))))),
    ));
    rows.push(("refused (with the line)".into(), refused_text(t)));
    rows.push(("M codes".into(), m_text(t)));
    rows.push(("numbers".into(), numbers_text(t)));
    rows.push(("comments".into(), comments_text(t.comments).into()));
    rows.push(("unknown codes".into(), unknown_text(t.unknown)));
    let mut out = format!("#### {} (`--dialect {}`)\n\n| | |\n|---|---|\n", t.title, t.name);
    for (k, v) in rows {
        out.push_str(&format!("| {k} | {v} |\n"));
    }
    out
}

fn family_text(t: &DialectTable) -> String {
    match t.family {
        crate::Dialect::LinuxCnc => "RS274/NGC blocks (LinuxCNC family)".into(),
        crate::Dialect::Fanuc => "Fanuc blocks with Custom Macro B (Fanuc family)".into(),
    }
}

/// Every G code (x 10, 0 to G999.9) whose meaning passes `keep`, as `G0 G1 G54.1`.
fn codes_where(t: &DialectTable, keep: impl Fn(Meaning) -> bool) -> String {
    list((0..10_000u16).filter(|&c| t.g_codes.iter().flat_map(|l| l.iter()).any(|e| (e.from..=e.to).contains(&c)) && keep(t.g_meaning(c))))
}

/// Codes x 10 as `G0-G3 G17`: runs of three or more whole numbers joined.
fn list(codes: impl Iterator<Item = u16>) -> String {
    let codes: Vec<u16> = codes.collect();
    let mut parts = Vec::new();
    let mut i = 0;
    while i < codes.len() {
        let mut j = i;
        while j + 1 < codes.len() && codes[i] % 10 == 0 && codes[j + 1] == codes[j] + 10 {
            j += 1;
        }
        if j >= i + 2 {
            parts.push(format!("G{}-G{}", gcode_text(codes[i]), gcode_text(codes[j])));
            i = j + 1;
        } else {
            parts.push(format!("G{}", gcode_text(codes[i])));
            i += 1;
        }
    }
    parts.join(" ")
}

fn refused_text(t: &DialectTable) -> String {
    let mut reasons: Vec<(&str, Vec<u16>)> = Vec::new();
    for c in 0..10_000u16 {
        let listed = t.g_codes.iter().flat_map(|l| l.iter()).any(|e| (e.from..=e.to).contains(&c));
        if let (true, Meaning::Refused(why)) = (listed, t.g_meaning(c)) {
            match reasons.iter_mut().find(|(w, _)| *w == why) {
                Some((_, codes)) => codes.push(c),
                None => reasons.push((why, vec![c])),
            }
        }
    }
    let mut parts: Vec<String> = reasons.into_iter().map(|(why, codes)| format!("{} {}", list(codes.into_iter()), why)).collect();
    parts.extend(t.refused_words.iter().map(|(l, why)| format!("`{}` words {why}", *l as char)));
    parts.extend(t.m_refused.iter().map(|m| format!("{} {}", m_range(m.from, m.to), m.refused.unwrap_or(""))));
    parts.join("; ")
}

fn m_range(from: u16, to: u16) -> String {
    if from == to {
        format!("M{from}")
    } else {
        format!("M{from}-M{to}")
    }
}

fn m_text(t: &DialectTable) -> String {
    let groups: Vec<String> = t.m_groups.iter().map(|g| g.iter().map(|m| format!("M{m}")).collect::<Vec<_>>().join(" ")).collect();
    let known = match t.m_codes {
        None => "any (a machine's M codes are its builder's: passed through)".to_string(),
        Some(lists) => lists.iter().flat_map(|l| l.iter()).map(|m| m_range(m.from, m.to)).collect::<Vec<_>>().join(" "),
    };
    format!("{known}; one a line of each of {{{}}}", groups.join("}, {"))
}

fn numbers_text(t: &DialectTable) -> String {
    let n = t.numbers;
    let integers = if n.integers_are_increments {
        "a dimension word without a decimal point counts in least input increments (0.001 mm, 0.0001 inch: IS-B); written with its decimal point"
    } else {
        "a number without a decimal point is in mm or inch"
    };
    format!("{integers}; written with {} decimals in mm, {} in inch", n.decimals_mm, n.decimals_inch)
}

fn comments_text(c: Comments) -> &'static str {
    match c {
        Comments::ParenthesesAndSemicolon => "`( )`, and `;` to the end of the line",
        Comments::ParenthesesSemicolonEndsBlock => "`( )`; a `;` ends the block (EOB)",
        Comments::Semicolon => "`;` to the end of the line",
    }
}

fn unknown_text(u: Unknown) -> String {
    match u {
        Unknown::PassThrough => {
            "passed through unchanged with a warning naming the line (assumed to move nothing); refused with the line when the line has axis words".into()
        }
        Unknown::Alarm(alarm) => format!("refused with the line: {alarm}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// docs/nc.md holds every table as the data writes it (`cargo test -p trueaxis-nc` prints
    /// the tables to paste when they differ).
    #[test]
    fn docs_hold_the_tables() {
        let page = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/nc.md")).unwrap();
        let mut missing = Vec::new();
        for c in Controller::ALL {
            let table = markdown(c);
            if !page.contains(&table) {
                println!("{table}");
                missing.push(c.to_string());
            }
        }
        assert!(missing.is_empty(), "docs/nc.md lacks the tables of {missing:?} as printed above");
    }

    #[test]
    fn runs_of_codes() {
        assert_eq!(list([0, 10, 20, 30, 170, 541, 800, 810].into_iter()), "G0-G3 G17 G54.1 G80 G81");
    }
}
