//! Fanuc Custom Macro B statements (0i-MF operator's manual, "Custom macro"): a block that
//! is a macro statement runs here and produces no block of its own.
//!
//! ```text
//! #i = <expression>            assignment (#3000 = n (message): alarm 3000+n)
//! IF [<condition>] GOTO n      jump to sequence number n if the condition holds
//! IF [<condition>] THEN #i=…   one assignment if it holds
//! GOTO n                       n: a number, #i or [expression]
//! WHILE [<condition>] DO m     m = 1…3; the body up to END m runs while it holds
//! DO m … END m                 without WHILE: an endless loop (bounded by machine data)
//! G65 P<program> L<count> <arguments>   macro call; G66 the same, modal
//! ```
//!
//! Loops nest three deep; a jump out of a loop is allowed. Every backward jump and every
//! loop pass counts against `program.max_loop_iterations`, so no program runs for ever.

use super::super::calls::{Args, CallKind, DoLoop, Mark, ModalCall, Pending, Target};
use super::super::fault::{fault, Fault, R};
use super::super::interpreter::Interpreter;
use super::super::lexer::Cursor;
use super::super::macro_b::{expr, slot, Slot, Value, LOCALS};
use super::super::number;
use super::super::words::Val;
use crate::alarm::AlarmCode;
use crate::dialect::GEffect;

/// WHILE … DO loops open at once (0i-MF: DO 1 … DO 3).
const MAX_LOOPS: usize = 3;

/// Which macro statement a block is.
enum Kind {
    Assign,
    If,
    Goto,
    While,
    Do,
    End,
    /// G65 (false) or G66 (true).
    Call(bool),
}

