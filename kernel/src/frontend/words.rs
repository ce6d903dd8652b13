//! The words of one block as the word loop collects them, before they are interpreted: a
//! G code may follow the axis words it governs, so nothing is applied while reading. Each
//! address has one slot (or a short list), and the checks every word gets are here: a value
//! within range, a whole number where one is required, an address at most once.

use super::fault::{fault, Offset, R};
use super::number::Number;
use crate::alarm::AlarmCode;

/// Largest magnitude of any programmed value (mm, mm/min, s, ...): beyond it a value is a
/// typing error, and keeping values bounded keeps every later computation finite.
pub const MAX_VALUE: f64 = 1e9;

/// A value as written, with the byte offset of its address letter. Flat rather than holding
/// a [`Number`], so that it packs into 16 bytes and `Option<Val>` stays 16 bytes too.
#[derive(Clone, Copy, Debug)]
pub struct Val {
    pub value: f64,
    pub at: u32,
    /// A decimal point was written.
    pub has_point: bool,
}

impl Val {
    pub fn new(n: Number, at: usize) -> Self {
        Val {
            value: n.value,
            at: at as u32,
            has_point: n.has_point,
        }
    }

    /// A value an expression computed for the word at `at` (a decimal point implied).
    pub fn computed(value: f64, at: usize) -> Self {
        Val {
            value,
            at: at as u32,
            has_point: true,
        }
    }

    pub fn pos(self) -> usize {
        self.at as usize
    }
}

/// A chamfer or corner word (Fanuc `,C` `,R`) with its value.
#[derive(Clone, Copy, Debug)]
pub struct CornerWord {
    pub kind: super::build::CornerKind,
    /// The word as the dialect writes it, for messages.
    pub text: &'static str,
    pub value: Val,
}

/// `DIAMON`, `DIAMOF`, `DIAM90` (SINUMERIK diameter programming).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiameterWord {
    On,
    Off,
    /// Diameter where X is absolute, radius where it is incremental.
    Absolute,
}

/// SINUMERIK path words of more than one letter (Fundamentals, "Motion commands";
/// frontend/sinumerik/words.rs reads them).
#[derive(Clone, Copy, Default)]
pub struct PathWords {
    /// `CIP` or `CT`: the motion command, with where it stands.
    pub motion: Option<(super::block::MotionMode, u32)>,
    /// `AP=`: polar angle.
    pub ap: Option<Val>,
    /// `RP=`: polar radius.
    pub rp: Option<Val>,
    /// `AP=AC(…)` (Some(false)) or `AP=IC(…)` (Some(true)), whatever G90/G91 say.
    pub ap_incremental: Option<bool>,
    /// `I1=` `J1=` `K1=`: the intermediate point of CIP.
    pub inter: [Option<Val>; 3],
    /// The intermediate point's coordinates written with `AC()` / `IC()`, as bits.
    pub inter_absolute: u8,
    pub inter_incremental: u8,
    /// `TURN=`: full turns of a helix.
    pub turn: Option<Val>,
    /// `RNDM=`: modal rounding radius.
    pub rndm: Option<Val>,
    /// `FRC=` / `FRCM=`: the feed of a chamfer or rounding, for this block / modal.
    pub frc: Option<Val>,
    pub frcm: Option<Val>,
}

impl PathWords {
    pub fn is_empty(&self) -> bool {
        self.motion.is_none()
            && self.ap.is_none()
            && self.rp.is_none()
            && self.inter.iter().all(Option::is_none)
            && self.turn.is_none()
            && self.rndm.is_none()
            && self.frc.is_none()
            && self.frcm.is_none()
    }

    /// The block programs a point in polar coordinates.
    pub fn polar(&self) -> bool {
        self.ap.is_some() || self.rp.is_some()
    }
}

/// The words of one block. The auxiliary words (F S T D M H) also go straight into the block
/// being built, in program order.
#[derive(Clone, Default)]
pub struct Words {
    /// G numbers with their offsets, in program order.
    pub g: heapless::Vec<(u16, u32), 16>,
    /// X Y Z
    pub axis: [Option<Val>; 3],
    /// The additional axes U V W A B C (those the machine has).
    pub additional: [Option<Val>; crate::machine_data::ADDITIONAL],
    /// I J K
    pub centre: [Option<Val>; 3],
    /// Arc radius (`CR=` or `R`).
    pub radius: Option<Val>,
    /// Polar angle A.
    pub angle: Option<Val>,
    /// Polar radius U or B.
    pub polar_radius: Option<Val>,
    pub f: Option<Val>,
    /// Canned cycles: the peck depth or shift Q.
    pub q: Option<Val>,
    /// Fanuc lathe: the axes written with their incremental word (U for X, W for Z), as bits.
    pub incremental: u8,
    /// SINUMERIK `X=AC(…)`: the axes absolute in this block whatever the distance mode, as bits.
    pub absolute: u8,
    /// SINUMERIK `I=AC(…)`: the centre coordinates given absolute, not from the start, as bits.
    pub centre_absolute: u8,
    /// SINUMERIK path words (AP RP CIP CT TURN RNDM FRC …).
    pub path: PathWords,
    /// Fanuc: the repeat count L of M98.
    pub l: Option<Val>,
    /// Fanuc dwell time in milliseconds.
    pub p: Option<Val>,
    /// ISG: a number standing alone after the dwell G code (`G04 3.0`).
    pub bare: Option<Val>,
    pub d: Option<Val>,
    /// Fanuc: the tool length offset's H register.
    pub h: Option<Val>,
    /// Siemens `LIMS=`: the spindle speed limit.
    pub lims: Option<Val>,
    pub t: Option<Val>,
    pub m: heapless::Vec<Val, 8>,
    /// @ command numbers with their offsets.
    pub at_codes: heapless::Vec<(u32, u32), 4>,
    /// `DIAMON`, `DIAMOF`, `DIAM90`.
    pub diameter: Option<DiameterWord>,
    /// A chamfer or corner at the end of the block's move.
    pub corner: Option<CornerWord>,
    /// Where the program wrote the active tool radius.
    pub radius_written: Option<u32>,
    /// A variable was assigned.
    pub calculation: bool,
    /// SINUMERIK `SUPA`: zero offsets and frames suppressed in this block.
    pub suppress: bool,
}

