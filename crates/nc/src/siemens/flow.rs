//! Program flow of the SINUMERIK 840D sl (Programming Manual Job Planning, "Flexible NC
//! programming": "Program jumps to jump markers (GOTOB, GOTOF, GOTO, GOTOC)", "Conditional program
//! jumps (IF, GOTOB, GOTOF)", "Control structures": IF-ELSE-ENDIF, LOOP-ENDLOOP, FOR-ENDFOR,
//! WHILE-ENDWHILE, REPEAT-UNTIL): which lines belong together (their [`Link`]s, with the
//! interpreter's links of LinuxCNC O-words, so that the planner keeps or expands them as it does
//! those), where each jump lands, and the flow at each statement.
//!
//! A jump goes to the block that carries its label (`NAME:` at the start of a block) or its
//! block number (`N100`): GOTOF searches towards the end of the program, GOTOB towards its start,
//! GOTO forward first, then backward; GOTOC as GOTO, but a target not found continues with the
//! next block where the others stop with alarm 14080. A jump into a control structure from
//! outside it is refused (the 840D forbids it); a jump out of one is taken (`LOOP` is left only
//! this way). `FOR counter = a TO b` runs its blocks with the counter a, a + 1, ... while it is
//! at most b (b evaluated at each pass); `REPEAT` runs its blocks until the condition of `UNTIL`
//! holds, at least once; `WHILE` while its condition holds.

use crate::expr::{Environment, ExprId, ParamRef};
use crate::interpret::{Exec, Flow};
use crate::lexer::Statement;
use crate::program::{Link, SourceFile};

/// A SINUMERIK control statement (one a block).
#[derive(Clone, Debug, PartialEq)]
pub enum Control {
    If(ExprId),
    Else,
    EndIf,
    While(ExprId),
    EndWhile,
    Loop,
    EndLoop,
    Repeat,
    Until(ExprId),
    For {
        counter: ParamRef,
        from: ExprId,
        to: ExprId,
    },
    EndFor,
    /// `GOTOF`/`GOTOB`/`GOTO`/`GOTOC`, after `IF condition` or alone.
    Jump(Jump),
}

/// A jump and where it lands (found when the file is indexed).
#[derive(Clone, Debug, PartialEq)]
pub struct Jump {
    pub condition: Option<ExprId>,
    pub kind: JumpKind,
    pub target: Target,
    /// The line of the target (0-based), if there is one in the jump's direction.
    pub line: Option<usize>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JumpKind {
    /// GOTOF
    Forward,
    /// GOTOB
    Backward,
    /// GOTO: forward, then backward
    Both,
    /// GOTOC: as GOTO, no alarm without a target
    NoAlarm,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Target {
    Label(Box<str>),
    Block(u32),
}

impl JumpKind {
    pub fn keyword(self) -> &'static str {
        match self {
            JumpKind::Forward => "GOTOF",
            JumpKind::Backward => "GOTOB",
            JumpKind::Both => "GOTO",
            JumpKind::NoAlarm => "GOTOC",
        }
    }
}

impl std::fmt::Display for Target {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Target::Label(l) => write!(f, "{l}"),
            Target::Block(n) => write!(f, "N{n}"),
        }
    }
}

impl Control {
    /// The structure a statement opens, continues or closes, as the 840D names it.
    fn structure(&self) -> &'static str {
        match self {
            Control::If(_) | Control::Else | Control::EndIf => "IF",
            Control::While(_) | Control::EndWhile => "WHILE",
            Control::Loop | Control::EndLoop => "LOOP",
            Control::Repeat | Control::Until(_) => "REPEAT",
            Control::For { .. } | Control::EndFor => "FOR",
            Control::Jump(j) => j.kind.keyword(),
        }
    }

    /// The name of the structure a line opens (for the notes of expanded parts).
    pub fn name(&self) -> String {
        match self {
            Control::If(_) | Control::Loop => self.structure().into(),
            c => format!("{} loop", c.structure()),
        }
    }
}

