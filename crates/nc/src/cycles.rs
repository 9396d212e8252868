//! Canned cycles expanded into their moves, as LinuxCNC 2.9 makes them (`interp_cycles.cc`) in any
//! plane (G17: along Z; G18: along Y; G19: along X), with the same moves for the Fanuc dialect:
//!
//! - positioning: if the current level is below R, first straight up to R; then, for each repeat
//!   (`L`, Fanuc `K`; in G91 the hole position is an increment), a rapid to the hole at the current
//!   level (first hole) or the clearance level, and down to R;
//! - G81 feed to the bottom, rapid out; G82 with a dwell at the bottom; G85 feed in and out to R;
//!   G89 dwell, feed out; G86 dwell, spindle stop, rapid out, spindle restart; G73 pecks of Q with a
//!   retraction of 0.010 inch (Fanuc: the peck clearance setting); G83 pecks of Q back to R and down
//!   to that clearance above the last depth; G74/G84 (LinuxCNC floating tapping) feed in, spindle
//!   reversed, dwell, feed out, spindle restored, overrides off meanwhile; Fanuc G74/G84 (rigid
//!   tapping, after `M29 S..` or not) feed in, dwell, feed out to R, then to the initial level with
//!   G98; G87 back boring;
//! - the retraction goes to R (G99) or to the initial level (G98) when that is above R;
//! - in G91, R is an increment from the initial level and the bottom an increment from R.
//!
//! The moves are the same canonical moves rs274 prints; dwells and spindle codes between them are
//! recorded as actions, so that an expanded copy runs the same cycle. A cycle run in G90 (no polar
//! words, not G87) is recorded as a [`crate::trace::CycleHole`], to be written as a cycle again with
//! its hole position and levels corrected; otherwise, or with `expand_cycles`, its block is
//! expanded. Tapping follows the spindle and cannot become plain moves: it is always kept, and
//! refused in G91.

use crate::dialect::Dialect;
use crate::execute::Words;
use crate::interpret::Exec;
use crate::modal::{Motion, PlaneSelect, Spindle, Vec9, MM_PER_INCH};
use crate::tools::AXIS_LETTERS;
use crate::trace::Role;

/// LinuxCNC `G83_RAPID_DELTA` (inch).
const RAPID_DELTA_INCH: f64 = 0.010;

