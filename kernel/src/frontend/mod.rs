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
//! statements    a statement of the control's language, run in place (no block)
//! plain         the plain motion block, read and built in one pass
//! word_loop     the block's words (words, number, lexer; ISG expressions: expr, variables)
//!   └ build     the block from its words, in the order of execution
//!               (build/gcodes, technology, flow, motion; arc)
//! ```
//!
//! Where the languages' larger features go:
//!
//! - **Statements of each language** are a module each under `statements/`, next to
//!   `statements/isg.rs` (`$IF`, `$FOR`, `$WHILE`, `V.` assignments): Fanuc Macro B
//!   (`#` variables, `IF … GOTO`, `WHILE … DO … END`), the Sinumerik high-level language
//!   (`IF`/`LOOP`/`FOR`/`WHILE`/`REPEAT`, `GOTOF`/`GOTOB`, `DEF`, R parameters).
//!   `statements/mod.rs` tells a statement block from a block of words for the dialect.
//! - **Variable stores** live in `variables.rs`, one namespace per language (Fanuc local,
//!   common and permanent `#` ranges, Sinumerik R parameters and user variables, ISG `V.`);
//!   the store a call level owns (locals) moves with that level.
//! - **A subprogram call stack** extends the interpreter's reading position (`pos`, `line`,
//!   `line_start`) and its open control structures into one frame per call level: a call
//!   (Fanuc M98/G65, Sinumerik `L`/`CALL`, ISG `L`) pushes a frame with its program text and
//!   locals, a return (M99, `RET`/M17) pops it. The codes come into the dialect tables as
//!   effects, like the program stops (`MEffect`).
//! - **Canned cycles** (drilling G81…G89, Sinumerik `CYCLE…`) become a G or call effect in
//!   the tables and a module of their own under `build/`: the build takes the cycle's
//!   parameters from the words and expands it into several blocks, which the interpreter hands
//!   out one per `next_block` before it reads the next block's text; a modal cycle repeats at
//!   every following position, like the motion mode.

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
mod statements;
mod variables;
mod word_loop;
mod words;

pub use block::*;
pub use build::CycleKind;
pub use interpreter::Interpreter;

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
