//! LinuxCNC 2.9 (RS274/NGC as `interp_*.cc` of LinuxCNC and its manual's "G-code overview" and
//! "M-codes" pages define it), and the G codes every dialect of the RS274 family shares (NIST
//! RS274/NGC version 3, Kramer, Proctor and Messina 2000; the Fanuc 0i/30i operator's manuals).

use super::Group::*;
use super::{g, g_range, m, m_refused, refused, Comments, DialectTable, GCodes, MCodes, Numbers, Unknown};
use crate::dialect::Dialect;

pub(super) const CUTTER_COMP: &str =
    "(cutter radius compensation) cannot be corrected point by point: program the tool-centre path (CAM: compensation in computer)";
pub(super) const PROBING: &str = "(probing) stops where the probe touches: the moves after it are not known beforehand";
pub(super) const SPINDLE_SYNC: &str = "(spindle-synchronised motion) is locked to the spindle position and cannot be split or shifted";

/// The codes RS274/NGC and the Fanuc family share, with one meaning.
pub(super) const COMMON: &[GCodes] = &[
    g(0, Motion),
    g(10, Motion),
    g(20, Motion),
    g(30, Motion),
    g(730, Motion),
    g(800, Motion),
    g(810, Motion),
    g(820, Motion),
    g(830, Motion),
    g(850, Motion),
    g(860, Motion),
    g(890, Motion),
    g(170, Plane),
    g(180, Plane),
    g(190, Plane),
    g(900, Distance),
    g(910, Distance),
    g(200, Units),
    g(210, Units),
    g(400, CutterComp),
    g(430, ToolLength),
    g(490, ToolLength),
    g(980, Retract),
    g(990, Retract),
    g(540, System),
    g(550, System),
    g(560, System),
    g(570, System),
    g(580, System),
    g(590, System),
    g(610, Path),
    g(640, Path),
    g(40, NonModal),
    g(100, NonModal),
    g(280, NonModal),
    g(300, NonModal),
    g(520, NonModal),
    g(530, NonModal),
    g(920, NonModal),
    g(940, FeedMode),
    g(950, FeedMode),
    g(960, SpindleMode),
    g(970, SpindleMode),
    refused(410, 411, CUTTER_COMP),
    refused(420, 421, CUTTER_COMP),
    refused(382, 385, PROBING),
];

/// LinuxCNC's own codes.
const OWN: &[GCodes] = &[
    refused(330, 331, SPINDLE_SYNC),
    refused(760, 760, SPINDLE_SYNC),
    g(740, Motion),
    g(840, Motion),
    g(870, Motion),
    g(880, Motion),
    g(901, ArcDistance),
    g(911, ArcDistance),
    g(930, FeedMode),
    g(431, ToolLength),
    g(432, ToolLength),
    g_range(591, 593, System),
    g(611, Path),
    g(70, Lathe),
    g(80, Lathe),
    g(281, NonModal),
    g(301, NonModal),
    g_range(921, 923, NonModal),
    g(50, Motion),
    g(51, Motion),
    g(52, Motion),
    g(53, Motion),
    refused(700, 700, "(lathe roughing cycle) is not supported"),
    refused(710, 711, "(lathe roughing cycle) is not supported"),
    refused(720, 721, "(lathe roughing cycle) is not supported"),
    refused(171, 171, "(U V W planes) is not supported"),
    refused(181, 181, "(U V W planes) is not supported"),
    refused(191, 191, "(U V W planes) is not supported"),
];

/// LinuxCNC's M codes (M100-M199 are user programs: passed through).
const M_CODES: &[MCodes] = &[m(0, 9), m(19, 19), m(30, 30), m(48, 53), m(60, 68), m(70, 73), m(100, 199)];

/// The M code groups of RS274/NGC (stopping, spindle, tool change, overrides, modal state).
pub(super) const M_GROUPS: &[&[u16]] = &[&[0, 1, 2, 30, 60], &[3, 4, 5], &[6, 61], &[48, 49, 50, 51, 52, 53], &[70, 71, 72, 73]];

/// G codes other than motion that take axis words in RS274/NGC.
pub(super) const AXIS_CODES: &[u16] = &[100, 280, 300, 520, 920, 431, 432];

pub(super) const RS274_NUMBERS: Numbers = Numbers { integers_are_increments: false, decimals_mm: 5, decimals_inch: 6 };

pub(super) const FANUC_SUBPROGRAM: &str = "is a Fanuc subprogram call; this program reads as LinuxCNC (choose --dialect fanuc?)";

pub static LINUXCNC: DialectTable = DialectTable {
    name: "linuxcnc",
    title: "LinuxCNC 2.9",
    source: "LinuxCNC 2.9 manual, G-code overview and M-codes; interp_*.cc",
    family: Dialect::LinuxCnc,
    g_codes: &[OWN, COMMON],
    m_codes: Some(&[M_CODES]),
    m_refused: &[m_refused(98, 99, FANUC_SUBPROGRAM)],
    m_groups: M_GROUPS,
    axis_codes: AXIS_CODES,
    refused_words: &[],
    numbers: RS274_NUMBERS,
    comments: Comments::ParenthesesAndSemicolon,
    unknown: Unknown::PassThrough,
    keeps_feed: false,
};
