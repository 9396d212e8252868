//! The header of a corrected program: comment lines naming trueaxis and the machine and error
//! files the program was corrected for, each with its SHA-256 (FIPS 180-4, the digest
//! `sha256sum FILE` prints), so that a program on the shop floor says what it was corrected for;
//! and the check that refuses to correct a corrected program again (the correction would be
//! applied twice), unless forced.
//!
//! Each header line stays within LinuxCNC's 252 characters (file names are shortened to their
//! last 100 characters); a Fanuc-family dialect gets it in upper case, without `<>#`.

use super::{Dialect, NcError};
use sha2::{Digest, Sha256};

/// A file by its name (as given) and the SHA-256 of its bytes (lower-case hexadecimal).
#[derive(Clone, Debug, PartialEq)]
pub struct FileId {
    pub name: String,
    pub sha256: String,
}

impl FileId {
    pub fn of(name: &str, bytes: &[u8]) -> FileId {
        let digest = Sha256::digest(bytes);
        FileId { name: name.to_string(), sha256: digest.iter().map(|b| format!("{b:02x}")).collect() }
    }
}

/// What a corrected program was corrected for.
#[derive(Clone, Debug, PartialEq)]
pub struct Header {
    pub machine: FileId,
    pub errors: FileId,
}

/// The words every header's first line starts with (case-insensitive): the mark [`find`] looks for.
const MARK: &str = "trueaxis";
const CORRECTED: &str = "corrected program";

impl Header {
    /// The comment lines of the header in `dialect`.
    pub fn lines(&self, dialect: Dialect) -> Vec<String> {
        let short = |s: &str| {
            let chars: Vec<char> = s.chars().filter(|c| !matches!(c, '(' | ')')).collect();
            chars[chars.len().saturating_sub(100)..].iter().collect::<String>()
        };
        let lines = [
            format!("({MARK} {}: {CORRECTED}; do not correct it again)", env!("CARGO_PKG_VERSION")),
            format!("({MARK} machine {} sha256 {})", short(&self.machine.name), self.machine.sha256),
            format!("({MARK} errors {} sha256 {})", short(&self.errors.name), self.errors.sha256),
        ];
        match dialect {
            Dialect::LinuxCnc => lines.to_vec(),
            Dialect::Fanuc => lines.iter().map(|l| l.to_uppercase().replace(['<', '>', '#'], " ")).collect(),
        }
    }
}

/// The comment line that states the tool-length assumption: the tools that were not in a tool
/// table, the length they were taken as, and how far 100 mm of a real tool's length from it moves
/// that tool's corrected points (um, rounded to 0.1).
pub fn assumed_tools_line(tools: &[u32], setup: &super::ProgramSetup, um_per_100mm: f64, dialect: Dialect) -> String {
    let mut names: Vec<String> = tools.iter().take(12).map(|t| format!("T{t}")).collect();
    if tools.len() > 12 {
        names.push(format!("and {} more", tools.len() - 12));
    }
    let length = match setup.unknown_tools {
        super::UnknownTools::Assume(l) => l * if setup.machine_inch { super::MM_PER_INCH } else { 1.0 },
        super::UnknownTools::Refuse => 0.0,
    };
    let line = format!(
        "({MARK}: {} not in a tool table, taken as {length} mm long from the machine file's tool point; \
         100 mm of a real tool's length from that moves its corrected points by up to {um_per_100mm:.1} um)",
        names.join(" ")
    );
    match dialect {
        Dialect::LinuxCnc => line,
        Dialect::Fanuc => line.to_uppercase().replace(['<', '>', '#'], " "),
    }
}

/// The first line (1-based) of the first 100 whose comment says the program was corrected by
/// trueaxis (a header, or the note on expanded parts of an older version), and that comment.
pub fn find(program: &[u8]) -> Option<(usize, String)> {
    for (k, line) in program.split(|&b| b == b'\n' || b == b'\r').filter(|l| !l.is_empty()).take(100).enumerate() {
        let text = String::from_utf8_lossy(line).to_ascii_lowercase();
        for comment in text.split(['(', ';']).skip(1) {
            let body = comment.trim_start();
            if body.starts_with(MARK) && body.contains(CORRECTED) {
                let end = comment.find(')').unwrap_or(comment.len());
                return Some((k + 1, comment[..end].trim().to_string()));
            }
        }
    }
    None
}

/// Refuses a program that carries the mark of a correction.
pub fn check_uncorrected(program: &[u8], origin: &str) -> Result<(), NcError> {
    match find(program) {
        None => Ok(()),
        Some((line, comment)) => Err(NcError {
            file: origin.to_string(),
            line,
            message: format!(
                "this program was corrected by trueaxis already (`{comment}`): correcting it again would apply the correction twice; \
                 correct the original program (or give --force)"
            ),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digests_lines_and_the_mark() {
        // FIPS 180-4 examples
        assert_eq!(FileId::of("a", b"abc").sha256, "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
        assert_eq!(FileId::of("e", b"").sha256, "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
        let h = Header { machine: FileId::of("m.toml", b"abc"), errors: FileId::of(&"x".repeat(300), b"") };
        for dialect in [Dialect::LinuxCnc, Dialect::Fanuc] {
            let lines = h.lines(dialect);
            assert!(lines.iter().all(|l| l.len() <= 252), "{lines:?}");
            let text = format!("%\nO1\n{}\nG0 X1\n", lines.join("\n"));
            assert_eq!(find(text.as_bytes()).map(|f| f.0), Some(3));
            assert!(check_uncorrected(text.as_bytes(), "p.nc").unwrap_err().to_string().starts_with("p.nc: line 3: this program"));
        }
        assert_eq!(find(b"(trueaxis: corrected program; expanded into plain moves)\nG0 X1\n").map(|f| f.0), Some(1));
        // the tool line is one comment (no parentheses inside: LinuxCNC refuses nested comments)
        let setup = crate::compensate::nc::ProgramSetup::zero(&crate::compensate::nc::MachineAxes { name: "m".into(), axes: vec![] });
        let tools = assumed_tools_line(&[1, 2], &setup, 3.81, Dialect::LinuxCnc);
        assert_eq!(tools.matches('(').count() + tools.matches(')').count(), 2, "{tools}");
        assert!(tools.ends_with("by up to 3.8 um)"), "{tools}");
        assert_eq!(find(b"G0 X1 (corrected by hand)\n; trueaxis rocks\n"), None);
    }
}
