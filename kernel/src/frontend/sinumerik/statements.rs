//! SINUMERIK statements (Job planning, "Flexible NC programming"; docs/sinumerik.md): the
//! control structures run through the links [`Structure`] found before the program started,
//! the jumps GOTOF/GOTOB/GOTO/GOTOC to labels and block numbers, DEF, STOPRE, MSG and SETAL,
//! and assignments to R parameters and user variables among a block's words.

use super::super::fault::{fault, Fault, R};
use super::super::interpreter::Interpreter;
use super::super::lexer::Cursor;
use super::expr::{self, identifier, r_number, truthy};
use super::structure::{Link, Mark, Structure};
use super::{Store, Type, MAX_ELEMENTS};
use crate::alarm::AlarmCode;

/// The words that start a statement block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Keyword {
    If,
    Else,
    EndIf,
    While,
    EndWhile,
    For,
    EndFor,
    Repeat,
    Until,
    Loop,
    EndLoop,
    GotoF,
    GotoB,
    Goto,
    GotoC,
    Def,
    Stopre,
    Msg,
    Setal,
    /// A drilling cycle call (CYCLE81 … CYCLE89, CYCLE840; cycles/mod.rs).
    Cycle,
    Case,
    Trans,
    ATrans,
    Rot,
    ARot,
    Scale,
    AScale,
    Mirror,
    AMirror,
    Proc,
    Extern,
    Mcall,
    Ret,
}

const KEYWORDS: &[(&str, Keyword)] = &[
    ("IF", Keyword::If),
    ("ELSE", Keyword::Else),
    ("ENDIF", Keyword::EndIf),
    ("WHILE", Keyword::While),
    ("ENDWHILE", Keyword::EndWhile),
    ("FOR", Keyword::For),
    ("ENDFOR", Keyword::EndFor),
    ("REPEAT", Keyword::Repeat),
    ("UNTIL", Keyword::Until),
    ("LOOP", Keyword::Loop),
    ("ENDLOOP", Keyword::EndLoop),
    ("GOTOF", Keyword::GotoF),
    ("GOTOB", Keyword::GotoB),
    ("GOTO", Keyword::Goto),
    ("GOTOC", Keyword::GotoC),
    ("DEF", Keyword::Def),
    ("STOPRE", Keyword::Stopre),
    ("MSG", Keyword::Msg),
    ("SETAL", Keyword::Setal),
    ("CASE", Keyword::Case),
    ("CYCLE81", Keyword::Cycle),
    ("CYCLE82", Keyword::Cycle),
    ("CYCLE83", Keyword::Cycle),
    ("CYCLE84", Keyword::Cycle),
    ("CYCLE840", Keyword::Cycle),
    ("CYCLE85", Keyword::Cycle),
    ("CYCLE86", Keyword::Cycle),
    ("CYCLE87", Keyword::Cycle),
    ("CYCLE88", Keyword::Cycle),
    ("CYCLE89", Keyword::Cycle),
    ("CYCLE93", Keyword::Cycle),
    ("CYCLE95", Keyword::Cycle),
    ("CYCLE97", Keyword::Cycle),
    ("TRANS", Keyword::Trans),
    ("ATRANS", Keyword::ATrans),
    ("ROT", Keyword::Rot),
    ("AROT", Keyword::ARot),
    ("SCALE", Keyword::Scale),
    ("ASCALE", Keyword::AScale),
    ("MIRROR", Keyword::Mirror),
    ("AMIRROR", Keyword::AMirror),
    ("PROC", Keyword::Proc),
    ("EXTERN", Keyword::Extern),
    ("MCALL", Keyword::Mcall),
    ("RET", Keyword::Ret),
];

impl Keyword {
    /// The statement word at the cursor (a whole word), without moving it.
    pub fn at(c: &Cursor) -> Option<Keyword> {
        if !c.peek().is_some_and(|b| b.is_ascii_alphabetic()) {
            return None;
        }
        let mut probe = *c;
        let name = expr::identifier_span(&mut probe);
        KEYWORDS
            .iter()
            .find(|k| k.0.as_bytes().eq_ignore_ascii_case(name))
            .map(|k| k.1)
    }

    pub fn text(self) -> &'static str {
        KEYWORDS.iter().find(|k| k.1 == self).map_or("?", |k| k.0)
    }

    pub fn is_structure(self) -> bool {
        matches!(
            self,
            Keyword::If
                | Keyword::Else
                | Keyword::EndIf
                | Keyword::While
                | Keyword::EndWhile
                | Keyword::For
                | Keyword::EndFor
                | Keyword::Repeat
                | Keyword::Until
                | Keyword::Loop
                | Keyword::EndLoop
        )
    }

    /// A frame statement (TRANS … AMIRROR).
    fn is_frame(self) -> bool {
        matches!(
            self,
            Keyword::Trans
                | Keyword::ATrans
                | Keyword::Rot
                | Keyword::ARot
                | Keyword::Scale
                | Keyword::AScale
                | Keyword::Mirror
                | Keyword::AMirror
        )
    }

    fn is_jump(self) -> bool {
        matches!(
            self,
            Keyword::GotoF | Keyword::GotoB | Keyword::Goto | Keyword::GotoC
        )
    }
}

