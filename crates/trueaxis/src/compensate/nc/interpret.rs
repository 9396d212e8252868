//! Interpretation of RS274/NGC blocks into moves in machine axis positions: the modal state (motion
//! mode G0/G1/G2/G3, distance mode G90/G91, units G20/G21, plane G17/G18/G19, work offsets
//! G54-G59, G53 machine coordinates), and a clear refusal of everything that would change the meaning
//! of coordinates in ways this corrector does not model (cutter and tool-length compensation, G92,
//! G10, G28/G30, canned cycles, inverse-time feed, absolute arc centres).

use super::parse::Block;
use crate::machine::{AxisKind, Machine};

/// Millimetres per inch.
pub const MM_PER_INCH: f64 = 25.4;

/// Axis letters a program may use.
const AXIS_LETTERS: [char; 9] = ['X', 'Y', 'Z', 'A', 'B', 'C', 'U', 'V', 'W'];

/// The plane of an arc: machine axis indices of the first and second plane axes and the normal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plane {
    pub first: usize,
    pub second: usize,
    pub normal: usize,
    /// Program letters of the arc-centre words for the first and second axes (I J, K I, J K).
    pub centre_letters: [char; 2],
}

/// What a move does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MoveKind {
    /// G0: only the end point matters.
    Rapid,
    /// G1: a straight line in axis space.
    Feed,
    /// G2 (clockwise) / G3: a circular (helical) arc; `centre` in machine coordinates (mm) of the
    /// plane's first and second axes; `r_format` when the block gave R instead of the centre words.
    Arc { clockwise: bool, plane: Plane, centre: [f64; 2], r_format: bool },
}

/// One programmed move, in machine axis positions (mm, deg; canonical axis order).
#[derive(Clone, Debug, PartialEq)]
pub struct Move {
    /// Index of the block in the program.
    pub block: usize,
    pub kind: MoveKind,
    pub start: Vec<f64>,
    pub end: Vec<f64>,
    /// Distance mode and units in force for the block.
    pub incremental: bool,
    pub inch: bool,
    /// Program coordinate = machine position - offset (mm, deg); zero for G53 blocks.
    pub offset: Vec<f64>,
}

/// Initial state and work offsets.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramSetup {
    /// Machine position before the first move (mm, deg); rs274 starts at 0.
    pub start: Vec<f64>,
    /// Work offsets G54 ... G59 (index 0 ... 5), machine positions of the program zero (mm, deg).
    pub work_offsets: [Vec<f64>; 6],
}

impl ProgramSetup {
    /// All zero for `machine`.
    pub fn zero(machine: &Machine) -> ProgramSetup {
        let z = vec![0.0; machine.axis_count()];
        ProgramSetup { start: z.clone(), work_offsets: std::array::from_fn(|_| z.clone()) }
    }
}

/// Program units of `axis` to machine units (mm, deg).
pub fn to_machine_units(machine: &Machine, axis: usize, value: f64, inch: bool) -> f64 {
    if inch && machine.axes()[axis].kind == AxisKind::Linear {
        value * MM_PER_INCH
    } else {
        value
    }
}

/// Machine units of `axis` to program units.
pub fn to_program_units(machine: &Machine, axis: usize, value: f64, inch: bool) -> f64 {
    if inch && machine.axes()[axis].kind == AxisKind::Linear {
        value / MM_PER_INCH
    } else {
        value
    }
}

struct Modal {
    motion: Option<u32>,
    incremental: bool,
    inch: bool,
    plane: u32,
    offset: usize,
    position: Vec<f64>,
}

