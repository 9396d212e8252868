//! A loaded program: its files (the main program and the subroutine files found on the search
//! path), their lines, expression trees, and the index of their control structures: which `if`,
//! `elseif`, `else` and `endif` belong together, where each loop and subroutine starts and ends
//! (LinuxCNC O-words), where each `N` label, `WHILE ... DO m`/`END m` pair and `O` program number is
//! (Fanuc).

use crate::dialect::Dialect;
use crate::expr::Node;
use crate::lexer::{parse_line, Label, Line, OKind, Statement};
use crate::source::{decode_part, Ending, SourceText};
use crate::{Controller, NcError};
use std::collections::HashMap;
use std::ops::Range;
use std::path::PathBuf;

/// How a control line connects to the others of its structure (line indices in the same file).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Link {
    #[default]
    None,
    /// `if`/`elseif`/`else`: the next branch line and the `endif`.
    Branch { next: usize, end: usize },
    /// The first line of a loop (`while`, `do`, `repeat`, Fanuc `WHILE`/`DO`) and its last line.
    LoopStart { end: usize },
    /// The last line of a loop (`endwhile`, `while` of a `do`, `endrepeat`, Fanuc `END`).
    LoopEnd { start: usize },
    /// `break`/`continue`: the loop's first and last lines.
    LoopJump { start: usize, end: usize },
    /// `sub`: its `endsub`.
    Sub { end: usize },
    /// `return`/`endsub`: the `sub`.
    SubEnd { start: usize },
}

/// Reads one line of a file (text, 1-based number, family, expression arena, read byte for byte).
pub(crate) type LineReader = fn(&str, usize, Dialect, &mut Vec<Node>, bool) -> Result<Line, String>;

/// One file of the program.
#[derive(Clone, Debug)]
pub struct SourceFile {
    pub name: String,
    /// The lines joined by `\n` (see [`crate::source`] for line ends and bytes).
    pub text: String,
    /// How each line ends, the lines read byte for byte, a byte-order mark at the start.
    pub endings: Vec<Ending>,
    pub bytewise: Vec<usize>,
    pub bom: bool,
    /// Byte range of each line in `text`.
    pub ranges: Vec<Range<usize>>,
    /// Each line read, or why it cannot be read (an error only if the line is executed).
    pub(crate) lines: Vec<Result<Line, String>>,
    pub arena: Vec<Node>,
    pub links: Vec<Link>,
    /// LinuxCNC subroutines of this file: label -> (`sub` line, `endsub` line).
    pub subs: HashMap<Label, (usize, usize)>,
    /// Fanuc: `N` number -> lines with it.
    pub sequence: HashMap<u32, Vec<usize>>,
    /// Fanuc: `O` number -> its first line.
    pub programs: HashMap<u32, usize>,
    /// The lines to run: after a leading `%` up to the next `%` (or the end).
    pub body: Range<usize>,
    /// A part of a file read in parts ([`crate::parts`]): the 0-based line of the file its line 0
    /// is (0 for a whole file), whether the file's first line is a `%`, and whether the lines to
    /// run continue in the next part.
    pub first_line: usize,
    pub leading_percent: bool,
    pub continues: bool,
}

/// Where a file read in parts stands after the parts read so far: whether its first line that
/// is not empty was a `%` (unknown until one is read), and whether its body has ended (a
/// closing `%`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PartState {
    pub leading_percent: Option<bool>,
    pub closed: bool,
    /// Lines read so far.
    pub lines: usize,
}

/// An error at index `k` of the lines of file `name`, located at its line.
fn located(name: &str) -> impl Fn((usize, String)) -> NcError + '_ {
    move |(k, message)| NcError { file: name.to_string(), line: k + 1, message }
}

impl SourceFile {
    /// How many lines the file (or part) has.
    pub fn line_count(&self) -> usize {
        self.lines.len()
    }

    /// Reads and indexes a file with the lexer of `dialect`'s family; an error names the line of a
    /// control structure that does not close or match.
    pub fn load(name: &str, bytes: &[u8], dialect: Dialect) -> Result<SourceFile, NcError> {
        Self::read_part(name, bytes, dialect, &mut PartState::default(), true, parse_line).map_err(located(name))
    }

