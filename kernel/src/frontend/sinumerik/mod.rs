//! The SINUMERIK language of the 808D, 828D and 840D sl (Programming Manual Fundamentals and
//! Job planning; docs/sinumerik.md): R parameters and user variables (`DEF`), expressions in
//! addresses (`X=R1+5`), control structures (IF/ELSE/ENDIF, WHILE, FOR, REPEAT, LOOP), jump
//! labels and GOTOF/GOTOB/GOTO/GOTOC, subprograms (calls by name, PROC, MCALL, RET).
//!
//! - [`expr`]: arithmetic, comparisons, logic and the functions.
//! - [`statements`]: the statements and assignments, run as the interpreter reaches them.
//! - [`frames`]: the frame statements TRANS, ROT, SCALE, MIRROR and their additive forms.
//! - [`structure`]: the control structures of a whole program, matched before it starts.
//! - [`words`]: the path words of more than one letter (CIP, CT, AP=, RP=, TURN=, RNDM= …).
//! - [`procs`]: a program's PROC line, read with its structure.
//! - [`calls`]: subprogram calls (also the 840C's `L123 P3`), MCALL, RET.
//! - [`compensation`]: NORM, KONT, DISC= and the smooth approach's DISR=, DISCL=, DISRP=,
//!   FAD= among a block's words; [`approach`]: the smooth approach's geometry.

pub(super) mod approach;
pub(super) mod calls;
pub(super) mod compensation;
pub(super) mod cycles;
pub(super) mod expr;
mod frames;
pub(super) mod procs;
pub(super) mod statements;
pub(super) mod structure;
pub(super) mod system;
pub(super) mod words;

use super::fault::{fault, R};
use crate::alarm::AlarmCode;

/// A user variable's or parameter's type (Job planning, "Definition of user variables (DEF)").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Type {
    Int,
    Real,
    Bool,
    /// One character, held as its code 0 … 255 (Job planning, "Variable types").
    Char,
    /// An axis, held as its place in the machine's axis names (X = 0 … C = 8), −1 for none.
    Axis,
}

impl Type {
    pub fn of(word: &str) -> Option<Type> {
        match word {
            "INT" => Some(Type::Int),
            "REAL" => Some(Type::Real),
            "BOOL" => Some(Type::Bool),
            "CHAR" => Some(Type::Char),
            "AXIS" => Some(Type::Axis),
            _ => None,
        }
    }

    /// `v` converted for a variable of this type (REAL to INT rounds; not 0 is TRUE).
    fn convert(self, v: f64, at: usize) -> R<f64> {
        match self {
            Type::Real => Ok(v),
            Type::Bool => Ok((v != 0.0) as u8 as f64),
            Type::Axis => Ok(v),
            Type::Char => {
                let code = libm::round(v);
                if !(0.0..=255.0).contains(&code) {
                    return Err(fault(
                        AlarmCode::Arithmetic,
                        at,
                        format!("{v} is no character code (0 … 255)"),
                    ));
                }
                Ok(code)
            }
            Type::Int => {
                let i = libm::round(v);
                if i.abs() > 2_147_483_647.0 {
                    return Err(fault(
                        AlarmCode::Arithmetic,
                        at,
                        format!("{v} is out of the INT range"),
                    ));
                }
                Ok(i)
            }
        }
    }
}

#[derive(Clone, Debug)]
struct Variable {
    name: Box<str>,
    ty: Type,
    value: f64,
    /// Where its DEF stands: reached again, it starts the variable afresh.
    defined_at: usize,
    /// A VAR parameter: the caller's variable it stands for (reads and writes go there).
    target: Option<Ref>,
    /// An array's dimensions and elements; `None` for a single value.
    array: Option<Box<Array>>,
    /// A STRING variable's text and its most characters; `None` for a number.
    text: Option<Box<(String, usize)>>,
}

/// The elements of an array variable (Job planning, "Definition and initialization of array
/// variables"): up to three dimensions, indices from 0, stored row by row.
#[derive(Clone, Debug)]
pub struct Array {
    pub dims: heapless::Vec<usize, 3>,
    values: Box<[f64]>,
    /// The values it starts with (SET, REP or zeros): a DEF reached again restores them.
    start: Box<[f64]>,
}

/// More elements than this in one array are refused (the store's memory stays bounded).
pub const MAX_ELEMENTS: usize = 10_000;

