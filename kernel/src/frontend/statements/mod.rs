//! Statements: what a control's programming language adds to the word address format —
//! control flow (conditions, loops) and variable assignments. Each language has its own
//! module; a block that is a statement is run here and produces no
//! block of its own, while an assignment may stand among a block's words.
//!
//! - [`isg`]: ISG `$IF`/`$ELSEIF`/`$ELSE`/`$ENDIF`, `$FOR`, `$WHILE`, `V.` assignments.

pub(super) mod isg;

use super::fault::R;
use super::interpreter::Interpreter;
use super::lexer::Cursor;

impl Interpreter<'_> {
    /// Whether the block at the cursor (after its number) is a statement of the dialect's
    /// language.
    #[inline(always)]
    pub(super) fn is_statement(&self, c: &Cursor) -> bool {
        self.d.variables && c.peek() == Some(b'$')
    }

    /// Runs a statement block.
    pub(super) fn statement(&mut self, c: Cursor) -> R<()> {
        self.isg_statement(c)
    }
}