    /// Reads and indexes the part of a file that follows the parts `state` has seen (`last`: it
    /// ends the file), its lines read as `controller` reads them (the SINUMERIK's own language by
    /// [`crate::siemens::parse_line`] into the same lines); line numbers of an error are those of
    /// the part. The body of a part runs from its first line, or after the file's leading `%`, to
    /// a closing `%` or its end.
    pub fn load_part(name: &str, bytes: &[u8], controller: Controller, state: &mut PartState, last: bool) -> Result<SourceFile, NcError> {
        Self::read_part(name, bytes, controller.family(), state, last, controller.line_reader()).map_err(located(name))
    }

    /// [`SourceFile::load_part`], the error at the index of its line.
    fn read_part(
        name: &str,
        bytes: &[u8],
        dialect: Dialect,
        state: &mut PartState,
        last: bool,
        read: LineReader,
    ) -> Result<SourceFile, (usize, String)> {
        let SourceText { text, bom, endings, bytewise } = decode_part(bytes, state.lines == 0)?;
        let mut ranges = Vec::with_capacity(endings.len());
        let mut start = 0;
        for piece in text.split('\n').take(endings.len()) {
            ranges.push(start..start + piece.len());
            start += piece.len() + 1;
        }
        let mut arena = Vec::new();
        let lines: Vec<Result<Line, String>> = ranges
            .iter()
            .enumerate()
            .map(|(i, r)| read(&text[r.clone()], i + 1, dialect, &mut arena, bytewise.binary_search(&i).is_ok()))
            .collect();
        let percent = |k: usize| matches!(&lines[k], Ok(l) if l.percent);
        let closing = |from: usize| (from..lines.len()).find(|&k| percent(k));
        let first_line = state.lines;
        let body = match state.leading_percent {
            _ if state.closed => lines.len()..lines.len(),
            Some(true) => 0..closing(0).unwrap_or(lines.len()),
            Some(false) => 0..lines.len(),
            None => match lines.iter().position(|l| !matches!(l, Ok(l) if l.is_empty() && !l.percent)) {
                Some(f) if percent(f) => {
                    state.leading_percent = Some(true);
                    f + 1..closing(f + 1).unwrap_or(lines.len())
                }
                Some(_) => {
                    state.leading_percent = Some(false);
                    0..lines.len()
                }
                None => 0..lines.len(),
            },
        };
        let leading_percent = state.leading_percent == Some(true);
        state.closed |= leading_percent && body.end < lines.len();
        state.lines += lines.len();
        let mut file = SourceFile {
            name: name.to_string(),
            text,
            endings,
            bytewise,
            bom,
            ranges,
            links: vec![Link::None; lines.len()],
            lines,
            arena,
            subs: HashMap::new(),
            sequence: HashMap::new(),
            programs: HashMap::new(),
            continues: !last && !state.closed,
            body,
            first_line,
            leading_percent,
        };
        file.index_numbers()?;
        match dialect {
            Dialect::LinuxCnc => {
                file.index_owords()?;
                crate::siemens::flow::index(&mut file)?;
            }
            Dialect::Fanuc => file.index_fanuc()?,
        }
        Ok(file)
    }

    /// The text of line `index`.
    pub fn line_text(&self, index: usize) -> &str {
        &self.text[self.ranges[index].clone()]
    }

    fn statement(&self, k: usize) -> Option<&Statement> {
        self.lines[k].as_ref().ok().and_then(|l| l.statement.as_ref())
    }