impl Interpreter<'_> {
    /// Whether the block at the cursor is a macro statement (the dialect has Macro B).
    pub(in crate::frontend) fn is_macro_statement(&self, c: &Cursor) -> bool {
        self.macro_kind(c).is_some()
    }

    fn macro_kind(&self, c: &Cursor) -> Option<Kind> {
        match c.letter() {
            None => (c.peek() == Some(b'#')).then_some(Kind::Assign),
            Some(b'I') if c.keyword("IF") => Some(Kind::If),
            Some(b'W') if c.keyword("WHILE") => Some(Kind::While),
            Some(b'D') if c.keyword("DO") => Some(Kind::Do),
            Some(b'E') if c.keyword("END") => Some(Kind::End),
            Some(b'G') if c.keyword("GOTO") => Some(Kind::Goto),
            Some(b'G') => match self.leading_g(c)? {
                GEffect::MacroCall => Some(Kind::Call(false)),
                GEffect::ModalMacroCall => Some(Kind::Call(true)),
                _ => None,
            },
            _ => None,
        }
    }

    /// The effect of a G code standing first in the block, if it is a whole number.
    fn leading_g(&self, c: &Cursor) -> Option<GEffect> {
        let (n, _) = number::parse(c.b, c.i + 1).filter(|(_, e)| *e <= c.end)?;
        let whole = !n.has_point && n.value >= 0.0 && n.value < 1000.0;
        whole
            .then(|| self.d.gcode(n.value as u16))
            .flatten()
            .map(|def| def.effect)
    }

    /// Runs a macro statement whose text starts at `start`; true if it produced a block.
    pub(in crate::frontend) fn macro_statement(&mut self, mut c: Cursor, start: usize) -> R<bool> {
        let at = c.i;
        let head = (start, self.blk_line, self.blk_line_start);
        match self.macro_kind(&c) {
            Some(Kind::Assign) => self.assign_statement(&mut c),
            Some(Kind::If) => self.if_statement(&mut c),
            Some(Kind::Goto) => {
                c.i += 4;
                let n = self.label_operand(&mut c, at)?;
                end_of_statement(&mut c)?;
                self.goto(n, at)
            }
            Some(Kind::While) => self.while_statement(&mut c, head, at),
            Some(Kind::Do) => {
                c.i += 2;
                let m = loop_number(&mut c, self, at)?;
                end_of_statement(&mut c)?;
                self.open_loop(m, (self.pos, self.line, self.line_start), true, at)
            }
            Some(Kind::End) => {
                c.i += 3;
                let m = loop_number(&mut c, self, at)?;
                end_of_statement(&mut c)?;
                self.end_loop(m, at)
            }
            Some(Kind::Call(modal)) => self.macro_call(&mut c, modal, at),
            None => Ok(false),
        }
    }

    /// `#i = expression`.
    fn assign_statement(&mut self, c: &mut Cursor) -> R<bool> {
        let (n, at) = expr::variable(c, &*self)?;
        c.skip_blanks();
        if c.peek() != Some(b'=') {
            return Err(syntax(c.i, format!("'=' expected after #{n}")));
        }
        c.i += 1;
        let v = expr::eval(c, &*self)?;
        let message = trailing_comment(c)?;
        self.write_variable(n, v, at, message)?;
        Ok(false)
    }

    /// Writes `#n`; #0 and the read-only system variables are refused at `at`.
    fn write_variable(&mut self, n: i64, v: Value, at: usize, message: String) -> R<()> {
        match slot(n) {
            Slot::Vacant => Err(fault(
                AlarmCode::UndefinedName,
                at,
                "#0 is always vacant and cannot be written",
            )),
            Slot::System(3000) => Err(self.program_alarm(v, at, message)),
            // 0i-MF "#3006": stop after the blocks before, with the message shown.
            Slot::System(3006) => {
                self.macros.stop_message = Some(message.trim().into());
                Ok(())
            }
            Slot::System(n) => Err(fault(
                AlarmCode::UndefinedName,
                at,
                format!("#{n} cannot be written (docs/macros.md lists the writable variables)"),
            )),
            s => {
                self.macros.set_program(s, v);
                Ok(())
            }
        }
    }

    /// `#3000 = n (message)`: alarm 3000 + n with the program's message (n = 0…200).
    fn program_alarm(&self, v: Value, at: usize, message: String) -> Box<Fault> {
        let n = v.unwrap_or(0.0);
        if !(0.0..=200.0).contains(&n) || n.fract() != 0.0 {
            return fault(
                AlarmCode::BadNumber,
                at,
                format!("#3000 takes an alarm number 0…200, not {n}"),
            );
        }
        fault(
            AlarmCode::ProgramAlarm,
            at,
            format!("MC{} {}", 3000 + n as u32, message.trim()),
        )
    }

    /// `IF [condition] GOTO n` or `IF [condition] THEN #i = …`.
    fn if_statement(&mut self, c: &mut Cursor) -> R<bool> {
        c.i += 2;
        let cond = self.condition(c, "IF")?;
        c.skip_blanks();
        if c.keyword("GOTO") {
            let goto_at = c.i;
            c.i += 4;
            let n = self.label_operand(c, goto_at)?;
            end_of_statement(c)?;
            return if expr::truthy(cond) {
                self.goto(n, goto_at)
            } else {
                Ok(false)
            };
        }
        if !c.keyword("THEN") {
            return Err(syntax(c.i, "GOTO or THEN expected after the IF condition"));
        }
        c.i += 4;
        c.skip_blanks();
        if c.peek() != Some(b'#') {
            return Err(syntax(c.i, "THEN takes one assignment #i = …"));
        }
        if !expr::truthy(cond) {
            // The statement is still read, so a syntax error shows at once.
            let mut probe = *c;
            expr::variable(&mut probe, &*self)?;
            return Ok(false);
        }
        self.assign_statement(c)
    }

    /// `[condition]` after IF or WHILE.
    fn condition(&mut self, c: &mut Cursor, what: &str) -> R<Value> {
        c.skip_blanks();
        if c.peek() != Some(b'[') {
            return Err(syntax(c.i, format!("{what} needs its condition in [ ]")));
        }
        expr::operand(c, &*self)
    }

    /// The sequence number after GOTO: a number, `#i` or `[expression]`.
    fn label_operand(&mut self, c: &mut Cursor, at: usize) -> R<u32> {
        c.skip_blanks();
        let v = if expr::at_operand(c) {
            expr::operand(c, &*self)?
        } else {
            let (n, next) = number::parse(c.b, c.i)
                .filter(|(_, e)| *e <= c.end)
                .ok_or_else(|| syntax(c.i, "GOTO needs a sequence number"))?;
            c.i = next;
            Some(n.value)
        };
        let v = v.ok_or_else(|| {
            fault(
                AlarmCode::MissingValue,
                at,
                "GOTO to a vacant variable's sequence number",
            )
        })?;
        sequence_number(v, at)
    }

    /// Goes on at sequence number `n`; a jump backwards counts as a loop pass. Loops that
    /// began after the target are left.
    fn goto(&mut self, n: u32, at: usize) -> R<bool> {
        let target = self.find_label(n, at)?;
        if target.0 < self.pos {
            self.next_pass(at)?;
        }
        self.calls.loops.retain(|l| l.head.0 < target.0);
        (self.pos, self.line, self.line_start) = target;
        Ok(false)
    }

    /// `WHILE [condition] DO m`: enters the body or skips past its END m.
    fn while_statement(&mut self, c: &mut Cursor, head: Mark, at: usize) -> R<bool> {
        c.i += 5;
        let cond = self.condition(c, "WHILE")?;
        c.skip_blanks();
        if !c.keyword("DO") {
            return Err(syntax(c.i, "DO m expected after the WHILE condition"));
        }
        c.i += 2;
        let m = loop_number(c, self, at)?;
        end_of_statement(c)?;
        if expr::truthy(cond) {
            self.open_loop(m, head, false, at)
        } else {
            self.skip_past_end(m, at).map(|()| false)
        }
    }

    /// A loop pass begins: DO m is open (again), with its head.
    fn open_loop(&mut self, m: u8, head: Mark, endless: bool, at: usize) -> R<bool> {
        self.next_pass(at)?;
        let loops = &mut self.calls.loops;
        // The same DO m open already: a loop a jump left; it ends here (the loops opened
        // after it stay).
        if let Some(k) = loops.iter().position(|l| l.m == m) {
            loops.remove(k);
        }
        if loops.len() >= MAX_LOOPS {
            return Err(fault(
                AlarmCode::ControlNesting,
                at,
                format!("more than {MAX_LOOPS} WHILE … DO loops nested"),
            ));
        }
        loops.push(DoLoop { m, head, endless });
        Ok(false)
    }

    /// `END m`: back to the WHILE, which tests its condition again (or to the body after a
    /// plain DO).
    fn end_loop(&mut self, m: u8, at: usize) -> R<bool> {
        let Some(k) = self.calls.loops.iter().rposition(|l| l.m == m) else {
            return Err(fault(
                AlarmCode::ControlNesting,
                at,
                format!("END {m} without an open DO {m}"),
            ));
        };
        // Loops still open inside it were left by a jump (a crossing END shows later: its
        // DO is gone).
        self.calls.loops.truncate(k + 1);
        let l = self.calls.loops[k];
        if l.endless {
            self.next_pass(at)?;
        } else {
            self.calls.loops.truncate(k);
        }
        (self.pos, self.line, self.line_start) = l.head;
        Ok(false)
    }

    /// Skips blocks up to and including `END m` of the running program.
    fn skip_past_end(&mut self, m: u8, at: usize) -> R<()> {
        let origin = (self.blk_line, self.blk_line_start);
        while let Some((s, e)) = self.next_segment() {
            let mut c = Cursor::new(self.src, s, e);
            super::super::block_text::skip_prefix(&mut c);
            if c.letter() == Some(b'O') && s != self.calls.running.start.0 {
                break;
            }
            if c.keyword("END") {
                c.i += 3;
                if loop_number(&mut c, self, at).ok() == Some(m) {
                    return Ok(());
                }
            }
        }
        (self.blk_line, self.blk_line_start) = origin;
        Err(fault(
            AlarmCode::ControlNesting,
            at,
            format!("DO {m} has no END {m} in this program"),
        ))
    }

    /// `G65`/`G66 P… L… <arguments>`: the call runs when the block is complete (G65), or
    /// after every following move until G67 (G66).
    fn macro_call(&mut self, c: &mut Cursor, modal: bool, at: usize) -> R<bool> {
        c.i += 1;
        let (_, next) = number::parse(c.b, c.i).ok_or_else(|| syntax(at, "G code expected"))?;
        c.i = next;
        let call = self.call_words(c)?;
        let number = call.program.ok_or_else(|| {
            fault(
                AlarmCode::MissingValue,
                at,
                "a macro call needs the program number P",
            )
        })?;
        if modal {
            self.calls.modal = Some(ModalCall {
                target: Target::Number(number),
                repeats: call.repeats,
                args: Args::Locals(Box::new(call.args)),
                depth: self.calls.depth(),
            });
        } else {
            self.calls.pending = Some(Pending::Call {
                target: Target::Number(number),
                repeats: call.repeats,
                kind: CallKind::Macro,
                args: Args::Locals(Box::new(call.args)),
                at,
            });
            self.run_pending()?;
        }
        Ok(false)
    }

    /// The words of a G65/G66 block: P, L and the arguments (specification I, and II for
    /// repeated I J K: the n-th set goes to #4+3(n-1) …; a later word wins, as on the
    /// control).
    fn call_words(&mut self, c: &mut Cursor) -> R<CallWords> {
        let mut w = CallWords {
            program: None,
            repeats: 1,
            args: [None; LOCALS],
        };
        let mut set = (0usize, 0usize); // (I J K set, next letter index in it)
        loop {
            c.skip_blanks();
            let Some(ch) = c.peek() else { break };
            if ch == b'(' {
                if !c.skip_comment() {
                    return Err(syntax(c.i, "comment not closed with ')'"));
                }
                continue;
            }
            let word_at = c.i;
            let letter = c
                .letter()
                .ok_or_else(|| syntax(word_at, "an argument address expected"))?;
            c.i += 1;
            let Some(v) = self.argument_value(c, letter, word_at)? else {
                continue;
            };
            match letter {
                b'P' => w.program = Some(program_number(v, word_at)?),
                b'L' => w.repeats = count(v, word_at)?,
                b'I' | b'J' | b'K' => {
                    let k = (letter - b'I') as usize;
                    if k < set.1 {
                        set.0 += 1;
                    }
                    set.1 = k + 1;
                    let n = 4 + 3 * set.0 + k;
                    if n > LOCALS {
                        return Err(syntax(word_at, "more than ten I J K argument sets"));
                    }
                    w.args[n - 1] = Some(v);
                }
                _ => {
                    let n = argument_number(letter).ok_or_else(|| {
                        syntax(
                            word_at,
                            format!("{} cannot be a macro argument", letter as char),
                        )
                    })?;
                    w.args[n - 1] = Some(v);
                }
            }
        }
        Ok(w)
    }

    /// An argument's value: a number (scaled by the decimal-input switch for a length
    /// address), or a macro operand (vacant: the argument is left out).
    fn argument_value(&mut self, c: &mut Cursor, letter: u8, at: usize) -> R<Value> {
        if expr::at_operand(c) {
            return expr::operand(c, &*self);
        }
        let (n, next) = number::parse(c.b, c.i)
            .filter(|(_, e)| *e <= c.end)
            .ok_or_else(|| {
                fault(
                    AlarmCode::BadNumber,
                    at,
                    format!("{} must be followed by a number", letter as char),
                )
            })?;
        c.i = next;
        let length = matches!(letter, b'A'..=b'C' | b'I'..=b'K' | b'Q' | b'R' | b'U'..=b'Z');
        Ok(Some(if length {
            self.in_program_units(Val::new(n, at), self.block.modal.units)
        } else {
            n.value
        }))
    }
}

