//! grbl 1.1's system commands, the lines starting with `$` that a sender streams beside the
//! G-code (grbl wiki, "Grbl v1.1 Commands" and "Grbl v1.1 Jogging"; `doc/markdown/commands.md` and
//! `jogging.md` of gnea/grbl), and what a corrector does with each:
//!
//! - `$J=<block>` jogs: a linear move at the block's `F` (required) to its `X Y Z`, with `G20`/`G21`,
//!   `G90`/`G91` and `G53` for this move only; the G-code modes (motion, units, distance mode,
//!   feed) stay as they were, and the position after it is the jog's end. It is read as such a
//!   move and corrected like a `G1`, its words rewritten in place after the `$J=`. Any other word
//!   is refused, as grbl refuses it (error:3 or error:20s of the jog's parser);
//! - `$H` homes: the machine seeks its switches and stops at the pull-off (`$27`), a place the
//!   program does not state. Before the first move of the program it is passed through, the
//!   machine taken to be at the start position given (`--start`: where homing leaves it); after a
//!   move it is refused (the moves after it start from a place the corrector cannot know);
//! - the real-time commands `?` (status), `~` (resume) and `!` (feed hold) on a line of their own
//!   (grbl picks them out of the stream; the motion goes on as programmed) are passed through with
//!   a warning;
//! - `$X` (unlock), `$$`, `$#`, `$G`, `$I`, `$N` (reports), `$Nx=<block>` (a startup block, run at
//!   the next reset, not here) and settings `$x=<value>` move nothing: passed through unchanged
//!   with a warning naming the line; the settings that change where the axes go are refused:
//!   `$3` (direction invert) and `$100`-`$102` (steps per mm: the scale of the axes the error
//!   model was identified at);
//! - `$C` (check mode: the lines after it are parsed but not run, and leaving it resets grbl),
//!   `$RST=` (restores defaults: settings, or with `$RST=#` the work offsets) and `$SLP` (sleep:
//!   grbl needs a reset) are refused: what follows is not the program's moves at the setup's
//!   offsets.
//!
//! In any other dialect a `$` system command is refused with the line (`--dialect grbl` reads it).

use crate::dialects::Controller;
use crate::interpret::{Exec, Flow};
use crate::lexer::Line;
use crate::modal::{FeedMode, Motion};
use crate::program::SourceFile;