    fn index_owords(&mut self) -> Result<(), (usize, String)> {
        // open structures: (label, kind, line, branch lines so far)
        let mut stack: Vec<(Label, &'static str, usize, Vec<usize>)> = Vec::new();
        let err = |k: usize, m: String| Err((k, m));
        for k in self.body.clone() {
            let Some(Statement::O(label, kind)) = self.statement(k).cloned() else { continue };
            let top_is = |stack: &[(Label, &str, usize, Vec<usize>)], what: &str| stack.last().is_some_and(|t| t.0 == label && t.1 == what);
            match kind {
                OKind::Sub => {
                    if let Some(open) = stack.last() {
                        return err(k, format!("`{label} sub` inside `{} {}` of line {}", open.0, open.1, open.2 + 1));
                    }
                    stack.push((label, "sub", k, Vec::new()));
                }
                OKind::EndSub(_) => {
                    if !top_is(&stack, "sub") {
                        return err(k, format!("`{label} endsub` without its `{label} sub`"));
                    }
                    let (_, _, start, _) = stack.pop().expect("checked");
                    self.links[start] = Link::Sub { end: k };
                    self.links[k] = Link::SubEnd { start };
                    if self.subs.insert(label.clone(), (start, k)).is_some() {
                        return err(start, format!("subroutine `{label}` is defined twice"));
                    }
                }
                // `return` may carry the label of an enclosing `if` or loop (LinuxCNC's own samples do)
                OKind::Return(_) => match stack.iter().rev().find(|t| t.1 == "sub") {
                    Some(t) => self.links[k] = Link::SubEnd { start: t.2 },
                    None => return err(k, format!("`{label} return` outside a subroutine")),
                },
                OKind::If(_) => stack.push((label, "if", k, vec![k])),
                OKind::ElseIf(_) | OKind::Else => {
                    if !top_is(&stack, "if") {
                        return err(
                            k,
                            format!("`{label} {}` without its `{label} if`", if kind == OKind::Else { "else" } else { "elseif" }),
                        );
                    }
                    let top = stack.last_mut().expect("checked");
                    if top.3.len() > 1 && matches!(self.statement(*top.3.last().expect("branch")), Some(Statement::O(_, OKind::Else))) {
                        return err(k, format!("`{label}` has a branch after its `else`"));
                    }
                    top.3.push(k);
                }
                OKind::EndIf => {
                    if !top_is(&stack, "if") {
                        return err(k, format!("`{label} endif` without its `{label} if`"));
                    }
                    let (_, _, _, branches) = stack.pop().expect("checked");
                    for (i, &b) in branches.iter().enumerate() {
                        self.links[b] = Link::Branch { next: branches.get(i + 1).copied().unwrap_or(k), end: k };
                    }
                }
                OKind::While(_) if top_is(&stack, "do") => {
                    let (_, _, start, _) = stack.pop().expect("checked");
                    self.links[start] = Link::LoopStart { end: k };
                    self.links[k] = Link::LoopEnd { start };
                }
                OKind::While(_) => stack.push((label, "while", k, Vec::new())),
                OKind::Do => stack.push((label, "do", k, Vec::new())),
                OKind::Repeat(_) => stack.push((label, "repeat", k, Vec::new())),
                OKind::EndWhile | OKind::EndRepeat => {
                    let what = if kind == OKind::EndWhile { "while" } else { "repeat" };
                    if !top_is(&stack, what) {
                        return err(k, format!("`{label} end{what}` without its `{label} {what}`"));
                    }
                    let (_, _, start, _) = stack.pop().expect("checked");
                    self.links[start] = Link::LoopStart { end: k };
                    self.links[k] = Link::LoopEnd { start };
                }
                OKind::Break | OKind::Continue => {
                    if !stack.iter().any(|t| t.0 == label && matches!(t.1, "while" | "do" | "repeat")) {
                        return err(
                            k,
                            format!("`{label} {}` outside the loop `{label}`", if kind == OKind::Break { "break" } else { "continue" }),
                        );
                    }
                }
                OKind::Call(_) => {}
            }
        }
        if let Some((label, what, k, _)) = stack.pop() {
            return err(k, format!("`{label} {what}` is never closed"));
        }
        // break / continue: their loop's ends are known now
        for k in self.body.clone() {
            if let Some(Statement::O(label, OKind::Break | OKind::Continue)) = self.statement(k) {
                let start = (self.body.start..k)
                    .rev()
                    .find(|&s| {
                        matches!(self.links[s], Link::LoopStart { end } if end > k)
                            && matches!(self.statement(s), Some(Statement::O(l, _)) if l == label)
                    })
                    .expect("checked above");
                let Link::LoopStart { end } = self.links[start] else { unreachable!() };
                self.links[k] = Link::LoopJump { start, end };
            }
        }
        Ok(())
    }

    /// The `N` numbers and `O` program numbers (Fanuc family; Mach3/Mach4 subprograms).
    fn index_numbers(&mut self) -> Result<(), (usize, String)> {
        for k in self.body.clone() {
            let Ok(line) = &self.lines[k] else { continue };
            if let Some(n) = line.sequence {
                self.sequence.entry(n).or_default().push(k);
            }
            if let Some(o) = line.program_number {
                if self.programs.insert(o, k).is_some() {
                    return Err((k, format!("program O{o} appears twice")));
                }
            }
        }
        Ok(())
    }

    fn index_fanuc(&mut self) -> Result<(), (usize, String)> {
        let mut stack: Vec<(u32, usize)> = Vec::new();
        for k in self.body.clone() {
            let Ok(line) = &self.lines[k] else { continue };
            match line.statement {
                Some(Statement::While(_, m)) | Some(Statement::Do(m)) => stack.push((m, k)),
                Some(Statement::End(m)) => match stack.pop() {
                    Some((open, start)) if open == m => {
                        self.links[start] = Link::LoopStart { end: k };
                        self.links[k] = Link::LoopEnd { start };
                    }
                    Some((open, start)) => return Err((k, format!("END {m} closes DO {open} of line {}", start + 1))),
                    None => return Err((k, format!("END {m} without its DO {m}"))),
                },
                _ => {}
            }
        }
        if let Some((m, k)) = stack.pop() {
            return Err((k, format!("DO {m} without its END {m}")));
        }
        Ok(())
    }
}

/// Where subroutine files are looked for, in this order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SearchPath(pub Vec<PathBuf>);

/// A program: the main file (index 0) and the subroutine files loaded so far.
#[derive(Clone, Debug)]
pub struct Program {
    pub dialect: Dialect,
    /// The controller whose codes it is run with (of the family `dialect`).
    pub controller: crate::Controller,
    pub files: Vec<SourceFile>,
    pub search: SearchPath,
}

impl Program {
    /// The main file; an error names its line.
    pub fn new(name: &str, bytes: &[u8], dialect: Dialect, search: SearchPath) -> Result<Program, NcError> {
        let main = SourceFile::load(name, bytes, dialect)?;
        Ok(Program { dialect, controller: crate::Controller::of_family(dialect), files: vec![main], search })
    }

