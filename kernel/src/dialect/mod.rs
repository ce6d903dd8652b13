//! Dialects: one table per control, mapping its G codes onto dialect-free effects and
//! policies, plus the handful of lexical rules in which the controls differ. Nothing outside
//! this module knows a G number.

mod fanuc;
mod isg;
mod siemens_808d;
mod siemens_840c;

use crate::alarm::AlarmCode;
use crate::frontend::block::{
    CornerPolicy, Distance, FeedAdaption, MotionMode, Plane, SelectionPolicy, TrcSide,
};
use crate::machine_data::{DialectName, Units};
use crate::trc::TrcRules;
use std::sync::OnceLock;

/// What a G code does, independent of its number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GEffect {
    Motion(MotionMode),
    /// Non-modal dwell; the time comes from the dialect's dwell addresses.
    Dwell,
    /// Non-modal exact stop at block end.
    ExactStopBlock,
    /// Modal exact stop on (true) or continuous-path mode (false).
    ExactStopModal(bool),
    Plane(Plane),
    Units(Units),
    Distance(Distance),
    Trc(TrcSide),
    Corner(CornerPolicy),
    /// Block-level selection method (840C G455/G456, ISG G05): non-modal.
    Approach(SelectionPolicy),
    /// Modal selection method (ISG G138…G239).
    Selection(SelectionPolicy),
    FeedAdaption(FeedAdaption),
    /// ISG contour masking G140 (false) / G141 (true).
    Masking(bool),
    /// Working zero offset: 0 = off, 1..=4 = G54..G57.
    WorkOffset(u8),
    /// 840C G25 (min) / G26 (max) working area limitation, values from the axis words.
    WorkingArea {
        max: bool,
    },
    /// 880/840C G110: the current position becomes the pole.
    PoleHere,
    /// A code the dialect defines that softnc recognises but does not implement.
    Unsupported(&'static str),
}

impl GEffect {
    /// Modal group, for "two G codes of one group in a block" (alarm 12060).
    fn group(self) -> u8 {
        match self {
            GEffect::Motion(_) => 1,
            GEffect::Dwell => 2,
            GEffect::ExactStopBlock => 3,
            GEffect::ExactStopModal(_) => 4,
            GEffect::Plane(_) => 5,
            GEffect::Units(_) => 6,
            GEffect::Distance(_) => 7,
            GEffect::Trc(_) => 8,
            GEffect::Corner(_) => 9,
            GEffect::Approach(_) => 10,
            GEffect::Selection(_) => 11,
            GEffect::FeedAdaption(_) => 12,
            GEffect::Masking(_) => 13,
            GEffect::WorkOffset(_) => 14,
            GEffect::WorkingArea { .. } => 15,
            GEffect::PoleHere => 16,
            GEffect::Unsupported(_) => 17,
        }
    }
}

/// One row of a dialect's G-code table.
#[derive(Clone, Copy, Debug)]
pub struct GCodeDef {
    pub code: u16,
    pub effect: GEffect,
    /// Not allowed while TRC is active (840C 11.4).
    pub forbidden_with_trc: bool,
}

pub(crate) const fn g(code: u16, effect: GEffect) -> GCodeDef {
    GCodeDef {
        code,
        effect,
        forbidden_with_trc: false,
    }
}

pub(crate) const fn g_no_trc(code: u16, effect: GEffect) -> GCodeDef {
    GCodeDef {
        code,
        effect,
        forbidden_with_trc: true,
    }
}

/// What `;` means.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Semicolon {
    /// Comment to the end of the line (Siemens, ISG).
    Comment,
    /// End of block (Fanuc EOB).
    EndOfBlock,
}

/// How an arc radius is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadiusWord {
    /// `CR=…` (Siemens)
    CrEquals,
    /// `R…` (ISG, Fanuc)
    R,
}

/// Addresses that give a dwell time with G04.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DwellWords {
    /// Seconds under X.
    pub x_seconds: bool,
    /// Seconds under F.
    pub f_seconds: bool,
    /// Milliseconds under P (Fanuc).
    pub p_millis: bool,
    /// A bare number after G04 (ISG `G04 3.0`).
    pub bare_seconds: bool,
}