impl Array {
    /// An array of `dims` holding `start` (its length is the product of `dims`).
    pub fn new(dims: heapless::Vec<usize, 3>, start: Box<[f64]>) -> Array {
        Array {
            dims,
            values: start.clone(),
            start,
        }
    }

    /// The element at `idx` (one index per dimension): its place in `values`.
    fn place(&self, idx: &[f64], name: &str, at: usize) -> R<usize> {
        if idx.len() != self.dims.len() {
            return Err(fault(
                AlarmCode::Syntax,
                at,
                format!(
                    "{name} has {} dimension(s), {} index(es) given",
                    self.dims.len(),
                    idx.len()
                ),
            ));
        }
        let mut k = 0;
        for (&i, &n) in idx.iter().zip(&self.dims) {
            if i < 0.0 || i.fract() != 0.0 || i >= n as f64 {
                return Err(fault(
                    AlarmCode::ArrayIndex,
                    at,
                    format!("{name}: index {i} outside 0 … {}", n - 1),
                ));
            }
            k = k * n + i as usize;
        }
        Ok(k)
    }
}

/// A variable a VAR parameter stands for (Job planning, "Parameter transfer": call by
/// reference): an R parameter, or a variable of a calling level (its index in the store).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ref {
    R(usize),
    Var(usize),
}

/// A parameter of a called program as the call binds it.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    pub name: Box<str>,
    pub ty: Type,
    pub value: Binding,
}

/// A parameter's actual value: a value (converted to the parameter's type), or a variable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Binding {
    Value(f64),
    Ref(Ref),
}

/// The R parameters and the user variables (LUD) of each program level: a called program
/// sees its own DEF variables and parameters, not its caller's; R parameters are global.
#[derive(Clone, Debug, Default)]
pub struct Store {
    /// R0 … R(count − 1); allocated at the first write (a program without R parameters
    /// allocates nothing for them).
    r: Vec<f64>,
    count: usize,
    vars: Vec<Variable>,
    /// The running level's first variable; the callers' below it.
    level: usize,
    callers: Vec<usize>,
    /// What the system variables of the block being read give (system.rs).
    pub system: Option<Box<system::SystemValues>>,
    /// A main-run variable was read: the block stops preprocessing.
    pub main_run_read: std::cell::Cell<bool>,
}

/// More user variables than this in one run are refused (a bound on a name search).
const MAX_VARIABLES: usize = 1000;

/// `defined_at` of a parameter: no DEF stands there.
const PARAMETER: usize = usize::MAX;

impl Store {
    /// `count` R parameters, R0 … R(count − 1), all 0 (machine data `program.r_parameters`).
    pub fn new(count: usize) -> Self {
        Store {
            r: Vec::new(),
            count,
            ..Store::default()
        }
    }

    pub fn r(&self, n: usize, at: usize) -> R<f64> {
        if n >= self.count {
            return Err(self.no_r(n, at));
        }
        Ok(self.r.get(n).copied().unwrap_or(0.0))
    }

    pub fn set_r(&mut self, n: usize, v: f64, at: usize) -> R<()> {
        if n >= self.count {
            return Err(self.no_r(n, at));
        }
        if self.r.is_empty() {
            self.r = vec![0.0; self.count];
        }
        self.r[n] = v;
        Ok(())
    }

    #[cold]
    fn no_r(&self, n: usize, at: usize) -> Box<super::fault::Fault> {
        fault(
            AlarmCode::UndefinedName,
            at,
            format!(
                "R{n} does not exist: R0 … R{} (machine data program.r_parameters)",
                self.count.saturating_sub(1)
            ),
        )
    }

    /// The index of the running level's variable `name` (upper case).
    fn find(&self, name: &str) -> Option<usize> {
        let k = self.vars[self.level..]
            .iter()
            .position(|v| &*v.name == name)?;
        Some(self.level + k)
    }

    #[cold]
    fn undefined(name: &str, at: usize) -> Box<super::fault::Fault> {
        fault(
            AlarmCode::UndefinedName,
            at,
            format!("{name} is not defined (DEF)"),
        )
    }

