//! The SINUMERIK 840D sl native language, read into the interpreter's lines (SINUMERIK 840D sl
//! Programming Manual Fundamentals, the chapters cited in each file): [`lexer`] reads a block
//! (addresses with a number or `=` and an expression, `CR=` arcs, R parameters, `TRANS`/`ATRANS`,
//! text calls that move nothing), [`expr`] its arithmetic, [`cycles`] the drilling cycles run
//! (their values and strokes: [`drilling`]; written as cycles again: [`kept`]),
//! [`subprograms`] the calls of subprogram files. What the 840D does that LinuxCNC's
//! interpreter does the same way is run by it: a `CR=` arc is an R arc (negative: the arc over
//! 180 degrees, as LinuxCNC's negative R), `TRANS X Y Z` is the `G52` shift of every axis named or
//! not (the programmable frame replaced), `ATRANS` adds to it, `SUPA` is `G53`, `D1`... switch the
//! tool length offset on (`G43` with the tool in the spindle, also after each `M6`, as the 840D's
//! default cutting edge D1 does) and `D0` off (`G49`).
//!
//! R parameters `R0`-`R999` are kept as the numbered parameters `#1000`-`#1999` of the run.

pub mod arcs;
pub mod cycles;
pub mod drilling;
pub mod expr;
pub mod flow;
pub mod kept;
pub mod lexer;
pub mod statements;
pub mod subprograms;
pub mod variables;
pub mod write;

pub use cycles::Call;
pub use lexer::is_file_header;
pub(crate) use lexer::parse_line;

/// The first numbered parameter that holds `R0`.
pub const R_BASE: u32 = 1000;
/// R parameters read: `R0`-`R999`.
pub const R_COUNT: u32 = 1000;
