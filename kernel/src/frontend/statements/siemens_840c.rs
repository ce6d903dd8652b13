//! The SINUMERIK 840C's own language (the 880/840C programming guides' "Parameters" and
//! "Programming of cycles"; docs/sinumerik.md, "The 840C's R parameters and @ commands"), not
//! the 808D/840D high-level language: R parameters assigned among a block's words
//! (`R1=R2*2+5`) and read by an address (`X R1`, `X-R1`), and the `@` commands with their
//! operands — K constants, R parameters, P pointers — that compute into R parameters and jump
//! to block numbers (`N` or the main block's `:`). What a code does comes from the dialect's
//! table (`AtEffect`); nothing here knows an `@` number.
//!
//! A block holding only the language (its number, assignments, `@` commands, comments) is a
//! statement: it runs where it stands and hands out no block. A jump acts when its block is
//! complete; a backward one counts against `program.max_loop_iterations`.

use super::super::block_text::numbered;
use super::super::calls::Mark;
use super::super::fault::{fault, Fault, R};
use super::super::interpreter::Interpreter;
use super::super::lexer::Cursor;
use super::super::number;
use super::super::words::{push, Words};
use crate::alarm::AlarmCode;
use crate::dialect::{AtEffect, AtFunction};

/// R0 … R(count − 1), all 0 at program start; allocated at the first write, so that a program
/// without R parameters allocates nothing for them.
#[derive(Clone, Debug, Default)]
pub struct RParameters {
    r: Vec<f64>,
    count: usize,
}

impl RParameters {
    /// `count` parameters (machine data `program.r_parameters`).
    pub fn new(count: usize) -> Self {
        RParameters {
            r: Vec::new(),
            count,
        }
    }

    pub fn get(&self, n: usize, at: usize) -> R<f64> {
        if n >= self.count {
            return Err(self.missing(n, at));
        }
        Ok(self.r.get(n).copied().unwrap_or(0.0))
    }

    pub fn set(&mut self, n: usize, v: f64, at: usize) -> R<()> {
        if n >= self.count {
            return Err(self.missing(n, at));
        }
        if !v.is_finite() {
            return Err(fault(
                AlarmCode::Arithmetic,
                at,
                format!("R{n} would not be a finite number"),
            ));
        }
        if self.r.is_empty() {
            self.r = vec![0.0; self.count];
        }
        self.r[n] = v;
        Ok(())
    }

    #[cold]
    fn missing(&self, n: usize, at: usize) -> Box<Fault> {
        fault(
            AlarmCode::UndefinedName,
            at,
            format!(
                "R{n} does not exist: R0 … R{} (machine data program.r_parameters)",
                self.count.saturating_sub(1)
            ),
        )
    }
}

/// A jump an `@` command asks for, done when its block is complete.
#[derive(Clone, Copy, Debug)]
pub struct Jump {
    number: u32,
    /// Search toward the program's start (the destination was written negative).
    back: bool,
    /// The destination operand and the command, for alarms.
    at: usize,
    command: usize,
    /// The block after the jump's block, and the jump's block's line start.
    next: Mark,
    here: usize,
}

/// The language's state in the interpreter.
#[derive(Clone, Debug, Default)]
pub struct Language {
    pub r: RParameters,
    pub jump: Option<Jump>,
}

/// An operand of an `@` command as written.
#[derive(Clone, Copy, Debug)]
struct Operand {
    kind: Kind,
    /// K: the constant; R, P: the parameter's number.
    value: f64,
    at: usize,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// A constant.
    K,
    /// An R parameter.
    R,
    /// A pointer: the R parameter whose number the parameter holds.
    P,
}

/// Operands of one command at most (a case block's value/destination pairs).
const MAX_OPERANDS: usize = 33;
type Operands = heapless::Vec<Operand, MAX_OPERANDS>;