/// A variable's name in a DEF and where it stands (the cursor left after it and its blanks):
/// its first two characters letters or `_`, no R parameter, function or statement.
fn def_name(c: &mut Cursor) -> R<(String, usize)> {
    c.skip_blanks();
    let name_at = c.i;
    let name = identifier(c);
    if !valid_name(&name) || Keyword::at(&Cursor::new(c.b, name_at, c.end)).is_some() {
        return Err(fault(
            AlarmCode::Syntax,
            name_at,
            format!("'{name}' is no variable name: the first two characters are letters or _, and it is no R parameter, function or statement"),
        ));
    }
    c.skip_blanks();
    Ok((name, name_at))
}

/// The `=` of an assignment (not `==`), the cursor past it.
fn assign_sign(c: &mut Cursor) -> R<()> {
    c.skip_blanks();
    if c.peek() != Some(b'=') || c.peek_at(1) == Some(b'=') {
        return Err(fault(AlarmCode::Syntax, c.i, "'=' expected"));
    }
    c.i += 1;
    Ok(())
}

/// The next byte after blanks.
fn skip_to(c: &Cursor) -> Option<u8> {
    let mut p = *c;
    p.skip_blanks();
    p.peek()
}

/// A CASE constant: a whole number, signed.
fn case_constant(c: &mut Cursor) -> R<f64> {
    let at = c.i;
    let sign = if c.peek() == Some(b'-') {
        c.i += 1;
        -1.0
    } else {
        1.0
    };
    match crate::frontend::number::parse(c.b, c.i).filter(|(n, e)| *e <= c.end && !n.has_point) {
        Some((n, next)) => {
            c.i = next;
            Ok(sign * n.value)
        }
        None => Err(fault(
            AlarmCode::Syntax,
            at,
            "a whole-number constant or DEFAULT expected",
        )),
    }
}

/// A CASE branch's jump: the word, its destination and where that stands.
fn case_jump(c: &mut Cursor) -> R<(Keyword, String, usize)> {
    c.skip_blanks();
    let Some(word) = Keyword::at(c).filter(|w| w.is_jump()) else {
        return Err(fault(
            AlarmCode::Syntax,
            c.i,
            "GOTOF, GOTOB, GOTO or GOTOC expected",
        ));
    };
    c.i += word.text().len();
    c.skip_blanks();
    let target_at = c.i;
    let target = identifier(c);
    if target.is_empty() {
        return Err(fault(
            AlarmCode::Syntax,
            target_at,
            "jump destination expected",
        ));
    }
    Ok((word, target, target_at))
}

/// Where a jump word stands in the rest of the block (`IF cond GOTOF label`), if one does.
pub fn jump_in(c: &Cursor) -> Option<usize> {
    let mut k = c.i;
    while k < c.end {
        let b = c.b[k];
        if b == b';' {
            return None;
        }
        let starts_word = k == c.i || !(c.b[k - 1].is_ascii_alphanumeric() || c.b[k - 1] == b'_');
        if starts_word && b.is_ascii_alphabetic() {
            let probe = Cursor::new(c.b, k, c.end);
            if Keyword::at(&probe).is_some_and(Keyword::is_jump) {
                return Some(k);
            }
        }
        k += 1;
    }
    None
}

/// The language's state in the interpreter: the variables, and the structure of each program
/// text that ran (index: the program's file, 0 the main program's; calls.rs `Running`).
#[derive(Clone, Debug, Default)]
pub struct Sinumerik {
    pub store: Store,
    pub structures: Vec<Option<Structure>>,
    /// The moves of an MCALL'd cycle are being handed out: the block that ends them is no
    /// move that calls again.
    pub modal_cycle_running: bool,
    /// This interpreter reads a turning cycle's contour (cycles/contour.rs): a cycle in it
    /// would read a contour again.
    pub reading_contour: bool,
}

impl Sinumerik {
    /// The main program's structure (its text is read as the program reaches it).
    fn main_structure(&mut self) -> Option<&mut Structure> {
        self.structures.first_mut().and_then(Option::as_mut)
    }

    /// The structure of program text `program`, if it was read.
    pub fn structure(&self, program: u16) -> Option<&Structure> {
        self.structures.get(program as usize)?.as_ref()
    }
}