/// The moves of a program; an error names the line.
pub fn interpret(machine: &Machine, blocks: &[Block], setup: &ProgramSetup) -> Result<Vec<Move>, String> {
    machine.check_range(&setup.start).map_err(|m| format!("the start point (before the first move) leaves the machine's travel: {m}"))?;
    let mut state = Modal { motion: None, incremental: false, inch: false, plane: 17, offset: 0, position: setup.start.clone() };
    let mut moves = Vec::new();
    for (index, block) in blocks.iter().enumerate() {
        let line = block.line;
        let mut g53 = false;
        let mut motion = None;
        for w in block.words_of('G') {
            let code = (w.value * 10.0).round() as i64;
            match code {
                0 | 10 | 20 | 30 => motion = Some((code / 10) as u32),
                40 | 170 | 180 | 190 | 400 | 490 | 610 | 611 | 640 | 800 | 911 | 940 => {}
                200 => state.inch = true,
                210 => state.inch = false,
                900 => state.incremental = false,
                910 => state.incremental = true,
                530 => g53 = true,
                540 | 550 | 560 | 570 | 580 | 590 => state.offset = (code as usize - 540) / 10,
                410 | 420 | 411 | 421 => return Err(format!("line {line}: cutter radius compensation (G{}) is not supported; program the tool centre path", w.value)),
                430..=432 => return Err(format!("line {line}: tool length compensation (G{}) is not supported; put the tool point in the machine file instead", w.value)),
                901 => return Err(format!("line {line}: absolute arc centres (G90.1) are not supported; use the default incremental IJK (G91.1)")),
                930 => return Err(format!("line {line}: inverse-time feed (G93) is not supported: splitting moves would change their times")),
                _ => return Err(format!("line {line}: G{} is not supported by the NC corrector (supported: G0 G1 G2 G3 G17-G19 G20 G21 G40 G49 G53 G54-G59 G61 G64 G80 G90 G91 G91.1 G94)", w.value)),
            }
            match code {
                170 | 180 | 190 => state.plane = (code / 10) as u32,
                800 => state.motion = None,
                _ => {}
            }
        }
        if g53 && matches!(motion, Some(2 | 3)) {
            return Err(format!("line {line}: G53 works with G0 and G1 only"));
        }
        if let Some(m) = motion {
            state.motion = Some(m);
        }
        let axis_words: Vec<_> = block.words.iter().filter(|w| AXIS_LETTERS.contains(&w.letter)).collect();
        if axis_words.is_empty() {
            if motion.is_some_and(|m| m >= 2) {
                return Err(format!("line {line}: an arc needs an end point"));
            }
            continue;
        }
        let mode = state.motion.ok_or_else(|| format!("line {line}: axis words without a motion mode (G0, G1, G2 or G3)"))?;
        let offset = if g53 { vec![0.0; machine.axis_count()] } else { setup.work_offsets[state.offset].clone() };
        let start = state.position.clone();
        let mut end = start.clone();
        for w in &axis_words {
            let axis = machine.axis_index(w.letter).ok_or_else(|| {
                format!("line {line}: axis {} is not an axis of machine `{}` (axes: {})", w.letter, machine.name, machine.axis_letters())
            })?;
            if block.words_of(w.letter).count() > 1 {
                return Err(format!("line {line}: axis word {} appears twice", w.letter));
            }
            let v = to_machine_units(machine, axis, w.value, state.inch);
            end[axis] = if state.incremental && !g53 { start[axis] + v } else { v + offset[axis] };
        }
        let kind = match mode {
            0 => MoveKind::Rapid,
            1 => MoveKind::Feed,
            _ => arc(machine, block, &state, &start, &end, mode == 2)?,
        };
        if let Err(m) = machine.check_range(&end) {
            return Err(format!("line {line}: the end point leaves the machine's travel: {m}"));
        }
        moves.push(Move { block: index, kind, start, end: end.clone(), incremental: state.incremental && !g53, inch: state.inch, offset });
        state.position = end;
    }
    Ok(moves)
}

/// Plane axes of G17 / G18 / G19.
fn plane_of(machine: &Machine, plane: u32, line: usize) -> Result<Plane, String> {
    let (letters, centre_letters) = match plane {
        17 => (['X', 'Y', 'Z'], ['I', 'J']),
        18 => (['Z', 'X', 'Y'], ['K', 'I']),
        _ => (['Y', 'Z', 'X'], ['J', 'K']),
    };
    let idx = |c: char| {
        machine.axis_index(c).ok_or_else(|| format!("line {line}: an arc in G{plane} needs axis {c}, which the machine does not have"))
    };
    Ok(Plane { first: idx(letters[0])?, second: idx(letters[1])?, normal: idx(letters[2])?, centre_letters })
}

fn arc(machine: &Machine, block: &Block, state: &Modal, start: &[f64], end: &[f64], clockwise: bool) -> Result<MoveKind, String> {
    let line = block.line;
    let plane = plane_of(machine, state.plane, line)?;
    if let Some(p) = block.value('P') {
        if p != 1.0 {
            return Err(format!("line {line}: arcs with several turns (P{p}) are not supported"));
        }
    }
    let (s, e) = ([start[plane.first], start[plane.second]], [end[plane.first], end[plane.second]]);
    let unit = |v: f64| if state.inch { v * MM_PER_INCH } else { v };
    let (centre, r_format) = match block.value('R') {
        Some(r) => {
            let r = unit(r);
            let (dx, dy) = (e[0] - s[0], e[1] - s[1]);
            let chord = (dx * dx + dy * dy).sqrt();
            if chord == 0.0 || chord > 2.0 * r.abs() * (1.0 + 1e-9) {
                return Err(format!("line {line}: no arc of radius {} mm joins the start and end points", r.abs()));
            }
            let h = (r * r - chord * chord / 4.0).max(0.0).sqrt();
            // centre on the left of the chord for a counterclockwise arc shorter than a half turn
            let side = if clockwise == (r > 0.0) { -1.0 } else { 1.0 };
            let (mx, my) = ((s[0] + e[0]) / 2.0, (s[1] + e[1]) / 2.0);
            ([mx - side * h * dy / chord, my + side * h * dx / chord], true)
        }
        None => {
            let [a, b] = plane.centre_letters;
            if block.value(a).is_none() && block.value(b).is_none() {
                return Err(format!("line {line}: an arc needs the centre words {a} {b} or a radius R"));
            }
            ([s[0] + unit(block.value(a).unwrap_or(0.0)), s[1] + unit(block.value(b).unwrap_or(0.0))], false)
        }
    };
    Ok(MoveKind::Arc { clockwise, plane, centre, r_format })
}