impl Interpreter<'_> {
    /// `Rn=expression` at the cursor among a block's words: assigned at once, left to right
    /// before the block's motion (so `R1=5 X R1` moves to 5).
    pub(in crate::frontend) fn c840_assignment(
        &mut self,
        c: &mut Cursor,
        w: &mut Words,
        at: usize,
    ) -> R<()> {
        c.i += 1;
        let n = parameter_number(c, at)?;
        c.skip_blanks();
        if c.peek() != Some(b'=') {
            return Err(fault(
                AlarmCode::Syntax,
                at,
                format!("R{n} is an R parameter: '=' and its value must follow (an arc's radius is CR=)"),
            ));
        }
        c.i += 1;
        let v = self.c840_sum(c)?;
        self.c840.r.set(n, v, at)?;
        w.calculation = true;
        Ok(())
    }

    /// An R parameter as an address's value (`X R1`, `X-R1`), if one stands at the cursor.
    /// The G code is no R parameter's (its number selects a function).
    pub(in crate::frontend) fn c840_address_value(
        &self,
        c: &mut Cursor,
        at: usize,
    ) -> R<Option<f64>> {
        let neg = match (c.peek(), c.peek_at(1)) {
            (Some(b'-'), Some(b'R' | b'r')) => true,
            (Some(b'+'), Some(b'R' | b'r')) => false,
            (Some(b'R' | b'r'), _) => false,
            _ => return Ok(None),
        };
        if c.b[at].eq_ignore_ascii_case(&b'G') {
            return Err(fault(
                AlarmCode::Syntax,
                c.i,
                "a G code cannot take an R parameter",
            ));
        }
        if c.peek() != Some(b'R') && c.peek() != Some(b'r') {
            c.i += 1;
        }
        let r_at = c.i;
        c.i += 1;
        let n = parameter_number(c, r_at)?;
        let v = self.c840.r.get(n, r_at)?;
        Ok(Some(if neg { -v } else { v }))
    }

    /// Terms joined by `+` and `-` (the expression of an assignment). `(` starts a comment on
    /// the 840C, so there are no brackets; `*` and `/` bind first **[unconfirmed]**.
    fn c840_sum(&self, c: &mut Cursor) -> R<f64> {
        let mut v = self.c840_product(c)?;
        loop {
            let mut probe = *c;
            probe.skip_blanks();
            let op = match probe.peek() {
                Some(op @ (b'+' | b'-')) => op,
                _ => return Ok(v),
            };
            probe.i += 1;
            *c = probe;
            let r = self.c840_product(c)?;
            v = if op == b'+' { v + r } else { v - r };
        }
    }

    /// Factors joined by `*` and `/`.
    fn c840_product(&self, c: &mut Cursor) -> R<f64> {
        let mut v = self.c840_factor(c)?;
        loop {
            let mut probe = *c;
            probe.skip_blanks();
            let (op, op_at) = match probe.peek() {
                Some(op @ (b'*' | b'/')) => (op, probe.i),
                _ => return Ok(v),
            };
            probe.i += 1;
            *c = probe;
            let r = self.c840_factor(c)?;
            if op == b'*' {
                v *= r;
            } else if r == 0.0 {
                return Err(fault(AlarmCode::Arithmetic, op_at, "division by 0"));
            } else {
                v /= r;
            }
        }
    }

    /// A number or an R parameter, with an optional sign.
    fn c840_factor(&self, c: &mut Cursor) -> R<f64> {
        c.skip_blanks();
        let neg = match c.peek() {
            Some(s @ (b'+' | b'-')) => {
                c.i += 1;
                s == b'-'
            }
            _ => false,
        };
        let at = c.i;
        let v = match c.peek() {
            Some(b'R' | b'r') => {
                c.i += 1;
                let n = parameter_number(c, at)?;
                self.c840.r.get(n, at)?
            }
            Some(b'0'..=b'9' | b'.') => {
                match number::parse(c.b, c.i).filter(|(_, e)| *e <= c.end) {
                    Some((n, next)) => {
                        c.i = next;
                        n.value
                    }
                    None => return Err(operand_expected(at)),
                }
            }
            _ => return Err(operand_expected(at)),
        };
        Ok(if neg { -v } else { v })
    }

    /// An `@` command with operands (the cursor after its number): a function computed into
    /// its R parameter now, or a jump recorded for the block's end.
    pub(in crate::frontend) fn c840_at(
        &mut self,
        c: &mut Cursor,
        w: &mut Words,
        effect: AtEffect,
        code: u32,
        at: usize,
    ) -> R<()> {
        if effect == AtEffect::PreprocessStop {
            return push(&mut w.at_codes, (code, at as u32), at);
        }
        w.calculation = true;
        match effect {
            AtEffect::PreprocessStop => Ok(()),
            AtEffect::Function(f) => {
                let ops = self.at_operands(c, code, 1 + f.sources(), 1 + f.sources())?;
                self.at_function(f, &ops)
            }
            AtEffect::Jump => {
                let ops = self.at_operands(c, code, 1, 1)?;
                self.at_jump(&ops[0], at)
            }
            AtEffect::JumpIf(cmp) => {
                let ops = self.at_operands(c, code, 3, 3)?;
                let a = self.at_tested(&ops[0], code)?;
                if cmp.holds(a, self.operand_value(&ops[1])?) {
                    self.at_jump(&ops[2], at)?;
                }
                Ok(())
            }
            AtEffect::Case => {
                let ops = self.at_operands(c, code, 3, MAX_OPERANDS)?;
                self.at_case(&ops, code, at, c.i)
            }
        }
    }

    /// A case block: `R` then value/destination pairs; the first value equal to R jumps.
    fn at_case(&mut self, ops: &Operands, code: u32, at: usize, end: usize) -> R<()> {
        if ops.len().is_multiple_of(2) {
            return Err(fault(
                AlarmCode::MissingValue,
                end,
                format!("@{code}: the last value has no destination"),
            ));
        }
        let a = self.at_tested(&ops[0], code)?;
        for pair in ops[1..].chunks_exact(2) {
            if self.operand_value(&pair[0])? == a {
                return self.at_jump(&pair[1], at);
            }
        }
        Ok(())
    }

    /// `f` of the operands after the first into the first (an R parameter or a pointer).
    fn at_function(&mut self, f: AtFunction, ops: &Operands) -> R<()> {
        let n = self.at_result(&ops[0])?;
        let own = self.c840.r.get(n, ops[0].at)?;
        let a = match ops.get(1) {
            Some(op) => self.operand_value(op)?,
            None => own,
        };
        let v = match f {
            AtFunction::Abs => a.abs(),
            AtFunction::Sqrt if a < 0.0 => {
                return Err(fault(
                    AlarmCode::Arithmetic,
                    ops[1].at,
                    format!("square root of {a}"),
                ))
            }
            AtFunction::Sqrt => libm::sqrt(a),
            AtFunction::Hypot => libm::hypot(a, self.operand_value(&ops[2])?),
            AtFunction::Increment => own + 1.0,
            AtFunction::Decrement => own - 1.0,
            AtFunction::IntegerPart => libm::trunc(own),
            AtFunction::Sin => libm::sin(a.to_radians()),
            AtFunction::Cos => libm::cos(a.to_radians()),
        };
        self.c840.r.set(n, v, ops[0].at)
    }

    /// The value an operand stands for: the constant, the parameter, the parameter pointed to.
    fn operand_value(&self, op: &Operand) -> R<f64> {
        match op.kind {
            Kind::K => Ok(op.value),
            Kind::R => self.c840.r.get(op.value as usize, op.at),
            Kind::P => self.c840.r.get(self.at_pointed(op)?, op.at),
        }
    }

    /// The R parameter a pointer's parameter names.
    fn at_pointed(&self, op: &Operand) -> R<usize> {
        let p = self.c840.r.get(op.value as usize, op.at)?;
        if p >= 0.0 && p.fract() == 0.0 && p < usize::MAX as f64 {
            Ok(p as usize)
        } else {
            Err(fault(
                AlarmCode::BadNumber,
                op.at,
                format!(
                    "P{}: R{} holds {p}, no parameter number",
                    op.value, op.value
                ),
            ))
        }
    }

    /// The parameter a result goes into.
    fn at_result(&self, op: &Operand) -> R<usize> {
        match op.kind {
            Kind::R => Ok(op.value as usize),
            Kind::P => self.at_pointed(op),
            Kind::K => Err(fault(
                AlarmCode::Syntax,
                op.at,
                "the result goes into an R parameter (R or P), not a constant",
            )),
        }
    }

    /// The parameter a comparison tests (the manuals write an R parameter first).
    fn at_tested(&self, op: &Operand, code: u32) -> R<f64> {
        if op.kind == Kind::K {
            return Err(fault(
                AlarmCode::Syntax,
                op.at,
                format!("@{code} tests an R parameter (R or P) first, not a constant"),
            ));
        }
        self.operand_value(op)
    }

    /// Records the jump of the command at `at` to the block number of `op`: a negative one
    /// searches backward.
    fn at_jump(&mut self, op: &Operand, at: usize) -> R<()> {
        let v = self.operand_value(op)?;
        let number = v.abs();
        if number.fract() != 0.0 || number > u32::MAX as f64 {
            return Err(fault(
                AlarmCode::BadNumber,
                op.at,
                format!("jump destination {v} is no block number"),
            ));
        }
        let jump = Jump {
            number: number as u32,
            back: v < 0.0,
            at: op.at,
            command: at,
            next: (self.pos, self.line, self.line_start),
            here: self.blk_line_start,
        };
        if self.c840.jump.replace(jump).is_some() {
            return Err(fault(
                AlarmCode::SameGroupTwice,
                op.at,
                "two jumps in one block",
            ));
        }
        Ok(())
    }

    /// The operands after an `@` command's number: at least `min`, at most `max` K, R or P
    /// words (the words after them belong to the block again).
    fn at_operands(&self, c: &mut Cursor, code: u32, min: usize, max: usize) -> R<Operands> {
        let mut ops = Operands::new();
        while ops.len() < max {
            skip_blanks_and_comments(c)?;
            let Some(op) = operand(c)? else { break };
            push(&mut ops, op, op.at)?;
        }
        if ops.len() < min {
            skip_blanks_and_comments(c)?;
            return Err(fault(
                AlarmCode::MissingValue,
                c.i,
                format!("@{code} needs {min} operands (K constant, R parameter, P pointer)"),
            ));
        }
        Ok(ops)
    }

    /// At the end of a block: the jump its `@` command asked for, if any. Not found is an
    /// alarm at the destination. Out of line: the plain path's caller stays as it was.
    #[cold]
    #[inline(never)]
    pub(in crate::frontend) fn c840_block_end(&mut self) -> R<()> {
        let Some(j) = self.c840.jump.take() else {
            return Ok(());
        };
        if self.finished {
            return Ok(());
        }
        let (colon, end) = (self.d.main_block_colon, self.src.len());
        // Backward: the last from the program's start up to the jump's own block; forward:
        // the first after it.
        let to = if j.back {
            let start = self.calls.running.start;
            numbered(self.src, start, end, j.number, j.here, colon).backward
        } else {
            numbered(self.src, j.next, end, j.number, j.here, colon).forward
        };
        let Some(to) = to else {
            return Err(fault(
                AlarmCode::JumpTarget,
                j.at,
                format!(
                    "jump destination: no block N{} {}",
                    j.number,
                    if j.back {
                        "before this one (searched backward)"
                    } else {
                        "after this one (searched forward)"
                    }
                ),
            ));
        };
        if j.back {
            self.next_pass(j.command)?;
        }
        (self.pos, self.line, self.line_start) = to;
        Ok(())
    }
}