/// What a system command is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Command {
    Jog,
    Home,
    /// Moves nothing (`$X`, reports, startup blocks, settings that do not move the axes).
    Passive(&'static str),
    Refused(&'static str),
}

/// What the command `text` (the line from its `$`, trimmed) is.
fn classify(text: &str) -> Command {
    // grbl reads a line without its blanks
    let upper: String = text.chars().filter(|c| !c.is_whitespace()).collect::<String>().to_ascii_uppercase();
    let after = &upper[1..];
    let setting = after.split_once('=').and_then(|(n, _)| n.parse::<u32>().ok());
    match upper.as_str() {
        "?" => return Command::Passive("asks for a status report (a real-time command: grbl takes it out of the stream)"),
        "~" => return Command::Passive("resumes a feed hold (a real-time command)"),
        "!" => return Command::Passive("holds the feed until `~` (a real-time command: the moves go on from where they stopped)"),
        _ => {}
    }
    match after {
        _ if after.starts_with("J=") => Command::Jog,
        "H" => Command::Home,
        "X" => Command::Passive("unlocks the alarm state"),
        "$" | "#" | "G" | "I" | "N" => Command::Passive("prints a report"),
        "C" => Command::Refused(
            "(check mode) parses the lines after it without moving, and leaving it resets grbl: correct the program without it",
        ),
        "SLP" => Command::Refused("(sleep) stops grbl until a reset: the lines after it are not run"),
        _ if after.starts_with("RST=") => {
            Command::Refused("restores grbl's defaults (with `$RST=#` its work offsets): the moves after it are not at the setup's offsets")
        }
        _ if after.starts_with('N') && after[1..].starts_with(|c: char| c.is_ascii_digit()) && after.contains('=') => {
            Command::Passive("stores a startup block, run at grbl's next reset, not here")
        }
        _ => match setting {
            Some(3 | 100..=102) => Command::Refused(
                "changes the direction or the steps per mm of the axes: the error model holds for the settings it was identified at",
            ),
            Some(_) => Command::Passive("changes a setting that moves nothing"),
            None => Command::Refused("is not a grbl 1.1 system command (grbl: error:3)"),
        },
    }
}

/// The G codes a jog may hold (x10, as the dialect tables key them): G20 G21 G53 G90 G91.
const JOG_CODES: [u16; 5] = [200, 210, 530, 900, 910];

/// Runs the system command of `line` (its text `command`) at step `step`.
pub(crate) fn run(exec: &mut Exec, file: &SourceFile, pc: (usize, usize), line: &Line, step: usize) -> Result<Flow, String> {
    let range = line.system.clone().expect("a system command line");
    let text = file.line_text(pc.1)[range].trim_end();
    if !std::ptr::eq(exec.table, Controller::Grbl.table()) {
        return Err(format!("`{text}` is a grbl system command; this program reads as {} (choose --dialect grbl?)", exec.table.title));
    }
    match classify(text) {
        Command::Jog => jog(exec, file, pc, line, step),
        Command::Home if exec.trace.moves.is_empty() => {
            exec.warn(format!(
                "`{text}` homes grbl: passed through; the moves after it start from the start position given (--start), taken as where homing leaves the machine"
            ));
            Ok(Flow::Next)
        }
        Command::Home => Err(format!(
            "`{text}` homes grbl after moves: where homing leaves the machine (its switches and the pull-off $27) is not in the program; home before the first move"
        )),
        Command::Passive(what) => {
            exec.warn(format!("`{text}` {what}: passed through unchanged"));
            Ok(Flow::Next)
        }
        Command::Refused(why) => Err(format!("`{text}` {why}")),
    }
}

/// `$J=...`: a `G1` to the jog's end at its `F`, in its own units and distance mode; the modes of
/// the program restored after it.
fn jog(exec: &mut Exec, file: &SourceFile, pc: (usize, usize), line: &Line, step: usize) -> Result<Flow, String> {
    for w in &line.words {
        let code = match &w.value {
            crate::lexer::Operand::Number(v) => (v * 10.0).round() as u16,
            _ => 0,
        };
        let allowed = matches!(w.letter, b'X' | b'Y' | b'Z' | b'F' | b'N') || w.letter == b'G' && JOG_CODES.contains(&code);
        if !allowed {
            let word = format!("{}{}", w.letter as char, &file.line_text(pc.1)[w.span.clone()]);
            return Err(format!("a jog takes X Y Z, F and G20 G21 G53 G90 G91 only: `{word}` (grbl: error:3)"));
        }
    }
    if line.word(b'F').is_none() {
        return Err("a jog needs its feed F (grbl: error:22)".into());
    }
    if !line.words.iter().any(|w| matches!(w.letter, b'X' | b'Y' | b'Z')) {
        return Err("a jog without X, Y or Z (grbl: error:26)".into());
    }
    let saved = exec.state;
    exec.state.motion = Motion::Feed;
    exec.state.feed_mode = FeedMode::PerMinute;
    let flow = exec.block_steps(file, pc, line, step);
    let inch = saved.frame.inch;
    exec.state.set_inch(inch);
    exec.state.motion = saved.motion;
    exec.state.group01 = saved.group01;
    exec.state.feed_mode = saved.feed_mode;
    exec.state.feed = saved.feed;
    exec.state.frame.incremental = saved.frame.incremental;
    flow
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axes::{AxisSpec, MachineAxes};
    use crate::{ProgramSetup, Trace};

    fn run(text: &str, controller: Controller) -> Result<Trace, String> {
        let axis = |letter| AxisSpec { letter, rotary: false, range: None };
        let axes = MachineAxes { name: "mill".into(), axes: vec![axis('X'), axis('Y'), axis('Z')] };
        let setup = ProgramSetup::zero(&axes);
        crate::run(&axes, text.as_bytes(), "p.nc", Some(controller), &setup)
            .map(|(t, _)| t)
            .map_err(|e| format!("line {}: {}", e.line, e.message))
    }

    /// A sender's stream: `$X` and `$H` pass with a warning naming their lines; a `$J=` in G91 and
    /// inch moves by its increment in inch (25.4 mm) and leaves the program in G90 and mm; the
    /// next `G1` is a feed move again.
    #[test]
    fn a_stream_with_system_commands_and_jogs_is_read() {
        let text = "$X\n$H\nG21 G90 G1 F100\n$J=G91 G20 X1 Y-0.5 F20\nG0 Z1\n$J=X-3 F300\nG1 X5\n$#\nM2\n";
        let t = run(text, Controller::Grbl).unwrap();
        let ends: Vec<[f64; 3]> = t.moves.iter().map(|m| [m.end[0], m.end[1], m.end[2]]).collect();
        let want = [[0.0, 0.0, 0.0], [25.4, -12.7, 0.0], [25.4, -12.7, 1.0], [-3.0, -12.7, 1.0], [5.0, -12.7, 1.0]];
        for (a, b) in ends.iter().zip(&want) {
            assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12), "{ends:?}");
        }
        assert_eq!(ends.len(), want.len());
        assert!(matches!(t.moves[2].kind, crate::MoveKind::Rapid) && matches!(t.moves[4].kind, crate::MoveKind::Feed));
        let warned: Vec<u32> = t.warnings.iter().map(|w| w.line).collect();
        assert_eq!(warned, vec![1, 2, 8]);
        assert!(t.warnings[1].message.starts_with("`$H` homes grbl: passed through"), "{}", t.warnings[1].message);
    }

    /// What stays refused, each with its line and grbl's reason.
    #[test]
    fn what_cannot_be_known_is_refused_with_the_line() {
        let refused = |text: &str| run(text, Controller::Grbl).unwrap_err();
        assert!(refused("G21 G90\nG0 X1\n$H\nG0 X2\nM2\n").starts_with("line 3: `$H` homes grbl after moves"));
        assert_eq!(refused("G21\n$J=G91 X10\nM2\n"), "line 2: a jog needs its feed F (grbl: error:22)");
        assert_eq!(refused("G21\n$J=G1 X10 F100\nM2\n"), "line 2: a jog takes X Y Z, F and G20 G21 G53 G90 G91 only: `G1` (grbl: error:3)");
        assert_eq!(refused("G21\n$J=F100\nM2\n"), "line 2: a jog without X, Y or Z (grbl: error:26)");
        assert!(refused("$C\nG0 X1\nM2\n").starts_with("line 1: `$C` (check mode)"));
        assert!(refused("$100=250\nG0 X1\nM2\n").starts_with("line 1: `$100=250` changes the direction or the steps per mm"));
        let linuxcnc = run("$H\nG0 X1\nM2\n", Controller::LinuxCnc).unwrap_err();
        assert_eq!(linuxcnc, "line 1: `$H` is a grbl system command; this program reads as LinuxCNC 2.9 (choose --dialect grbl?)");
        // LinuxCNC's spindle word `$1` is no system command
        assert!(run("G21\nM3 $0 S1000\nG0 X1\nM2\n", Controller::LinuxCnc).is_ok());
    }

    #[test]
    fn commands_are_told_apart() {
        assert_eq!(classify("$J=G91 X10 F500"), Command::Jog);
        assert_eq!(classify("$h"), Command::Home);
        assert!(matches!(classify("$X"), Command::Passive(_)));
        assert!(matches!(classify("$#"), Command::Passive(_)));
        assert!(matches!(classify("$N0=G20 G54"), Command::Passive(_)));
        assert!(matches!(classify("$32=1"), Command::Passive(_)));
        assert!(matches!(classify("$100=250"), Command::Refused(_)));
        assert!(matches!(classify("$3=1"), Command::Refused(_)));
        assert!(matches!(classify("$C"), Command::Refused(_)));
        assert!(matches!(classify("$RST=#"), Command::Refused(_)));
        assert!(matches!(classify("$SLP"), Command::Refused(_)));
        assert_eq!(classify("$Q"), Command::Refused("is not a grbl 1.1 system command (grbl: error:3)"));
        assert!(matches!(classify("$ i"), Command::Passive(_)));
    }

    /// A laser-engraving stream as senders write it: reports with `;` comments after them (grbl
    /// takes comments and blanks out of a line before it reads a `$` command), and a first cut
    /// before any `F` (grbl runs it at the feed rate the stream before left): both pass with a
    /// warning naming the line; LinuxCNC refuses the cut without a feed, as rs274 does.
    #[test]
    fn reports_with_comments_and_a_cut_before_any_feed() {
        let text = "$I  ; View build info\n$G (parser state)\n?  ; View current status\nG21 G90\nG1 X2 Y1\nG1 X3 F800\nM2\n";
        let t = run(text, Controller::Grbl).unwrap();
        let warned: Vec<u32> = t.warnings.iter().map(|w| w.line).collect();
        assert_eq!(warned, vec![1, 2, 3, 5]);
        assert!(t.warnings[0].message.starts_with("`$I` prints a report"), "{}", t.warnings[0].message);
        assert!(t.warnings[2].message.starts_with("`?` asks for a status report"), "{}", t.warnings[2].message);
        assert!(t.warnings[3].message.starts_with("a feed move before any F: grbl 1.1 runs it"), "{}", t.warnings[3].message);
        let ends: Vec<f64> = t.moves.iter().map(|m| m.end[0]).collect();
        assert_eq!(ends, vec![2.0, 3.0]);
        let linuxcnc = run("G21 G90\nG1 X2 Y1\nM2\n", Controller::LinuxCnc).unwrap_err();
        assert!(linuxcnc.starts_with("line 2: a feed move with zero feed rate (LinuxCNC 2.9 stops here;"), "{linuxcnc}");
    }
}