/// P, L and the local variables of a call.
struct CallWords {
    program: Option<u32>,
    repeats: u32,
    args: [Value; LOCALS],
}

/// Argument specification I: the local variable an address gives (G L N O P give none).
fn argument_number(letter: u8) -> Option<usize> {
    Some(match letter {
        b'A' => 1,
        b'B' => 2,
        b'C' => 3,
        b'D' => 7,
        b'E' => 8,
        b'F' => 9,
        b'H' => 11,
        b'M' => 13,
        b'Q' => 17,
        b'R' => 18,
        b'S' => 19,
        b'T' => 20,
        b'U' => 21,
        b'V' => 22,
        b'W' => 23,
        b'X' => 24,
        b'Y' => 25,
        b'Z' => 26,
        _ => return None,
    })
}

/// A program number (O0001 … O9999).
pub(in crate::frontend) fn program_number(v: f64, at: usize) -> R<u32> {
    whole_in(v, at, "program number", 1..=9999)
}

/// A repeat count L (0 … 9999).
pub(in crate::frontend) fn count(v: f64, at: usize) -> R<u32> {
    whole_in(v, at, "repeat count", 0..=9999)
}

/// A sequence number (GOTO, M99 P): 1 … 99999.
pub(in crate::frontend) fn sequence_number(v: f64, at: usize) -> R<u32> {
    whole_in(v, at, "sequence number", 1..=99_999)
}