/// The digits of an R parameter's number at the cursor (`R01` is R1); `at` is its R.
fn parameter_number(c: &mut Cursor, at: usize) -> R<usize> {
    let start = c.i;
    let mut n: usize = 0;
    while let Some(d @ b'0'..=b'9') = c.peek() {
        n = n.saturating_mul(10).saturating_add((d - b'0') as usize);
        c.i += 1;
    }
    if c.i == start {
        return Err(fault(
            AlarmCode::Syntax,
            at,
            "R must be followed by the parameter's number",
        ));
    }
    Ok(n)
}

/// A K, R or P operand at the cursor; `None` if what stands there is none (another word, an
/// assignment `R1=…`, the block's end).
fn operand(c: &mut Cursor) -> R<Option<Operand>> {
    let kind = match c.letter() {
        Some(b'K') => Kind::K,
        Some(b'R') => Kind::R,
        Some(b'P') => Kind::P,
        _ => return Ok(None),
    };
    let at = c.i;
    let mut probe = *c;
    probe.i += 1;
    let value = if kind == Kind::K {
        let (n, next) = number::parse(probe.b, probe.i)
            .filter(|(_, e)| *e <= probe.end)
            .ok_or_else(|| fault(AlarmCode::BadNumber, at, "K must be followed by a number"))?;
        probe.i = next;
        n.value
    } else {
        let n = parameter_number(&mut probe, at)?;
        let mut after = probe;
        after.skip_blanks();
        if after.peek() == Some(b'=') {
            // An assignment after the command, not its operand.
            return Ok(None);
        }
        n as f64
    };
    *c = probe;
    Ok(Some(Operand { kind, value, at }))
}

