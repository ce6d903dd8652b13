//! The front end: part-program text in, interpreted blocks out (lexer, parser and interpreter
//! with one dialect table per control).

mod arc;
pub mod block;
mod block_text;
mod build;
pub mod expr;
mod fault;
mod interpreter;
pub mod jsonl;
mod lexer;
pub mod number;
mod plain;
mod statements;
mod variables;
mod word_loop;
mod words;

pub use block::*;
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
