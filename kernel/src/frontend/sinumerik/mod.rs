//! The SINUMERIK language of the 808D, 828D and 840D sl (Programming Manual Fundamentals and
//! Job planning; docs/sinumerik.md): R parameters and user variables (`DEF`), expressions in
//! addresses (`X=R1+5`), control structures (IF/ELSE/ENDIF, WHILE, FOR, REPEAT, LOOP), jump
//! labels and GOTOF/GOTOB/GOTO/GOTOC.
//!
//! - [`expr`]: arithmetic, comparisons, logic and the functions.
//! - [`statements`]: the statements and assignments, run as the interpreter reaches them.
//! - [`structure`]: the control structures of a whole program, matched before it starts.

pub(super) mod expr;
pub(super) mod statements;
pub(super) mod structure;

use super::fault::{fault, R};
use crate::alarm::AlarmCode;

/// A user variable's type (Job planning, "Definition of user variables (DEF)").
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
}

/// The R parameters and the program's user variables (LUD, one set for the main program).
#[derive(Clone, Debug, Default)]
pub struct Store {
    r: Vec<f64>,
    vars: Vec<Variable>,
}

/// More user variables than this in one program are refused (a bound on a name search).
const MAX_VARIABLES: usize = 1000;

impl Store {
    /// `count` R parameters, R0 … R(count − 1), all 0 (machine data `program.r_parameters`).
    pub fn new(count: usize) -> Self {
        Store {
            r: vec![0.0; count],
            vars: Vec::new(),
        }
    }

    pub fn r(&self, n: usize, at: usize) -> R<f64> {
        self.r.get(n).copied().ok_or_else(|| self.no_r(n, at))
    }

    pub fn set_r(&mut self, n: usize, v: f64, at: usize) -> R<()> {
        let no = self.no_r(n, at);
        *self.r.get_mut(n).ok_or(no)? = v;
        Ok(())
    }

    #[cold]
    fn no_r(&self, n: usize, at: usize) -> Box<super::fault::Fault> {
        fault(
            AlarmCode::UndefinedName,
            at,
            format!(
                "R{n} does not exist: R0 … R{} (machine data program.r_parameters)",
                self.r.len().saturating_sub(1)
            ),
        )
    }

    /// The value of user variable `name`.
    pub fn get(&self, name: &str, at: usize) -> R<f64> {
        match self.vars.iter().find(|v| &*v.name == name) {
            Some(v) => Ok(v.value),
            None => Err(fault(
                AlarmCode::UndefinedName,
                at,
                format!("{name} is not defined (DEF)"),
            )),
        }
    }

    /// Whether `name` is a user variable.
    pub fn has(&self, name: &str) -> bool {
        self.vars.iter().any(|v| &*v.name == name)
    }

    pub fn set(&mut self, name: &str, v: f64, at: usize) -> R<()> {
        let Some(var) = self.vars.iter_mut().find(|x| &*x.name == name) else {
            return Err(fault(
                AlarmCode::UndefinedName,
                at,
                format!("{name} is not defined (DEF)"),
            ));
        };
        var.value = var.ty.convert(v, at)?;
        Ok(())
    }

    /// `DEF ty name = v`: a new variable (a name defined twice is an alarm).
    pub fn define(&mut self, name: &str, ty: Type, v: f64, at: usize) -> R<()> {
        if self.has(name) {
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
        let value = ty.convert(v, at)?;
        self.vars.push(Variable {
            name: name.into(),
            ty,
            value,
        });
        Ok(())
    }
}
