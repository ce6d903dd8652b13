//! Fanuc Custom Macro B (0i-MF operator's manual, "Custom macro"): the `#` variables, their
//! expressions ([`expr`]) and the system variables bound to the interpreter's state
//! ([`system`]). The statements that use them (`#i=…`, `IF`, `WHILE … DO`/`END`, `GOTO`)
//! are in `statements/fanuc.rs`, the calls (`M98`, `G65`, `G66`) in `calls.rs`.
//!
//! Variables by number (0i-MF, "Types of variables"):
//!
//! ```text
//! #0            always vacant; cannot be written
//! #1 … #33      local: one set per macro call level (G65/G66 open a level, M98 does not)
//! #100 … #199   common: shared by every level, vacant at program start
//! #500 … #999   common, kept: shared, and kept in the caller's file between runs
//! #1000 …       system variables (system.rs)
//! ```

pub mod expr;
mod system;

pub use expr::Value;

/// Local variables of one call level.
pub const LOCALS: usize = 33;
const COMMON: std::ops::RangeInclusive<i64> = 100..=199;
/// The kept range as the file has it (macro_variables.rs).
const KEPT: std::ops::RangeInclusive<i64> =
    *crate::macro_variables::KEPT.start() as i64..=*crate::macro_variables::KEPT.end() as i64;

/// The `#` variable stores of one program run.
#[derive(Clone, Debug)]
pub struct MacroVariables {
    /// #1 … #33 of the level running now; a call saves the caller's in its frame.
    pub locals: [Value; LOCALS],
    /// #100 … #199.
    common: Vec<Value>,
    /// #500 … #999.
    kept: Vec<Value>,
    /// `#3006 = n (message)` was written: the statement's block stops with it.
    pub stop_message: Option<Box<str>>,
}

impl Default for MacroVariables {
    fn default() -> Self {
        MacroVariables {
            locals: [None; LOCALS],
            common: vec![None; 100],
            kept: vec![None; 500],
            stop_message: None,
        }
    }
}

/// Which store a variable number belongs to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Slot {
    Vacant,
    Local(usize),
    Common(usize),
    Kept(usize),
    System(i64),
}

pub fn slot(n: i64) -> Slot {
    match n {
        0 => Slot::Vacant,
        1..=33 => Slot::Local(n as usize - 1),
        _ if COMMON.contains(&n) => Slot::Common((n - 100) as usize),
        _ if KEPT.contains(&n) => Slot::Kept((n - 500) as usize),
        _ => Slot::System(n),
    }
}

impl MacroVariables {
    /// The value of a program variable (not a system variable).
    pub fn program(&self, s: Slot) -> Value {
        match s {
            Slot::Local(i) => self.locals[i],
            Slot::Common(i) => self.common[i],
            Slot::Kept(i) => self.kept[i],
            Slot::Vacant | Slot::System(_) => None,
        }
    }

    /// Writes a program variable; false for #0 and system variables.
    pub fn set_program(&mut self, s: Slot, v: Value) -> bool {
        let place = match s {
            Slot::Local(i) => &mut self.locals[i],
            Slot::Common(i) => &mut self.common[i],
            Slot::Kept(i) => &mut self.kept[i],
            Slot::Vacant | Slot::System(_) => return false,
        };
        *place = v;
        true
    }

    /// The kept variables #500 … #999 (index 0 is #500), to save after a run.
    pub fn kept(&self) -> &[Value] {
        &self.kept
    }

    /// Starts a run with kept variables from a file: `(number, value)`, numbers 500…999.
    pub fn with_kept(mut self, values: &[(u32, f64)]) -> Self {
        for &(n, v) in values {
            if let Slot::Kept(i) = slot(n as i64) {
                self.kept[i] = Some(v);
            }
        }
        self
    }
}