impl Words {
    /// No word at all besides the auxiliary ones (which the caller checks).
    pub fn is_empty(&self) -> bool {
        self.only_calculation() && !self.calculation
    }

    /// No word besides assignments and the language's commands (and the auxiliary ones,
    /// which the caller checks).
    pub fn only_calculation(&self) -> bool {
        self.g.is_empty()
            && self.axis.iter().all(Option::is_none)
            && self.additional.iter().all(Option::is_none)
            && self.centre.iter().all(Option::is_none)
            && self.radius.is_none()
            && self.angle.is_none()
            && self.polar_radius.is_none()
            && self.p.is_none()
            && self.bare.is_none()
            && self.at_codes.is_empty()
            && self.diameter.is_none()
            && self.h.is_none()
            && self.l.is_none()
            && self.q.is_none()
            && self.lims.is_none()
            && self.corner.is_none()
            && !self.suppress
            && self.path.is_empty()
    }
}

/// Word names for alarms, as statics: an array literal at the call would be built on the
/// stack for every word.
pub static AXIS_WORDS: [&str; 3] = ["X", "Y", "Z"];
pub static ADDITIONAL_WORDS: [&str; 6] = ["U", "V", "W", "A", "B", "C"];
pub static CENTRE_WORDS: [&str; 3] = ["I", "J", "K"];

/// A value is finite and within ±[`MAX_VALUE`].
pub fn checked(v: Val) -> R<Val> {
    if v.value.is_finite() && v.value.abs() <= MAX_VALUE {
        Ok(v)
    } else {
        Err(fault(
            AlarmCode::BadNumber,
            v.at,
            format!("value {} is out of range (±{MAX_VALUE})", v.value),
        ))
    }
}

/// One more word of a kind a block holds a few of.
pub fn push<T, const N: usize>(v: &mut heapless::Vec<T, N>, x: T, at: usize) -> R<()> {
    v.push(x).map_err(|_| {
        fault(
            AlarmCode::TooManyWords,
            at,
            format!("more than {N} words of this kind in one block"),
        )
    })
}

/// An address at most once per block. `name` is `&'static` so that callers pass a constant,
/// not a string built for every word.
#[inline(always)]
pub fn set_once(slot: &mut Option<Val>, v: Val, name: &'static str) -> R<()> {
    if slot.is_some() {
        return Err(fault(
            AlarmCode::AddressTwice,
            v.at,
            format!("{name} is programmed twice in this block"),
        ));
    }
    *slot = Some(v);
    Ok(())
}

/// A value that must be a non-negative integer (G, M, T, D numbers).
pub fn int_value(v: f64, at: impl Offset, what: &str) -> R<u32> {
    // `v as u32 as f64 == v` tests for a whole number without a call to `trunc`.
    if v >= 0.0 && v <= u32::MAX as f64 && v as u32 as f64 == v {
        Ok(v as u32)
    } else {
        Err(fault(
            AlarmCode::BadNumber,
            at,
            format!("{what} must be a whole number, not {v}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn val(value: f64) -> Val {
        Val {
            value,
            at: 4,
            has_point: true,
        }
    }

    #[test]
    fn values_are_bounded_and_counted() {
        assert!(checked(val(1e9)).is_ok());
        assert_eq!(checked(val(-1.5e9)).unwrap_err().code, AlarmCode::BadNumber);
        assert_eq!(int_value(12.0, 0usize, "T").unwrap(), 12);
        assert_eq!(int_value(1.5, 3usize, "T").unwrap_err().at, 3);
        assert!(int_value(-1.0, 0usize, "T").is_err());
        let mut slot = None;
        set_once(&mut slot, val(1.0), "X").unwrap();
        let f = set_once(&mut slot, val(2.0), "X").unwrap_err();
        assert_eq!((f.code, f.at), (AlarmCode::AddressTwice, 4));
        let mut v: heapless::Vec<u8, 1> = heapless::Vec::new();
        push(&mut v, 1, 0).unwrap();
        assert_eq!(
            push(&mut v, 2, 9).unwrap_err().code,
            AlarmCode::TooManyWords
        );
    }
}
