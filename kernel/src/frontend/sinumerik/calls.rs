//! Subprogram calls of the SINUMERIK language (Job planning, "Subprogram technique";
//! docs/sinumerik.md, "Subprograms") and the 840C's DIN-style `L123 P3`:
//!
//! - `NAME`, `L123`, `NAME(1.5, R3+2)`, each with `P n` for n passes, in a block of its own:
//!   the program file `NAME.SPF` (else `NAME.MPF`) of the program library (programs.rs);
//!   `_N_NAME_SPF` and the other written forms name the same file.
//! - The called program's PROC line (procs.rs, read with its structure before it runs) gives
//!   the parameters: values are converted to their types, a `VAR` parameter takes the
//!   caller's variable; an omitted value parameter is 0. The parameters are the called
//!   level's first user variables (sinumerik/mod.rs `Store`).
//! - `MCALL NAME(…)` calls after every block that moves, `MCALL` alone ends it; `RET` (and
//!   M17, build/flow.rs) returns. The end of a called program's text returns as M17 does.
//! - `MCALL CYCLE81(…)`: a drilling cycle (cycles/) after every block that moves.

use super::super::calls::{Args, CallKind, ModalCall, Pending, Target};
use super::super::fault::{fault, R};
use super::super::interpreter::Interpreter;
use super::super::lexer::Cursor;
use super::expr::{self, identifier_span, r_number};
use super::procs::{is_l_name, Formal, ProcDecl};
use super::structure::Structure;
use super::{Binding, Param, Ref, Store};
use crate::alarm::AlarmCode;
use crate::frontend::block::ProgramStop;

/// Most passes a call may ask for with P (Fundamentals, "Program repetition": 1 … 9999
/// **[unconfirmed]**).
const MAX_PASSES: u32 = 9999;

/// Words of the language that may stand alone in a block but name no program: a block with
/// one of them is no call (the word loop reads it, or refuses it as a word it does not know).
const NOT_PROGRAMS: &[&str] = &[
    "CIP", "CT", "SUPA", "NORM", "KONT", "KONTC", "KONTT", "DIAMON", "DIAMOF", "DIAM90",
];

/// What a call block asks for: a program file with its parameters bound and its passes.
struct Callee {
    program: u16,
    params: Box<[Param]>,
    passes: u32,
}

