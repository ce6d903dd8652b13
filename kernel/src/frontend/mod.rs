//! The front end: part-program text in, interpreted [`Block`]s out. The [`Interpreter`]
//! streams: it reads one block's text at a time and hands out the block in the dialect-free
//! terms of block.rs; what differs between controls is looked up in the dialect's table
//! (`crate::dialect`), never written as a number here.
//!
//! The way of one block, module by module:
//!
//! ```text
//! interpreter   the Interpreter: its state, the stream of blocks, faults to alarms (fault)
//! block_text    where a block's text ends; `%`, `/` and `O` lines; the N number
//!   then one of
//! statements    a statement of the control's language, run in place (no block, or a
//!               preprocessing stop)
//! plain         the plain motion block, read and built in one pass
//! word_loop     the block's words (words, number, lexer; ISG expressions: expr, variables)
//!   └ build     the block from its words, in the order of execution
//!               (build/gcodes, technology, flow, motion; arc)
//! ```
//!
//! Where the languages' larger features go:
//!
//! - **Statements of each language** are a module each under `statements/`: `isg.rs`
//!   (`$IF`, `$FOR`, `$WHILE`, `V.` assignments), `fanuc.rs` (Custom Macro B: `#`
//!   assignments, `IF … GOTO`/`THEN`, `WHILE … DO … END`, `GOTO`, G65/G66 calls) and
//!   `siemens_840c.rs` (the 840C's R parameters and `@` commands, read among a block's words
//!   by the word loop; a block of them alone hands out nothing); the
//!   SINUMERIK language is `sinumerik/` (its store, expressions, statements and the
//!   structure read before the first block). `statements/mod.rs` tells a statement block
//!   from a block of words for the dialect.
//! - **Variable stores**: `variables.rs` (ISG `V.`), `macro_b/` (Fanuc local, common and
//!   kept `#` ranges, the system variables bound to the interpreter's state); the locals a
//!   call level owns move with that level.
//! - **The call stack** (`calls.rs`) extends the interpreter's reading position (`src`,
//!   `pos`, `line`, `line_start`) and its open loops into one frame per call level: a call
//!   (M98, G65, G66) pushes a frame, a return (M99) pops it. The codes are dialect-table
//!   effects (`MEffect::Call`, `GEffect::MacroCall` …).
//! - **Blocks that become several moves** (`build/expand.rs`): canned cycles
//!   (`build/cycles/`, one module per family) and the reference point return
//!   (`build/reference.rs`) put their first move into the programmed block and hand the rest
//!   out one per `next_block`, before the next block's text is read.
//! - **The zero and the frame** (`coordinates.rs`, `frame.rs`, `build/settings.rs`,
//!   `build/frames.rs`): work offset plus G92/G52 shifts, the program's G10 copies of the
//!   tables, and the mirror/scale/rotation map under which a block is computed in program
//!   coordinates and then mapped.

mod arc;
pub mod block;
mod block_text;
mod build;
mod calls;
mod coordinates;
pub mod expr;
mod fault;
mod frame;
mod interpreter;
pub mod jsonl;
mod lexer;
mod macro_b;
pub mod number;
mod plain;
mod plane;
mod sinumerik;
mod statements;
mod variables;
mod word_loop;
mod words;

pub use block::*;
pub use build::{CornerKind, CycleKind};
pub use interpreter::Interpreter;
pub use sinumerik::approach::{SarContour, SarPath, SarSide};

use crate::alarm::Alarm;
use crate::machine_data::MachineData;
use crate::tools::ToolTable;

/// Interprets a whole program. Stops at the first alarm.
pub fn interpret(
    name: &str,
    source: &str,
    md: &MachineData,
    tools: &ToolTable,
) -> Result<Vec<Block>, Alarm> {
    Interpreter::new(name, source, md, tools).collect()
}

impl Iterator for Interpreter<'_> {
    type Item = Result<Block, Alarm>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_block().map(|b| b.cloned()).transpose()
    }
}

/// A program interpreted in a dialect with its built-in machine data and the shipped tools.
#[cfg(test)]
fn run(dialect: &str, src: &str) -> Result<Vec<Block>, Alarm> {
    let md = MachineData::load(None, &[format!("dialect={dialect}")]).expect("machine data");
    interpret("p", src, &md, &ToolTable::builtin())
}

/// Every move of a program that must run (`run`): its kind, end and centre.
#[cfg(test)]
fn moves(dialect: &str, src: &str) -> Vec<(MotionKind, Pos, Pos)> {
    run(dialect, src)
        .unwrap_or_else(|a| panic!("{a}"))
        .iter()
        .filter_map(|b| b.motion)
        .map(|m| (m.kind, m.end, m.center))
        .collect()
}

/// Two points agree to 1e-9 in every axis.
#[cfg(test)]
fn near(a: Pos, b: Pos) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() < 1e-9)
}

/// The code, line and column of the alarm a program must stop with (`run`).
#[cfg(test)]
fn alarm_at(dialect: &str, src: &str) -> (crate::alarm::AlarmCode, u32, u32) {
    let a = run(dialect, src).unwrap_err();
    (a.code, a.line, a.col)
}

/// The X of every move's end of a program that must run (`run`).
#[cfg(test)]
fn end_xs(dialect: &str, src: &str) -> Vec<f64> {
    run(dialect, src)
        .unwrap_or_else(|a| panic!("{a}"))
        .iter()
        .filter_map(|b| b.motion.map(|m| m.end[0]))
        .collect()
}