    /// The value of user variable `name`.
    pub fn get(&self, name: &str, at: usize) -> R<f64> {
        let k = self.find(name).ok_or_else(|| Self::undefined(name, at))?;
        if self.vars[k].array.is_some() {
            return Err(whole_array(name, at));
        }
        if self.vars[k].text.is_some() {
            return Err(a_string(name, at));
        }
        if self.vars[k].ty == Type::Axis {
            return Err(fault(
                AlarmCode::Syntax,
                at,
                format!(
                    "{name} is an AXIS: no number (AX[{name}]=… moves it, $P_EP[{name}] reads it)"
                ),
            ));
        }
        match self.vars[k].target {
            Some(Ref::R(n)) => self.r(n, at),
            Some(Ref::Var(i)) => Ok(self.vars.get(i).map_or(0.0, |v| v.value)),
            None => Ok(self.vars[k].value),
        }
    }

    /// Whether `name` (as written, any case) is a user variable of the running level.
    pub fn has_name(&self, name: &[u8]) -> bool {
        self.vars[self.level..]
            .iter()
            .any(|v| v.name.as_bytes().eq_ignore_ascii_case(name))
    }

    pub fn set(&mut self, name: &str, v: f64, at: usize) -> R<()> {
        let k = self.find(name).ok_or_else(|| Self::undefined(name, at))?;
        if self.vars[k].array.is_some() {
            return Err(whole_array(name, at));
        }
        if self.vars[k].text.is_some() {
            return Err(a_string(name, at));
        }
        match self.vars[k].target {
            Some(Ref::R(n)) => self.set_r(n, v, at),
            Some(Ref::Var(i)) => self.set_at(i, v, at),
            None => self.set_at(k, v, at),
        }
    }

    fn set_at(&mut self, k: usize, v: f64, at: usize) -> R<()> {
        if let Some(var) = self.vars.get_mut(k) {
            var.value = var.ty.convert(v, at)?;
        }
        Ok(())
    }

    /// The variable a VAR parameter takes for user variable `name` of the running level
    /// (a VAR parameter passes its own variable on).
    pub fn reference(&self, name: &str) -> Option<Ref> {
        let k = self
            .find(name)
            .filter(|&k| self.vars[k].array.is_none() && self.vars[k].text.is_none())?;
        Some(self.vars[k].target.unwrap_or(Ref::Var(k)))
    }

    /// A called program's level: its parameters, no other variables.
    pub fn push_level(&mut self, params: &[Param], at: usize) -> R<()> {
        self.callers.push(self.level);
        self.level = self.vars.len();
        self.declare(params, at)
    }

    /// Parameters as the running level's variables.
    pub fn declare(&mut self, params: &[Param], at: usize) -> R<()> {
        for p in params {
            let (value, target) = match p.value {
                Binding::Value(v) => (p.ty.convert(v, at)?, None),
                Binding::Ref(r) => (0.0, Some(r)),
            };
            self.add(&p.name, p.ty, value, PARAMETER, target, at)?;
        }
        Ok(())
    }

    /// Back to the caller's level: the called program's variables are gone.
    pub fn pop_level(&mut self) {
        self.vars.truncate(self.level);
        self.level = self.callers.pop().unwrap_or(0);
    }

    /// `DEF ty name = v` at `at`: a new variable (a name defined twice is an alarm; the same
    /// DEF reached again by a jump back starts it afresh).
    pub fn define(&mut self, name: &str, ty: Type, v: f64, at: usize) -> R<()> {
        if let Some(var) = self.vars[self.level..]
            .iter_mut()
            .find(|x| &*x.name == name && x.defined_at == at)
        {
            var.value = ty.convert(v, at)?;
            return Ok(());
        }
        let value = ty.convert(v, at)?;
        self.add(name, ty, value, at, None, at)
    }

    fn add(
        &mut self,
        name: &str,
        ty: Type,
        value: f64,
        defined_at: usize,
        target: Option<Ref>,
        at: usize,
    ) -> R<()> {
        if self.has_name(name.as_bytes()) {
            return Err(fault(
                AlarmCode::Syntax,
                at,
                format!("{name} is defined twice"),
            ));
        }
        if self.vars.len() >= MAX_VARIABLES {
            return Err(fault(
                AlarmCode::NotSupported,
                at,
                format!("more than {MAX_VARIABLES} user variables"),
            ));
        }
        self.vars.push(Variable {
            name: name.into(),
            ty,
            value,
            defined_at,
            target,
            array: None,
            text: None,
        });
        Ok(())
    }

