//! ISG statements (TF5200): the control structures `$FOR var = start, end, step … $ENDFOR`,
//! `$IF … [$ELSEIF …] [$ELSE] $ENDIF` and `$WHILE … $ENDWHILE`, and `V.` variable
//! assignments among a block's words. A control statement stands alone in its block, with
//! only the block number and `/` before it. The end value of `$FOR` is inclusive; a
//! condition is true when its absolute value is at least 0.5.
//!
//! The interpreter streams: a false branch or a finished loop is skipped by reading on to
//! its closing statement, and a loop jumps back in the text to its body.

use super::super::block_text::{block_number, skip_prefix};
use super::super::expr;
use super::super::fault::{fault, Fault, R};
use super::super::interpreter::Interpreter;
use super::super::lexer::Cursor;
use super::super::variables::{Variables, Written};
use super::super::words::Words;
use crate::alarm::AlarmCode;

/// A statement as read. Byte offsets point at the `$`.
#[derive(Debug)]
enum Statement {
    For(For),
    EndFor {
        at: usize,
    },
    While {
        cond: f64,
        cond_range: (usize, usize),
        at: usize,
    },
    EndWhile {
        at: usize,
    },
    If {
        cond: f64,
        at: usize,
    },
    /// The condition is evaluated only when the branch is reached.
    ElseIf {
        at: usize,
    },
    Else {
        at: usize,
    },
    EndIf {
        at: usize,
    },
}

/// `$FOR var = start, end, step`.
#[derive(Debug)]
struct For {
    var: String,
    var_at: usize,
    start: f64,
    end: f64,
    step: f64,
    at: usize,
}

/// Where to jump back to: (byte offset, line number, line start).
type Mark = (usize, u32, usize);

/// An open control structure. `origin` is (line, line start, byte offset) of its opening.
#[derive(Clone, Debug)]
pub enum Frame {
    For {
        var: String,
        end: f64,
        step: f64,
        body: Mark,
        origin: (u32, usize, usize),
    },
    While {
        cond: (usize, usize),
        body: Mark,
        origin: (u32, usize, usize),
    },
    If {
        origin: (u32, usize, usize),
    },
}

impl Frame {
    pub fn origin(&self) -> (u32, usize, usize) {
        match self {
            Frame::For { origin, .. } | Frame::While { origin, .. } | Frame::If { origin } => {
                *origin
            }
        }
    }
    pub fn opener(&self) -> &'static str {
        match self {
            Frame::For { .. } => "$FOR",
            Frame::While { .. } => "$WHILE",
            Frame::If { .. } => "$IF",
        }
    }
    pub fn closer(&self) -> &'static str {
        match self {
            Frame::For { .. } => "$ENDFOR",
            Frame::While { .. } => "$ENDWHILE",
            Frame::If { .. } => "$ENDIF",
        }
    }
}

/// The open control structures, innermost last, and the program's loop budget.
#[derive(Clone, Debug, Default)]
pub struct Structures {
    frames: Vec<Frame>,
    /// Loop passes of the whole program: bounds nested loops too (their product would not be).
    loop_passes: u32,
}

impl Structures {
    pub fn innermost(&self) -> Option<&Frame> {
        self.frames.last()
    }
}