impl Interpreter<'_> {
    /// Before the first block: the program's structures and labels (a fault names the
    /// block it belongs to).
    pub(in crate::frontend) fn read_structure(&mut self) -> R<()> {
        self.structure_pending = false;
        let end = self.src.len();
        let mut s = Structure::new(self.pos, end, self.line);
        let from = (self.pos, self.line, self.line_start);
        // The first block now (a PROC line declares parameters); the rest as it is reached.
        self.frontier = s
            .read_first_block(self.src, from)
            .map_err(|e| self.located(e))?;
        // The main program's parameters (PROC MAIN(REAL A)): no caller gives them, they are 0.
        if let Some(decl) = &s.proc {
            let params: Vec<_> = decl
                .params
                .iter()
                .map(|f| super::Param {
                    name: f.name.clone(),
                    ty: f.ty,
                    value: super::Binding::Value(0.0),
                })
                .collect();
            self.sinumerik.store.declare(&params, decl.name_at)?;
        }
        self.keep_structure(self.calls.running.program, s);
        Ok(())
    }

    /// Keeps the structure of program text `program`.
    pub(in crate::frontend) fn keep_structure(&mut self, program: u16, s: Structure) {
        let k = program as usize;
        let all = &mut self.sinumerik.structures;
        if all.len() <= k {
            all.resize_with(k + 1, || None);
        }
        all[k] = Some(s);
    }

    /// A fault of the structure read, at its block of the running program's text.
    pub(in crate::frontend) fn located(&mut self, e: super::structure::Located) -> Box<Fault> {
        let (f, line, line_start) = e;
        (self.blk_line, self.blk_line_start) = (line, line_start);
        let mut c = Cursor::new(self.src, line_start, self.src.len());
        c.skip_blanks();
        self.blk_number = super::super::block_text::read_block_number(&mut c)
            .ok()
            .flatten();
        f
    }

    /// The link of the structure word in the block at `start` of the running program: an
    /// opening word's link is known once its structure closes, so the main program's text
    /// is read on until then.
    fn link(&mut self, word: Keyword, c: &Cursor, start: usize) -> R<Option<Link>> {
        let ahead = match word {
            Keyword::If => jump_in(c).is_none(),
            _ => matches!(word, Keyword::Else | Keyword::While | Keyword::For),
        };
        if ahead {
            self.structure_until(|s| s.link(start).is_some())?;
        }
        let program = self.calls.running.program;
        Ok(self
            .sinumerik
            .structure(program)
            .and_then(|s| s.link(start)))
    }

    /// The main program's text read on to the line at `start` (before its block runs).
    #[cold]
    #[inline(never)]
    pub(in crate::frontend) fn structure_to(&mut self, start: usize) -> R<()> {
        let Some(s) = self.sinumerik.main_structure() else {
            return Ok(());
        };
        match s.read(self.src, self.frontier, start) {
            Ok(at) => {
                self.frontier = at;
                Ok(())
            }
            Err(e) => Err(self.located(e)),
        }
    }

    /// The main program's text read on, line by line, until `done` holds or it is all
    /// read (then checked: nothing may be left open). Only while the main program runs.
    fn structure_until(&mut self, done: impl Fn(&Structure) -> bool) -> R<()> {
        if self.calls.running.program != 0 {
            return Ok(());
        }
        loop {
            let Some(s) = self.sinumerik.main_structure() else {
                return Ok(());
            };
            if done(s) || s.complete() {
                return Ok(());
            }
            if self.frontier.0 >= s.end() {
                return self.structure_end();
            }
            let read = s.read(self.src, self.frontier, self.frontier.0);
            self.frontier = read.map_err(|e| self.located(e))?;
        }
    }

    /// At the main program's end: the rest of its text read and checked.
    #[cold]
    #[inline(never)]
    pub(in crate::frontend) fn structure_end(&mut self) -> R<()> {
        let at = self.frontier;
        self.frontier.0 = usize::MAX;
        let Some(s) = self.sinumerik.main_structure() else {
            return Ok(());
        };
        s.finish(self.src, at).map_err(|e| self.located(e))
    }

    /// Runs the statement block at `start` (its words from the cursor, after the number and
    /// the label); true if it produced a block (STOPRE, MSG).
    pub(in crate::frontend) fn sinumerik_statement(
        &mut self,
        mut c: Cursor,
        start: usize,
    ) -> R<bool> {
        let Some(word) = Keyword::at(&c) else {
            return self.call_block(c);
        };
        let at = c.i;
        if word == Keyword::Cycle {
            self.drilling_cycle(&mut c, at)?;
            self.end_of_statement(&mut c)?;
            return Ok(true);
        }
        c.i += word.text().len();
        let link = self.link(word, &c, start)?;
        match (word, link) {
            (Keyword::If, _) => self.if_block(&mut c, link, start, at)?,
            (Keyword::Else, Some(Link::Else { after_end })) => self.go(after_end, at, false)?,
            (Keyword::While, Some(Link::Head { after_end })) => {
                if !truthy(self.test(&mut c)?) {
                    self.go(after_end, at, false)?;
                }
            }
            (Keyword::EndWhile, Some(Link::EndWhile { head })) => self.go(head, at, true)?,
            (Keyword::For, Some(Link::Head { after_end })) => {
                self.for_start(&mut c, after_end, at)?
            }
            (Keyword::EndFor, Some(Link::EndFor { head, body })) => {
                self.for_next(head, body, at)?
            }
            (Keyword::Until, Some(Link::Back { body })) => {
                if !truthy(self.test(&mut c)?) {
                    self.go(body, at, true)?;
                }
            }
            (Keyword::EndLoop, Some(Link::Back { body })) => self.go(body, at, true)?,
            (Keyword::EndIf | Keyword::Repeat | Keyword::Loop, _) => {}
            (Keyword::GotoF | Keyword::GotoB | Keyword::Goto | Keyword::GotoC, _) => {
                self.jump(word, &mut c, start, at)?
            }
            (Keyword::Def, _) => self.define(&mut c)?,
            (Keyword::Case, _) => self.case(&mut c, start, at)?,
            (Keyword::Stopre, _) => {
                self.end_of_statement(&mut c)?;
                return self.statement_block(at, None).map(|()| true);
            }
            (Keyword::Msg, _) => return self.msg(&mut c, at).map(|()| true),
            (Keyword::Setal, _) => return Err(self.setal(&mut c, at)),
            // Read with the structure before the program ran; bound by the call.
            (Keyword::Proc, _) => {}
            (Keyword::Extern, _) => super::calls::extern_declaration(&mut c)?,
            (Keyword::Mcall, _) => self.mcall(&mut c)?,
            (Keyword::Ret, _) => {
                self.end_of_statement(&mut c)?;
                return self.ret_statement(at);
            }
            (w, _) if w.is_frame() => self.frame_statement(w, &mut c, at)?,
            _ => {
                return Err(fault(
                    AlarmCode::ControlNesting,
                    at,
                    format!("{} is not part of a control structure", word.text()),
                ))
            }
        }
        Ok(false)
    }

    /// A condition and nothing after it but a comment.
    fn test(&mut self, c: &mut Cursor) -> R<f64> {
        let v = expr::eval(c, &self.sinumerik.store)?;
        self.end_of_statement(c)?;
        Ok(v)
    }

    pub(in crate::frontend) fn end_of_statement(&self, c: &mut Cursor) -> R<()> {
        c.skip_blanks();
        match c.peek() {
            None | Some(b';') => Ok(()),
            Some(_) => Err(fault(
                AlarmCode::Syntax,
                c.i,
                "end of the statement expected",
            )),
        }
    }

    /// Reading goes on at `to`; a jump back counts against the loop budget.
    fn go(&mut self, to: Mark, at: usize, back: bool) -> R<()> {
        if back {
            self.next_pass(at)?;
        }
        (self.pos, self.line, self.line_start) = to;
        Ok(())
    }

    /// IF: the structure's branch, or the jump of `IF cond GOTOF label`.
    fn if_block(&mut self, c: &mut Cursor, link: Option<Link>, start: usize, at: usize) -> R<()> {
        if let Some(j) = jump_in(c) {
            let mut cond = Cursor::new(c.b, c.i, j);
            let v = expr::eval(&mut cond, &self.sinumerik.store)?;
            self.end_of_statement(&mut cond)?;
            let mut rest = Cursor::new(c.b, j, c.end);
            let word = Keyword::at(&rest).unwrap_or(Keyword::Goto);
            rest.i += word.text().len();
            return if truthy(v) {
                self.jump(word, &mut rest, start, j)
            } else {
                Ok(())
            };
        }
        let v = self.test(c)?;
        match link {
            Some(Link::If { otherwise }) if !truthy(v) => self.go(otherwise, at, false),
            Some(Link::If { .. }) => Ok(()),
            _ => Err(fault(
                AlarmCode::ControlNesting,
                at,
                "IF is not part of a control structure",
            )),
        }
    }

    /// `FOR var = a TO b`: the variable starts at a; a loop that does not run goes past its
    /// ENDFOR.
    fn for_start(&mut self, c: &mut Cursor, after_end: Mark, at: usize) -> R<()> {
        let (var, start, end) = self.for_head(c)?;
        self.assign(&var, start, at)?;
        // The first pass counts against the program's loop budget too.
        self.add_passes(1, at)?;
        if start > end {
            self.go(after_end, at, false)?;
        }
        Ok(())
    }

    /// ENDFOR: the variable counts up by 1 and the body runs again while it is at most the
    /// end value (read again from the FOR block).
    fn for_next(&mut self, head: Mark, body: Mark, at: usize) -> R<()> {
        let stop = self.src[head.0..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(self.src.len(), |k| head.0 + k);
        let mut c = Cursor::new(self.src, head.0, stop);
        c.skip_blanks();
        super::structure::block_number(&mut c);
        c.i += Keyword::For.text().len();
        let (var, _, end) = self.for_head(&mut c).map_err(|mut f| {
            f.at = at;
            f
        })?;
        let v = self.value_of(&var, at)? + 1.0;
        self.assign(&var, v, at)?;
        if v <= end {
            self.go(body, at, true)?;
        }
        Ok(())
    }

    /// `var = a TO b` after FOR.
    fn for_head(&mut self, c: &mut Cursor) -> R<(String, f64, f64)> {
        c.skip_blanks();
        let var = identifier(c);
        c.skip_blanks();
        if var.is_empty() || c.peek() != Some(b'=') {
            return Err(fault(
                AlarmCode::Syntax,
                c.i,
                "FOR variable = start TO end expected",
            ));
        }
        c.i += 1;
        let to =
            to_keyword(c).ok_or_else(|| fault(AlarmCode::Syntax, c.i, "TO expected in FOR"))?;
        let mut first = Cursor::new(c.b, c.i, to);
        let start = expr::eval(&mut first, &self.sinumerik.store)?;
        self.end_of_statement(&mut first)?;
        c.i = to + 2;
        let end = self.test(c)?;
        Ok((var, start, end))
    }

    /// An R parameter's or a user variable's value.
    fn value_of(&self, name: &str, at: usize) -> R<f64> {
        match r_number(name) {
            Some(n) => self.sinumerik.store.r(n, at),
            None => self.sinumerik.store.get(name, at),
        }
    }

    /// Writes an R parameter or a user variable.
    pub(in crate::frontend) fn assign(&mut self, name: &str, v: f64, at: usize) -> R<()> {
        match r_number(name) {
            Some(n) => self.sinumerik.store.set_r(n, v, at),
            None => self.sinumerik.store.set(name, v, at),
        }
    }

    /// GOTOF / GOTOB / GOTO / GOTOC to a label or a block number (`N100`).
    fn jump(&mut self, word: Keyword, c: &mut Cursor, start: usize, at: usize) -> R<()> {
        c.skip_blanks();
        let target_at = c.i;
        let target = identifier(c);
        self.end_of_statement(c)?;
        self.jump_to(word, &target, target_at, start, at)
    }

    /// `CASE(expr) OF c GOTOF dest … DEFAULT GOTOF dest` (Job planning, "Program jumps"):
    /// the first constant equal to the value picks its jump, else DEFAULT; with neither,
    /// reading goes on with the next block. The whole list is read before the jump.
    fn case(&mut self, c: &mut Cursor, start: usize, at: usize) -> R<()> {
        c.skip_blanks();
        if c.peek() != Some(b'(') {
            return Err(fault(AlarmCode::Syntax, c.i, "CASE(expression) expected"));
        }
        let v = expr::eval(c, &self.sinumerik.store)?;
        c.skip_blanks();
        if !c.keyword("OF") {
            return Err(fault(AlarmCode::Syntax, c.i, "OF expected"));
        }
        c.i += 2;
        let (mut chosen, mut default) = (None, None);
        loop {
            c.skip_blanks();
            if matches!(c.peek(), None | Some(b';')) {
                break;
            }
            let is_default = c.keyword("DEFAULT");
            let key = if is_default {
                c.i += "DEFAULT".len();
                None
            } else {
                Some(case_constant(c)?)
            };
            let branch = case_jump(c)?;
            if is_default {
                default = Some(branch);
            } else if chosen.is_none() && key == Some(v) {
                chosen = Some(branch);
            }
        }
        match chosen.or(default) {
            Some((word, target, target_at)) => self.jump_to(word, &target, target_at, start, at),
            None => Ok(()),
        }
    }

    /// Reading goes on at jump destination `target` (a label or `N…`) of `word`, searched
    /// from the block at `start`.
    fn jump_to(
        &mut self,
        word: Keyword,
        target: &str,
        target_at: usize,
        start: usize,
        at: usize,
    ) -> R<()> {
        if word != Keyword::GotoB
            && target
                .strip_prefix('N')
                .is_none_or(|n| n.parse::<u32>().is_err())
        {
            // A label ahead: the text is read on until one is known after the jump.
            self.structure_until(|s| s.labels(target).iter().any(|m| m.0 > start))?;
        }
        let program = self.calls.running.program;
        let Some(s) = self.sinumerik.structure(program) else {
            return Err(fault(
                AlarmCode::JumpTarget,
                target_at,
                "no jump destinations",
            ));
        };
        let found = match target.strip_prefix('N').and_then(|n| n.parse::<u32>().ok()) {
            Some(n) => s.numbered(self.src, n, start),
            None => {
                let marks = s.labels(target);
                super::structure::Numbered {
                    first: marks.first().copied(),
                    backward: marks.iter().rfind(|m| m.0 <= start).copied(),
                    forward: marks.iter().find(|m| m.0 > start).copied(),
                }
            }
        };
        let (forward, backward, from_start) = (found.forward, found.backward, found.first);
        let to = match word {
            Keyword::GotoF => forward,
            Keyword::GotoB => backward,
            _ => forward.or(from_start),
        };
        match to {
            Some(m) => self.go(m, at, m.0 <= start),
            None if word == Keyword::GotoC => Ok(()),
            None if target.is_empty() => Err(fault(
                AlarmCode::Syntax,
                target_at,
                "jump destination expected",
            )),
            None => Err(fault(
                AlarmCode::JumpTarget,
                target_at,
                format!(
                    "jump destination {target} not found ({} searches {})",
                    word.text(),
                    match word {
                        Keyword::GotoF => "forward",
                        Keyword::GotoB => "backward",
                        _ => "forward, then from the program's start",
                    }
                ),
            )),
        }
    }

    /// `DEF INT I, J=2`: user variables. Run again (a jump back before it) it starts the
    /// variables afresh.
    fn define(&mut self, c: &mut Cursor) -> R<()> {
        c.skip_blanks();
        let ty_at = c.i;
        let ty_name = identifier(c);
        if ty_name == "STRING" {
            return self.string_definition(c);
        }
        let ty = Type::of(&ty_name).ok_or_else(|| {
            fault(
                AlarmCode::NotSupported,
                ty_at,
                format!("DEF {ty_name}: the types are INT, REAL, BOOL, CHAR, STRING and AXIS (FRAME is not built)"),
            )
        })?;
        loop {
            let (name, name_at) = def_name(c)?;
            if c.peek() == Some(b'[') {
                self.array_definition(c, &name, ty, name_at)?;
            } else {
                let mut v = if ty == Type::Axis { -1.0 } else { 0.0 };
                if c.peek() == Some(b'=') {
                    c.i += 1;
                    v = if ty == Type::Axis {
                        self.axis_value(c)?
                    } else {
                        expr::eval(c, &self.sinumerik.store)?
                    };
                }
                self.sinumerik.store.define(&name, ty, v, name_at)?;
            }
            c.skip_blanks();
            match c.peek() {
                Some(b',') => c.i += 1,
                _ => break,
            }
        }
        self.end_of_statement(c)
    }

    /// `NAME[d1, d2, d3]` with `=SET(v, …)` (the first elements, row by row) or `=REP(v)`
    /// (every element) or nothing (zeros): Job planning, "Definition and initialization of
    /// array variables".
    fn array_definition(&mut self, c: &mut Cursor, name: &str, ty: Type, at: usize) -> R<()> {
        let dims_at = c.i;
        let mut dims = heapless::Vec::new();
        for d in expr::indices(c, &self.sinumerik.store)? {
            if d < 1.0 || d.fract() != 0.0 {
                return Err(fault(
                    AlarmCode::BadNumber,
                    dims_at,
                    format!("array dimension {d}: a whole number ≥ 1"),
                ));
            }
            let _ = dims.push(d.min(1e9) as usize);
        }
        let n = dims
            .iter()
            .try_fold(1usize, |n, &d| n.checked_mul(d))
            .filter(|&n| n <= MAX_ELEMENTS);
        let Some(n) = n else {
            return Err(fault(
                AlarmCode::NotSupported,
                dims_at,
                format!("more than {MAX_ELEMENTS} elements in one array"),
            ));
        };
        let mut start = vec![0.0; n];
        c.skip_blanks();
        if c.peek() == Some(b'=') {
            c.i += 1;
            c.skip_blanks();
            let (rep, list_at) = (c.keyword("REP"), c.i);
            if !(rep || c.keyword("SET")) {
                return Err(fault(
                    AlarmCode::Syntax,
                    c.i,
                    "SET(values) or REP(value) expected",
                ));
            }
            c.i += 3;
            let values = self.value_list(c)?;
            match (rep, values.as_slice()) {
                (true, [v]) => start.fill(*v),
                (false, v) if v.len() <= n => start[..v.len()].copy_from_slice(v),
                _ => {
                    return Err(fault(
                        AlarmCode::Syntax,
                        list_at,
                        format!("REP takes one value, SET at most {n}"),
                    ))
                }
            }
        }
        let array = super::Array::new(dims, start.into_boxed_slice());
        self.sinumerik.store.define_array(name, ty, array, at)
    }

    /// `DEF STRING[n] NAME="text", …` (Job planning, "Variable types": at most n
    /// characters, n from 1 to 200 **[unconfirmed]**).
    fn string_definition(&mut self, c: &mut Cursor) -> R<()> {
        c.skip_blanks();
        let len_at = c.i;
        let max = match c.peek() {
            Some(b'[') => expr::indices(c, &self.sinumerik.store)?,
            _ => return Err(fault(AlarmCode::Syntax, len_at, "STRING[length] expected")),
        };
        let max = match max.as_slice() {
            [n] if (1.0..=200.0).contains(n) && n.fract() == 0.0 => *n as usize,
            _ => {
                return Err(fault(
                    AlarmCode::BadNumber,
                    len_at,
                    "a STRING's length is 1 … 200",
                ))
            }
        };
        loop {
            let (name, name_at) = def_name(c)?;
            let mut text = String::new();
            if c.peek() == Some(b'=') {
                c.i += 1;
                text = self.string_expr(c)?;
            }
            self.sinumerik
                .store
                .define_string(&name, max, text, name_at)?;
            c.skip_blanks();
            match c.peek() {
                Some(b',') => c.i += 1,
                _ => break,
            }
        }
        self.end_of_statement(c)
    }

    /// A string: texts `"…"`, STRING variables and numbers joined by `<<` (Job planning,
    /// "String operations"; a number as written shortest: 5, 2.5 **[unconfirmed]**).
    pub(in crate::frontend) fn string_expr(&mut self, c: &mut Cursor) -> R<String> {
        let mut out = String::new();
        loop {
            c.skip_blanks();
            if c.peek() == Some(b'"') {
                out.push_str(&quoted(c)?);
            } else {
                let mut probe = *c;
                let name = identifier(&mut probe);
                let store = &self.sinumerik.store;
                // A CHAR variable alone is its character; in arithmetic (`CC+1`), its code.
                let alone = matches!(skip_to(&probe), None | Some(b')' | b';' | b',' | b'<'));
                match (store.string(&name), store.char_of(&name).filter(|_| alone)) {
                    (Some(t), _) => {
                        out.push_str(t);
                        *c = probe;
                    }
                    (None, Some(ch)) => {
                        out.push(ch);
                        *c = probe;
                    }
                    (None, None) => {
                        let v = expr::eval_term(c, &self.sinumerik.store)?;
                        out.push_str(&format!("{v}"));
                    }
                }
            }
            c.skip_blanks();
            if (c.peek(), c.peek_at(1)) != (Some(b'<'), Some(b'<')) {
                return Ok(out);
            }
            c.i += 2;
        }
    }

    /// An axis for an AXIS variable: the name of an axis of the machine (`X`, `C`) or another
    /// AXIS variable; its place in the machine's axis names.
    fn axis_value(&mut self, c: &mut Cursor) -> R<f64> {
        let letter = self.axis_name(c)?;
        let k = crate::machine_data::AXIS_NAMES
            .iter()
            .position(|&n| n as u8 == letter);
        Ok(k.map_or(-1.0, |k| k as f64))
    }

    /// An axis as written: its letter, or an AXIS variable's (Job planning, "AXIS").
    pub(in crate::frontend) fn axis_name(&mut self, c: &mut Cursor) -> R<u8> {
        c.skip_blanks();
        let at = c.i;
        let name = identifier(c);
        if let Some(axis) = self.sinumerik.store.axis_of(&name) {
            return axis.ok_or_else(|| {
                fault(
                    AlarmCode::UndefinedName,
                    at,
                    format!("{name} names no axis yet"),
                )
            });
        }
        match name.as_bytes() {
            [l] if self.md.axes.of_letter(*l).is_some() => Ok(*l),
            _ => Err(fault(
                AlarmCode::UnknownAddress,
                at,
                format!("{name} is no axis of this machine"),
            )),
        }
    }

    /// `AX[axis]=value` (Fundamentals, "Axial addresses"): the axis word of the axis an
    /// AXIS variable or a letter names, with AC/IC as on the letter itself.
    pub(in crate::frontend) fn axial_address(
        &mut self,
        c: &mut Cursor,
        w: &mut super::super::words::Words,
        at: usize,
    ) -> R<()> {
        c.i += 2;
        c.skip_blanks();
        if c.peek() != Some(b'[') {
            return Err(fault(AlarmCode::Syntax, c.i, "AX[axis] expected"));
        }
        c.i += 1;
        let letter = self.axis_name(c)?;
        c.skip_blanks();
        if c.peek() != Some(b']') {
            return Err(fault(AlarmCode::Syntax, c.i, "']' expected"));
        }
        c.i += 1;
        c.skip_blanks();
        if c.peek() != Some(b'=') {
            return Err(fault(AlarmCode::Syntax, c.i, "'=' expected"));
        }
        self.sinumerik_word(c, w, letter, at)
    }

    /// `(v1, v2, …)`: expressions (at most [`MAX_ELEMENTS`]).
    fn value_list(&mut self, c: &mut Cursor) -> R<Vec<f64>> {
        c.skip_blanks();
        if c.peek() != Some(b'(') {
            return Err(fault(AlarmCode::Syntax, c.i, "'(' expected"));
        }
        c.i += 1;
        let mut out = Vec::new();
        loop {
            out.push(expr::eval(c, &self.sinumerik.store)?);
            c.skip_blanks();
            match c.peek() {
                Some(b',') if out.len() < MAX_ELEMENTS => c.i += 1,
                Some(b')') => {
                    c.i += 1;
                    return Ok(out);
                }
                _ => return Err(fault(AlarmCode::Syntax, c.i, "',' or ')' expected")),
            }
        }
    }

    /// A block of its own for the statement at `at`: STOPRE stops preprocessing there, MSG
    /// carries its text (the operator's message, warning 65001).
    pub(in crate::frontend) fn statement_block(
        &mut self,
        at: usize,
        message: Option<Box<str>>,
    ) -> R<()> {
        let col = super::super::lexer::column(self.src, self.blk_line_start, at);
        let (line, number, program) = (self.blk_line, self.blk_number, self.block.program);
        self.empty_block_at(line, col, number);
        self.block.program = program;
        self.block.preprocess_stop = message.is_none();
        self.block.message = message;
        Ok(())
    }

    /// `MSG("text")`: the text as the block's message; `MSG()` clears it (nothing to show).
    fn msg(&mut self, c: &mut Cursor, at: usize) -> R<()> {
        c.skip_blanks();
        if c.peek() != Some(b'(') {
            return Err(fault(AlarmCode::Syntax, c.i, "'(' expected"));
        }
        c.i += 1;
        c.skip_blanks();
        let text = if c.peek() == Some(b')') {
            String::new()
        } else {
            self.string_expr(c)?
        };
        c.skip_blanks();
        if c.peek() != Some(b')') {
            return Err(fault(AlarmCode::Syntax, c.i, "')' expected"));
        }
        c.i += 1;
        self.end_of_statement(c)?;
        self.statement_block(at, None)?;
        self.block.preprocess_stop = false;
        if !text.is_empty() {
            self.block.message = Some(text.into());
        }
        Ok(())
    }

    /// `SETAL(n)`: the program raises alarm n (Job planning: user range 60000 … 69999).
    fn setal(&mut self, c: &mut Cursor, at: usize) -> Box<Fault> {
        c.skip_blanks();
        if c.peek() != Some(b'(') {
            return fault(AlarmCode::Syntax, c.i, "SETAL(alarm number) expected");
        }
        let n = match expr::eval(c, &self.sinumerik.store) {
            Ok(v) => v,
            Err(f) => return f,
        };
        if !(60000.0..=69999.0).contains(&n) || n.fract() != 0.0 {
            return fault(
                AlarmCode::BadNumber,
                at,
                format!("SETAL({n}): the cycle alarms are 60000 … 69999"),
            );
        }
        fault(
            AlarmCode::ProgramAlarm,
            at,
            format!("SETAL({n}): alarm {n} set by the program"),
        )
    }
}