fn skip_blanks_and_comments(c: &mut Cursor) -> R<()> {
    loop {
        c.skip_blanks();
        if c.peek() != Some(b'(') {
            return Ok(());
        }
        let open = c.i;
        if !c.skip_comment() {
            return Err(fault(
                AlarmCode::Syntax,
                open,
                "comment not closed with ')'",
            ));
        }
    }
}

#[cold]
fn operand_expected(at: usize) -> Box<Fault> {
    fault(
        AlarmCode::BadNumber,
        at,
        "a number or an R parameter expected",
    )
}

#[cfg(test)]
mod tests {
    use super::super::super::{end_xs, run};
    use crate::alarm::AlarmCode;

    fn xs(src: &str) -> Vec<f64> {
        end_xs("siemens-840c", src)
    }

    fn ends(src: &str) -> Vec<[f64; 3]> {
        super::super::super::moves("siemens-840c", src)
            .iter()
            .map(|m| m.1)
            .collect()
    }

    fn alarm(src: &str) -> (AlarmCode, u32, u32) {
        super::super::super::alarm_at("siemens-840c", src)
    }

    #[test]
    fn parameters_are_assigned_left_to_right_and_read_by_addresses() {
        // R2 = 10·2 + 5 = 25; X R1, Y−R2, Z+R2; R3 = 2 + 3·4 − 10/5 = 12 (× and / first).
        let p = "R1=10 R2=R1*2+5\nG1 F100 X R1 Y-R2 Z+R2\nR3=2+3*4-10/5 R4=-R3 X R3 YR4\n";
        assert_eq!(ends(p), [[10.0, -25.0, 25.0], [12.0, -12.0, 25.0]]);
        // A block of assignments alone is a statement: no block of its own.
        let b = run("siemens-840c", "N10 R1=5\nN20 G0 X R1\n").unwrap();
        assert_eq!(b.len(), 1);
        assert!(b[0].motion.is_some() && b[0].number.unwrap().value == 20);
        // R01 is R1; blanks around '=' and the operators.
        assert_eq!(xs("R01 = 4 * 2\nG0 X R1\n"), [8.0]);
    }