/// Runs canned cycle `code` (x 10) of the block.
pub(crate) fn cycle(exec: &mut Exec, code: u16, w: &mut Words, step: usize) -> Result<(), String> {
    let fanuc = exec.dialect == Dialect::Fanuc;
    let plane = exec.state.plane;
    if fanuc && plane != PlaneSelect::Xy {
        return Err("canned cycles are supported in G17 only on a Fanuc".into());
    }
    let [a, b, c] = plane.axes();
    let (la, lb, lc) = (AXIS_LETTERS[a], AXIS_LETTERS[b], AXIS_LETTERS[c]);
    let same = exec.state.motion == Motion::Cycle(code);
    let name = format!("G{}", code / 10);
    let r_word = match w.take(b'R') {
        Some(r) => r,
        None if same => exec.state.cycle.r,
        None => return Err(format!("{name} needs the R level the first time")),
    };
    let repeats = {
        let l = if fanuc { w.take(b'K').or_else(|| w.take(b'L')) } else { w.take(b'L') };
        match l {
            Some(l) if l < 0.0 || l.fract() != 0.0 => return Err(format!("repeat count {l} of {name} is not a whole number")),
            Some(l) if l == 0.0 && !fanuc => return Err(format!("{name} with L0 (no repeat)")),
            Some(l) => l as u32,
            None => 1,
        }
    };
    let bottom_word = match w.get(lc) {
        Some(v) => v,
        None if same => exec.state.cycle.bottom,
        None => return Err(format!("{name} needs the bottom {} the first time", lc as char)),
    };
    let s = exec.state;
    let old_cc = s.cycle.initial.unwrap_or(s.position[c]);
    let initial_level = old_cc;
    exec.state.cycle.initial = Some(old_cc);
    let (mut aa, mut bb, r, cc, inc_a, inc_b, inc_radius, inc_angle);
    let (polar_r, polar_t) = (w.get(b'@'), w.get(b'^').map(f64::to_radians));
    if (polar_r.is_some() || polar_t.is_some()) && plane != PlaneSelect::Xy {
        return Err("polar coordinates in a canned cycle need G17".into());
    }
    if !s.frame.incremental {
        r = r_word;
        cc = bottom_word;
        (inc_a, inc_b, inc_radius, inc_angle) = (0.0, 0.0, 0.0, 0.0);
        if polar_r.is_some() || polar_t.is_some() {
            let radius = polar_r.unwrap_or_else(|| s.position[1].hypot(s.position[0]));
            let theta = polar_t.unwrap_or_else(|| s.position[1].atan2(s.position[0]));
            (aa, bb) = (radius * theta.cos(), radius * theta.sin());
        } else {
            aa = w.get(la).map_or(s.position[a], |v| if a == 0 && s.frame.diameter { v / 2.0 } else { v });
            bb = w.get(lb).map_or(s.position[b], |v| if b == 0 && s.frame.diameter { v / 2.0 } else { v });
        }
    } else {
        inc_a = w.get(la).unwrap_or(0.0);
        inc_b = w.get(lb).unwrap_or(0.0);
        inc_radius = polar_r.unwrap_or(0.0);
        inc_angle = polar_t.unwrap_or(0.0);
        r = r_word + old_cc;
        cc = r + bottom_word;
        (aa, bb) = (s.position[a], s.position[b]);
    }
    w.use_axes();
    let tapping = matches!(code, 740 | 840);
    let absolute = !s.frame.incremental && polar_r.is_none() && polar_t.is_none() && !s.frame.diameter && code != 870;
    if tapping && !absolute {
        return Err(format!(
            "{name} in G91 (incremental) or with polar words: a tapping cycle follows the spindle, so it is kept as a cycle, which is written in G90 with its hole position only"
        ));
    }
    let keep = absolute && (tapping || !exec.expand_cycles);
    if !keep {
        exec.trace.steps[step].flags |= crate::trace::flags::EXPAND;
    }
    if r < cc {
        return Err(format!("the R level {r} of {name} is below its bottom {cc}"));
    }
    // the cycle's own parameters, remembered between blocks of the same cycle
    let mut take_remembered = |letter: u8, memory: f64, what: &str| -> Result<f64, String> {
        match w.take(letter) {
            Some(v) => Ok(v),
            None if same => Ok(memory),
            None => Err(format!("{name} needs {what} {} the first time", letter as char)),
        }
    };
    let mut dwell = 0.0;
    let mut peck = 0.0;
    let (mut ci, mut cj, mut ck) = (0.0, 0.0, 0.0);
    match code {
        820 | 860 | 890 => dwell = take_remembered(b'P', s.cycle.p, "the dwell time")?,
        740 | 840 => dwell = w.take(b'P').unwrap_or(if same { s.cycle.p } else { 0.0 }),
        730 | 830 => {
            peck = take_remembered(b'Q', s.cycle.q, "the peck depth")?;
            if peck <= 0.0 {
                return Err(format!("{name} with the peck depth Q{peck}: Q must be positive"));
            }
        }
        870 => {
            ci = take_remembered(b'I', s.cycle.i, "the offset")?;
            cj = take_remembered(b'J', s.cycle.j, "the offset")?;
            ck = take_remembered(b'K', s.cycle.k, "the top of the counterbore")?;
        }
        _ => {}
    }
    if fanuc {
        // a Fanuc cycle keeps P and Q modal even in other cycles
        w.take(b'P');
        w.take(b'Q');
    }
    let spindle = s.spindle;
    if matches!(code, 860 | 870) && spindle == Spindle::Stopped {
        return Err(format!("{name} needs the spindle turning"));
    }
    // a Fanuc taps rigidly after `M29 S..` without M3
    if tapping && !fanuc {
        match (code, spindle) {
            (_, Spindle::Stopped) => return Err(format!("{name} needs the spindle turning")),
            (840, Spindle::CounterClockwise) => return Err("G84 with the spindle turning counterclockwise".into()),
            (740, Spindle::Clockwise) => return Err("G74 with the spindle turning clockwise".into()),
            _ => {}
        }
    }
    let rapid_delta = if fanuc {
        exec.fanuc.peck_clearance_mm / if s.frame.inch { MM_PER_INCH } else { 1.0 }
    } else if s.frame.inch {
        RAPID_DELTA_INCH
    } else {
        RAPID_DELTA_INCH * MM_PER_INCH
    };
    let point = |exec: &Exec, pa: f64, pb: f64, pc: f64| -> Vec9 {
        let mut p = exec.state.position;
        p[a] = pa;
        p[b] = pb;
        p[c] = pc;
        p
    };
    // the moves of the block, from the rise to R if there is one
    let first_move = exec.trace.moves.len();
    let mut current_cc = s.position[c];
    let mut old_cc = old_cc;
    if old_cc < r {
        let p = point(exec, s.position[a], s.position[b], r);
        exec.straight(true, p, Role::Generated, false, 0)?;
        old_cc = r;
        current_cc = r;
    }
    let clear = if s.retract_to_r { r } else { old_cc };
    // LinuxCNC runs cycles in exact path mode
    let exact = !fanuc && s.path_mode != 610;
    if exact {
        exec.action(&[(b'G', 61.0)]);
    }
    let ccw_code = if spindle == Spindle::Clockwise { 3.0 } else { 4.0 };
    let since_first = |exec: &Exec| (exec.trace.moves.len() - 1 - first_move) as u32;
    let mut r_move = 0;
    for repeat in 0..repeats {
        aa += inc_a;
        bb += inc_b;
        if inc_radius != 0.0 || inc_angle != 0.0 {
            if aa == 0.0 && bb == 0.0 {
                return Err("incremental polar coordinates at the origin are indeterminate".into());
            }
            let (radius, theta) = (bb.hypot(aa) + inc_radius, bb.atan2(aa) + inc_angle);
            (aa, bb) = (radius * theta.cos(), radius * theta.sin());
        }
        let rapid = |exec: &mut Exec, pa: f64, pb: f64, pc: f64| {
            let p = point(exec, pa, pb, pc);
            exec.straight(true, p, Role::Generated, false, 0)
        };
        let feed = |exec: &mut Exec, pa: f64, pb: f64, pc: f64| {
            let p = point(exec, pa, pb, pc);
            exec.straight(false, p, Role::Generated, false, 0)
        };
        if repeat == 0 && current_cc > r {
            rapid(exec, aa, bb, current_cc)?;
            rapid(exec, aa, bb, r)?;
        } else {
            rapid(exec, aa, bb, clear)?;
            if clear > r {
                rapid(exec, aa, bb, r)?;
            }
        }
        if repeat == 0 {
            r_move = since_first(exec);
        }
        let dwell_action = |exec: &mut Exec| exec.action(&[(b'G', 4.0), (b'P', dwell)]);
        match code {
            810 => {
                feed(exec, aa, bb, cc)?;
                rapid(exec, aa, bb, clear)?;
            }
            820 => {
                feed(exec, aa, bb, cc)?;
                dwell_action(exec);
                rapid(exec, aa, bb, clear)?;
            }
            850 => {
                feed(exec, aa, bb, cc)?;
                feed(exec, aa, bb, r)?;
                rapid(exec, aa, bb, clear)?;
            }
            890 => {
                feed(exec, aa, bb, cc)?;
                dwell_action(exec);
                feed(exec, aa, bb, clear)?;
            }
            860 => {
                feed(exec, aa, bb, cc)?;
                dwell_action(exec);
                exec.action(&[(b'M', 5.0)]);
                rapid(exec, aa, bb, clear)?;
                exec.action(&[(b'M', ccw_code)]);
            }
            730 | 830 => {
                let mut depth = r - peck;
                while depth > cc {
                    feed(exec, aa, bb, depth)?;
                    if code == 830 {
                        rapid(exec, aa, bb, r)?;
                    }
                    rapid(exec, aa, bb, depth + rapid_delta)?;
                    depth -= peck;
                }
                feed(exec, aa, bb, cc)?;
                rapid(exec, aa, bb, clear)?;
            }
            740 | 840 if fanuc => {
                // rigid tapping: in to the bottom, out to R, to the initial level with G98
                feed(exec, aa, bb, cc)?;
                dwell_action(exec);
                feed(exec, aa, bb, r)?;
                if clear > r {
                    rapid(exec, aa, bb, clear)?;
                }
            }
            740 | 840 => {
                let (reverse, forward) = if code == 840 { (4.0, 3.0) } else { (3.0, 4.0) };
                // two blocks: M50 and M51 are one modal group (rs274: "Two m codes used from same modal group")
                exec.action(&[(b'M', 50.0), (b'P', 0.0)]);
                exec.action(&[(b'M', 51.0), (b'P', 0.0)]);
                feed(exec, aa, bb, cc)?;
                exec.action(&[(b'M', 5.0)]);
                exec.action(&[(b'M', reverse)]);
                dwell_action(exec);
                feed(exec, aa, bb, clear)?;
                exec.action(&[(b'M', 5.0)]);
                exec.action(&[(b'M', forward)]);
                exec.action(&[(b'M', 50.0), (b'P', 1.0)]);
                exec.action(&[(b'M', 51.0), (b'P', 1.0)]);
            }
            870 => {
                let middle = if s.frame.incremental { cc + ck } else { ck };
                let (oa, ob) = (aa + ci, bb + cj);
                let orient = [(b'M', 19.0), (b'R', 0.0), (b'P', if spindle == Spindle::Clockwise { 1.0 } else { 2.0 })];
                rapid(exec, oa, ob, r)?;
                exec.action(&[(b'M', 5.0)]);
                exec.action(&orient);
                rapid(exec, oa, ob, cc)?;
                rapid(exec, aa, bb, cc)?;
                exec.action(&[(b'M', ccw_code)]);
                feed(exec, aa, bb, middle)?;
                feed(exec, aa, bb, cc)?;
                exec.action(&[(b'M', 5.0)]);
                exec.action(&orient);
                rapid(exec, oa, ob, cc)?;
                rapid(exec, oa, ob, clear)?;
                rapid(exec, aa, bb, clear)?;
                exec.action(&[(b'M', ccw_code)]);
            }
            880 => return Err("G88 leaves the retraction to the operator: it cannot be expanded".into()),
            _ => return Err(format!("{name} is not a canned cycle")),
        }
    }
    if exact {
        let mut restore = vec![(b'G', f64::from(s.path_mode) / 10.0)];
        if s.path_mode == 640 {
            if let Some(p) = s.path_tolerance {
                restore.push((b'P', p));
            }
            if let Some(q) = s.naive_tolerance {
                restore.push((b'Q', q));
            }
        }
        exec.action(&restore);
    }
    if keep {
        // the bottom: the first move after R that ends there
        let after_r = first_move + r_move as usize + 1;
        let bottom_move =
            exec.trace.moves[after_r..].iter().position(|m| m.program_end[c] == cc).map_or(0, |k| (k + after_r - first_move) as u32);
        exec.trace.holes.push(crate::trace::CycleHole {
            step: step as u32,
            code,
            plane,
            r,
            bottom: cc,
            clear,
            initial: initial_level,
            retract_to_r: s.retract_to_r,
            first: s.cycle.initial.is_none(),
            peck,
            dwell,
            r_move,
            bottom_move,
        });
    }
    let st = &mut exec.state;
    st.position[a] = aa;
    st.position[b] = bb;
    st.position[c] = clear;
    st.cycle.bottom = bottom_word;
    st.cycle.r = r_word;
    st.cycle.p = dwell;
    if peck > 0.0 {
        st.cycle.q = peck;
    }
    (st.cycle.i, st.cycle.j, st.cycle.k) = (ci, cj, ck);
    st.motion = Motion::Cycle(code);
    exec.position = exec.program_to_machine(&exec.state.position);
    Ok(())
}

/// The pecks of a G73 or G83 before the last feed to the bottom, as the loop above makes them:
/// the feeds to `r - k q` while above the bottom.
pub fn pecks(r: f64, bottom: f64, q: f64) -> u32 {
    let mut depth = r - q;
    let mut n = 0;
    while depth > bottom {
        n += 1;
        depth -= q;
    }
    n
}

impl Exec<'_> {
    /// Codes an expanded copy writes before the step's next move (or after its last).
    pub(crate) fn action(&mut self, words: &[(u8, f64)]) {
        let step = self.trace.steps.last().expect("a step");
        let index = self.trace.moves.len() as u32 - step.moves.start;
        let start = self.trace.words.len() as u32;
        self.trace.words.extend_from_slice(words);
        self.trace.actions.push((index, start..self.trace.words.len() as u32));
        let end = self.trace.actions.len() as u32;
        self.trace.steps.last_mut().expect("a step").actions.end = end;
    }
}