/// A user variable's name: its first two characters letters or `_` (Fundamentals, "Names"),
/// no R parameter, no function, no constant.
pub fn valid_name(name: &str) -> bool {
    let b = name.as_bytes();
    b.len() >= 2
        && b[..2].iter().all(|c| c.is_ascii_alphabetic() || *c == b'_')
        && r_number(name).is_none()
        && !expr::is_reserved(name)
}

/// The byte offset of the word TO in `c`'s rest, if it stands there as a word.
fn to_keyword(c: &Cursor) -> Option<usize> {
    let mut k = c.i;
    while k + 1 < c.end {
        let before = k == c.i || !(c.b[k - 1].is_ascii_alphanumeric() || c.b[k - 1] == b'_');
        let after =
            c.b.get(k + 2)
                .is_none_or(|b| !(b.is_ascii_alphanumeric() || *b == b'_'));
        if before
            && after
            && c.b[k].eq_ignore_ascii_case(&b'T')
            && c.b[k + 1].eq_ignore_ascii_case(&b'O')
        {
            return Some(k);
        }
        k += 1;
    }
    None
}

/// `"text"` at the cursor (on the opening quote): the text.
fn quoted(c: &mut Cursor) -> R<String> {
    let open = c.i;
    c.i += 1;
    let from = c.i;
    while c.peek().is_some_and(|b| b != b'"') {
        c.i += 1;
    }
    if c.peek() != Some(b'"') {
        return Err(fault(
            AlarmCode::Syntax,
            open,
            "string not closed with '\"'",
        ));
    }
    let text = String::from_utf8_lossy(&c.b[from..c.i]).into_owned();
    c.i += 1;
    Ok(text)
}