    /// `DEF STRING[max] name = text` at `at` (reached again: the text afresh).
    pub fn define_string(&mut self, name: &str, max: usize, text: String, at: usize) -> R<()> {
        check_length(name, &text, max, at)?;
        if let Some(var) = self.vars[self.level..]
            .iter_mut()
            .find(|x| &*x.name == name && x.defined_at == at)
        {
            var.text = Some(Box::new((text, max)));
            return Ok(());
        }
        self.add(name, Type::Real, 0.0, at, None, at)?;
        if let Some(var) = self.vars.last_mut() {
            var.text = Some(Box::new((text, max)));
        }
        Ok(())
    }

    /// The axis letter of AXIS variable `name` (upper case) of the running level, if it is
    /// one and names an axis.
    pub fn axis_of(&self, name: &str) -> Option<Option<u8>> {
        let v = &self.vars[self.find(name)?];
        (v.ty == Type::Axis && v.array.is_none()).then(|| {
            crate::machine_data::AXIS_NAMES
                .get(usize::try_from(v.value as i64).ok()?)
                .map(|&c| c as u8)
        })
    }

    /// The character of CHAR variable `name` (upper case) of the running level, if it is one.
    pub fn char_of(&self, name: &str) -> Option<char> {
        let v = &self.vars[self.find(name)?];
        (v.ty == Type::Char && v.array.is_none() && v.target.is_none())
            .then(|| char::from(v.value as u8))
    }

    /// The text of STRING variable `name` (upper case) of the running level, if it is one.
    pub fn string(&self, name: &str) -> Option<&str> {
        let k = self.find(name)?;
        self.vars[k].text.as_deref().map(|t| t.0.as_str())
    }

    /// STRING variable `name` set to `text` (no longer than its DEF allows).
    pub fn set_string(&mut self, name: &str, text: String, at: usize) -> R<()> {
        let k = self.find(name).ok_or_else(|| Self::undefined(name, at))?;
        let Some(t) = self.vars[k].text.as_deref_mut() else {
            return Err(fault(AlarmCode::Syntax, at, format!("{name} is no STRING")));
        };
        check_length(name, &text, t.1, at)?;
        t.0 = text;
        Ok(())
    }

    /// `DEF ty name[dims] = …` at `at`: an array holding `start` (reached again: restored).
    pub fn define_array(&mut self, name: &str, ty: Type, array: Array, at: usize) -> R<()> {
        if let Some(var) = self.vars[self.level..]
            .iter_mut()
            .find(|x| &*x.name == name && x.defined_at == at)
        {
            var.array = Some(Box::new(array));
            return Ok(());
        }
        for v in array.start.iter() {
            ty.convert(*v, at)?;
        }
        self.add(name, ty, 0.0, at, None, at)?;
        if let Some(var) = self.vars.last_mut() {
            var.array = Some(Box::new(array));
        }
        Ok(())
    }

    /// Whether `name` (upper case) is an array of the running level.
    pub fn is_array(&self, name: &str) -> bool {
        self.find(name)
            .is_some_and(|k| self.vars[k].array.is_some())
    }

    /// Element `idx` of array `name`.
    pub fn element(&self, name: &str, idx: &[f64], at: usize) -> R<f64> {
        let k = self.find(name).ok_or_else(|| Self::undefined(name, at))?;
        let Some(a) = self.vars[k].array.as_deref() else {
            return Err(not_array(name, at));
        };
        Ok(a.values[a.place(idx, name, at)?])
    }

    /// Element `idx` of array `name` set to `v` (converted to the array's type).
    pub fn set_element(&mut self, name: &str, idx: &[f64], v: f64, at: usize) -> R<()> {
        let k = self.find(name).ok_or_else(|| Self::undefined(name, at))?;
        let ty = self.vars[k].ty;
        let Some(a) = self.vars[k].array.as_deref_mut() else {
            return Err(not_array(name, at));
        };
        let place = a.place(idx, name, at)?;
        a.values[place] = ty.convert(v, at)?;
        Ok(())
    }
}

/// A STRING's text fits its DEF's length.
fn check_length(name: &str, text: &str, max: usize, at: usize) -> R<()> {
    if text.chars().count() > max {
        return Err(fault(
            AlarmCode::Syntax,
            at,
            format!("{name} holds at most {max} characters (DEF STRING[{max}])"),
        ));
    }
    Ok(())
}

