//! The rules the repository keeps about itself (docs/design.md, Errors, Validation and Finding your
//! way), checked on the source text: no new public function of the libraries returns a `String` as
//! its error (those left are listed and the list only shrinks), the libraries never speak of exit statuses, the folders of the core form no circle, every
//! page and section of the documentation the code cites exists, and each crate keeps its tests in
//! one binary (`tests/it/main.rs`, at most 3 files directly in `tests/`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().unwrap()
}

/// Every `.rs` file below `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The text of a source file without its `#[cfg(test)]` part and its comment lines.
fn code_of(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let code = text.split("#[cfg(test)]").next().unwrap_or("");
    code.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n")
}

/// The libraries whose public API the rules cover.
const LIBRARIES: [&str; 4] = ["crates/trueaxis/src", "crates/nc/src", "crates/report/src", "crates/live/src"];

/// No public function of the libraries returns a message as its error: `trueaxis::Error`, the NC
/// interpreter's `NcError` (file and line) or a typed error instead.
#[test]
fn no_public_function_returns_a_string_as_its_error() {
    let mut found = Vec::new();
    for library in LIBRARIES {
        for file in rust_files(&workspace().join(library)) {
            let code = code_of(&file);
            for (start, _) in code.match_indices("pub fn ") {
                let signature: String = code[start..].chars().take_while(|&c| c != '{' && c != ';').collect();
                let compact: String = signature.chars().filter(|c| !c.is_whitespace()).collect();
                if compact.contains(",String>") && compact.contains("Result<") {
                    let name: String = signature["pub fn ".len()..].chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
                    found.push(format!("{}: {name}", file.strip_prefix(workspace()).unwrap().display()));
                }
            }
        }
    }
    assert!(found.is_empty(), "public functions returning Result<_, String> (return trueaxis::Error or a typed error):\n{found:?}");
}

#[test]
fn the_libraries_never_speak_of_exit_statuses() {
    let mut found = Vec::new();
    for library in LIBRARIES {
        for file in rust_files(&workspace().join(library)) {
            let text = std::fs::read_to_string(&file).unwrap().to_lowercase();
            for (n, line) in text.lines().enumerate() {
                if line.contains("exit status") || line.contains("exit code") {
                    found.push(format!("{}:{}", file.strip_prefix(workspace()).unwrap().display(), n + 1));
                }
            }
        }
    }
    assert!(found.is_empty(), "the command line decides exit statuses (crates/cli/src/exit.rs), not:\n{}", found.join("\n"));
}

/// The top-level modules of the core each module uses (`crate::<module>` outside its tests).
fn module_graph() -> BTreeMap<String, BTreeMap<String, Vec<String>>> {
    let src = workspace().join("crates/trueaxis/src");
    let mut modules = BTreeMap::new();
    for entry in std::fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        if name != "lib" && (path.is_dir() || path.extension().is_some_and(|e| e == "rs")) {
            let files = if path.is_dir() { rust_files(&path) } else { vec![path.clone()] };
            modules.insert(name, files);
        }
    }
    let names: Vec<String> = modules.keys().cloned().collect();
    let mut graph = BTreeMap::new();
    for (module, files) in &modules {
        let mut uses: BTreeMap<String, Vec<String>> = BTreeMap::new();
        for file in files {
            let code = code_of(file);
            for other in names.iter().filter(|o| *o != module) {
                let direct = format!("crate::{other}::");
                let grouped = code.match_indices("crate::{").any(|(i, _)| {
                    let group = &code[i + 8..i + 8 + code[i + 8..].find('}').unwrap_or(0)];
                    group.split(|c: char| !(c.is_alphanumeric() || c == '_')).any(|w| w == other)
                });
                if code.contains(&direct) || code.contains(&format!("crate::{other};")) || grouped {
                    uses.entry(other.clone()).or_default().push(file.strip_prefix(&src).unwrap().display().to_string());
                }
            }
        }
        graph.insert(module.clone(), uses);
    }
    graph
}

