//! The controllers whose programs are read, each as a table of data: which G codes it knows and
//! in which modal group, which it refuses and why, which M codes it knows, which codes take axis
//! words, how its numbers and comments are written, and what it does with a code it does not know.
//! The grammar of a block (expressions, parameters, subprograms, the meaning of a number without a
//! decimal point) is that of its family, [`Dialect`]: RS274/NGC as LinuxCNC reads it, or the ISO
//! and Custom Macro B language of a Fanuc. docs/nc.md prints every table ([`DialectTable::markdown`]
//! writes them; a test keeps the page and the tables equal).
//!
//! G codes are held as ten times their number (`G59.3` is 593, `G1` is 10), as the interpreter
//! holds them.

mod docs;
mod fanuc;
mod grbl;
mod linuxcnc;
mod mach;
mod siemens;

use crate::dialect::Dialect;
use std::fmt;

/// Modal groups of G codes (a code of a group replaces the one before it; two of one group on a
/// line are refused).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Group {
    /// Motion: G0-G3, canned cycles, splines, G80 (Fanuc: groups 01 and 09).
    Motion,
    Plane,
    Distance,
    /// Arc centre distance mode (G90.1/G91.1).
    ArcDistance,
    FeedMode,
    Units,
    CutterComp,
    ToolLength,
    /// Canned cycle return level (G98/G99).
    Retract,
    /// Work coordinate systems.
    System,
    /// Path control (exact stop, blending).
    Path,
    /// Spindle speed mode (G96/G97).
    SpindleMode,
    /// Lathe diameter/radius mode (G7/G8).
    Lathe,
    /// G4, G10, G28, G30, G52, G53, G92 and the like: for their own block.
    NonModal,
    /// Passed through unchanged, without effect on positions.
    Other,
    /// Not a code of the dialect: passed through with a warning when its line has no axis words.
    Unknown,
}

/// What a G code (or a range of them) is in a dialect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Meaning {
    In(Group),
    /// Refused, with the reason (after the code: `G41 (cutter radius compensation) cannot ...`).
    Refused(&'static str),
}

/// G codes `from..=to` (x 10) and their meaning.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GCodes {
    pub from: u16,
    pub to: u16,
    pub meaning: Meaning,
}

/// One G code (x 10) in `group`.
pub const fn g(code: u16, group: Group) -> GCodes {
    GCodes { from: code, to: code, meaning: Meaning::In(group) }
}

/// The G codes `from..=to` (x 10: every tenth in between too) in `group`.
pub const fn g_range(from: u16, to: u16, group: Group) -> GCodes {
    GCodes { from, to, meaning: Meaning::In(group) }
}

/// G codes `from..=to` (x 10) refused for `why`.
pub const fn refused(from: u16, to: u16, why: &'static str) -> GCodes {
    GCodes { from, to, meaning: Meaning::Refused(why) }
}

/// M codes `from..=to`, and when they are refused, why.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MCodes {
    pub from: u16,
    pub to: u16,
    pub refused: Option<&'static str>,
}

pub const fn m(from: u16, to: u16) -> MCodes {
    MCodes { from, to, refused: None }
}

pub const fn m_refused(from: u16, to: u16, why: &'static str) -> MCodes {
    MCodes { from, to, refused: Some(why) }
}

/// How the controller reads and how trueaxis writes numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Numbers {
    /// A dimension word without a decimal point counts in least input increments (`X10` is
    /// 0.010 mm on a Fanuc with IS-B), else in mm or inch.
    pub integers_are_increments: bool,
    /// Decimals written in mm (and deg) and in inch by default.
    pub decimals_mm: usize,
    pub decimals_inch: usize,
}

/// Comment syntax.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Comments {
    /// `( ... )` and `;` to the end of the line (LinuxCNC, Mach3/Mach4, grbl).
    ParenthesesAndSemicolon,
    /// `( ... )`; `;` is the end of block (EOB) a Fanuc punches after every block.
    ParenthesesSemicolonEndsBlock,
    /// `;` to the end of the line; `( )` group expressions (Siemens).
    Semicolon,
}

/// What the controller does with a code it does not know.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unknown {
    /// A machine's own code: passed through unchanged with a warning naming the line, assumed to
    /// move nothing; refused with the line when the line has axis words.
    PassThrough,
    /// The controller stops with this alarm: refused with the line.
    Alarm(&'static str),
}

/// The data of one controller's dialect.
#[derive(Debug)]
pub struct DialectTable {
    /// The `--dialect` name.
    pub name: &'static str,
    /// The controller, as the user knows it.
    pub title: &'static str,
    /// Where its codes come from (manuals, documentation).
    pub source: &'static str,
    /// The grammar its blocks are read in.
    pub family: Dialect,
    /// G codes, searched in order: the first entry holding a code gives its meaning.
    pub g_codes: &'static [&'static [GCodes]],
    /// Known M codes (searched in order); `None`: every M code (a Fanuc's machine M codes are the
    /// builder's) passes through.
    pub m_codes: Option<&'static [&'static [MCodes]]>,
    /// M codes refused whatever the list above says.
    pub m_refused: &'static [MCodes],
    /// M codes of which a line holds one at most.
    pub m_groups: &'static [&'static [u16]],
    /// G codes other than motion that take the line's axis words (x 10).
    pub axis_codes: &'static [u16],
    /// Words refused wherever they stand, and why (`E` fixture offsets on a Fadal).
    pub refused_words: &'static [(u8, &'static str)],
    pub numbers: Numbers,
    pub comments: Comments,
    pub unknown: Unknown,
    /// Whether a feed move before any `F` runs at the feed rate an earlier program left (grbl keeps
    /// it until a reset; grbl wiki, error:22 "feed rate has not yet been set"): passed with a
    /// warning. Otherwise it is refused, as LinuxCNC ("Cannot do G1 with zero feed rate") and a
    /// Fanuc (alarm PS0011) stop there.
    pub keeps_feed: bool,
}