impl Interpreter<'_> {
    /// Whether the block at the cursor (after its number and label) of a SINUMERIK or 840C
    /// program is a subprogram call: `L` and a digit, or on SINUMERIK a name alone (with
    /// `(`…`)`, `P`, a comment) that is no variable, function or word of the language. Told
    /// from its first two bytes for most blocks.
    #[inline]
    pub(in crate::frontend) fn is_call(&self, c: &Cursor) -> bool {
        if matches!(c.peek(), Some(b'L' | b'l')) && matches!(c.peek_at(1), Some(b'0'..=b'9')) {
            return true;
        }
        let name_char = |k| matches!(c.peek_at(k), Some(b) if b.is_ascii_alphabetic() || b == b'_');
        self.d.sinumerik && name_char(0) && name_char(1) && self.named_call(c)
    }

    /// A name alone at the cursor, as a call has it.
    #[cold]
    fn named_call(&self, c: &Cursor) -> bool {
        let mut p = *c;
        let name = identifier_span(&mut p);
        if self.sinumerik.store.has_name(name) {
            return false;
        }
        p.skip_blanks();
        let alone = match p.peek() {
            None | Some(b';' | b'(') => true,
            Some(b'P' | b'p') => matches!(p.peek_at(1), Some(b'0'..=b'9' | b' ' | b'\t' | b'=')),
            _ => false,
        };
        let upper = String::from_utf8_lossy(name).to_ascii_uppercase();
        alone && !expr::is_reserved(&upper) && !NOT_PROGRAMS.contains(&upper.as_str())
    }

    /// Runs the call block at the cursor (at the program's name); it produces no block.
    pub(in crate::frontend) fn call_block(&mut self, mut c: Cursor) -> R<bool> {
        let at = c.i;
        let Callee {
            program,
            params,
            passes,
        } = self.read_call(&mut c)?;
        self.calls.pending = Some(Pending::Call {
            target: Target::File(program),
            repeats: passes,
            kind: CallKind::Procedure { modal: false },
            args: Args::Params(params),
            at,
        });
        self.run_pending()?;
        Ok(false)
    }

    /// `MCALL NAME(…)`: the call after every block that moves, until `MCALL` alone (Job
    /// planning, "Modal subprogram call").
    pub(in crate::frontend) fn mcall(&mut self, c: &mut Cursor) -> R<()> {
        c.skip_blanks();
        if matches!(c.peek(), None | Some(b';')) {
            self.calls.modal = None;
            return Ok(());
        }
        if super::statements::Keyword::at(c) == Some(super::statements::Keyword::Cycle) {
            let at = c.i;
            let (name, p) = self.cycle_call(c, at)?;
            self.calls.modal = Some(ModalCall {
                target: Target::Cycle(name, Box::new(p)),
                repeats: 1,
                args: Args::Params(Box::new([])),
                depth: self.calls.depth(),
            });
            return Ok(());
        }
        let Callee {
            program,
            params,
            passes,
        } = self.read_call(c)?;
        self.calls.modal = Some(ModalCall {
            target: Target::File(program),
            repeats: passes,
            args: Args::Params(params),
            depth: self.calls.depth(),
        });
        Ok(())
    }

    /// `RET`: back to the caller; in the main program the program's end, as M17.
    pub(in crate::frontend) fn ret_statement(&mut self, at: usize) -> R<bool> {
        if self.calls.depth() == 0 {
            self.statement_block(at, None)?;
            self.block.preprocess_stop = false;
            self.block.stop = Some(ProgramStop::End);
            self.finished = true;
            return Ok(true);
        }
        self.calls.pending = Some(Pending::Return { to: None, at });
        self.run_pending()?;
        Ok(false)
    }

    /// The end of a called program's text without M17 or RET: back to the caller, as M17
    /// (docs/sinumerik.md, "Subprograms"). A fault names the program's first line.
    pub(in crate::frontend) fn implicit_return(&mut self) -> R<()> {
        let (at, line, line_start) = self.calls.running.start;
        (self.blk_line, self.blk_line_start, self.blk_number) = (line, line_start, None);
        self.calls.pending = Some(Pending::Return { to: None, at });
        self.run_pending()
    }

    /// The call at the cursor: its program, parameters and passes, up to the block's end.
    fn read_call(&mut self, c: &mut Cursor) -> R<Callee> {
        let name_at = c.i;
        let name = call_name(c)?;
        let (stem, main) = program_key(&name);
        let library = &self.md.programs;
        let Some((program, file)) = library.find_named(stem, main) else {
            return Err(self.missing_program(stem, main, name_at));
        };
        super::super::calls::file_text(file, name_at)?;
        let params = if self.d.sinumerik {
            self.callee_structure(program, stem)?;
            let decl = self
                .sinumerik
                .structure(program)
                .and_then(|s| s.proc.as_ref());
            bind(c, decl, &self.sinumerik.store, stem, name_at)?
        } else {
            Box::new([])
        };
        let passes = self.passes(c)?;
        self.end_of_call(c)?;
        Ok(Callee {
            program,
            params,
            passes,
        })
    }

    /// The structure (and PROC line) of library program `k`, read once: a fault in it is an
    /// alarm in that file, at its line.
    fn callee_structure(&mut self, k: u16, stem: &str) -> R<()> {
        if self.sinumerik.structure(k).is_some() {
            return Ok(());
        }
        let text = self.library_text(k);
        let Some((_, src, _)) = text else {
            return Ok(());
        };
        let read = Structure::of(src, 0, src.len(), 1).and_then(|s| proc_named(s, stem));
        match read {
            Ok(s) => {
                self.keep_structure(k, s);
                Ok(())
            }
            Err(e) => {
                // The alarm names the called file and its line.
                self.enter(text, (0, 1, 0));
                Err(self.located(e))
            }
        }
    }

    /// `P n` after the call: n passes (1 … 9999); 1 without.
    fn passes(&mut self, c: &mut Cursor) -> R<u32> {
        c.skip_blanks();
        if !matches!(c.peek(), Some(b'P' | b'p')) {
            return Ok(1);
        }
        let at = c.i;
        c.i += 1;
        c.skip_blanks();
        let v = if self.d.sinumerik {
            if c.peek() == Some(b'=') {
                c.i += 1;
            }
            expr::eval(c, &self.sinumerik.store)?
        } else {
            let (n, next) = crate::frontend::number::parse(c.b, c.i)
                .filter(|(_, e)| *e <= c.end)
                .ok_or_else(|| fault(AlarmCode::BadNumber, at, "P must be followed by a number"))?;
            c.i = next;
            n.value
        };
        if v.fract() != 0.0 || !(1.0..=MAX_PASSES as f64).contains(&v) {
            let message = format!("P{v}: a program runs 1 … {MAX_PASSES} times");
            return Err(fault(AlarmCode::BadNumber, at, message));
        }
        Ok(v as u32)
    }

    /// Nothing but a comment (840C: and `LF`) after a call: it stands in a block of its own.
    fn end_of_call(&self, c: &mut Cursor) -> R<()> {
        loop {
            c.skip_blanks();
            match c.peek() {
                None | Some(b';') => return Ok(()),
                Some(b'(') if !self.d.sinumerik && c.skip_comment() => {}
                Some(b'L' | b'l') if self.d.lf_block_end && c.keyword("LF") => c.i += 2,
                Some(_) => {
                    let message = "a subprogram call stands in a block of its own: only P (passes) and a comment may follow it";
                    return Err(fault(AlarmCode::Syntax, c.i, message));
                }
            }
        }
    }

    /// Alarm 14011: no file for the program, and where softnc looked.
    #[cold]
    fn missing_program(
        &self,
        stem: &str,
        main: Option<bool>,
        at: usize,
    ) -> Box<super::super::fault::Fault> {
        let files = match main {
            Some(true) => format!("{stem}.MPF"),
            Some(false) => format!("{stem}.SPF"),
            None => format!("{stem}.SPF or {stem}.MPF"),
        };
        let path = &self.md.program.search_path;
        let search = if path.is_empty() {
            "program.search_path is empty".to_string()
        } else {
            format!("program.search_path: {}", path.join(", "))
        };
        let message = format!(
            "program {stem} not found: no {files} in the program's folder or the search path ({search}); a name alone in its block calls the program of that name"
        );
        fault(AlarmCode::MissingProgram, at, message)
    }
}

