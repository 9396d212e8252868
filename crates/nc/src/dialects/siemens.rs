//! Siemens SINUMERIK 840D sl, native language (SINUMERIK 840D sl Programming Manual Fundamentals:
//! the list of G functions). Its blocks are read by [`crate::siemens`], which states `TRANS` and
//! `ATRANS` as the `G52` shift, `SUPA` as `G53` and the cutting edge `D` as `G43`/`G49` (codes a
//! SINUMERIK program itself may not write: the reader refuses them in its text). A program in the
//! ISO dialect mode (`G291`) is a Fanuc program (`--dialect fanuc`).

use super::linuxcnc::{CUTTER_COMP, PROBING, SPINDLE_SYNC};
use super::Group::*;
use super::{g, refused, Comments, DialectTable, GCodes, Numbers, Unknown};
use crate::dialect::Dialect;

const POLAR: &str = "(polar coordinates) is not supported";
const WORKING_AREA: &str = "(working area limitation) is not supported";

const CODES: &[GCodes] = &[
    g(0, Motion),
    g(10, Motion),
    g(20, Motion),
    g(30, Motion),
    g(40, NonModal),
    g(90, Other),
    g(170, Plane),
    g(180, Plane),
    g(190, Plane),
    g(400, CutterComp),
    g(430, ToolLength),
    g(490, ToolLength),
    g(520, NonModal),
    refused(410, 420, CUTTER_COMP),
    g(530, NonModal),
    g(540, System),
    g(550, System),
    g(560, System),
    g(570, System),
    g(600, Path),
    g(640, Path),
    g(6010, Other),
    g(6020, Other),
    g(6030, Other),
    g(6410, Path),
    g(6420, Path),
    g(700, Units),
    g(710, Units),
    g(7000, Units),
    g(7100, Units),
    g(900, Distance),
    g(910, Distance),
    g(940, FeedMode),
    g(950, FeedMode),
    g(960, SpindleMode),
    g(970, SpindleMode),
    g(1530, NonModal),
    g(4500, Other),
    g(4510, Other),
    refused(330, 330, SPINDLE_SYNC),
    refused(3310, 3320, SPINDLE_SYNC),
    refused(1100, 1100, POLAR),
    refused(1110, 1110, POLAR),
    refused(1120, 1120, POLAR),
    refused(250, 250, WORKING_AREA),
    refused(260, 260, WORKING_AREA),
    refused(5000, 5000, "(settable zero offset off) is not supported"),
    refused(382, 385, PROBING),
];

pub static SIEMENS: DialectTable = DialectTable {
    name: "siemens",
    title: "Siemens SINUMERIK 840D (native)",
    source: "SINUMERIK 840D sl Programming Manual Fundamentals: list of G functions",
    family: Dialect::LinuxCnc,
    g_codes: &[CODES],
    m_codes: None,
    m_refused: &[],
    m_groups: &[&[0, 1, 2, 17, 30], &[3, 4, 5]],
    axis_codes: &[520, 1530],
    refused_words: &[],
    numbers: Numbers { integers_are_increments: false, decimals_mm: 4, decimals_inch: 5 },
    comments: Comments::Semicolon,
    unknown: Unknown::Alarm("the SINUMERIK stops with alarm 12470 (unknown G function)"),
    keeps_feed: false,
};