/// A whole number within `range`, or alarm 12160 naming `what`.
fn whole_in(v: f64, at: usize, what: &str, range: std::ops::RangeInclusive<u32>) -> R<u32> {
    let n = expr::whole(v, at, &format!("a {what}"))?;
    u32::try_from(n)
        .ok()
        .filter(|n| range.contains(n))
        .ok_or_else(|| {
            fault(
                AlarmCode::BadNumber,
                at,
                format!("{what} {n} is not in {}…{}", range.start(), range.end()),
            )
        })
}

/// The loop identification m after DO/END: 1, 2 or 3.
fn loop_number(c: &mut Cursor, it: &Interpreter, at: usize) -> R<u8> {
    c.skip_blanks();
    let v = if expr::at_operand(c) {
        expr::operand(c, it)?.unwrap_or(0.0)
    } else {
        let (n, next) = number::parse(c.b, c.i)
            .filter(|(_, e)| *e <= c.end)
            .ok_or_else(|| syntax(c.i, "the loop number 1, 2 or 3 expected"))?;
        c.i = next;
        n.value
    };
    match v {
        1.0 => Ok(1),
        2.0 => Ok(2),
        3.0 => Ok(3),
        _ => Err(fault(
            AlarmCode::BadNumber,
            at,
            format!("loop number {v} is not 1, 2 or 3"),
        )),
    }
}