    #[test]
    fn a_counted_loop_jumps_back_while_the_comparison_holds() {
        // N20 runs with R1 = 0, 10, 20; at 30 @124 (<) no longer jumps.
        let p = "N10 R1=0\nN20 G1 F100 X R1\nN30 R1=R1+10\nN40 @124 R1 K30 K-20\nN50 M30\n";
        assert_eq!(xs(p), [0.0, 10.0, 20.0]);
        // Every comparison: 121 ≠, 122 =, 123 ≤, 124 <, 125 ≥, 126 >; R2 = 5 against 5.
        let cmp = |code: u32, want: f64| {
            let p = format!("R2=5\nN10 @{code} R2 K5 K+30\nN20 G0 X1\nN30 G0 X{want}\n");
            let got = xs(&p);
            assert_eq!(got.last(), Some(&want), "@{code}: {got:?}");
            got.len()
        };
        // Jumped over N20: one move; not jumped: two.
        assert_eq!(cmp(121, 9.0), 2);
        assert_eq!(cmp(122, 9.0), 1);
        assert_eq!(cmp(123, 9.0), 1);
        assert_eq!(cmp(124, 9.0), 2);
        assert_eq!(cmp(125, 9.0), 1);
        assert_eq!(cmp(126, 9.0), 2);
    }