#[test]
fn the_folders_of_the_core_form_no_circle() {
    let graph = module_graph();
    // depth-first search; a module met again on the current path closes a circle
    fn visit(
        m: &str,
        graph: &BTreeMap<String, BTreeMap<String, Vec<String>>>,
        path: &mut Vec<String>,
        done: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|p| p == m) {
            let mut circle = path[at..].to_vec();
            circle.push(m.to_string());
            return Some(circle);
        }
        if done.iter().any(|d| d == m) {
            return None;
        }
        path.push(m.to_string());
        for next in graph[m].keys() {
            if let Some(c) = visit(next, graph, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.push(m.to_string());
        None
    }
    let mut done = Vec::new();
    for m in graph.keys() {
        if let Some(circle) = visit(m, &graph, &mut Vec::new(), &mut done) {
            let steps: Vec<String> =
                circle.windows(2).map(|w| format!("{} -> {} ({})", w[0], w[1], graph[&w[0]][&w[1]].join(", "))).collect();
            panic!("a circle across the core's folders:\n{}", steps.join("\n"));
        }
    }
    // the layers docs/design.md names: the bottom uses nothing above it
    assert!(graph["geometry"].is_empty(), "geometry uses {:?}", graph["geometry"].keys());
    assert!(graph["files"].is_empty(), "files uses {:?}", graph["files"].keys());
}

/// The headings of a Markdown page, without their `#`s.
fn headings(page: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(page).unwrap_or_default();
    text.lines().filter(|l| l.starts_with('#')).map(|l| l.trim_start_matches('#').trim().to_string()).collect()
}

#[test]
fn every_cited_page_and_section_exists() {
    let root = workspace();
    let mut files = Vec::new();
    for dir in ["crates", "fuzz"] {
        files.extend(rust_files(&root.join(dir)).into_iter().filter(|f| !f.components().any(|c| c.as_os_str() == "target")));
    }
    let mut missing = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for (at, _) in text.match_indices("docs/") {
            let rest = &text[at..];
            let Some(end) = rest.find(".md") else { continue };
            let name = &rest[..end + 3];
            if !name[5..end].chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '_' || c == '/') {
                continue;
            }
            let page = root.join(name);
            let place = format!("{}", file.strip_prefix(&root).unwrap().display());
            if !page.is_file() {
                missing.push(format!("{place}: {name}"));
                continue;
            }
            // "docs/<page>.md, <Section> ...": a heading of that page starts the words after the comma
            let after = &rest[end + 3..];
            if let Some(section) = after.strip_prefix(", ").filter(|s| s.starts_with(|c: char| c.is_ascii_uppercase())) {
                let section: String = section.lines().next().unwrap_or("").trim_start_matches("//!").trim().to_string();
                let found = headings(&page).iter().any(|h| {
                    let h = h.split(':').next().unwrap_or(h).trim();
                    !h.is_empty() && section.to_lowercase().starts_with(&h.to_lowercase())
                });
                if !found {
                    missing.push(format!("{place}: {name}, {section}"));
                }
            }
        }
    }
    assert!(missing.is_empty(), "citations of pages or sections that do not exist:\n{}", missing.join("\n"));
}

#[test]
fn each_crate_keeps_its_tests_in_one_binary() {
    let root = workspace();
    for entry in std::fs::read_dir(root.join("crates")).unwrap() {
        let tests = entry.unwrap().path().join("tests");
        if !tests.is_dir() {
            continue;
        }
        let direct: Vec<String> = std::fs::read_dir(&tests)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "rs"))
            .map(|p| p.file_name().unwrap().to_string_lossy().to_string())
            .collect();
        assert!(direct.len() <= 3, "{}: {} test files directly in tests/: {direct:?}", tests.display(), direct.len());
    }
}

#[test]
fn every_cited_file_of_the_repository_exists() {
    let root = workspace();
    let mut missing = Vec::new();
    for file in rust_files(&root.join("crates")).into_iter().chain(rust_files(&root.join("fuzz"))) {
        if file.components().any(|c| c.as_os_str() == "target") {
            continue;
        }
        let text = std::fs::read_to_string(&file).unwrap();
        for (at, _) in text.match_indices("crates/") {
            if at > 0 && text[..at].ends_with(|c: char| c.is_alphanumeric() || c == '/' || c == '.') {
                continue;
            }
            let cited: String = text[at..].chars().take_while(|c| c.is_alphanumeric() || "_./-".contains(*c)).collect();
            let cited = cited.trim_end_matches(['.', '/']);
            let has_extension = ["rs", "md", "toml", "h", "py", "csv"].iter().any(|e| cited.ends_with(&format!(".{e}")));
            if has_extension && !root.join(cited).exists() {
                missing.push(format!("{}: {cited}", file.strip_prefix(&root).unwrap().display()));
            }
        }
    }
    assert!(missing.is_empty(), "files cited that are not in the repository:\n{}", missing.join("\n"));
}
