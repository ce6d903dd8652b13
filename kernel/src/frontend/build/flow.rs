//! Program flow in the block build: the program-flow M functions (stop, optional stop, end),
//! the `@` commands (840C preprocessing stop) and the dwell, whose time the dialect's dwell
//! addresses carry instead of a position.

use super::super::block::*;
use super::super::calls::{Args, CallKind, Pending, Target};
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::macro_b::expr;
use super::super::statements::fanuc::{count, program_number, sequence_number};
use super::super::words::{Val, Words};
use crate::alarm::AlarmCode;
use crate::dialect::{AtEffect, MEffect};
use crate::machine_data::DecimalInput;

impl Interpreter<'_> {
    /// Step 3: `@` commands that act on the block (the word loop looked them up in the
    /// dialect's table and ran the language's); some are forbidden while TRC is active (840C
    /// 11.4).
    #[inline(always)]
    pub(super) fn at_commands(&mut self, w: &Words) -> R<()> {
        for &(code, at) in &w.at_codes {
            let Some(def) = self.d.at_command(code) else {
                continue;
            };
            if def.forbidden_with_trc && self.block.modal.trc != TrcSide::Off {
                return Err(self.forbidden_with_trc(&format!("@{code}"), at));
            }
            if def.effect == AtEffect::PreprocessStop {
                self.block.preprocess_stop = true;
            }
        }
        Ok(())
    }

    /// Step 7: the M functions the dialect's table knows (program flow, the spindle's
    /// direction); every M word also goes on to the PLC as written (but the program-flow
    /// ones).
    #[inline(always)]
    pub(super) fn m_functions(&mut self, w: &Words, new: &mut ModalState) -> R<()> {
        let mut spindle = None;
        for m in &w.m {
            match self.d.mcode(m.value).map(|def| def.effect) {
                // SINUMERIK, 840C: M2/M30 in a called program end it like M17.
                Some(MEffect::Stop(s)) if s.ends_program() && self.returns_at_end() => {
                    self.subprogram_end(m.at)?
                }
                Some(MEffect::Stop(s)) => self.program_stop(s, m.at)?,
                Some(MEffect::SubprogramEnd) => self.subprogram_end(m.at)?,
                Some(MEffect::Spindle(dir)) => {
                    if spindle.is_some_and(|d| d != dir) {
                        return Err(fault(
                            AlarmCode::SameGroupTwice,
                            m.at,
                            "two spindle M functions in one block",
                        ));
                    }
                    spindle = Some(dir);
                    new.spindle_dir = dir;
                }
                Some(MEffect::Call) => self.subprogram_call(w, m.at)?,
                Some(MEffect::Return) => {
                    let to = w.p.map(|p| sequence_number(p.value, p.pos())).transpose()?;
                    self.set_pending(Pending::Return { to, at: m.pos() }, m.at)?;
                }
                None => {}
            }
        }
        if self.calls.pending.is_some() {
            // Calls and returns (M98, M99, M17) act in the control; they go to no PLC.
            let d = self.d;
            let returning = matches!(self.calls.pending, Some(Pending::Return { .. }))
                && d.has_subprogram_end();
            self.block.words.retain(|x| {
                x.address != b'M'
                    || !match d.mcode(x.value).map(|def| def.effect) {
                        Some(MEffect::Call | MEffect::Return | MEffect::SubprogramEnd) => true,
                        Some(MEffect::Stop(s)) => returning && s.ends_program(),
                        _ => false,
                    }
            });
        }
        Ok(())
    }

    /// A program end in a called program returns to the caller (a dialect with M17).
    fn returns_at_end(&self) -> bool {
        self.calls.depth() > 0 && self.d.has_subprogram_end()
    }

    /// M17 (or M2/M30 in a called program): back to the caller when the block is complete;
    /// in the main program the program's end (Fundamentals, "Program end": M2, M17, M30).
    fn subprogram_end(&mut self, at: u32) -> R<()> {
        if self.calls.depth() == 0 {
            return self.program_stop(ProgramStop::End, at);
        }
        let to = None;
        self.set_pending(
            Pending::Return {
                to,
                at: at as usize,
            },
            at,
        )
    }

    /// M98 P… (L…): the call runs when the block is complete. A P of more than four digits
    /// carries the repeat count before the program number (P30010: O0010 three times).
    fn subprogram_call(&mut self, w: &Words, at: u32) -> R<()> {
        let p = w.p.ok_or_else(|| {
            let call = self.d.m_name(MEffect::Call);
            fault(
                AlarmCode::MissingValue,
                at,
                format!("{call} needs the program number P"),
            )
        })?;
        let digits = expr::whole(p.value, p.pos(), "P")?;
        let (count_in_p, number) = (digits / 10_000, digits % 10_000);
        let repeats = match w.l {
            Some(l) => count(l.value, l.pos())?,
            None if count_in_p > 0 => count(count_in_p as f64, p.pos())?,
            None => 1,
        };
        let number = program_number(number as f64, p.pos())?;
        let call = Pending::Call {
            target: Target::Number(number),
            repeats,
            kind: CallKind::Subprogram,
            args: Args::Locals(Box::new([None; crate::frontend::macro_b::LOCALS])),
            at: p.pos(),
        };
        self.set_pending(call, at)
    }

    fn set_pending(&mut self, p: Pending, at: u32) -> R<()> {
        if self.calls.pending.replace(p).is_some() {
            return Err(fault(
                AlarmCode::SameGroupTwice,
                at,
                "two calls or returns in one block",
            ));
        }
        Ok(())
    }

    /// A program stop at block end; two different ones in a block are an alarm.
    fn program_stop(&mut self, s: ProgramStop, at: u32) -> R<()> {
        let blk = &mut self.block;
        if blk.stop.is_some_and(|prev| prev != s) {
            return Err(fault(
                AlarmCode::SameGroupTwice,
                at,
                "two program-flow M functions in one block",
            ));
        }
        blk.stop = Some(s);
        Ok(())
    }

    /// Step 8: a dwell block (G code `code`): its time, and no axis moves. `revolutions`:
    /// the S word of a dialect that dwells for spindle revolutions (SINUMERIK `G4 S…`).
    pub(super) fn dwell(
        &mut self,
        w: &Words,
        code: u16,
        revolutions: Option<f64>,
        new: &ModalState,
        block_col: usize,
    ) -> R<()> {
        if self.d.sinumerik {
            self.dwell_alone(w, code, block_col)?;
        }
        let secs = match (self.dwell_time(w), revolutions) {
            (Some(t), None) => t,
            (None, Some(n)) => Val::computed(self.revolutions_time(n, new, block_col)?, block_col),
            (Some(t), Some(_)) => {
                return Err(fault(
                    AlarmCode::AddressTwice,
                    t.at,
                    format!("G{code} takes a time or spindle revolutions, not both"),
                ))
            }
            (None, None) => {
                return Err(fault(
                    AlarmCode::MissingValue,
                    block_col,
                    format!("G{code} needs a dwell time"),
                ))
            }
        };
        if secs.value < 0.0 || secs.value > 1e6 {
            return Err(fault(
                AlarmCode::BadNumber,
                secs.at,
                "dwell time out of range",
            ));
        }
        let axis_used_as_time = self.d.dwell.x_seconds && w.axis[0].is_some();
        for (i, a) in w.axis.iter().enumerate() {
            if let (Some(a), false) = (a, i == 0 && axis_used_as_time) {
                return Err(fault(
                    AlarmCode::Syntax,
                    a.at,
                    format!("a dwell block (G{code}) cannot move axes"),
                ));
            }
        }
        self.block.dwell = Some(secs.value);
        Ok(())
    }

    /// The seconds `n` spindle revolutions take at the speed the spindle turns at where the
    /// block starts (under constant cutting speed, at the X there).
    fn revolutions_time(&self, n: f64, new: &ModalState, block_col: usize) -> R<f64> {
        let rpm = crate::ipo::spindle_setpoint(
            &new.technology().spindle,
            self.cur[0],
            self.md.spindle.max_speed,
        )
        .abs();
        if rpm <= 0.0 {
            return Err(fault(
                AlarmCode::BadNumber,
                block_col,
                "a dwell in spindle revolutions needs the spindle turning at a speed",
            ));
        }
        Ok(n * 60.0 / rpm)
    }

    /// SINUMERIK: G4 stands in a block of its own, with its F or S (Fundamentals, "Dwell
    /// time (G4)": "G4 must be programmed in a separate block").
    fn dwell_alone(&self, w: &Words, code: u16, block_col: usize) -> R<()> {
        let word =
            w.g.iter()
                .find(|&&(c, _)| c != code)
                .map(|&(_, at)| at)
                .or(w.m.first().map(|v| v.at))
                .or(w.t.or(w.d).or(w.lims).or(w.radius).map(|v| v.at))
                .or(w.centre.iter().flatten().next().map(|v| v.at));
        let other = word.map(|at| at as usize).or_else(|| {
            (w.diameter.is_some() || w.corner.is_some() || !w.path.is_empty() || w.calculation)
                .then_some(block_col)
        });
        match other {
            Some(at) => Err(fault(
                AlarmCode::Syntax,
                at,
                format!("G{code} stands in a block of its own (with its F or S only)"),
            )),
            None => Ok(()),
        }
    }

    /// The dwell time in seconds from the first of the dialect's dwell addresses written:
    /// X, F, P (milliseconds) or a bare number (docs/dialects.md, "Lexical rules").
    fn dwell_time(&self, w: &Words) -> Option<Val> {
        let dwell = self.d.dwell;
        if let (true, Some(mut x)) = (dwell.x_seconds, w.axis[0]) {
            // Fanuc increment input: X1000 without a decimal point is 1000 ms.
            if self.d.decimal_switch
                && !x.has_point
                && self.md.program.decimal_input == DecimalInput::Increment
            {
                x.value *= 0.001;
            }
            Some(x)
        } else if let (true, Some(f)) = (dwell.f_seconds, w.f) {
            Some(f)
        } else if let (true, Some(p)) = (dwell.p_millis, w.p) {
            Some(Val {
                value: p.value / 1000.0,
                at: p.at,
                has_point: true,
            })
        } else {
            w.bare
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::run;
    use super::*;

    fn stops(dialect: &str, src: &str) -> Vec<Option<ProgramStop>> {
        run(dialect, src).unwrap().iter().map(|b| b.stop).collect()
    }

    #[test]
    fn program_stops_act_per_dialect() {
        // 840C 11.10 lists M18 with M00/M01/M02/M30; elsewhere it is a plain M word.
        let src = "M0\nM1\nM18\nM3\nM2\n";
        let c840 = [
            Some(ProgramStop::Stop),
            Some(ProgramStop::OptionalStop),
            Some(ProgramStop::StopAtEnd),
            None,
            Some(ProgramStop::End),
        ];
        assert_eq!(stops("siemens-840c", src), c840);
        assert_eq!(stops("isg", src)[2], None);
        // Nothing after M30 is read.
        assert_eq!(stops("fanuc", "M30\nQ\n"), [Some(ProgramStop::EndRewind)]);
        let a = run("isg", "M0 M30\n").unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::SameGroupTwice, 4));
        assert!(run("isg", "M0 M0\n").is_ok());
    }

    #[test]
    fn dwell_times_come_from_the_dialects_words() {
        let dwell = |d: &str, src: &str| run(d, src).unwrap()[0].dwell;
        assert_eq!(dwell("siemens-840c", "G4 F2.5\n"), Some(2.5));
        assert_eq!(dwell("isg", "G04 3.0\n"), Some(3.0));
        assert_eq!(dwell("fanuc", "G4 P500\n"), Some(0.5));
        let a = run("siemens-840c", "G4 X1 Y2\n").unwrap_err();
        assert_eq!((a.code, a.col), (AlarmCode::Syntax, 7));
        assert_eq!(a.message, "a dwell block (G4) cannot move axes");
        let a = run("siemens-840c", "G04\n").unwrap_err();
        assert_eq!(
            (a.code, a.message.as_str()),
            (AlarmCode::MissingValue, "G4 needs a dwell time")
        );
    }

    #[test]
    fn sinumerik_dwells_for_spindle_revolutions_in_a_block_of_its_own() {
        // 10 revolutions at 1000 rev/min: 0.6 s; the S word is no speed and leaves the block.
        let b = run("siemens-840d", "S1000 M3\nG4 S10\n").unwrap();
        assert_eq!((b[1].dwell, b[1].modal.spindle), (Some(0.6), 1000.0));
        assert!(b[1].words.is_empty());
        let alarm = |src: &str| {
            let a = run("siemens-840d", src).unwrap_err();
            (a.code, a.line, a.col)
        };
        assert_eq!(alarm("G4 S10\n"), (AlarmCode::BadNumber, 1, 1));
        assert_eq!(
            alarm("S100 M3\nG4 F1 S2\n"),
            (AlarmCode::AddressTwice, 2, 4)
        );
        assert_eq!(alarm("G4 F1 M8\n"), (AlarmCode::Syntax, 1, 7));
        assert_eq!(alarm("G4 G1 F1\n"), (AlarmCode::Syntax, 1, 4));
        // Elsewhere S beside G4 stays a speed.
        let b = run("siemens-840c", "G4 F1 S500\n").unwrap();
        assert_eq!((b[0].dwell, b[0].modal.spindle), (Some(1.0), 500.0));
    }

    #[test]
    fn at_714_stops_preprocessing() {
        assert!(run("siemens-840c", "@714\n").unwrap()[0].preprocess_stop);
        let a = run("siemens-840c", "@715\n").unwrap_err();
        assert_eq!(a.code, AlarmCode::NotSupported);
        let a = run("siemens-840c", "G41 D1 G1 X0 Y0 F100\nX10 @714\n").unwrap_err();
        assert_eq!((a.code, a.line, a.col), (AlarmCode::ForbiddenWithTrc, 2, 5));
    }
}
