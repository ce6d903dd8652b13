//! A program's PROC line (Job planning, "Subprogram technique", "Parameter transfer"):
//! `PROC NAME(REAL A, INT B, VAR REAL C)` as the program's first block names the program and
//! its formal parameters, with its type before each; `VAR` makes a parameter call-by-reference.
//! It is read with the program's structure (structure.rs), before the program runs, so that
//! a call can bind its actual parameters before it enters the program.

use super::super::fault::{fault, R};
use super::super::lexer::Cursor;
use super::expr::{identifier, identifier_span};
use super::statements::Keyword;
use super::Type;
use crate::alarm::AlarmCode;

/// A formal parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Formal {
    pub name: Box<str>,
    pub ty: Type,
    /// `VAR`: the actual parameter must be a variable, which the program reads and writes.
    pub by_ref: bool,
}

/// A program's PROC line: its name and formal parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct ProcDecl {
    pub name: Box<str>,
    /// Where the name stands (for an alarm about it), and the line and line start of the
    /// PROC block.
    pub name_at: usize,
    pub line: (u32, usize),
    pub params: Vec<Formal>,
}

/// Attributes after the parameter list that only concern the display and single block:
/// accepted and without effect here.
const DISPLAY_ONLY: &[&str] = &["DISPLOF", "DISPLON", "SBLOF", "SBLON", "ACTBLOCNO"];

/// More formal parameters than this are refused (a bound on the list).
pub const MAX_PARAMS: usize = 64;

/// The PROC line's rest, after the keyword: the name, the parameters, the attributes.
pub fn read(c: &mut Cursor) -> R<ProcDecl> {
    c.skip_blanks();
    let name_at = c.i;
    let name = identifier(c);
    if !super::statements::valid_name(&name) && !is_l_name(&name) {
        return Err(fault(
            AlarmCode::Syntax,
            name_at,
            "PROC needs the program's name",
        ));
    }
    c.skip_blanks();
    let mut params = Vec::new();
    if c.peek() == Some(b'(') {
        c.i += 1;
        params = formals(c)?;
    }
    attributes(c)?;
    Ok(ProcDecl {
        name: name.into(),
        name_at,
        line: (0, 0),
        params,
    })
}

/// `L123`: a DIN-style program name (Fundamentals, "Subprogram names").
pub fn is_l_name(name: &str) -> bool {
    name.strip_prefix('L')
        .is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
}

/// The formal parameters up to the closing bracket (the opening one is read).
fn formals(c: &mut Cursor) -> R<Vec<Formal>> {
    let mut out: Vec<Formal> = Vec::new();
    c.skip_blanks();
    if c.peek() == Some(b')') {
        c.i += 1;
        return Ok(out);
    }
    loop {
        c.skip_blanks();
        let at = c.i;
        let f = formal(c)?;
        if out.iter().any(|o| o.name == f.name) {
            let message = format!("parameter {} is defined twice", f.name);
            return Err(fault(AlarmCode::Syntax, at, message));
        }
        if out.len() >= MAX_PARAMS {
            let message = format!("more than {MAX_PARAMS} parameters");
            return Err(fault(AlarmCode::NotSupported, at, message));
        }
        out.push(f);
        c.skip_blanks();
        match c.peek() {
            Some(b',') => c.i += 1,
            Some(b')') => {
                c.i += 1;
                return Ok(out);
            }
            _ => return Err(fault(AlarmCode::Syntax, c.i, "',' or ')' expected")),
        }
    }
}