impl Interpreter<'_> {
    /// Runs one control statement; the cursor stands on the `$`.
    pub(in crate::frontend) fn isg_statement(&mut self, mut c: Cursor) -> R<()> {
        match parse(&mut c, &self.vars)? {
            Statement::For(f) => self.for_loop(f),
            Statement::EndFor { at } => self.end_for(at),
            Statement::While {
                cond,
                cond_range,
                at,
            } => self.while_loop(cond, cond_range, at),
            Statement::EndWhile { at } => self.end_while(at),
            Statement::If { cond, at } => self.if_branch(cond, at),
            Statement::Else { at } | Statement::ElseIf { at } => self.else_branch(at),
            Statement::EndIf { at } => match self.structures.frames.pop() {
                Some(Frame::If { .. }) => Ok(()),
                other => Err(self.mismatch(other, "$ENDIF", at)),
            },
        }
    }

    /// A `V.` assignment among a block's words (a calculation block); the cursor stands on
    /// the variable.
    pub(in crate::frontend) fn assignment(
        &mut self,
        c: &mut Cursor,
        w: &mut Words,
        at: usize,
    ) -> R<()> {
        let name = c.name();
        c.skip_blanks();
        if c.peek() != Some(b'=') || c.peek_at(1) == Some(b'=') {
            return Err(fault(
                AlarmCode::Syntax,
                c.i,
                format!("'=' expected after {name}"),
            ));
        }
        c.i += 1;
        let value = expr::eval(c, &self.vars)?;
        if self.vars.set(&name, value, at)? == Written::ToolRadius {
            w.radius_written = Some(at as u32);
        }
        w.calculation = true;
        Ok(())
    }

    /// (line, line start) of the statement being run, and where the next block starts.
    fn here(&self) -> ((u32, usize), Mark) {
        (
            (self.blk_line, self.blk_line_start),
            (self.pos, self.line, self.line_start),
        )
    }

    fn for_loop(&mut self, f: For) -> R<()> {
        if f.step == 0.0 {
            return Err(fault(
                AlarmCode::BadNumber,
                f.at,
                "$FOR with step 0 would never end",
            ));
        }
        self.vars.set(&f.var, f.start, f.var_at)?;
        if !for_continues(f.start, f.end, f.step) {
            return self.skip_to(&["ENDFOR"], f.at).map(drop);
        }
        // The first pass counts against the program's loop budget too.
        let s = &mut self.structures;
        s.loop_passes = s.loop_passes.saturating_add(1);
        let ((line, line_start), body) = self.here();
        self.structures.frames.push(Frame::For {
            var: f.var,
            end: f.end,
            step: f.step,
            body,
            origin: (line, line_start, f.at),
        });
        Ok(())
    }

    fn end_for(&mut self, at: usize) -> R<()> {
        let (var, end, step, body, origin) = match self.structures.frames.pop() {
            Some(Frame::For {
                var,
                end,
                step,
                body,
                origin,
            }) => (var, end, step, body, origin),
            other => return Err(self.mismatch(other, "$ENDFOR", at)),
        };
        let v = self.vars.get(&var).unwrap_or(end) + step;
        // It was written at the $FOR already, so it is a program variable.
        let _ = self.vars.set(&var, v, origin.2);
        if for_continues(v, end, step) {
            self.next_pass(at)?;
            (self.pos, self.line, self.line_start) = body;
            self.structures.frames.push(Frame::For {
                var,
                end,
                step,
                body,
                origin,
            });
        }
        Ok(())
    }

    fn while_loop(&mut self, cond: f64, cond_range: (usize, usize), at: usize) -> R<()> {
        if !expr::truthy(cond) {
            return self.skip_to(&["ENDWHILE"], at).map(drop);
        }
        // The first pass counts against the program's loop budget too.
        let s = &mut self.structures;
        s.loop_passes = s.loop_passes.saturating_add(1);
        let ((line, line_start), body) = self.here();
        self.structures.frames.push(Frame::While {
            cond: cond_range,
            body,
            origin: (line, line_start, at),
        });
        Ok(())
    }

    fn end_while(&mut self, at: usize) -> R<()> {
        let (cond, body, origin) = match self.structures.frames.pop() {
            Some(Frame::While { cond, body, origin }) => (cond, body, origin),
            other => return Err(self.mismatch(other, "$ENDWHILE", at)),
        };
        let mut cc = Cursor::new(self.src, cond.0, cond.1);
        // A fault in the condition points at the $ENDWHILE that evaluates it.
        let v = expr::eval(&mut cc, &self.vars).map_err(|mut f| {
            f.at = at;
            f
        })?;
        if expr::truthy(v) {
            self.next_pass(at)?;
            (self.pos, self.line, self.line_start) = body;
            self.structures
                .frames
                .push(Frame::While { cond, body, origin });
        }
        Ok(())
    }

    /// `$IF`: walks `$ELSEIF` / `$ELSE` until a branch is taken, or on to `$ENDIF`.
    fn if_branch(&mut self, cond: f64, at: usize) -> R<()> {
        let ((line, line_start), _) = self.here();
        let mut taken = expr::truthy(cond);
        let mut at_kw = at;
        while !taken {
            let (kw, (s, e)) = self.skip_to(&["ELSEIF", "ELSE", "ENDIF"], at_kw)?;
            match kw.as_str() {
                "ENDIF" => return Ok(()),
                "ELSE" => taken = true,
                _ => {
                    // The $ELSEIF line was consumed by skip_to; evaluate its condition.
                    let (cond, cat) = elseif_condition(self.src, s, e, &self.vars)?;
                    taken = expr::truthy(cond);
                    at_kw = cat;
                }
            }
        }
        self.structures.frames.push(Frame::If {
            origin: (line, line_start, at),
        });
        Ok(())
    }

    /// `$ELSEIF` / `$ELSE` reached: the taken branch ends here, skip the rest up to `$ENDIF`.
    fn else_branch(&mut self, at: usize) -> R<()> {
        match self.structures.frames.pop() {
            Some(Frame::If { .. }) => self.skip_to(&["ENDIF"], at).map(drop),
            other => Err(self.mismatch(other, "$ELSE", at)),
        }
    }

    /// Counts one more loop pass; the budget covers the whole program, so nested loops are
    /// bounded by it too.
    pub(in crate::frontend) fn next_pass(&mut self, at: usize) -> R<()> {
        self.add_passes(1, at)
    }

    /// Counts `n` more passes at once (a cycle's repetitions and pecks).
    pub(in crate::frontend) fn add_passes(&mut self, n: u64, at: usize) -> R<()> {
        let max = self.md.program.max_loop_iterations;
        let total = self.structures.loop_passes as u64 + n;
        if total > max as u64 {
            return Err(fault(
                AlarmCode::LoopLimit,
                at,
                format!("loops ran {max} passes (machine data program.max_loop_iterations, counted over the whole program)"),
            ));
        }
        self.structures.loop_passes = total as u32;
        Ok(())
    }

    #[cold]
    fn mismatch(&self, open: Option<Frame>, close: &str, at: usize) -> Box<Fault> {
        match open {
            Some(f) => fault(
                AlarmCode::ControlNesting,
                at,
                format!(
                    "{close} does not close {} (line {})",
                    f.opener(),
                    f.origin().0
                ),
            ),
            None => fault(
                AlarmCode::ControlNesting,
                at,
                format!("{close} without an opening statement"),
            ),
        }
    }

    /// Skips blocks up to the `$keyword` (one of `targets`) that matches at this nesting
    /// level; returns the keyword found and its block's text. Leaves `pos` after that line.
    /// Used for false conditions and finished loops.
    fn skip_to(&mut self, targets: &[&str], at: usize) -> R<(String, (usize, usize))> {
        let origin = (self.blk_line, self.blk_line_start);
        let mut depth = 0u32;
        while let Some((s, e)) = self.next_segment() {
            let Some(kw) = keyword_of(self.src, s, e) else {
                continue;
            };
            match kw.as_str() {
                "FOR" | "WHILE" | "IF" => depth += 1,
                "ENDFOR" | "ENDWHILE" | "ENDIF" if depth > 0 => depth -= 1,
                k if depth == 0 && targets.contains(&k) => {
                    self.blk_number = block_number(self.src, s, e);
                    return Ok((kw, (s, e)));
                }
                _ => {}
            }
        }
        (self.blk_line, self.blk_line_start) = origin;
        Err(fault(
            AlarmCode::ControlNesting,
            at,
            format!(
                "missing ${} for this statement",
                targets.last().copied().unwrap_or("END")
            ),
        ))
    }
}