    #[test]
    fn unconditional_and_case_jumps_find_block_numbers_and_main_blocks() {
        // @100 K+40 over N30; :50 is a main block (`:` for N).
        let p = "N10 G0 X1\nN20 @100 K+40\nN30 X2\nN40 X3\nN45 @100 K50\nN48 X4\n:50 X5\n";
        assert_eq!(xs(p), [1.0, 3.0, 5.0]);
        // Case: R2 = 13 → the destination after K13.
        let p = "R2=13\n@111 R2 K12 K100 K13 K200\nG0 X9\nN100 X1\nN200 X2\n";
        assert_eq!(xs(p), [2.0]);
        // No value equal: on with the next block.
        assert_eq!(xs(&p.replace("R2=13", "R2=14")), [9.0, 1.0, 2.0]);
        // The destination from an R parameter; its sign gives the direction.
        let p = "R5=-10\nN10 R1=R1+1\nG0 X R1\n@123 R1 K2 R5\n";
        assert_eq!(xs(p), [1.0, 2.0, 3.0]);
    }

    #[test]
    fn functions_compute_into_their_parameter() {
        // sin 30 = 0.5, cos 60 = 0.5, √(9+16) = 5, √16 = 4, |−7| = 7, int(2.7) = 2, 2+1, 2−1.
        let p = "R1=30 R9=-7 R8=2.7\n@630 R2 R1\n@631 R3 K60\n@614 R4 K3 K4\n@613 R5 K16\n\
                 @610 R6 R9\n@622 R8\n@620 R7\n@620 R7\n@621 R7\nG0 X R2 Y R3 Z R4\nX R5 Y R6 Z R8\nX R7\n";
        let e = ends(p);
        let want = [[0.5, 0.5, 5.0], [4.0, 7.0, 2.0], [1.0, 7.0, 2.0]];
        for (g, w) in e.iter().zip(want) {
            assert!((0..3).all(|i| (g[i] - w[i]).abs() < 1e-12), "{e:?}");
        }
        // P: R10 holds 3, so P10 is R3.
        assert_eq!(
            xs("R10=3 R3=42\n@610 R1 P10\n@620 P10\nG0 X R1 Y R3\n"),
            [42.0]
        );
        assert_eq!(ends("R10=3 R3=42\n@620 P10\nG0 X R3\n"), [[43.0, 0.0, 0.0]]);
    }