/// `[VAR] type name`.
fn formal(c: &mut Cursor) -> R<Formal> {
    c.skip_blanks();
    let by_ref = c.keyword("VAR");
    if by_ref {
        c.i += 3;
        c.skip_blanks();
    }
    let ty_at = c.i;
    let ty_name = identifier(c);
    // AXIS parameters would take an axis name at the call, not a value: not built.
    let ty = Type::of(&ty_name)
        .filter(|t| *t != Type::Axis)
        .ok_or_else(|| {
            let message =
                format!("parameter type {ty_name}: the types are INT, REAL, BOOL and CHAR");
            let code = if ty_name.is_empty() {
                AlarmCode::Syntax
            } else {
                AlarmCode::NotSupported
            };
            fault(code, ty_at, message)
        })?;
    c.skip_blanks();
    let name_at = c.i;
    let name = identifier(c);
    if !super::statements::valid_name(&name)
        || Keyword::at(&Cursor::new(c.b, name_at, c.end)).is_some()
    {
        let message = format!("'{name}' is no parameter name: the first two characters are letters or _, and it is no R parameter, function or statement");
        return Err(fault(AlarmCode::Syntax, name_at, message));
    }
    c.skip_blanks();
    if c.peek() == Some(b'[') {
        let message = "array parameters are not supported";
        return Err(fault(AlarmCode::NotSupported, c.i, message));
    }
    Ok(Formal {
        name: name.into(),
        ty,
        by_ref,
    })
}

/// What may follow the parameters: display attributes, a comment.
fn attributes(c: &mut Cursor) -> R<()> {
    loop {
        c.skip_blanks();
        match c.peek() {
            None | Some(b';') => return Ok(()),
            Some(b) if b.is_ascii_alphabetic() => {
                let at = c.i;
                let word = identifier_span(c);
                if DISPLAY_ONLY
                    .iter()
                    .any(|w| w.as_bytes().eq_ignore_ascii_case(word))
                {
                    continue;
                }
                let word = String::from_utf8_lossy(word).to_ascii_uppercase();
                let message = format!(
                    "PROC … {word} is not supported (SAVE and the other attributes are not built)"
                );
                return Err(fault(AlarmCode::NotSupported, at, message));
            }
            Some(_) => {
                return Err(fault(
                    AlarmCode::Syntax,
                    c.i,
                    "end of the PROC line expected",
                ))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decl(text: &str) -> R<ProcDecl> {
        let mut c = Cursor::new(text.as_bytes(), 0, text.len());
        read(&mut c)
    }

    #[test]
    fn proc_lines_name_the_program_and_its_parameters() {
        let d = decl(" POCKET_A(REAL LEN, int cnt, VAR REAL LAST) DISPLOF ; note").unwrap();
        assert_eq!((&*d.name, d.name_at), ("POCKET_A", 1));
        let got: Vec<_> = d
            .params
            .iter()
            .map(|f| (&*f.name, f.ty, f.by_ref))
            .collect();
        assert_eq!(
            got,
            [
                ("LEN", Type::Real, false),
                ("CNT", Type::Int, false),
                ("LAST", Type::Real, true)
            ]
        );
        assert!(decl(" L123").unwrap().params.is_empty());
        assert!(decl(" TOP()").unwrap().params.is_empty());
    }

    #[test]
    fn bad_proc_lines_are_alarms_at_their_word() {
        let code = |t: &str| decl(t).map(|_| ()).map_err(|f| (f.code, f.at));
        assert_eq!(code(" 12AB"), Err((AlarmCode::Syntax, 1)));
        assert_eq!(code(" PP(REAL AB, REAL AB)"), Err((AlarmCode::Syntax, 13)));
        assert_eq!(code(" PP(STRING[8] S)"), Err((AlarmCode::NotSupported, 4)));
        assert_eq!(code(" PP(REAL R1)"), Err((AlarmCode::Syntax, 9)));
        assert_eq!(code(" PP(REAL AB[3])"), Err((AlarmCode::NotSupported, 11)));
        assert_eq!(
            code(" PP(REAL AB) SAVE"),
            Err((AlarmCode::NotSupported, 13))
        );
        assert_eq!(code(" PP(REAL AB"), Err((AlarmCode::Syntax, 11)));
    }
}