/// Lexical and structural rules of one control's program language.
#[derive(Debug)]
pub struct Dialect {
    pub name: DialectName,
    pub gcodes: &'static [GCodeDef],
    pub semicolon: Semicolon,
    pub radius_word: RadiusWord,
    /// 840C listings end blocks with `LF`.
    pub lf_block_end: bool,
    /// ISG: V.P./V.L./V.G. variables, `[…]` expressions, `$FOR`/`$IF`/`$WHILE`.
    pub variables: bool,
    /// 840C `@` commands (@714).
    pub at_commands: bool,
    /// 880/840C polar coordinates: A (angle), U or B (radius).
    pub polar_words: bool,
    /// 808D `DIAMON`/`DIAMOF`.
    pub diameter_words: bool,
    /// Fanuc `O` program numbers.
    pub o_numbers: bool,
    /// Fanuc: numbers without a decimal point follow the machine-data switch.
    pub decimal_switch: bool,
    /// Tools carry several cutting edges: D is looked up under the active T (808D).
    pub tool_edges: bool,
    pub dwell: DwellWords,
    /// Alarm for TRC selection/deselection in a circular block.
    pub trc_not_linear: AlarmCode,
    /// D0 deselects TRC (840C 11.5: "D0 corresponds to TRC deselection").
    pub d0_deselects: bool,
    /// M18 is a programmed stop at block end (840C 11.10 lists it with M00/M01/M02/M30).
    pub m18_stops: bool,
    pub initial_motion: MotionMode,
    pub initial_corner_intersection: CornerPolicy,
    pub initial_selection: SelectionPolicy,
    /// The control's TRC rules in dialect-free terms.
    pub trc: TrcRules,
}

impl Dialect {
    pub fn get(name: DialectName) -> &'static Dialect {
        match name {
            DialectName::Siemens840C => &siemens_840c::DIALECT,
            DialectName::Isg => &isg::DIALECT,
            DialectName::Fanuc => &fanuc::DIALECT,
            DialectName::Siemens808D => &siemens_808d::DIALECT,
        }
    }

    /// The table row for G`code`, in O(1).
    pub fn gcode(&self, code: u16) -> Option<&'static GCodeDef> {
        let index = self.index();
        let slot = *index.get(code as usize)?;
        if slot == 0 {
            None
        } else {
            self.gcodes.get(slot as usize - 1)
        }
    }

    fn index(&self) -> &'static [u16; 1000] {
        static INDEX: [OnceLock<Box<[u16; 1000]>>; 4] = [
            OnceLock::new(),
            OnceLock::new(),
            OnceLock::new(),
            OnceLock::new(),
        ];
        let i = match self.name {
            DialectName::Siemens840C => 0,
            DialectName::Isg => 1,
            DialectName::Fanuc => 2,
            DialectName::Siemens808D => 3,
        };
        INDEX[i].get_or_init(|| {
            let mut t = Box::new([0u16; 1000]);
            for (k, def) in self.gcodes.iter().enumerate() {
                t[def.code as usize] = k as u16 + 1;
            }
            t
        })
    }

    pub(crate) fn same_group(a: GEffect, b: GEffect) -> bool {
        a.group() == b.group()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_have_unique_codes_below_1000() {
        for name in [
            DialectName::Siemens840C,
            DialectName::Isg,
            DialectName::Fanuc,
            DialectName::Siemens808D,
        ] {
            let d = Dialect::get(name);
            for (i, a) in d.gcodes.iter().enumerate() {
                assert!(a.code < 1000);
                assert!(
                    d.gcodes[i + 1..].iter().all(|b| b.code != a.code),
                    "{name:?}: G{} twice",
                    a.code
                );
                assert_eq!(d.gcode(a.code).unwrap().code, a.code);
            }
        }
    }

    #[test]
    fn same_number_different_meaning() {
        let c = Dialect::get(DialectName::Siemens840C);
        let i = Dialect::get(DialectName::Isg);
        assert_eq!(
            c.gcode(10).unwrap().effect,
            GEffect::Motion(MotionMode::PolarRapid)
        );
        assert_eq!(
            i.gcode(10).unwrap().effect,
            GEffect::FeedAdaption(FeedAdaption::Centre)
        );
        assert_eq!(
            c.gcode(25).unwrap().effect,
            GEffect::WorkingArea { max: false }
        );
        assert_eq!(
            i.gcode(25).unwrap().effect,
            GEffect::Corner(CornerPolicy::LinearTransition)
        );
    }
}