/// The program name at the cursor (upper case): `L` and digits, or a name.
fn call_name(c: &mut Cursor) -> R<String> {
    let at = c.i;
    let l_digits =
        matches!(c.peek(), Some(b'L' | b'l')) && matches!(c.peek_at(1), Some(b'0'..=b'9'));
    let name = if l_digits {
        c.i += 1;
        while matches!(c.peek(), Some(b'0'..=b'9')) {
            c.i += 1;
        }
        String::from_utf8_lossy(&c.b[at..c.i]).to_ascii_uppercase()
    } else {
        expr::identifier(c)
    };
    let after = c
        .peek()
        .is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_');
    if after || !(is_l_name(&name) || super::statements::valid_name(&name)) {
        let message = "a program name expected: L and digits, or a name whose first two characters are letters or _";
        return Err(fault(AlarmCode::Syntax, at, message));
    }
    Ok(name)
}

/// A name as a call writes it (`POCKET`, `_N_POCKET`, `POCKET_SPF`, `_N_POCKET_SPF`):
/// the program's name and, with a suffix, whether it is the main program (Job planning 828D,
/// "Subprogram names").
fn program_key(name: &str) -> (&str, Option<bool>) {
    let stem = name.strip_prefix("_N_").unwrap_or(name);
    match (stem.strip_suffix("_SPF"), stem.strip_suffix("_MPF")) {
        (Some(s), _) if !s.is_empty() => (s, Some(false)),
        (_, Some(s)) if !s.is_empty() => (s, Some(true)),
        _ => (stem, None),
    }
}

