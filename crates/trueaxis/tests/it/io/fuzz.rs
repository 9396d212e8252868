//! The readers of instrument files never panic, whatever the bytes: random bytes, random text
//! made of the characters these formats use, and mutations of the shipped example files (characters
//! replaced, inserted or deleted, lines duplicated or dropped) go through every reader and, where a
//! file is read, through the evaluations that consume it; each ends in a value or an error message
//! naming the file.

use proptest::prelude::*;
use trueaxis::data::CsvTable;
use trueaxis::evaluate::iso230_2::{evaluate, plausibility, runs_of};
use trueaxis::instruments::ballbar::trace_of;
use trueaxis::io::{etalon, rtl, text_of};
use trueaxis::machine::Machine;
use trueaxis::poses::poses_of;

const EXAMPLES: [&str; 6] = [
    include_str!("../../../../../examples/data/laser_x.rtl"),
    include_str!("../../../../../examples/data/vmc3_etalon.exc"),
    include_str!("../../../../../examples/ballbar/export_xy.txt"),
    include_str!("../../../../../examples/data/iso230_2_x.csv"),
    include_str!("../../../../../examples/ballbar/vmc3_xy.csv"),
    include_str!("../../../../../examples/poses/vmc3.csv"),
];

/// Every reader on one text; errors must name the file.
fn read_everything(text: &str) {
    let origin = "fuzz.txt";
    let machine = Machine::from_toml_str(include_str!("../../../../../examples/machines/vmc3.toml"), "vmc3").unwrap();
    if let Err(e) = rtl::parse(text, origin) {
        assert!(e.to_string().starts_with(origin), "{e}");
    }
    match etalon::parse(text, origin) {
        Ok(f) => {
            if let Err(e) = f.to_error_values(&machine, origin) {
                assert!(e.to_string().starts_with(origin), "{e}");
            }
        }
        Err(e) => assert!(e.to_string().starts_with(origin), "{e}"),
    }
    match CsvTable::from_text(text, origin) {
        Ok(table) => {
            if let Ok(data) = runs_of(&table) {
                let _ = plausibility(&table, &data);
                let _ = evaluate(&data);
            }
            let _ = trace_of(&table, &["angle", "C"]);
            let _ = poses_of(&table, &machine);
            let _ = table.to_canonical_csv();
            let _ = trueaxis::instruments::ballbar::ballbar_header(&table);
        }
        Err(e) => assert!(e.to_string().starts_with(origin), "{e}"),
    }
}

#[derive(Clone, Debug)]
enum Mutation {
    Replace(usize, char),
    Insert(usize, char),
    Delete(usize, usize),
    DuplicateLine(usize),
    DropLine(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let special = prop::sample::select(vec![',', ';', '\t', '\n', '\r', ':', '[', '}', '-', 'e', '.', '#', '"', '9', 'µ']);
    let c = prop_oneof![special, any::<char>()];
    prop_oneof![
        (any::<usize>(), c.clone()).prop_map(|(i, c)| Mutation::Replace(i, c)),
        (any::<usize>(), c).prop_map(|(i, c)| Mutation::Insert(i, c)),
        (any::<usize>(), 1usize..40).prop_map(|(i, n)| Mutation::Delete(i, n)),
        any::<usize>().prop_map(Mutation::DuplicateLine),
        any::<usize>().prop_map(Mutation::DropLine),
    ]
}

fn mutate(text: &str, mutations: &[Mutation]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for m in mutations {
        let n = chars.len().max(1);
        match *m {
            Mutation::Replace(i, c) if !chars.is_empty() => chars[i % n] = c,
            Mutation::Insert(i, c) => chars.insert(i % (chars.len() + 1), c),
            Mutation::Delete(i, k) if !chars.is_empty() => {
                let at = i % n;
                chars.drain(at..(at + k).min(chars.len()));
            }
            Mutation::DuplicateLine(i) | Mutation::DropLine(i) => {
                let s: String = chars.iter().collect();
                let mut lines: Vec<&str> = s.split('\n').collect();
                let at = i % lines.len();
                if matches!(m, Mutation::DropLine(_)) {
                    lines.remove(at);
                } else {
                    lines.insert(at, lines[at]);
                }
                chars = lines.join("\n").chars().collect();
            }
            _ => {}
        }
    }
    chars.into_iter().collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, .. ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..2000)) {
        if let Ok(text) = text_of(bytes, "fuzz.txt") {
            read_everything(&text);
        }
    }

    #[test]
    fn random_text_of_format_characters_never_panics(text in "[0-9a-zA-Z:;,\\t\\r\\n .+\\-\\[\\]{}=/#\"µ°]{0,600}") {
        read_everything(&text);
        read_everything(&format!("TARGET DATA::\nTarget-count: 3\nTargets :\n{text}"));
        read_everything(&format!("[EXX]\nGridpoints = {{\n{text}"));
    }

    #[test]
    fn mutated_example_files_never_panic(which in 0usize..EXAMPLES.len(), mutations in proptest::collection::vec(mutation(), 1..8)) {
        read_everything(&mutate(EXAMPLES[which], &mutations));
    }
}