/// Whether a `$FOR` loop runs another pass with the variable at `v`. A tolerance of 1e-9 of a
/// step keeps decimal steps (0.1) from losing their last pass to rounding.
fn for_continues(v: f64, end: f64, step: f64) -> bool {
    let eps = 1e-9 * step.abs();
    if step > 0.0 {
        v <= end + eps
    } else {
        v >= end - eps
    }
}

fn syntax(at: usize, m: impl Into<String>) -> Box<Fault> {
    fault(AlarmCode::Syntax, at, m)
}

fn keyword(c: &mut Cursor) -> String {
    let start = c.i;
    while matches!(c.peek(), Some(ch) if ch.is_ascii_alphabetic()) {
        c.i += 1;
    }
    String::from_utf8_lossy(&c.b[start..c.i]).to_ascii_uppercase()
}

/// After a statement only a comment may follow.
fn end_of_statement(c: &mut Cursor) -> R<()> {
    loop {
        c.skip_blanks();
        match c.peek() {
            None | Some(b';') => return Ok(()),
            Some(b'(') => {
                if !c.skip_comment() {
                    return Ok(()); // ISG: an unclosed `(` comments out the rest
                }
            }
            Some(_) => {
                return Err(syntax(
                    c.i,
                    "a control statement must stand alone in its block",
                ))
            }
        }
    }
}

fn expect(c: &mut Cursor, ch: u8, what: &str) -> R<()> {
    c.skip_blanks();
    if c.peek() == Some(ch) {
        c.i += 1;
        Ok(())
    } else {
        Err(syntax(c.i, format!("'{}' expected {what}", ch as char)))
    }
}

