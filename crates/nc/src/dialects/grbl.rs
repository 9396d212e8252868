//! grbl 1.1 (the grbl wiki, "Grbl v1.1 Commands", and `doc/markdown/commands.md` of gnea/grbl): the
//! G and M codes it supports and nothing else; any other code stops it with `error:20`
//! (unsupported or invalid g-code command). Read as RS274/NGC. No canned cycles, no tool length
//! offset from a table (only `G43.1` dynamic), no `G59.x`, no parameters or subprograms. Its `$`
//! system commands and `$J=` jogs: [`crate::grbl_system`].

use super::linuxcnc::{CUTTER_COMP, PROBING, RS274_NUMBERS};
use super::Group::*;
use super::{g, g_range, m, refused, Comments, DialectTable, GCodes, MCodes, Unknown};
use crate::dialect::Dialect;

const CODES: &[GCodes] = &[
    g(0, Motion),
    g(10, Motion),
    g(20, Motion),
    g(30, Motion),
    g(800, Motion),
    g(40, NonModal),
    g(100, NonModal),
    g(170, Plane),
    g(180, Plane),
    g(190, Plane),
    g(200, Units),
    g(210, Units),
    g(280, NonModal),
    g(281, NonModal),
    g(300, NonModal),
    g(301, NonModal),
    refused(382, 385, PROBING),
    g(400, CutterComp),
    g(431, ToolLength),
    g(490, ToolLength),
    g(530, NonModal),
    g(540, System),
    g(550, System),
    g(560, System),
    g(570, System),
    g(580, System),
    g(590, System),
    g(610, Path),
    g(900, Distance),
    g(910, Distance),
    g(911, ArcDistance),
    g_range(920, 921, NonModal),
    g(930, FeedMode),
    g(940, FeedMode),
    refused(410, 411, CUTTER_COMP),
    refused(420, 421, CUTTER_COMP),
];

/// M0 M1 (ignored) M2 M30, M3-M5, M7-M9, M56 (parking override).
const M_CODES: &[MCodes] = &[m(0, 5), m(7, 9), m(30, 30), m(56, 56)];

pub static GRBL: DialectTable = DialectTable {
    name: "grbl",
    title: "grbl 1.1",
    source: "grbl wiki, Grbl v1.1 Commands; gnea/grbl doc/markdown/commands.md",
    family: Dialect::LinuxCnc,
    g_codes: &[CODES],
    m_codes: Some(&[M_CODES]),
    m_refused: &[],
    // grbl's modal groups M4 (stopping), M7 (spindle), M8 (coolant: M7 and M8 together is error:21)
    m_groups: &[&[0, 1, 2, 30], &[3, 4, 5], &[7, 8, 9]],
    axis_codes: &[100, 280, 300, 920, 431],
    refused_words: &[],
    numbers: RS274_NUMBERS,
    comments: Comments::ParenthesesAndSemicolon,
    unknown: Unknown::Alarm("grbl 1.1 stops here with error:20 (unsupported or invalid g-code command)"),
    keeps_feed: true,
};
