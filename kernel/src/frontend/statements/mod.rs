//! Statements: what a control's programming language adds to the word address format —
//! control flow (conditions, loops) and variable assignments. Each language has its own
//! module; a block that is a statement is run here and produces no
//! block of its own, while an assignment may stand among a block's words.
//!
//! - [`isg`]: ISG `$IF`/`$ELSEIF`/`$ELSE`/`$ENDIF`, `$FOR`, `$WHILE`, `V.` assignments.
//! - [`fanuc`]: Fanuc Custom Macro B `#i = …`, `IF`, `GOTO`, `WHILE … DO`/`END`, G65/G66.
//! - [`siemens_840c`]: the 840C's R parameters (`R1=…`, `X R1`) and `@` commands with
//!   operands; they stand among a block's words, so the word loop reads them.
//! - SINUMERIK statements and calls (also the 840C's `L123 P3`: sinumerik/calls.rs) are in `sinumerik/`.

pub(super) mod fanuc;
pub(super) mod isg;
pub(super) mod siemens_840c;

use super::fault::R;
use super::interpreter::Interpreter;
use super::lexer::Cursor;

impl Interpreter<'_> {
    /// Whether the block at the cursor (after its number) is a statement of the dialect's
    /// language.
    #[inline(always)]
    pub(super) fn is_statement(&self, c: &Cursor) -> bool {
        (self.d.variables && c.peek() == Some(b'$'))
            || (self.d.macro_b && self.is_macro_statement(c))
            || (self.d.sinumerik && super::sinumerik::statements::Keyword::at(c).is_some())
            || ((self.d.sinumerik || self.d.l_calls) && self.is_call(c))
    }

    /// Runs a statement block whose text starts at `start`; true if it produced a block (a
    /// statement that reads the present position hands out a preprocessing stop).
    pub(super) fn statement(&mut self, c: Cursor, start: usize, block_col: usize) -> R<bool> {
        if self.d.variables {
            return self.isg_statement(c).map(|()| false);
        }
        if self.d.sinumerik {
            let produced = self.sinumerik_statement(c, start)?;
            if !produced && self.sinumerik.store.main_run_read.take() {
                // A main-run variable (`IF $AA_IW[X]>5 …`): an implicit STOPRE here.
                let col = super::lexer::column(self.src, self.blk_line_start, block_col);
                let (line, number, program) = (self.blk_line, self.blk_number, self.block.program);
                self.empty_block_at(line, col, number);
                self.block.program = program;
                self.block.preprocess_stop = true;
                return Ok(true);
            }
            return Ok(produced);
        }
        if self.d.l_calls {
            return self.call_block(c);
        }
        self.present_state_read.set(false);
        // The statement's own place: a jump, a skipped loop or a call moves the reading on.
        let col = super::lexer::column(self.src, self.blk_line_start, block_col);
        let (line, number, program) = (self.blk_line, self.blk_number, self.block.program);
        self.macro_statement(c, start)?;
        let message = self.macros.stop_message.take();
        if self.present_state_read.get() || message.is_some() {
            self.empty_block_at(line, col, number);
            self.block.program = program;
            self.block.preprocess_stop = self.present_state_read.get();
            if let Some(m) = message {
                self.block.stop = Some(crate::frontend::block::ProgramStop::Stop);
                self.block.message = Some(m);
            }
            return Ok(true);
        }
        Ok(false)
    }
}