impl Interpreter<'_> {
    /// `R1=…` or `NAME=…` (a user variable) at the cursor among a block's words: assigned,
    /// and true; false if the text is no assignment.
    pub(in crate::frontend) fn sinumerik_assignment(
        &mut self,
        c: &mut Cursor,
        w: &mut super::super::words::Words,
        at: usize,
    ) -> R<bool> {
        let mut probe = *c;
        // Most words are no assignment: told from the bytes, nothing allocated.
        let span = expr::identifier_span(&mut probe);
        let r_like =
            matches!(span.first(), Some(b'R' | b'r')) && span[1..].iter().all(u8::is_ascii_digit);
        if !r_like && !self.sinumerik.store.has_name(span) {
            return Ok(false);
        }
        let name = String::from_utf8_lossy(span).to_ascii_uppercase();
        if self.sinumerik.store.string(&name).is_some() {
            assign_sign(&mut probe)?;
            let text = self.string_expr(&mut probe)?;
            self.sinumerik.store.set_string(&name, text, at)?;
            *c = probe;
            w.calculation = true;
            return Ok(true);
        }
        if self.sinumerik.store.axis_of(&name).is_some() {
            assign_sign(&mut probe)?;
            let v = self.axis_value(&mut probe)?;
            self.sinumerik.store.set(&name, v, at)?;
            *c = probe;
            w.calculation = true;
            return Ok(true);
        }
        if probe.peek() == Some(b'[') && self.sinumerik.store.is_array(&name) {
            let idx = expr::indices(&mut probe, &self.sinumerik.store)?;
            assign_sign(&mut probe)?;
            let v = expr::eval(&mut probe, &self.sinumerik.store)?;
            self.sinumerik.store.set_element(&name, &idx, v, at)?;
            *c = probe;
            w.calculation = true;
            return Ok(true);
        }
        let index = if name == "R" && probe.peek() == Some(b'[') {
            probe.i += 1;
            let n = expr::eval(&mut probe, &self.sinumerik.store)?;
            probe.skip_blanks();
            if probe.peek() != Some(b']') {
                return Err(fault(AlarmCode::Syntax, probe.i, "']' expected"));
            }
            probe.i += 1;
            Some(expr::index(n, at)?)
        } else {
            None
        };
        probe.skip_blanks();
        if probe.peek() != Some(b'=') || probe.peek_at(1) == Some(b'=') {
            return Ok(false);
        }
        probe.i += 1;
        let v = expr::eval(&mut probe, &self.sinumerik.store)?;
        match index {
            Some(n) => self.sinumerik.store.set_r(n, v, at)?,
            None => self.assign(&name, v, at)?,
        }
        *c = probe;
        w.calculation = true;
        Ok(true)
    }

    /// `X=expr`, `X=AC(expr)`, `X=IC(expr)` (the cursor on the `=`): the word with its value;
    /// AC and IC make this axis absolute or incremental in this block only, and `I=AC(…)` a
    /// centre coordinate absolute (Fundamentals, "Absolute and incremental dimensions").
    pub(in crate::frontend) fn sinumerik_word(
        &mut self,
        c: &mut Cursor,
        w: &mut super::super::words::Words,
        letter: u8,
        at: usize,
    ) -> R<()> {
        c.i += 1;
        c.skip_blanks();
        let mode = super::words::dimension_mode(c);
        let value = expr::eval(c, &self.sinumerik.store)?;
        match (mode, letter) {
            (None, _) => {}
            (Some(m), b'X'..=b'Z') => {
                let bit = 1u8 << (letter - b'X');
                if m == b'I' {
                    w.incremental |= bit;
                } else {
                    w.absolute |= bit;
                }
            }
            // I J K are offsets from the start: IC() is what they are anyway.
            (Some(m), b'I'..=b'K') => {
                if m == b'A' {
                    w.centre_absolute |= 1 << (letter - b'I');
                }
            }
            (Some(_), _) => {
                return Err(fault(
                    AlarmCode::NotSupported,
                    at,
                    "AC()/IC() on an address other than X, Y, Z, I, J, K",
                ));
            }
        }
        let v = super::super::words::checked(super::super::words::Val::computed(value, at))?;
        self.word(w, letter, v, at)
    }
}