impl DialectTable {
    /// The meaning of G code `code` (x 10).
    pub fn g_meaning(&self, code: u16) -> Meaning {
        self.g_codes
            .iter()
            .flat_map(|list| list.iter())
            .find(|e| (e.from..=e.to).contains(&code))
            .map_or(Meaning::In(Group::Unknown), |e| e.meaning)
    }

    /// The group of G code `code` (x 10), or why it is refused.
    pub(crate) fn group(&self, code: u16) -> Result<Group, String> {
        match self.g_meaning(code) {
            Meaning::In(group) => Ok(group),
            Meaning::Refused(why) => Err(format!("G{} {why}", gcode_text(code))),
        }
    }

    /// Whether M code `code` is known (`Ok(false)`: unknown), or why it is refused.
    pub(crate) fn m_known(&self, code: u16) -> Result<bool, String> {
        if let Some(r) = self.m_refused.iter().find(|e| (e.from..=e.to).contains(&code)) {
            return Err(format!("M{code} {}", r.refused.unwrap_or("is refused")));
        }
        let Some(lists) = self.m_codes else { return Ok(true) };
        Ok(lists.iter().flat_map(|l| l.iter()).any(|e| (e.from..=e.to).contains(&code)))
    }

    /// Whether G code `code` (x 10), not a motion, takes the line's axis words.
    pub fn uses_axes(&self, code: u16) -> bool {
        self.axis_codes.contains(&code)
    }
}

/// The controllers whose dialects are read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Controller {
    LinuxCnc,
    Fanuc,
    Haas,
    Mach3,
    Mach4,
    Grbl,
    Fadal,
    Siemens,
}

impl Controller {
    pub const ALL: [Controller; 8] = [
        Controller::LinuxCnc,
        Controller::Fanuc,
        Controller::Haas,
        Controller::Mach3,
        Controller::Mach4,
        Controller::Grbl,
        Controller::Fadal,
        Controller::Siemens,
    ];

    /// The table of the dialect.
    pub fn table(self) -> &'static DialectTable {
        match self {
            Controller::LinuxCnc => &linuxcnc::LINUXCNC,
            Controller::Fanuc => &fanuc::FANUC,
            Controller::Haas => &fanuc::HAAS,
            Controller::Fadal => &fanuc::FADAL,
            Controller::Mach3 => &mach::MACH3,
            Controller::Mach4 => &mach::MACH4,
            Controller::Grbl => &grbl::GRBL,
            Controller::Siemens => &siemens::SIEMENS,
        }
    }

    /// The grammar its blocks are read in.
    pub fn family(self) -> Dialect {
        self.table().family
    }

    /// What reads its lines: the family's lexer, or the SINUMERIK's own.
    pub(crate) fn line_reader(self) -> crate::program::LineReader {
        match self {
            Controller::Siemens => crate::siemens::parse_line,
            Controller::Fadal => crate::fadal::parse_line,
            _ => crate::lexer::parse_line,
        }
    }

    /// The controller that stands for a family when none is named (LinuxCNC, Fanuc).
    pub fn of_family(family: Dialect) -> Controller {
        match family {
            Dialect::LinuxCnc => Controller::LinuxCnc,
            Dialect::Fanuc => Controller::Fanuc,
        }
    }

    /// A `--dialect` name (case-insensitive; `rs274ngc`, `ngc` for LinuxCNC, `840d`, `sinumerik`
    /// for Siemens).
    pub fn parse(name: &str) -> Option<Controller> {
        let name = name.to_ascii_lowercase();
        let alias = match name.as_str() {
            "rs274ngc" | "ngc" => "linuxcnc",
            "840d" | "sinumerik" => "siemens",
            other => other,
        };
        Controller::ALL.into_iter().find(|c| c.table().name == alias)
    }

    /// The names `--dialect` takes, `a|b|c`.
    pub fn names() -> String {
        Controller::ALL.map(|c| c.table().name).join("|")
    }

    /// The dialect a program is written in: its family from [`Dialect::detect`], then the
    /// controller from codes only it has (docs/nc.md, "Which dialect").
    pub fn detect(text: &str) -> Controller {
        detect::controller(text)
    }
}

impl fmt::Display for Controller {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.table().name)
    }
}

impl From<Dialect> for Controller {
    fn from(family: Dialect) -> Controller {
        Controller::of_family(family)
    }
}

mod detect;

/// The text of a G code held in tenths (`593` -> `59.3`, `10` -> `1`), as the tables key them.
pub fn gcode_text(code: u16) -> String {
    if code % 10 == 0 {
        format!("{}", code / 10)
    } else {
        format!("{}.{}", code / 10, code % 10)
    }
}

pub use docs::markdown;