/// A called program's structure, its PROC line (if any) checked against the name it was
/// called by: a file holds the program of its name (Job planning, "Subprogram names").
fn proc_named(s: Structure, stem: &str) -> Result<Structure, super::structure::Located> {
    match &s.proc {
        Some(decl) if &*decl.name != stem => {
            let message = format!(
                "PROC {} in the file of program {stem}: the names must be the same",
                decl.name
            );
            let (line, line_start) = decl.line;
            Err((
                fault(AlarmCode::Syntax, decl.name_at, message),
                line,
                line_start,
            ))
        }
        _ => Ok(s),
    }
}

/// The actual parameters at the cursor (`(…)`, or none) bound to the formal ones of `decl`:
/// values converted later to their types, `VAR` ones to the caller's variables; one left out
/// is 0 (Job planning, "Parameter transfer"); a `VAR` one cannot be left out.
fn bind(
    c: &mut Cursor,
    decl: Option<&ProcDecl>,
    store: &Store,
    name: &str,
    name_at: usize,
) -> R<Box<[Param]>> {
    let formals = decl.map_or(&[][..], |d| &d.params[..]);
    let mut out = Vec::with_capacity(formals.len());
    c.skip_blanks();
    if c.peek() == Some(b'(') {
        c.i += 1;
        c.skip_blanks();
        if c.peek() == Some(b')') {
            c.i += 1;
        } else {
            loop {
                c.skip_blanks();
                let at = c.i;
                let Some(formal) = formals.get(out.len()) else {
                    return Err(too_many(name, formals.len(), at));
                };
                let empty = matches!(c.peek(), Some(b',' | b')'));
                out.push(actual(c, formal, store, name, empty.then_some(at))?);
                c.skip_blanks();
                match c.peek() {
                    Some(b',') => c.i += 1,
                    Some(b')') => {
                        c.i += 1;
                        break;
                    }
                    _ => return Err(fault(AlarmCode::Syntax, c.i, "',' or ')' expected")),
                }
            }
        }
    }
    for formal in &formals[out.len()..] {
        out.push(actual(c, formal, store, name, Some(name_at))?);
    }
    Ok(out.into_boxed_slice())
}

#[cold]
fn too_many(name: &str, n: usize, at: usize) -> Box<super::super::fault::Fault> {
    let message = match n {
        0 => format!("{name} takes no parameters (no PROC line with parameters)"),
        _ => format!("{name} takes {n} parameters (its PROC line)"),
    };
    fault(AlarmCode::Syntax, at, message)
}

/// One actual parameter for `formal`; `omitted`: none is written (where it would stand).
fn actual(
    c: &mut Cursor,
    formal: &Formal,
    store: &Store,
    name: &str,
    omitted: Option<usize>,
) -> R<Param> {
    let value = match (omitted, formal.by_ref) {
        (Some(at), true) => {
            let message = format!(
                "VAR parameter {} of {name} needs a variable (an R parameter or a DEF variable); it cannot be left out",
                formal.name
            );
            return Err(fault(AlarmCode::ParameterNotVariable, at, message));
        }
        (Some(_), false) => Binding::Value(0.0),
        (None, true) => Binding::Ref(reference(c, store, &formal.name, name)?),
        (None, false) => Binding::Value(expr::eval(c, store)?),
    };
    Ok(Param {
        name: formal.name.clone(),
        ty: formal.ty,
        value,
    })
}