    #[test]
    fn endless_and_missing_jumps_are_alarms() {
        // The loop budget (100000) ends the loop at the @ command.
        assert_eq!(
            alarm("N10 R1=R1+1\nN20 @100 K-10\n"),
            (AlarmCode::LoopLimit, 2, 5)
        );
        // N10 lies behind: forward finds nothing; the alarm points at the destination.
        assert_eq!(
            alarm("N10 G0 X1\nN20 @100 K10\n"),
            (AlarmCode::JumpTarget, 2, 10)
        );
        assert_eq!(
            alarm("N10 @122 R1 K0 K-99\n"),
            (AlarmCode::JumpTarget, 1, 16)
        );
        assert_eq!(alarm("@100 K1.5\n"), (AlarmCode::BadNumber, 1, 6));
        // The operands are the command's; a word after them is the block's (here a centre K
        // without a circle).
        let a = run("siemens-840c", "@100 K1 K2\nN1 X1\n").unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::Syntax, 9), "{a}");
    }

    #[test]
    fn bad_operands_are_alarms_at_their_place() {
        assert_eq!(alarm("@610 K1 R2\n"), (AlarmCode::Syntax, 1, 6));
        assert_eq!(alarm("@121 K1 K2 K3\n"), (AlarmCode::Syntax, 1, 6));
        assert_eq!(alarm("@614 R1 K3\n"), (AlarmCode::MissingValue, 1, 11));
        assert_eq!(alarm("@111 R1 K1\n"), (AlarmCode::MissingValue, 1, 11));
        assert_eq!(alarm("@613 R1 K-4\n"), (AlarmCode::Arithmetic, 1, 9));
        assert_eq!(alarm("@630 R1 K\n"), (AlarmCode::BadNumber, 1, 9));
        assert_eq!(alarm("@715\n"), (AlarmCode::NotSupported, 1, 1));
        assert_eq!(alarm("@630 R1300 K1\n"), (AlarmCode::UndefinedName, 1, 6));
        assert_eq!(
            alarm("R1=0 R2=-1\n@610 R3 P2\n"),
            (AlarmCode::BadNumber, 2, 9)
        );
        assert_eq!(alarm("R1=5/0\n"), (AlarmCode::Arithmetic, 1, 5));
        assert_eq!(alarm("R1 5\n"), (AlarmCode::Syntax, 1, 1));
        assert_eq!(alarm("R=5\n"), (AlarmCode::Syntax, 1, 1));
        assert_eq!(alarm("R1=*2\n"), (AlarmCode::BadNumber, 1, 4));
        assert_eq!(alarm("G R1\n"), (AlarmCode::Syntax, 1, 3));
        assert_eq!(alarm("G0 X R1300\n"), (AlarmCode::UndefinedName, 1, 6));
    }

    #[test]
    fn the_spindle_limit_is_g92_s_or_g26_s() {
        let b = run("siemens-840c", "G92 S2500\nG26 S1800 X50\nG96 S200\n").unwrap();
        assert_eq!(b[0].modal.spindle_limit, 2500.0);
        // G26's S is the limit, its X the working area's; neither is the speed.
        assert_eq!(
            (b[1].modal.spindle_limit, b[1].modal.spindle),
            (1800.0, 0.0)
        );
        assert!(b[1].motion.is_none());
        // G26 S alone limits no axis.
        assert_eq!(xs("G26 S1800\nG0 X60\n"), [60.0]);
        assert_eq!(alarm("G26 X50\nG0 X60\n"), (AlarmCode::WorkingArea, 2, 1));
        // G92 sets no actual value here, and TRC forbids it (11.4).
        assert_eq!(alarm("G92 S100 X10\n"), (AlarmCode::NotSupported, 1, 10));
        assert_eq!(
            alarm("G0 X0 Y0 D1\nG41 G1 X10 F100\nG92 S100\n"),
            (AlarmCode::ForbiddenWithTrc, 3, 1)
        );
    }

    #[test]
    fn the_preprocessing_stop_stays_a_block_and_other_dialects_have_no_r() {
        let b = run("siemens-840c", "R1=1 @714\n").unwrap();
        assert!(b[0].preprocess_stop && b[0].calculation);
        assert!(run("isg", "G0 X R1\n").is_err());
        assert!(run("siemens-808d", "G0 X R1\n").is_err());
    }
}