#[cold]
fn not_array(name: &str, at: usize) -> Box<super::fault::Fault> {
    fault(
        AlarmCode::Syntax,
        at,
        format!("{name} is no array: no index"),
    )
}

#[cold]
fn a_string(name: &str, at: usize) -> Box<super::fault::Fault> {
    fault(
        AlarmCode::Syntax,
        at,
        format!("{name} is a STRING: no number (MSG and << take it)"),
    )
}

#[cold]
fn whole_array(name: &str, at: usize) -> Box<super::fault::Fault> {
    fault(
        AlarmCode::Syntax,
        at,
        format!("{name} is an array: {name}[index] is one of its elements"),
    )
}

#[cfg(test)]
mod tests {
    use super::super::run;
    use crate::alarm::AlarmCode;

    /// The X end points of a program's moves.
    fn xs(src: &str) -> Vec<f64> {
        super::super::end_xs("siemens-840d", src)
    }

    fn alarm(src: &str) -> (AlarmCode, u32, u32) {
        super::super::alarm_at("siemens-840d", src)
    }

    #[test]
    fn operators_bind_as_the_priority_table_says() {
        // * before +; comparisons last: 1+2*3 == 7 is TRUE; 0 AND 1 binds before <.
        let p = "G1 F1 X=1+2*3\nX=1+2*3==7\nX=2<3 AND 0\nX=7 DIV 2\nX=-7 MOD 3\nX=6 B_AND 3 B_OR 8\nX=NOT 0 + 2\n";
        // 2<3 AND 0 → 2 < (3 AND 0) → 2 < 0 → 0; NOT 0 + 2 → (NOT 0) + 2 → 3.
        assert_eq!(xs(p), [7.0, 1.0, 0.0, 3.0, -1.0, 10.0, 3.0]);
    }