/// The variable at the cursor for VAR parameter `formal` of `name`: `R5`, `R[expr]` or a
/// user variable of the caller, and nothing else up to the next `,` or `)`.
fn reference(c: &mut Cursor, store: &Store, formal: &str, name: &str) -> R<Ref> {
    let at = c.i;
    let mut p = *c;
    let span = identifier_span(&mut p);
    let word = String::from_utf8_lossy(span).to_ascii_uppercase();
    let found = if let Some(n) = r_number(&word) {
        store.r(n, at).map(|_| Some(Ref::R(n)))?
    } else if word == "R" && p.peek() == Some(b'[') {
        p.i += 1;
        let n = expr::index(expr::eval(&mut p, store)?, at)?;
        p.skip_blanks();
        if p.peek() != Some(b']') {
            return Err(fault(AlarmCode::Syntax, p.i, "']' expected"));
        }
        p.i += 1;
        store.r(n, at).map(|_| Some(Ref::R(n)))?
    } else {
        store.reference(&word)
    };
    p.skip_blanks();
    let alone = matches!(p.peek(), Some(b',' | b')'));
    match found {
        Some(r) if alone => {
            *c = p;
            Ok(r)
        }
        None if alone && super::statements::valid_name(&word) => Err(fault(
            AlarmCode::UndefinedName,
            at,
            format!("{word} is not defined (DEF)"),
        )),
        _ => {
            let message = format!(
                "VAR parameter {formal} of {name} needs a variable (an R parameter or a DEF variable), not an expression"
            );
            Err(fault(AlarmCode::ParameterNotVariable, at, message))
        }
    }
}

/// `EXTERN NAME(REAL, VAR INT)`: the caller's declaration of a subprogram with parameters.
/// softnc reads the called program's PROC line itself, so the declaration is only checked
/// to be one.
pub fn extern_declaration(c: &mut Cursor) -> R<()> {
    c.skip_blanks();
    call_name(c)?;
    c.skip_blanks();
    if c.peek() == Some(b'(') {
        let open = c.i;
        while c.peek().is_some_and(|b| b != b')') {
            c.i += 1;
        }
        if c.peek() != Some(b')') {
            return Err(fault(AlarmCode::Syntax, open, "'(' is not closed"));
        }
        c.i += 1;
    }
    c.skip_blanks();
    match c.peek() {
        None | Some(b';') => Ok(()),
        Some(_) => Err(fault(
            AlarmCode::Syntax,
            c.i,
            "end of the EXTERN line expected",
        )),
    }
}

#[cfg(test)]
mod tests {
    use crate::alarm::{Alarm, AlarmCode};
    use crate::frontend::{interpret, Block, ProgramStop};
    use crate::{MachineData, ProgramLibrary, ToolTable};

    /// `main` in `dialect` with the program files `files` (name, text) beside it.
    fn run(dialect: &str, main: &str, files: &[(&str, &str)]) -> Result<Vec<Block>, Alarm> {
        let mut md = MachineData::load(None, &[format!("dialect={dialect}")]).expect("md");
        let mut library = ProgramLibrary::default();
        for (file, text) in files {
            assert!(library.add(file, format!("lib/{file}"), text.to_string()));
        }
        md.programs = std::sync::Arc::new(library);
        interpret("main.mpf", main, &md, &ToolTable::builtin())
    }

    /// The end points (X, Y) of the moves.
    fn ends(dialect: &str, main: &str, files: &[(&str, &str)]) -> Vec<(f64, f64)> {
        run(dialect, main, files)
            .unwrap_or_else(|a| panic!("{a}"))
            .iter()
            .filter_map(|b| b.motion.map(|m| (m.end[0], m.end[1])))
            .collect()
    }

    fn alarm(dialect: &str, main: &str, files: &[(&str, &str)]) -> (AlarmCode, String, u32, u32) {
        let a = run(dialect, main, files).unwrap_err();
        (a.code, a.program, a.line, a.col)
    }