    /// The file holding subroutine `label`: the main file, a file loaded before, or `<name>.ngc`
    /// on the search path (LinuxCNC `o<name> call`); a Fanuc program number `O1234` is looked for
    /// in the loaded files, then on the search path as `O1234`, `O01234`, `1234` with `.nc`, `.NC`,
    /// `.ngc`, `.txt` or (for the `O` names) no extension.
    pub(crate) fn find_sub(&mut self, label: &Label) -> Result<(usize, usize, usize), String> {
        for (f, file) in self.files.iter().enumerate() {
            if let Some(&(start, end)) = file.subs.get(label) {
                return Ok((f, start, end));
            }
        }
        let Label::Name(name) = label else {
            return Err(format!("subroutine `{label}` is not defined"));
        };
        let candidates = [format!("{name}.ngc")];
        let (path, text) = self.read_on_path(&candidates).ok_or_else(|| {
            format!("subroutine `{label}` is neither in the program nor a file {name}.ngc on the search path ({})", self.search_list())
        })?;
        let file = SourceFile::load(&path, &text, self.dialect).map_err(|e| e.to_string())?;
        let &(start, end) = file.subs.get(label).ok_or_else(|| format!("{path} does not define `{label} sub`"))?;
        self.files.push(file);
        Ok((self.files.len() - 1, start, end))
    }

    /// The file and line of Fanuc program `O<number>`.
    pub(crate) fn find_program(&mut self, number: u32) -> Result<(usize, usize), String> {
        for (f, file) in self.files.iter().enumerate() {
            if let Some(&k) = file.programs.get(&number) {
                return Ok((f, k));
            }
        }
        // as the program is saved from a control (`O0010`, `O00010` on a 5-digit control) or by a
        // CAM post or a PC (`O10.nc`, `0010.nc`, `10.NC`)
        let names = [format!("O{number:04}"), format!("O{number:05}"), format!("O{number}"), format!("{number:04}"), format!("{number}")];
        let candidates: Vec<String> = names
            .iter()
            .flat_map(|n| [n.clone(), format!("{n}.nc"), format!("{n}.NC"), format!("{n}.ngc"), format!("{n}.txt")])
            .filter(|c| c.starts_with('O') || c.contains('.'))
            .collect();
        let (path, text) = self.read_on_path(&candidates).ok_or_else(|| {
            format!(
                "program O{number} is neither in the file (after M30, as `O{number} ... M99`) nor a file O{number} on the search path ({})",
                self.search_list()
            )
        })?;
        let file = SourceFile::load(&path, &text, self.dialect).map_err(|e| e.to_string())?;
        let &k = file.programs.get(&number).ok_or_else(|| format!("{path} does not start with O{number}"))?;
        self.files.push(file);
        Ok((self.files.len() - 1, k))
    }