    #[test]
    fn functions_take_degrees_and_round_half_away_from_zero() {
        let p = "G1 F1 X=SIN(30)\nX=ATAN2(1,1)\nX=POT(3)\nX=ROUND(-2.5)\nX=TRUNC(-2.5)\nX=BOUND(0,5,9)\nX=1.5EX2\n";
        let got = xs(p);
        let want = [0.5, 45.0, 9.0, -3.0, -2.0, 5.0, 150.0];
        assert!(
            got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-12),
            "{got:?}"
        );
    }

    #[test]
    fn int_variables_round_and_bool_variables_hold_truth() {
        let p = "DEF INT NN=2.5\nDEF BOOL BB=-3\nDEF REAL AA\nAA=NN+BB\nG1 F1 X=AA\n";
        assert_eq!(xs(p), [4.0]);
    }

    #[test]
    fn structures_are_matched_before_the_program_runs() {
        // The IF behind M30 is never reached, and still refused at its own place.
        assert_eq!(
            alarm("G1 F1 X1\nM30\n  IF R1>0\nX2\n"),
            (AlarmCode::ControlNesting, 3, 3)
        );
        assert_eq!(
            alarm("WHILE 1\nIF 1\nENDWHILE\nENDIF\n"),
            (AlarmCode::ControlNesting, 3, 1)
        );
        assert_eq!(
            alarm("IF 1\nELSE\nELSE\nENDIF\n"),
            (AlarmCode::ControlNesting, 3, 1)
        );
        assert_eq!(alarm("LAB: IF 1\nENDIF\n"), (AlarmCode::Syntax, 1, 6));
        assert_eq!(alarm("/IF 1\nENDIF\n"), (AlarmCode::Syntax, 1, 2));
    }

    #[test]
    fn a_jump_out_of_a_loop_leaves_nothing_open() {
        // Ten times out of a WHILE and back in through GOTOB: no structure piles up.
        let p =
            "G1 F1\nTOP: R1=R1+1\nWHILE 1\nIF R1>=10 GOTOF END\nGOTOB TOP\nENDWHILE\nEND: X=R1\n";
        assert_eq!(xs(p), [10.0]);
    }

    #[test]
    fn goto_searches_forward_then_from_the_start_and_gotoc_goes_on() {
        let p = "G1 F1\nR1=R1+1\nIF R1>2 GOTOF OUT\nX=R1\nGOTO N5\nN5 GOTOC NOWHERE\nGOTO TOP\nTOP: GOTO N3\nOUT: X99\n";
        // GOTO N5 finds N5 forward; GOTO TOP forward; GOTO N3 is not found: alarm.
        assert_eq!(alarm(p).0, AlarmCode::JumpTarget);
        let p = "G1 F1\nN3 R1=R1+1\nIF R1>2 GOTOF OUT\nX=R1\nGOTO N3\nOUT: X99\n";
        assert_eq!(xs(p), [1.0, 2.0, 99.0]);
    }

    #[test]
    fn names_are_unique_and_a_def_reached_again_starts_afresh() {
        assert_eq!(alarm("AB1: G1 F1 X1\nAB1: X2\n"), (AlarmCode::Syntax, 2, 1));
        assert_eq!(alarm("DEF INT I\n"), (AlarmCode::Syntax, 1, 9));
        assert_eq!(alarm("DEF REAL SIN\n"), (AlarmCode::Syntax, 1, 10));
        // The DEF runs three times: CNT starts at 1 each time, R1 counts the passes.
        let p = "G1 F1\nTOP: DEF INT CNT=1\nR1=R1+1 CNT=CNT+R1\nX=CNT\nIF R1<3 GOTOB TOP\n";
        assert_eq!(xs(p), [2.0, 3.0, 4.0]);
    }

    #[test]
    fn case_takes_the_first_equal_constant_then_default_then_the_next_block() {
        let p = |r5: &str, default: &str| {
            format!("G1 F1\nR5={r5}\nCASE(R5*2) OF 2 GOTOF ONE -4 GOTOF TWO 4 GOTOF ONE{default}\nONE: X1\nTWO: X2\nOTHER: X3\n")
        };
        assert_eq!(xs(&p("1", "")), [1.0, 2.0, 3.0]);
        assert_eq!(xs(&p("-2", "")), [2.0, 3.0]);
        assert_eq!(xs(&p("7", " DEFAULT GOTOF OTHER")), [3.0]);
        assert_eq!(xs(&p("9", "")), [1.0, 2.0, 3.0]);
        assert_eq!(alarm("CASE(R1) OF 0 GOTOF\n"), (AlarmCode::Syntax, 1, 20));
        assert_eq!(
            alarm("CASE(R1) OF 1.5 GOTOF A1\n"),
            (AlarmCode::Syntax, 1, 13)
        );
        assert_eq!(
            alarm("CASE(R1) OF 1 GOTOF A1 0 GOTOF NOWHERE\n"),
            (AlarmCode::JumpTarget, 1, 32)
        );
    }

    #[test]
    fn arrays_hold_rows_of_elements_set_rep_and_by_index() {
        // TAB row by row: [[1, 2], [3, 4], [5, 6]]; N all 7. TAB[1,0] = 3, TAB[2,1] + N[3]
        // = 13; TAB[0,1] = 1·10; N[2] = 2.6 rounds to 3 (INT): 13.
        let p = "DEF REAL TAB[3,2]=SET(1,2,3,4,5,6)\nDEF INT NN[4]=REP(7)\nG1 F1 X=TAB[1,0] Y=TAB[2,1]+NN[3]\nTAB[0,1]=TAB[0,0]*10 NN[2]=2.6\nX=TAB[0,1]+NN[2]\n";
        assert_eq!(xs(p), [3.0, 13.0]);
        let p = "DEF REAL XS[5]\nDEF INT KK\nFOR KK=0 TO 4\nXS[KK]=KK*KK\nENDFOR\nG1 F1 X=XS[4]+XS[0]\n";
        assert_eq!(xs(p), [16.0]);
        assert_eq!(
            alarm("DEF REAL TB[2]\nG1 F1 X=TB[2]\n"),
            (AlarmCode::ArrayIndex, 2, 9)
        );
        assert_eq!(
            alarm("DEF REAL TB[2]\nTB[1.5]=1\n"),
            (AlarmCode::ArrayIndex, 2, 1)
        );
        assert_eq!(alarm("DEF REAL TB[2]\nR1=TB\n"), (AlarmCode::Syntax, 2, 4));
        assert_eq!(
            alarm("DEF REAL TB[2]\nR1=TB[0,1]\n"),
            (AlarmCode::Syntax, 2, 4)
        );
        assert_eq!(
            alarm("DEF REAL TB[2]=SET(1,2,3)\n"),
            (AlarmCode::Syntax, 1, 16)
        );
        assert_eq!(
            alarm("DEF REAL TB[100,200]\n"),
            (AlarmCode::NotSupported, 1, 12)
        );
        assert_eq!(alarm("DEF REAL TB[0]\n"), (AlarmCode::BadNumber, 1, 12));
    }

    #[test]
    fn strings_join_texts_variables_and_numbers_for_msg() {
        let msg = |p: &str| -> Vec<String> {
            run("siemens-840d", p)
                .unwrap_or_else(|a| panic!("{a}"))
                .iter()
                .filter_map(|b| b.message.as_deref().map(str::to_string))
                .collect()
        };
        let p = "DEF STRING[20] PART=\"PLATE\", TXT\nR1=2.5\nTXT=PART << \"-\" << 3*4\nMSG(\"Part \" << TXT << \" at \" << R1)\nMSG()\n";
        assert_eq!(msg(p), ["Part PLATE-12 at 2.5"]);
        assert_eq!(
            alarm("DEF STRING[3] SS=\"ABCD\"\n"),
            (AlarmCode::Syntax, 1, 15)
        );
        assert_eq!(
            alarm("DEF STRING[9] SS\nR1=SS+1\n"),
            (AlarmCode::Syntax, 2, 4)
        );
        assert_eq!(alarm("R1=1 << 2\n"), (AlarmCode::Syntax, 1, 6));
        assert_eq!(alarm("DEF FRAME FF\n"), (AlarmCode::NotSupported, 1, 5));
        // CHAR: a character's code in arithmetic, the character in a string.
        let p = "DEF CHAR CC=\"A\"\nCC=CC+2\nMSG(\"row \" << CC << CC+0)\nG1 F1 X=CC-64\n";
        assert_eq!(msg(p), ["row C67"]);
        assert_eq!(xs(p), [3.0]);
        assert_eq!(alarm("DEF CHAR CC=256\n"), (AlarmCode::Arithmetic, 1, 10));
        assert_eq!(alarm("R1=\"AB\"\n"), (AlarmCode::Syntax, 1, 4));
        // Strings compare with == and <> (in a condition too).
        let p = "DEF STRING[9] SS=\"PLATE\"\nG1 F1 X=SS==\"PLATE\"\nX=SS<>\"PLATE\"\nIF SS==\"BOLT\" GOTOF DONE\nX=7\nDONE: X=8\n";
        assert_eq!(xs(p), [1.0, 0.0, 7.0, 8.0]);
        assert_eq!(
            alarm("DEF STRING[9] SS\nR1=SS>\"A\"\n"),
            (AlarmCode::Syntax, 2, 4)
        );
    }

    #[test]
    fn axis_variables_name_the_axis_an_axial_address_moves_and_an_index_reads() {
        // AX[AXV]=10 moves X; AXV=Y: AX[AXV]=IC(5) moves Y by 5; $P_EP[AXV] reads Y.
        let p = "DEF AXIS AXV=X, AXW\nG1 F100 AX[AXV]=10\nAXV=Y\nAX[AXV]=IC(5) AX[Z]=2\nAXW=AXV\nR1=$P_EP[AXW]\nX=R1\n";
        assert_eq!(
            super::super::moves("siemens-840d", p)
                .iter()
                .map(|m| m.1)
                .collect::<Vec<_>>(),
            [[10.0, 0.0, 0.0], [10.0, 5.0, 2.0], [5.0, 5.0, 2.0]]
        );
        assert_eq!(
            alarm("DEF AXIS AXV\nAX[AXV]=1\n"),
            (AlarmCode::UndefinedName, 2, 4)
        );
        assert_eq!(
            alarm("DEF AXIS AXV=Q\n"),
            (AlarmCode::UnknownAddress, 1, 14)
        );
        assert_eq!(
            alarm("DEF AXIS AXV=X\nR1=AXV+1\n"),
            (AlarmCode::Syntax, 2, 4)
        );
        assert_eq!(alarm("AX[X]5\n"), (AlarmCode::Syntax, 1, 6));
    }

    #[test]
    fn names_longer_than_an_address_are_names() {
        assert_eq!(alarm("XPOS=1\n"), (AlarmCode::UndefinedName, 1, 1));
        assert_eq!(alarm("G1 X10 GOTOF A\n"), (AlarmCode::UndefinedName, 1, 8));
        let p = "DEF REAL XPOS=4, ZZ\nZZ=XPOS*2 G1 F1 X=ZZ\n";
        assert_eq!(xs(p), [8.0]);
    }
}