/// Parses a statement; the cursor stands on the `$`.
fn parse(c: &mut Cursor, vars: &Variables) -> R<Statement> {
    let at = c.i;
    c.i += 1;
    let kw = keyword(c);
    let stmt = match kw.as_str() {
        "FOR" => Statement::For(parse_for(c, vars, at)?),
        "ENDFOR" => Statement::EndFor { at },
        "WHILE" => {
            let s = c.i;
            let cond = expr::eval(c, vars)?;
            Statement::While {
                cond,
                cond_range: (s, c.i),
                at,
            }
        }
        "ENDWHILE" => Statement::EndWhile { at },
        "IF" => Statement::If {
            cond: expr::eval(c, vars)?,
            at,
        },
        "ELSEIF" | "ELSIF" => {
            // Condition read later (only if the branch is reached); skip the text now.
            c.i = c.end;
            Statement::ElseIf { at }
        }
        "ELSE" => Statement::Else { at },
        "ENDIF" => Statement::EndIf { at },
        "" => return Err(syntax(at, "$ must be followed by a keyword")),
        other => {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!("${other} is not supported by softnc"),
            ))
        }
    };
    end_of_statement(c)?;
    Ok(stmt)
}

/// `$FOR var = start, end, step` after the keyword.
fn parse_for(c: &mut Cursor, vars: &Variables, at: usize) -> R<For> {
    c.skip_blanks();
    if !expr::at_variable(c) {
        return Err(syntax(
            c.i,
            "$FOR needs a V.P., V.L. or V.S. counting variable",
        ));
    }
    let var_at = c.i;
    let var = c.name();
    expect(c, b'=', "after the $FOR variable")?;
    let start = expr::eval(c, vars)?;
    expect(c, b',', "between start and end value")?;
    let end = expr::eval(c, vars)?;
    expect(c, b',', "between end value and step")?;
    let step = expr::eval(c, vars)?;
    Ok(For {
        var,
        var_at,
        start,
        end,
        step,
        at,
    })
}

/// The control keyword of a block's text, if it is a control statement.
fn keyword_of(src: &[u8], start: usize, end: usize) -> Option<String> {
    let mut c = Cursor::new(src, start, end);
    skip_prefix(&mut c);
    if c.peek() != Some(b'$') {
        return None;
    }
    c.i += 1;
    Some(keyword(&mut c))
}

/// Evaluates the condition of a `$ELSEIF` block. Returns the value and the `$` offset.
fn elseif_condition(src: &[u8], start: usize, end: usize, vars: &Variables) -> R<(f64, usize)> {
    let mut c = Cursor::new(src, start, end);
    skip_prefix(&mut c);
    let at = c.i;
    c.i += 1;
    keyword(&mut c);
    let v = expr::eval(&mut c, vars)?;
    end_of_statement(&mut c)?;
    Ok((v, at))
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use super::*;

    fn xs(src: &str) -> Vec<f64> {
        run("isg", src)
            .unwrap()
            .iter()
            .filter_map(|b| b.motion.map(|m| m.end[0]))
            .collect()
    }

    #[test]
    fn loops_run_their_passes() {
        // The end value is inclusive, a decimal step keeps its last pass.
        assert_eq!(
            xs("$FOR V.P.I = 0, 0.3, 0.1\nG0 X[V.P.I*10]\n$ENDFOR\n").len(),
            4
        );
        assert_eq!(
            xs("$FOR V.P.I = 3, 1, -1\nG0 XV.P.I\n$ENDFOR\n"),
            [3.0, 2.0, 1.0]
        );
        let src = "V.P.A = 0\n$WHILE V.P.A < 2\nV.P.A = V.P.A + 1\nG0 XV.P.A\n$ENDWHILE\n";
        assert_eq!(xs(src), [1.0, 2.0]);
    }

    #[test]
    fn the_first_true_branch_is_taken() {
        let src = "V.P.A = 2\n$IF V.P.A == 1\nG0 X1\n$ELSEIF V.P.A == 2\nG0 X2\n$ELSE\nG0 X3\n$ENDIF\nG0 X4\n";
        assert_eq!(xs(src), [2.0, 4.0]);
        let a = run("isg", "$ENDIF\n").unwrap_err();
        assert_eq!(a.message, "$ENDIF without an opening statement");
        let a = run("isg", "$FOR V.P.I = 0, 1, 1\n$ENDWHILE\n").unwrap_err();
        assert_eq!((a.code, a.line), (AlarmCode::ControlNesting, 2));
    }
}