fn syntax(at: usize, m: impl Into<String>) -> Box<Fault> {
    fault(AlarmCode::Syntax, at, m)
}

/// After a statement only a comment may follow.
fn end_of_statement(c: &mut Cursor) -> R<()> {
    trailing_comment(c).map(drop)
}

/// The text of the comments after a statement (the #3000 message); anything else is an
/// error.
fn trailing_comment(c: &mut Cursor) -> R<String> {
    let mut text = String::new();
    loop {
        c.skip_blanks();
        match c.peek() {
            None => return Ok(text),
            Some(b'(') => {
                let open = c.i;
                if !c.skip_comment() {
                    return Err(syntax(open, "comment not closed with ')'"));
                }
                text.push_str(&String::from_utf8_lossy(&c.b[open + 1..c.i - 1]));
            }
            Some(_) => {
                return Err(syntax(
                    c.i,
                    "a macro statement stands alone in its block (only a comment may follow)",
                ))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use crate::alarm::AlarmCode;

    /// The programmed end points (X, Y, Z) of the program's moves.
    fn ends(src: &str) -> Vec<[f64; 3]> {
        run("fanuc", src)
            .unwrap_or_else(|a| panic!("{a}"))
            .iter()
            .filter_map(|b| b.motion.map(|m| m.end))
            .collect()
    }

    fn xs(src: &str) -> Vec<f64> {
        ends(src).iter().map(|p| p[0]).collect()
    }

    #[test]
    fn variables_give_addresses_their_values() {
        let src = "#1=10.\n#2=[#1+5]*2\nG0 X#1 Y#2 Z-#1\nG1 X[#2/3] F100.\n";
        assert_eq!(ends(src), [[10.0, 30.0, -10.0], [10.0, 30.0, -10.0]]);
        // A vacant variable leaves its address out.
        assert_eq!(ends("G0 X5. Y5.\nG0 X#7 Y1.\n")[1], [5.0, 1.0, 0.0]);
    }

    #[test]
    fn while_loops_and_gotos_run_their_passes() {
        let src = "#1=0\nWHILE [#1 LT 3] DO 1\n#1=#1+1\nG0 X#1\nEND 1\nG0 X9.\n";
        assert_eq!(xs(src), [1.0, 2.0, 3.0, 9.0]);
        let src = "#1=0\nN10 #1=#1+1\nG0 X#1\nIF [#1 LT 3] GOTO 10\nG0 X9.\n";
        assert_eq!(xs(src), [1.0, 2.0, 3.0, 9.0]);
        // A false WHILE skips its body, nested loops keep their own numbers.
        let src = "#1=5\nWHILE [#1 LT 3] DO 1\nG0 X1.\nEND 1\n#2=0\nWHILE [#2 LT 2] DO 1\n#3=0\nWHILE [#3 LT 2] DO 2\n#3=#3+1\nG0 X[#2*10+#3]\nEND 2\n#2=#2+1\nEND 1\n";
        assert_eq!(xs(src), [1.0, 2.0, 11.0, 12.0]);
        let src = "#1=1\nIF [#1 EQ 1] THEN #2=7\nIF [#1 EQ 2] THEN #2=8\nG0 X#2\n";
        assert_eq!(xs(src), [7.0]);
    }

    #[test]
    fn subprograms_return_and_repeat() {
        let src = "O0001\nG91 G0 X1.\nM98 P1000 L2\nG90 G0 X0\nM30\nO1000\nG91 G0 X10.\nM99\n";
        assert_eq!(xs(src), [1.0, 11.0, 21.0, 0.0]);
        // P with the count before a four-digit number.
        let src = "O0001\nM98 P31000\nM30\nO1000\nG91 G0 X1.\nM99\n";
        assert_eq!(xs(src), [1.0, 2.0, 3.0]);
        let src = "O0001\nG65 P9000 A2. B3.\nG0 X#1\nM30\nO9000\nG0 X[#1*#2] Y#1\n#1=99\nM99\n";
        // The caller's #1 stays vacant: its X is left out and the block moves nothing.
        assert_eq!(ends(src), [[6.0, 2.0, 0.0]]);
    }

    #[test]
    fn errors_point_at_their_words() {
        let a = run("fanuc", "O0001\nM98 P2000\nM30\n").unwrap_err();
        assert_eq!((a.code, a.line, a.col), (AlarmCode::MissingProgram, 2, 5));
        let a = run("fanuc", "GOTO 50\n").unwrap_err();
        assert_eq!((a.code, a.line, a.col), (AlarmCode::JumpTarget, 1, 1));
        let a = run("fanuc", "N1 GOTO 1\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::LoopLimit);
        let a = run("fanuc", "#3000=12(TOOL BROKEN)\n").unwrap_err();
        assert_eq!(
            (a.code, a.message.as_str()),
            (AlarmCode::ProgramAlarm, "MC3012 TOOL BROKEN")
        );
        let a = run("fanuc", "O1\nM98 P1\nM30\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::CallNesting);
        let a = run("fanuc", "WHILE [1 EQ 0] DO 1\nG0 X1.\n").unwrap_err();
        assert_eq!((a.code, a.line), (AlarmCode::ControlNesting, 1));
    }
}

#[cfg(test)]
mod review {
    use super::super::super::run;
    use crate::alarm::AlarmCode;
    use crate::machine_data::MachineData;
    use crate::tools::ToolTable;

    fn xs(src: &str) -> Vec<f64> {
        super::super::super::end_xs("fanuc", src)
    }

    #[test]
    fn a_message_stop_stops_with_its_message() {
        let b = run("fanuc", "G0 X1.\n#3006=1(CHECK THE INSERT)\nG0 X2.\n").unwrap();
        assert_eq!(b[1].stop, Some(crate::frontend::block::ProgramStop::Stop));
        assert_eq!(
            (b[1].message.as_deref(), b[1].line),
            (Some("CHECK THE INSERT"), 2)
        );
        assert!(b[1].motion.is_none() && b[2].message.is_none());
    }

    #[test]
    fn a_program_stop_acts_after_the_last_move_of_its_block() {
        let md = MachineData::load(
            None,
            &[
                "dialect=fanuc".into(),
                "axes.X.reference_positions=[-100.0, 0.0, 0.0, 0.0]".into(),
            ],
        )
        .unwrap();
        let b = crate::frontend::interpret(
            "s.nc",
            "G0 X10. Y10. Z20.\nG91 G28 X0. Y0. M30\n",
            &md,
            &ToolTable::builtin(),
        )
        .unwrap();
        let last = b.last().unwrap();
        assert_eq!(last.motion.unwrap().end[0], -100.0);
        assert!(last.stop.is_some_and(|s| s.ends_program()));
        assert!(b[1].stop.is_none(), "not at the intermediate point");
    }

    #[test]
    fn jumps_and_program_ends_follow_the_text() {
        // A `;` inside a comment ends no block: N20 is the real one.
        assert_eq!(
            xs("GOTO 20;(TOOL 3; N20 FOLLOWS)\nG0 X50.\nN20 G0 X99.\nM30\n"),
            [99.0]
        );
        // A main program without an O line ends where the next O program begins.
        assert_eq!(xs("G0 X1.\nO1000\nG0 X2.\nM99\n"), [1.0]);
        // G66 L2 runs the macro twice after each move.
        assert_eq!(
            xs("O1\nG66 P9 L2\nG91 G0 X1.\nG67\nM30\nO9\nG91 G0 X10.\nM99\n"),
            [1.0, 11.0, 21.0]
        );
    }

    #[test]
    fn pecks_and_present_positions_in_words() {
        let md = MachineData::load(
            None,
            &[
                "dialect=fanuc".into(),
                "program.max_loop_iterations=10".into(),
            ],
        )
        .unwrap();
        let a = crate::frontend::interpret(
            "p.nc",
            "G0 Z10.\nG91 G99 G83 X10. Z-10. R-8. Q2. K3 F100.\n",
            &md,
            &ToolTable::builtin(),
        )
        .unwrap_err();
        assert_eq!(a.code, AlarmCode::LoopLimit);
        let b = run("fanuc", "G0 X10.\nG0 X[#5041+5.]\n").unwrap();
        assert!(b[1].preprocess_stop && !b[0].preprocess_stop);
        // A false WHILE that reads the position: its stop is at the WHILE, not at its END.
        let b = run(
            "fanuc",
            "G0 X10.\n  WHILE [#5041 GT 100.] DO 1\nG0 X1.\nEND 1\nG0 X2.\n",
        )
        .unwrap();
        assert_eq!((b[1].preprocess_stop, b[1].line, b[1].col), (true, 2, 3));
    }
}
