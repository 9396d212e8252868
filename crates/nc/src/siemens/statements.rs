//! Reading the SINUMERIK control statements and labels of a block (Programming Manual Job
//! Planning, "Program jumps to jump markers", "Conditional program jumps", "Control structures"),
//! run by [`super::flow`]: a label `NAME:` at the start of a block (after its `N` number), then
//! `IF condition` (a structure), `IF condition GOTOF target` (a conditional jump), `ELSE`,
//! `ENDIF`, `WHILE condition`/`ENDWHILE`, `LOOP`/`ENDLOOP`, `REPEAT`/`UNTIL condition`, `FOR
//! counter = a TO b`/`ENDFOR` (the counter an R parameter or a DEF variable), `GOTOF`, `GOTOB`,
//! `GOTO`, `GOTOC` with a label or a block number `N100`. A statement is the only item of its
//! block (a comment may follow). `REPEAT` with a label (program section repetition) and jumps to
//! a target held in a variable are refused with the line.

use super::expr::Parser;
use super::flow::{Control, Jump, JumpKind, Target};
use crate::expr::{Node, ParamRef};
use crate::lexer::Line;

/// The words that begin a control statement.
pub const KEYWORDS: [&str; 15] =
    ["IF", "ELSE", "ENDIF", "WHILE", "ENDWHILE", "LOOP", "ENDLOOP", "REPEAT", "UNTIL", "FOR", "ENDFOR", "GOTOF", "GOTOB", "GOTO", "GOTOC"];

/// A label `NAME:` at the cursor, read into `line`.
pub(crate) fn label(p: &mut Parser, line: &mut Line) {
    let start = {
        p.peek();
        p.i
    };
    let end = (start..p.s.len()).find(|&j| !(p.s[j].is_ascii_alphanumeric() || p.s[j] == b'_')).unwrap_or(p.s.len());
    let name = String::from_utf8_lossy(&p.s[start..end]).to_ascii_uppercase();
    if p.s.get(end) == Some(&b':') && super::variables::is_variable_name(&name) {
        line.siemens_label = Some(name.into());
        p.i = end + 1;
    }
}

/// The control statement that starts with `keyword` (read), to the end of the block.
pub(crate) fn statement(keyword: &str, p: &mut Parser, arena: &mut Vec<Node>) -> Result<Control, String> {
    let c = match keyword {
        "IF" => {
            let cond = p.expression(arena)?;
            match p.name().as_str() {
                "" => Control::If(cond),
                k @ ("GOTOF" | "GOTOB" | "GOTO" | "GOTOC") => jump(k, Some(cond), p)?,
                other => return Err(format!("IF ... {other}: a condition is followed by GOTOF/GOTOB/GOTO/GOTOC or the end of the block")),
            }
        }
        "ELSE" => Control::Else,
        "ENDIF" => Control::EndIf,
        "WHILE" => Control::While(p.expression(arena)?),
        "ENDWHILE" => Control::EndWhile,
        "LOOP" => Control::Loop,
        "ENDLOOP" => Control::EndLoop,
        "REPEAT" if !matches!(p.peek(), 0 | b';') => {
            return Err("REPEAT with a label (program section repetition) is not read yet: write the section as a loop".into())
        }
        "REPEAT" => Control::Repeat,
        "UNTIL" => Control::Until(p.expression(arena)?),
        "FOR" => {
            let name = p.name();
            let counter = match name.strip_prefix('R').and_then(|d| d.parse::<u32>().ok()) {
                Some(n) if n < super::R_COUNT => ParamRef::Numbered(super::R_BASE + n),
                _ if super::variables::is_variable_name(&name) => ParamRef::Named(name.clone().into()),
                _ => return Err(format!("FOR {name}: the counter is an R parameter or a DEF variable")),
            };
            if p.peek() != b'=' {
                return Err(format!("FOR {name} without `= start TO end`"));
            }
            p.i += 1;
            let from = p.expression(arena)?;
            if p.name() != "TO" {
                return Err("FOR counter = start TO end: `TO` expected".into());
            }
            let to = p.expression(arena)?;
            Control::For { counter, from, to }
        }
        "ENDFOR" => Control::EndFor,
        k => jump(k, None, p)?,
    };
    match p.peek() {
        0 | b';' => Ok(c),
        _ => Err(format!("{keyword} is written on a block of its own: `{}` after it", String::from_utf8_lossy(&p.s[p.i..]).trim_end())),
    }
}

/// `GOTOF target` and the others, from after the keyword.
fn jump(keyword: &str, condition: Option<u32>, p: &mut Parser) -> Result<Control, String> {
    let kind = match keyword {
        "GOTOF" => JumpKind::Forward,
        "GOTOB" => JumpKind::Backward,
        "GOTO" => JumpKind::Both,
        _ => JumpKind::NoAlarm,
    };
    let name = p.name();
    let target = match name.strip_prefix('N').and_then(|d| d.parse::<u32>().ok()) {
        Some(n) => Target::Block(n),
        None if super::variables::is_variable_name(&name) => Target::Label(name.into()),
        None => return Err(format!("{keyword}: a label or a block number N.. expected (a target in a variable is not read)")),
    };
    Ok(Control::Jump(Jump { condition, kind, target, line: None }))
}