    #[test]
    fn a_name_calls_its_file_with_parameters_by_value_and_by_reference() {
        let sub = "PROC STEP(REAL DX, INT NN, VAR REAL LAST)\nDEF INT II\nFOR II=1 TO NN\nG91 G1 X=DX F100\nENDFOR\nG90\nLAST=LAST+NN*DX\nM17\n";
        let main = "DEF REAL AT=1\nG0 X0 Y0\nSTEP(2.5, 1.6, AT)\nG1 X=AT Y1 F100\nstep(1,,R7) P2\nG1 Y=R7\nM30\n";
        // NN = 1.6 → 2: X 2.5, 5; AT = 1 + 5 = 6; then NN = 0 twice: R7 stays 0.
        assert_eq!(
            ends("siemens-840d", main, &[("STEP.SPF", sub)]),
            [(0.0, 0.0), (2.5, 0.0), (5.0, 0.0), (6.0, 1.0), (6.0, 0.0)]
        );
    }

    #[test]
    fn l_numbers_and_passes_on_the_840d_808d_and_840c() {
        let sub = "G91 G1 X10 F100\nG90\nM17\n";
        let main = "G0 X0 Y0\nL12 P3\nN20 L12\nG0 Y5\nM30\n";
        let want = [
            (0.0, 0.0),
            (10.0, 0.0),
            (20.0, 0.0),
            (30.0, 0.0),
            (40.0, 0.0),
            (40.0, 5.0),
        ];
        for d in ["siemens-840d", "siemens-808d", "siemens-840c"] {
            let got: Vec<_> = run(d, main, &[("L12.SPF", sub)])
                .unwrap_or_else(|a| panic!("{d}: {a}"))
                .iter()
                .filter_map(|b| b.motion.map(|m| (m.end[0], m.end[1])))
                .collect();
            assert_eq!(got, want, "{d}");
        }
        // L0012 is another program than L12 (the digits are its name).
        let a = alarm("siemens-840d", "L0012\n", &[("L12.SPF", sub)]);
        assert_eq!(a, (AlarmCode::MissingProgram, "main.mpf".into(), 1, 1));
        // 840C: a header line and LF ends are read as in a main program.
        let sub_840c = "%SPF12\nN1 G91 G1 X10 F100 LF\nN2 G90 M17 LF\n";
        let got = ends("siemens-840c", "N5 L12 P2 LF\n", &[("L12.SPF", sub_840c)]);
        assert_eq!(got, [(10.0, 0.0), (20.0, 0.0)]);
    }

    #[test]
    fn m17_ret_m30_and_the_text_end_return_and_end_the_main_program() {
        let files = [
            ("A_RET.SPF", "G1 X1 F100\nRET\nX99\n"),
            ("A_M30.SPF", "G1 Y2 F100\nM30\nX99\n"),
            ("A_END.SPF", "G1 X3 F100\n"),
        ];
        let main = "A_RET\nA_M30\nA_END\nG0 Y4\nM17\nG0 X99\n";
        let got = ends("siemens-840d", main, &files);
        assert_eq!(got, [(1.0, 0.0), (1.0, 2.0), (3.0, 2.0), (3.0, 4.0)]);
        let b = run("siemens-840d", "G0 X1\nRET\nX2\n", &[]).unwrap();
        assert_eq!(b.last().and_then(|b| b.stop), Some(ProgramStop::End));
        // M17 and M30 of a return go to no PLC; M17 ending the main program does.
        let b = run("siemens-840d", "A_M30\nM17\n", &files).unwrap();
        assert!(b[1].words.is_empty() && b[1].stop.is_none(), "{:?}", b[1]);
        assert_eq!((b[2].words.len(), b[2].stop), (1, Some(ProgramStop::End)));
    }

