//! The Fanuc family: Fanuc 0i/30i with Custom Macro B (operator's manuals, B-64484EN and
//! B-63944EN, G code lists), Haas (Fanuc plus its own codes: Haas Mill Operator's Manual, NGC, "G-codes"
//! and "M-codes"), and Fadal format 2 (Fanuc-compatible codes; Fadal VMC programming manual).

use super::linuxcnc::{AXIS_CODES, COMMON};
use super::Group::*;
use super::{g, refused, Comments, DialectTable, GCodes, Numbers, Unknown};
use crate::dialect::Dialect;

/// A Fanuc's own codes (the rest in [`COMMON`]).
const OWN: &[GCodes] = &[
    g(440, ToolLength),
    g(541, System),
    g(620, Path),
    g(630, Path),
    g(650, NonModal),
    g(930, FeedMode),
    g(931, FeedMode),
    // tapping (rigid with `M29 S..` before it): kept as a cycle
    g(740, Motion),
    g(840, Motion),
    // G9 exact stop, G5.1 AI contour, G8 look-ahead, G50 scaling off, G67 modal macro off, G69
    // rotation off, G15 polar off, G11 parameter input off: no effect on positions
    g(90, Other),
    g(51, Other),
    g(80, Other),
    g(500, Other),
    g(670, Other),
    g(690, Other),
    g(150, Other),
    g(110, Other),
    refused(760, 760, "(boring with spindle orientation and shift) cannot be expanded: the shift direction is a machine parameter"),
    refused(870, 870, "(boring with spindle orientation and shift) cannot be expanded: the shift direction is a machine parameter"),
    refused(880, 880, "(boring with manual retraction) cannot be expanded"),
    refused(160, 160, "(polar coordinate command) is not supported"),
    refused(310, 310, "(skip function) stops where a signal comes: the moves after it are not known beforehand"),
    refused(270, 270, "(reference position check/return from reference) is not supported"),
    refused(290, 290, "(reference position check/return from reference) is not supported"),
    refused(510, 511, "(scaling/mirroring) is not supported"),
    refused(680, 680, "(coordinate rotation / tilted working plane) is not supported"),
    refused(682, 683, "(coordinate rotation / tilted working plane) is not supported"),
    refused(434, 435, "(tool centre point / tool axis direction control) is not supported: correct the program in machine axes"),
    refused(531, 531, "(tool centre point / tool axis direction control) is not supported: correct the program in machine axes"),
    refused(660, 660, "(modal macro call) is not supported"),
    refused(120, 120, THREADING_OR_CIRCLE),
    refused(130, 130, THREADING_OR_CIRCLE),
    refused(320, 320, THREADING_OR_CIRCLE),
    refused(330, 330, THREADING_OR_CIRCLE),
    refused(340, 340, THREADING_OR_CIRCLE),
    refused(350, 350, THREADING_OR_CIRCLE),
];

const THREADING_OR_CIRCLE: &str = "is not supported (threading or circle cutting cycles)";

/// M codes of which a Fanuc line holds one at most (program stops, spindle); the rest are the
/// machine builder's.
const M_GROUPS: &[&[u16]] = &[&[0, 1, 2, 30], &[3, 4, 5]];

const FANUC_NUMBERS: Numbers = Numbers { integers_are_increments: true, decimals_mm: 3, decimals_inch: 4 };

/// The Fanuc table, from which the controllers of its family (Haas, Fadal) differ in a few fields.
const FANUC_BASE: DialectTable = DialectTable {
    name: "fanuc",
    title: "Fanuc 0i/30i (Custom Macro B)",
    source: "Fanuc Series 0i-MF and 30i-B operator's manuals (B-64604EN, B-64484EN): G code lists, Custom Macro B",
    family: Dialect::Fanuc,
    g_codes: &[COMMON, OWN],
    m_codes: None,
    m_refused: &[],
    m_groups: M_GROUPS,
    axis_codes: AXIS_CODES,
    refused_words: &[],
    numbers: FANUC_NUMBERS,
    comments: Comments::ParenthesesSemicolonEndsBlock,
    unknown: Unknown::PassThrough,
    keeps_feed: false,
};

pub static FANUC: DialectTable = FANUC_BASE;

/// Haas's codes beyond a Fanuc's.
const HAAS_OWN: &[GCodes] = &[
    // G154 P1-P99: the additional work offsets, read like G54.1 P
    g(1540, System),
    // G103 block look-ahead limit, G187 smoothness and accuracy: no effect on positions
    g(1030, Other),
    g(1870, Other),
    refused(470, 470, "(text engraving) makes moves of its own from a text: not supported"),
    refused(1000, 1000, "(mirror image) is not supported"),
    refused(1010, 1010, "(mirror image) is not supported"),
    refused(1500, 1500, "(general-purpose pocket milling) makes moves of its own: not supported"),
    refused(2340, 2340, "(tool centre point control) is not supported: correct the program in machine axes"),
    refused(2540, 2540, "(dynamic work offset) is not supported: correct the program in machine axes"),
];

pub static HAAS: DialectTable = DialectTable {
    name: "haas",
    title: "Haas (NGC and classic control)",
    source: "Haas Mill Operator's Manual (Next Generation Control): G-codes, M-codes, macros",
    g_codes: &[HAAS_OWN, COMMON, OWN],
    ..FANUC_BASE
};

/// A Fadal's codes where they differ from a Fanuc's (Fadal VMC programming manual, G and M code
/// summary): `G51` is its ramp slope control and `G51.2` its tool load compensation (feeds only);
/// `G45`-`G48` expand or reduce a move by the tool's offset; `G84.1`/`G74.1` are its rigid tapping
/// cycles and `G84.2`/`G74.2` their set-up, not read yet; `M17` ends a Fadal subroutine.
const FADAL_OWN: &[GCodes] = &[
    g(510, Other),
    g(512, Other),
    refused(450, 450, TOOL_OFFSET_MOVE),
    refused(460, 460, TOOL_OFFSET_MOVE),
    refused(470, 470, TOOL_OFFSET_MOVE),
    refused(480, 480, TOOL_OFFSET_MOVE),
    refused(511, 511, "(mirror image) is not supported"),
    refused(741, 742, "(Fadal rigid tapping) is not read yet: write G74 (floating tap)"),
    refused(841, 842, "(Fadal rigid tapping) is not read yet: write G84 (floating tap)"),
];

const TOOL_OFFSET_MOVE: &str = "(tool offset single/double expansion or reduction) moves by the tool's offset: not supported";

pub static FADAL: DialectTable = DialectTable {
    name: "fadal",
    title: "Fadal (format 2)",
    source: "Fadal VMC programming manual (format 2), section 1 summary: NC words, G and M codes; macro statements",
    g_codes: &[FADAL_OWN, COMMON, OWN],
    m_refused: &[super::m_refused(
        17,
        17,
        "(end of a Fadal subroutine) is not read yet: write the subroutine as an O program called by M98",
    )],
    ..FANUC_BASE
};
