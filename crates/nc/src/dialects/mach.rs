//! Mach3 and Mach4 (Artsoft/Newfangled Solutions): RS274/NGC-based ("Using Mach3Mill", chapter 10
//! "G- and M-code language reference"; "Mach4 Mill G and M code reference"). Their programs are
//! read as RS274/NGC: a number without a decimal point is in mm or inch. Their subprograms are a
//! Fanuc's (`M98 P.. L..`, `O` after `M30`, `M99`: [`crate::subprograms`]).

use super::linuxcnc::{AXIS_CODES, COMMON, PROBING, RS274_NUMBERS};
use super::Group::*;
use super::{g, g_range, m, m_refused, refused, Comments, DialectTable, GCodes, MCodes, Unknown};
use crate::dialect::Dialect;

const CIRCULAR_POCKET: &str = "(circular pocket) makes moves of its own: not supported";

const OWN: &[GCodes] = &[
    g(740, Motion),
    g(840, Motion),
    g(880, Motion),
    g(901, ArcDistance),
    g(911, ArcDistance),
    g(930, FeedMode),
    g(281, NonModal),
    g_range(921, 923, NonModal),
    // G15 polar off, G50 scaling off, G69 rotation off
    g(150, Other),
    g(500, Other),
    g(690, Other),
    refused(120, 120, CIRCULAR_POCKET),
    refused(130, 130, CIRCULAR_POCKET),
    refused(160, 160, "(polar coordinates) is not supported"),
    refused(310, 310, PROBING),
    refused(510, 510, "(scaling) is not supported"),
    refused(680, 680, "(coordinate rotation) is not supported"),
    refused(700, 700, "(inch by G70, Mach3's old form) is not supported: write G20"),
    refused(710, 710, "(mm by G71, Mach3's old form) is not supported: write G21"),
];

/// Mach4's codes beyond Mach3's.
const MACH4_OWN: &[GCodes] = &[refused(650, 660, "(macro call) is not supported")];

/// M0-M9, M30, M48/M49 (override on/off), M98/M99 (subprogram call and return); M100-M999 are
/// user macros (passed through).
const M_CODES: &[MCodes] = &[m(0, 9), m(30, 30), m(48, 49), m(98, 99), m(100, 999)];

/// M codes of which a line holds one at most.
const M_GROUPS: &[&[u16]] = &[&[0, 1, 2, 30], &[3, 4, 5], &[48, 49]];

const M_REFUSED: &[MCodes] = &[m_refused(47, 47, "(repeat from the first line) runs the program endlessly")];

/// The Mach3 table; Mach4 adds refusals of its own.
const MACH3_BASE: DialectTable = DialectTable {
    name: "mach3",
    title: "Mach3",
    source: "Using Mach3Mill, G- and M-code language reference",
    family: Dialect::LinuxCnc,
    g_codes: &[OWN, COMMON],
    m_codes: Some(&[M_CODES]),
    m_refused: M_REFUSED,
    m_groups: M_GROUPS,
    axis_codes: AXIS_CODES,
    refused_words: &[],
    numbers: RS274_NUMBERS,
    comments: Comments::ParenthesesAndSemicolon,
    unknown: Unknown::PassThrough,
    keeps_feed: false,
};

pub static MACH3: DialectTable = MACH3_BASE;

pub static MACH4: DialectTable = DialectTable {
    name: "mach4",
    title: "Mach4",
    source: "Mach4 Mill G and M code reference",
    g_codes: &[MACH4_OWN, OWN, COMMON],
    ..MACH3_BASE
};
