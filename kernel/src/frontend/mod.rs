//! The front end: part-program text in, interpreted blocks out (lexer, parser and interpreter
//! with one dialect table per control).

mod arc;
pub mod block;
mod control;
pub mod expr;
mod fault;
mod interp;
pub mod jsonl;
mod lexer;
pub mod number;
mod variables;

pub use block::*;
pub use interp::Interpreter;

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