    #[test]
    fn mcall_calls_after_each_move_and_not_inside_itself() {
        let files = [(
            "DRILL.SPF",
            "PROC DRILL(REAL DEPTH)\nG1 Z=DEPTH F100\nG0 Z2\n",
        )];
        let main = "G0 X0 Y0 Z2\nMCALL DRILL(-5)\nX10\nM3 S100\nY10\nMCALL\nX20\n";
        let zs: Vec<(f64, f64, f64)> = run("siemens-840d", main, &files)
            .unwrap_or_else(|a| panic!("{a}"))
            .iter()
            .filter_map(|b| b.motion.map(|m| (m.end[0], m.end[1], m.end[2])))
            .collect();
        // After X10 and Y10 (not after M3, not after the moves of DRILL, not after X20).
        let want = [
            (0.0, 0.0, 2.0),
            (10.0, 0.0, 2.0),
            (10.0, 0.0, -5.0),
            (10.0, 0.0, 2.0),
            (10.0, 10.0, 2.0),
            (10.0, 10.0, -5.0),
            (10.0, 10.0, 2.0),
            (20.0, 10.0, 2.0),
        ];
        assert_eq!(zs, want);
    }

    #[test]
    fn a_missing_program_is_14011_at_the_call_naming_where_softnc_looked() {
        let a = run("siemens-840d", "G0 X0\nN20 POCKET1 P2\n", &[]).unwrap_err();
        assert_eq!((a.code, a.line, a.col), (AlarmCode::MissingProgram, 2, 5));
        assert!(a.message.contains("POCKET1.SPF or POCKET1.MPF"), "{a}");
        assert!(a.message.contains("program.search_path"), "{a}");
        let a = alarm("siemens-840d", "_N_POCKET1_SPF\n", &[("POCKET1.MPF", "")]);
        assert_eq!(a, (AlarmCode::MissingProgram, "main.mpf".into(), 1, 1));
        assert!(run("siemens-840d", "_N_POCKET1_MPF\n", &[("pocket1.mpf", "")]).is_ok());
    }

    #[test]
    fn recursion_ends_at_the_program_levels() {
        let sub = [("DEEP.SPF", "R1=R1+1\nDEEP\n")];
        // 840D: main + 15 subprogram levels; the 16th call is refused in the subprogram.
        let a = run("siemens-840d", "DEEP\n", &sub).unwrap_err();
        assert_eq!(
            (a.code, a.program.as_str(), a.line, a.col),
            (AlarmCode::CallNesting, "lib/DEEP.SPF", 2, 1)
        );
        assert!(a.message.contains("16 program levels"), "{a}");
        let a = run("siemens-808d", "DEEP\nG0 X=R1\n", &sub).unwrap_err();
        assert!(a.message.contains("8 program levels"), "{a}");
        // R parameters are global: 7 levels ran before the refusal.
        let b = run(
            "siemens-808d",
            "R1=0\nDEEPER\n",
            &[("DEEPER.SPF", "R1=R1+1\nIF R1<7\nDEEPER\nENDIF\nG0 X=R1\n")],
        )
        .unwrap();
        let xs: Vec<f64> = b
            .iter()
            .filter_map(|b| b.motion.map(|m| m.end[0]))
            .collect();
        assert_eq!(xs, [7.0; 7]);
    }

    #[test]
    fn a_called_program_is_read_whole_before_it_runs() {
        let sub = [("OPEN_IF.SPF", "G1 X1 F100\n  IF R1>0\nX2\nM17\n")];
        let a = run("siemens-840d", "G0 X0\nOPEN_IF\n", &sub).unwrap_err();
        assert_eq!(
            (a.code, a.program.as_str(), a.line, a.col),
            (AlarmCode::ControlNesting, "lib/OPEN_IF.SPF", 2, 3)
        );
        let proc_late = [("LATE.SPF", "G0 X1\nPROC LATE\n")];
        let a = alarm("siemens-840d", "LATE\n", &proc_late);
        assert_eq!(a, (AlarmCode::Syntax, "lib/LATE.SPF".into(), 2, 1));
        let other = [("NAMED.SPF", "; named\nN5 PROC OTHER\n")];
        let a = alarm("siemens-840d", "NAMED\n", &other);
        assert_eq!(a, (AlarmCode::Syntax, "lib/NAMED.SPF".into(), 2, 9));
    }

