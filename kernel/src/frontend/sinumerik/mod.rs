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

pub(super) mod calls;
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
}

impl Type {
    pub fn of(word: &str) -> Option<Type> {
        match word {
            "INT" => Some(Type::Int),
            "REAL" => Some(Type::Real),
            "BOOL" => Some(Type::Bool),
            _ => None,
        }
    }

    /// `v` converted for a variable of this type (REAL to INT rounds; not 0 is TRUE).
    fn convert(self, v: f64, at: usize) -> R<f64> {
        match self {
            Type::Real => Ok(v),
            Type::Bool => Ok((v != 0.0) as u8 as f64),
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
        let k = self.find(name)?;
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
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::run;
    use crate::alarm::AlarmCode;

    /// The X end points of a program's moves.
    fn xs(src: &str) -> Vec<f64> {
        run("siemens-840d", src)
            .unwrap_or_else(|a| panic!("{a}"))
            .iter()
            .filter_map(|b| b.motion.map(|m| m.end[0]))
            .collect()
    }

    fn alarm(src: &str) -> (AlarmCode, u32, u32) {
        let a = run("siemens-840d", src).unwrap_err();
        (a.code, a.line, a.col)
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
    fn names_longer_than_an_address_are_names() {
        assert_eq!(alarm("XPOS=1\n"), (AlarmCode::UndefinedName, 1, 1));
        assert_eq!(alarm("G1 X10 GOTOF A\n"), (AlarmCode::UndefinedName, 1, 8));
        let p = "DEF REAL XPOS=4, ZZ\nZZ=XPOS*2 G1 F1 X=ZZ\n";
        assert_eq!(xs(p), [8.0]);
    }
}