fn control(file: &SourceFile, k: usize) -> Option<&Control> {
    match file.lines[k].as_ref().ok()?.statement.as_ref()? {
        Statement::Siemens(c) => Some(c),
        _ => None,
    }
}

/// Links the control structures of `file` and finds the lines its jumps land on; an error at
/// the index of the line of a structure that does not close or match, or of a jump into one.
pub(crate) fn index(file: &mut SourceFile) -> Result<(), (usize, String)> {
    definitions_first(file)?;
    // open structures: (name, line, IF and ELSE lines)
    let mut stack: Vec<(&'static str, usize, Vec<usize>)> = Vec::new();
    let mut structures: Vec<(usize, usize)> = Vec::new();
    let mut jumps = Vec::new();
    for k in file.body.clone() {
        let Some(c) = control(file, k) else { continue };
        let name = c.structure();
        let closes = match c {
            Control::If(_) | Control::While(_) | Control::Loop | Control::Repeat | Control::For { .. } => {
                stack.push((name, k, vec![k]));
                continue;
            }
            Control::Jump(_) => {
                jumps.push(k);
                continue;
            }
            Control::Else => {
                match stack.last_mut() {
                    Some(("IF", _, branches)) if branches.len() == 1 => branches.push(k),
                    Some(("IF", start, _)) => return Err((k, format!("a second ELSE for the IF of line {}", *start + 1))),
                    _ => return Err((k, "ELSE without its IF".into())),
                }
                continue;
            }
            Control::EndIf => "ENDIF",
            Control::EndWhile => "ENDWHILE",
            Control::EndLoop => "ENDLOOP",
            Control::Until(_) => "UNTIL",
            Control::EndFor => "ENDFOR",
        };
        let (open, start, branches) = match stack.pop() {
            Some((open, start, branches)) if open == name => (open, start, branches),
            Some((open, start, _)) => return Err((k, format!("{closes} closes the {open} of line {}", start + 1))),
            None => return Err((k, format!("{closes} without its {name}"))),
        };
        structures.push((start, k));
        if open == "IF" {
            for (i, &b) in branches.iter().enumerate() {
                file.links[b] = Link::Branch { next: branches.get(i + 1).copied().unwrap_or(k), end: k };
            }
        } else {
            file.links[start] = Link::LoopStart { end: k };
            file.links[k] = Link::LoopEnd { start };
        }
    }
    if let Some((open, start, _)) = stack.pop() {
        let end = match open {
            "IF" => "ENDIF",
            "REPEAT" => "UNTIL",
            other => return Err((start, format!("the {other} is never closed (END{other})"))),
        };
        return Err((start, format!("the {open} is never closed ({end})")));
    }
    for k in jumps {
        let Some(Control::Jump(j)) = control(file, k) else { unreachable!("a jump") };
        let line = landing(file, k, j);
        if let Some(t) = line {
            if let Some(&(s, e)) = structures.iter().find(|&&(s, e)| s < t && t <= e && !(s..=e).contains(&k)) {
                let what = control(file, s).map_or("", Control::structure);
                return Err((
                    k,
                    format!("{} {}: a jump into the {what} of lines {}-{} (the 840D refuses it)", j.kind.keyword(), j.target, s + 1, e + 1),
                ));
            }
        }
        if let Ok(l) = &mut file.lines[k] {
            if let Some(Statement::Siemens(Control::Jump(j))) = &mut l.statement {
                j.line = line;
            }
        }
    }
    Ok(())
}

/// `DEF` only before the first other statement of the file (the 840D's rule for local variables).
fn definitions_first(file: &SourceFile) -> Result<(), (usize, String)> {
    let def = |k: usize| matches!(&file.lines[k], Ok(l) if l.siemens_def);
    let Some(first) = file.body.clone().find(|&k| matches!(&file.lines[k], Ok(l) if !l.is_empty() && !l.siemens_def)) else {
        return Ok(());
    };
    match (first..file.body.end).find(|&k| def(k)) {
        Some(k) => Err((k, format!("DEF after the statements of line {}: the 840D takes DEF at the top of a program", first + 1))),
        None => Ok(()),
    }
}

/// The line a jump at `k` lands on, searched in its direction(s).
fn landing(file: &SourceFile, k: usize, j: &Jump) -> Option<usize> {
    let is_target = |t: usize| match (&j.target, &file.lines[t]) {
        (Target::Label(name), Ok(l)) => l.siemens_label.as_deref() == Some(&**name),
        (Target::Block(n), Ok(l)) => l.sequence == Some(*n),
        _ => false,
    };
    let forward = || (k + 1..file.body.end).find(|&t| is_target(t));
    let backward = || (file.body.start..k).rev().find(|&t| is_target(t));
    match j.kind {
        JumpKind::Forward => forward(),
        JumpKind::Backward => backward(),
        JumpKind::Both | JumpKind::NoAlarm => forward().or_else(backward),
    }
}

/// The flow at the control statement `c` of line `pc`.
pub(crate) fn flow(exec: &mut Exec, file: &SourceFile, pc: (usize, usize), c: &Control) -> Result<Flow, String> {
    let k = pc.1;
    let link = file.links[k];
    let mut holds = |e: ExprId| exec.eval(file, e).map(|v| !v.is_nan() && v != 0.0);
    Ok(match (c, link) {
        (Control::If(cond), Link::Branch { next, .. }) => {
            if holds(*cond)? {
                Flow::Next
            } else {
                Flow::Jump(next + 1)
            }
        }
        // reached at the end of the IF branch
        (Control::Else, Link::Branch { end, .. }) => Flow::Jump(end + 1),
        (Control::While(cond), Link::LoopStart { end }) => {
            if holds(*cond)? {
                Flow::Next
            } else {
                Flow::Jump(end + 1)
            }
        }
        (Control::EndWhile, Link::LoopEnd { start }) => Flow::Jump(start),
        (Control::EndLoop, Link::LoopEnd { start }) => Flow::Jump(start + 1),
        (Control::Until(cond), Link::LoopEnd { start }) => {
            if holds(*cond)? {
                Flow::Next
            } else {
                Flow::Jump(start + 1)
            }
        }
        (Control::For { counter, from, to }, Link::LoopStart { end }) => {
            let v = exec.eval(file, *from)?;
            exec.assign(counter, None, v)?;
            if v <= exec.eval(file, *to)? {
                Flow::Next
            } else {
                Flow::Jump(end + 1)
            }
        }
        (Control::EndFor, Link::LoopEnd { start }) => {
            let Some(Control::For { counter, to, .. }) = control(file, start) else { unreachable!("indexed FOR") };
            let v = exec.read(counter, None)? + 1.0;
            exec.assign(counter, None, v)?;
            if v <= exec.eval(file, *to)? {
                Flow::Jump(start + 1)
            } else {
                Flow::Next
            }
        }
        (Control::Jump(j), _) => {
            if let Some(cond) = j.condition {
                if !holds(cond)? {
                    return Ok(Flow::Next);
                }
            }
            match (j.line, j.kind) {
                (Some(t), _) => Flow::Jump(t),
                (None, JumpKind::NoAlarm) => Flow::Next,
                (None, kind) => {
                    let where_ = match kind {
                        JumpKind::Forward => "after this block",
                        JumpKind::Backward => "before this block",
                        _ => "in this program",
                    };
                    return Err(format!(
                        "{} {}: no block {} {where_} (the 840D stops with alarm 14080)",
                        kind.keyword(),
                        j.target,
                        j.target
                    ));
                }
            }
        }
        (Control::EndIf | Control::Loop | Control::Repeat, _) => Flow::Next,
        (c, l) => unreachable!("indexed {c:?} {l:?}"),
    })
}