    #[test]
    fn var_parameters_need_variables() {
        let sub = [(
            "SET_IT.SPF",
            "PROC SET_IT(VAR REAL OUT, REAL IN)\nOUT=IN*2\n",
        )];
        let a = alarm("siemens-840d", "R1=1\nSET_IT(R1+1, 2)\n", &sub);
        assert_eq!(
            a,
            (AlarmCode::ParameterNotVariable, "main.mpf".into(), 2, 8)
        );
        let a = alarm("siemens-840d", "SET_IT(, 2)\n", &sub);
        assert_eq!(
            a,
            (AlarmCode::ParameterNotVariable, "main.mpf".into(), 1, 8)
        );
        let a = alarm("siemens-840d", "SET_IT\n", &sub);
        assert_eq!(
            a,
            (AlarmCode::ParameterNotVariable, "main.mpf".into(), 1, 1)
        );
        let a = alarm("siemens-840d", "SET_IT(NOPE, 2)\n", &sub);
        assert_eq!(a, (AlarmCode::UndefinedName, "main.mpf".into(), 1, 8));
        let a = alarm("siemens-840d", "SET_IT(R1, 2, 3)\n", &sub);
        assert_eq!(a, (AlarmCode::Syntax, "main.mpf".into(), 1, 15));
        // A VAR parameter passes its own variable on; R[expr] is a variable.
        let pass = [
            (
                "SET_IT.SPF",
                "PROC SET_IT(VAR REAL OUT, REAL IN)\nOUT=IN*2\n",
            ),
            ("OUTER.SPF", "PROC OUTER(VAR REAL VV)\nSET_IT(VV, 21)\n"),
        ];
        let main = "DEF REAL KEEP\nOUTER(KEEP)\nR2=3\nSET_IT(R[R2], 4)\nG0 X=KEEP Y=R3\n";
        assert_eq!(ends("siemens-840d", main, &pass), [(42.0, 8.0)]);
    }

    #[test]
    fn each_level_has_its_own_variables() {
        let sub = [("LOCAL.SPF", "DEF REAL AA=5\nG0 X=AA\n")];
        // The main program's AA is not the subprogram's; its own DEF is no second definition.
        let main = "DEF REAL AA=1\nLOCAL\nLOCAL\nG0 X=AA\n";
        assert_eq!(
            ends("siemens-840d", main, &sub),
            [(5.0, 0.0), (5.0, 0.0), (1.0, 0.0)]
        );
        let peek = [("PEEK.SPF", "G0 X=AA\n")];
        let a = alarm("siemens-840d", "DEF REAL AA=1\nPEEK\n", &peek);
        assert_eq!(a, (AlarmCode::UndefinedName, "lib/PEEK.SPF".into(), 1, 6));
    }

    #[test]
    fn a_call_stands_alone_and_other_names_stay_what_they_were() {
        let sub = [("SUB1.SPF", "G0 X1\n")];
        let a = alarm("siemens-840d", "L10 X5\n", &[("L10.SPF", "")]);
        assert_eq!(a, (AlarmCode::Syntax, "main.mpf".into(), 1, 5));
        let a = alarm("siemens-840d", "SUB1 X5\n", &sub);
        assert_eq!(a, (AlarmCode::UndefinedName, "main.mpf".into(), 1, 1));
        // Words of the language alone are no calls: KONT chooses the approach, KONTC is
        // not built (12580).
        assert!(run("siemens-840d", "KONT\n", &[]).is_ok());
        let a = alarm("siemens-840d", "KONTC\n", &[]);
        assert_eq!(a.0, AlarmCode::NotSupported);
        assert!(run("siemens-840d", "TRANS\nDIAMON\n", &[]).is_ok());
        let a = alarm("siemens-840d", "SUB1 P0\n", &sub);
        assert_eq!(a, (AlarmCode::BadNumber, "main.mpf".into(), 1, 6));
        // EXTERN declares; PROC of the main program gives it parameters of 0.
        let main = "PROC MAIN(REAL START)\nEXTERN SUB1(REAL, VAR INT)\nG0 Y=START\nSUB1\n";
        assert_eq!(ends("siemens-840d", main, &sub), [(0.0, 0.0), (1.0, 0.0)]);
    }
}