    /// The file and first line of SINUMERIK subprogram `name` (`L10`, `PLATE`): a file loaded
    /// before, or `NAME.SPF`, `NAME.spf`, `_N_NAME_SPF` on the search path, read in the
    /// SINUMERIK's language.
    pub(crate) fn find_siemens_sub(&mut self, name: &str) -> Result<(usize, usize), String> {
        let candidates = [format!("{name}.SPF"), format!("{name}.spf"), format!("_N_{name}_SPF")];
        let loaded = |f: &SourceFile| {
            let base = std::path::Path::new(&f.name).file_name().map(|b| b.to_string_lossy().to_string());
            base.is_some_and(|b| candidates.contains(&b))
        };
        if let Some(f) = self.files.iter().skip(1).position(loaded) {
            return Ok((f + 1, self.files[f + 1].body.start));
        }
        let (path, text) = self.read_on_path(&candidates).ok_or_else(|| {
            format!("subprogram {name} is not a file {name}.SPF, {name}.spf or _N_{name}_SPF on the search path ({})", self.search_list())
        })?;
        let file = SourceFile::load_part(&path, &text, self.controller, &mut PartState::default(), true).map_err(|e| e.to_string())?;
        let start = file.body.start;
        self.files.push(file);
        Ok((self.files.len() - 1, start))
    }

    fn read_on_path(&self, candidates: &[String]) -> Option<(String, Vec<u8>)> {
        for dir in &self.search.0 {
            for c in candidates {
                let path = dir.join(c);
                if let Ok(text) = std::fs::read(&path) {
                    return Some((path.display().to_string(), text));
                }
            }
        }
        None
    }

    fn search_list(&self) -> String {
        if self.search.0.is_empty() {
            "empty".into()
        } else {
            self.search.0.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_structures_are_matched() {
        let text = "o1 sub\no2 if [#1 GT 0]\nG0 X1\no2 elseif [#1 LT 0]\nG0 X2\no2 else\nG0 X3\no2 endif\no3 do\no3 break\no3 while [1]\no1 endsub\nM2\n";
        let f = SourceFile::load("t.ngc", text.as_bytes(), Dialect::LinuxCnc).unwrap();
        assert_eq!(f.subs[&Label::Number(1)], (0, 11));
        assert_eq!(f.links[1], Link::Branch { next: 3, end: 7 });
        assert_eq!(f.links[3], Link::Branch { next: 5, end: 7 });
        assert_eq!(f.links[5], Link::Branch { next: 7, end: 7 });
        assert_eq!(f.links[8], Link::LoopStart { end: 10 });
        assert_eq!(f.links[9], Link::LoopJump { start: 8, end: 10 });
        assert_eq!(f.body, 0..13);
        let bad = SourceFile::load("t.ngc", b"o1 if [1]\nG0 X1\n", Dialect::LinuxCnc).unwrap_err();
        assert_eq!((bad.line, bad.message.as_str()), (1, "`o1 if` is never closed"));
        assert!(SourceFile::load("t.ngc", b"o1 endwhile\n", Dialect::LinuxCnc).is_err());
        let fanuc = "%\nO0001\nN10 #1=0\nWHILE [#1 LT 2] DO 1\n#1=#1+1\nEND 1\nM30\nO2000\nM99\n%\nignored\n";
        let f = SourceFile::load("t.nc", fanuc.as_bytes(), Dialect::Fanuc).unwrap();
        assert_eq!(f.body, 1..9);
        assert_eq!(f.links[3], Link::LoopStart { end: 5 });
        assert_eq!(f.programs[&2000], 7);
        assert_eq!(f.sequence[&10], vec![2]);
    }

    /// A Fanuc `M98 P9001` finds its program saved as the control saves it (`O9001`, `O09001.nc`) or
    /// as a PC names it (`9001.nc`, `9001.NC`): the first of these on the search path.
    #[test]
    fn o_programs_are_found_under_the_names_they_are_saved_as() {
        let dir = std::env::temp_dir().join(format!("trueaxis-o-names-{}", std::process::id()));
        for name in ["9001.nc", "O09002.nc", "9003.NC", "O9004"] {
            std::fs::create_dir_all(&dir).unwrap();
            let number: u32 = name.chars().filter(char::is_ascii_digit).collect::<String>().parse().unwrap();
            std::fs::write(dir.join(name), format!("%\nO{number}\nG0 X1.\nM99\n%\n")).unwrap();
        }
        let mut program = Program::new("main.nc", b"%\nO1\nM30\n%\n", Dialect::Fanuc, SearchPath(vec![dir.clone()])).unwrap();
        for number in [9001, 9002, 9003, 9004] {
            let (f, _) = program.find_program(number).unwrap_or_else(|e| panic!("{e}"));
            assert!(program.files[f].programs.contains_key(&number));
        }
        let missing = program.find_program(9005).unwrap_err();
        assert!(missing.starts_with("program O9005 is neither in the file"), "{missing}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
