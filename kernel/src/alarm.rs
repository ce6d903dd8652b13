//! Alarms: every problem softnc finds is an [`Alarm`] with a stable number, the program,
//! the source position and the block, printed like a compiler diagnostic.
//!
//! The numbers are listed in docs/alarms.md. Where a seed manual names a number (840C 3021,
//! Fanuc 026) softnc uses it; the others follow the SINUMERIK 840D numbering where a matching
//! alarm exists there, so that a Siemens user recognises them.

use std::fmt;

/// Stable alarm numbers. A number, once shipped, never changes meaning.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum AlarmCode {
    /// Fanuc P/S 026: compensation start or end in a block that is not G00/G01 (seed 003).
    FanucTrcNotLinear,
    /// 840C 3021: contour violation with TRC (11.11, 11.12).
    ContourViolation,
    /// TRC selection or deselection in a circular block (Siemens/ISG wording of Fanuc 026).
    TrcSelectionNotLinear,
    /// A function that may not be programmed while TRC is active (840C 11.4).
    ForbiddenWithTrc,
    /// Plane change while TRC is active.
    PlaneChangeWithTrc,
    /// Working area limitation (840C G25/G26) violated.
    WorkingArea,
    /// A prepared segment would take an axis past its software limit switch (840D 10720).
    SoftwareLimit,
    /// Syntax error: a character or token that cannot start or continue a word.
    Syntax,
    /// An address (word letter) that the dialect does not know, or an axis the machine lacks.
    UnknownAddress,
    /// The same address twice in one block.
    AddressTwice,
    /// Two G codes of the same modal group in one block.
    SameGroupTwice,
    /// A G code the dialect does not define.
    UnknownGCode,
    /// A number that cannot be read, or a value outside its range.
    BadNumber,
    /// A function the dialect defines but softnc does not implement.
    NotSupported,
    /// A variable that is read before it is defined, or that cannot be written.
    UndefinedName,
    /// Arithmetic error in an expression (division by zero, square root of a negative number).
    Arithmetic,
    /// Control structures ($FOR/$IF/$WHILE) not properly nested or not closed.
    ControlNesting,
    /// A loop ran more iterations than the machine data allows (guards against endless programs).
    LoopLimit,
    /// Circle end point not on the circle, or radius programming impossible.
    ArcEndPoint,
    /// Missing information for a motion (no centre for an arc, ...).
    MissingValue,
    /// Too many auxiliary functions or words in one block.
    TooManyWords,
    /// Tool offset (D, T/D) not in the tool table.
    UnknownOffset,
    /// A feed motion with no feed programmed.
    NoFeed,
    /// A circle on the tool side whose radius is not larger than the tool radius.
    ArcRadiusTooSmall,
    /// A tool radius change with TRC active in a block that is not linear (840C 11.7, ISG).
    RadiusChangeNotLinear,
    /// ISG inner-corner selection (G238) impossible: contour not closed, first block not
    /// linear, no inner corner at the selection point, or a radius/side change while active.
    InnerCornerSelection,
    /// Block preparation ended without finishing the program (an internal error): the path
    /// stops where the prepared part ends.
    PreparationFailed,
    /// `softnc simulate`: the machine time reached `simulate.max_machine_time`.
    SimulationTimeLimit,
    /// `softnc simulate`: the path stood still with nothing happening for
    /// `simulate.max_rest_time` (a program that would wait for ever).
    NoProgress,
    /// A called program is not there (Fanuc M98/G65/G66: no such O number).
    MissingProgram,
    /// A jump target is not in the program (Fanuc GOTO n, M99 P n: no such sequence number).
    JumpTarget,
    /// Subprogram or macro calls nested deeper than the control allows.
    CallNesting,
    /// A call passes no variable where the called program's parameter is call-by-reference
    /// (SINUMERIK `VAR`): an expression, a constant, or nothing (840D 12320: parameter is no
    /// variable).
    ParameterNotVariable,
    /// A chamfer or corner word in a block without a G01/G02/G03 move in the plane (840D
    /// 10882: chamfer or rounding without a traversing motion in the block).
    CornerWithoutMove,
    /// The block after a chamfer or corner word is not a move in the same plane, or there
    /// is none (840D 10880: no traversing block after the one with the chamfer or rounding).
    CornerNextBlock,
    /// The chamfer or the rounding does not fit the two moves (840D 10883: chamfer or
    /// radius must be reduced).
    CornerTooLarge,
    /// A SINUMERIK drilling cycle's parameters contradict each other or lie out of range
    /// (840D 61101 "reference plane defined incorrectly" and its neighbours).
    CycleParameter,
    /// A SINUMERIK cycle's machining type VARI is not one of its values (840D 61002 "type
    /// of machining incorrectly defined").
    CycleMachiningType,
    /// The contour a SINUMERIK turning cycle machines is missing or cannot be machined as
    /// programmed (840D 61605 "contour programmed incorrectly").
    CycleContour,
    /// An array element outside the array's dimensions (840D 17020 "illegal array index").
    ArrayIndex,
    /// A SINUMERIK smooth approach finds no contour element to lead onto: more blocks
    /// without a traversing motion than the control allows between it and the contour, or
    /// the program ends first (840D 10740, "too many empty blocks in WAB programming").
    SarBlocks,
    /// The moves of a smooth approach or retraction along the tool axis would turn back
    /// (840D 10741, "direction reversal with WAB infeed motion").
    SarReversal,
    /// A smooth approach's or retraction's distance is invalid or missing: DISR for a circle,
    /// a line of no length, a programmed circle of no radius, a negative DISCL or DISRP
    /// (840D 10742, "WAB distance invalid or not programmed").
    SarDistance,
    /// A smooth approach or retraction has no direction: the contour element it joins does
    /// not move in the plane, or the side of its circle cannot be found (840D 10744, "no
    /// valid WAB direction defined").
    SarDirection,
    /// The program raised an alarm itself (Fanuc `#3000 = n (message)`, shown as MC 3000+n;
    /// the number is the Sinumerik user-alarm range of SETAL).
    ProgramAlarm,
    /// A message of the program for the operator, reported as a warning where preparation
    /// reaches it (Fanuc `#3006 = n (message)`, which also stops there).
    ProgramMessage,
}

impl AlarmCode {
    pub const fn number(self) -> u32 {
        match self {
            AlarmCode::FanucTrcNotLinear => 26,
            AlarmCode::ContourViolation => 3021,
            AlarmCode::TrcSelectionNotLinear => 10751,
            AlarmCode::ForbiddenWithTrc => 10754,
            AlarmCode::PlaneChangeWithTrc => 10755,
            AlarmCode::WorkingArea => 10630,
            AlarmCode::SoftwareLimit => 10720,
            AlarmCode::Syntax => 12080,
            AlarmCode::UnknownAddress => 12050,
            AlarmCode::AddressTwice => 12040,
            AlarmCode::SameGroupTwice => 12060,
            AlarmCode::UnknownGCode => 12470,
            AlarmCode::BadNumber => 12160,
            AlarmCode::NotSupported => 12580,
            AlarmCode::UndefinedName => 12550,
            AlarmCode::Arithmetic => 14000,
            AlarmCode::ControlNesting => 12640,
            AlarmCode::LoopLimit => 12650,
            AlarmCode::ArcEndPoint => 14040,
            AlarmCode::MissingValue => 14045,
            AlarmCode::TooManyWords => 14750,
            AlarmCode::UnknownOffset => 17180,
            AlarmCode::NoFeed => 10860,
            AlarmCode::ArcRadiusTooSmall => 10758,
            AlarmCode::RadiusChangeNotLinear => 10760,
            AlarmCode::InnerCornerSelection => 10762,
            AlarmCode::PreparationFailed => 1011,
            AlarmCode::SimulationTimeLimit => 90001,
            AlarmCode::NoProgress => 90002,
            AlarmCode::MissingProgram => 14011,
            AlarmCode::JumpTarget => 14080,
            AlarmCode::CallNesting => 14012,
            AlarmCode::ParameterNotVariable => 12320,
            AlarmCode::CornerWithoutMove => 10882,
            AlarmCode::CornerNextBlock => 10880,
            AlarmCode::CornerTooLarge => 10883,
            AlarmCode::CycleParameter => 61101,
            AlarmCode::CycleMachiningType => 61002,
            AlarmCode::CycleContour => 61605,
            AlarmCode::ArrayIndex => 17020,
            AlarmCode::SarBlocks => 10740,
            AlarmCode::SarReversal => 10741,
            AlarmCode::SarDistance => 10742,
            AlarmCode::SarDirection => 10744,
            AlarmCode::ProgramAlarm => 65000,
            AlarmCode::ProgramMessage => 65001,
        }
    }
}

/// Where in which program an alarm arose. Lines and columns count from 1; columns count
/// characters, not bytes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Alarm {
    pub code: AlarmCode,
    pub program: String,
    pub line: u32,
    pub col: u32,
    /// The block's N word as written (`N20`), if it has one.
    pub block: Option<String>,
    pub message: String,
}

impl Alarm {
    /// Alarm `code` at block `at` of `program`: its line, column and N word.
    pub fn at(
        code: AlarmCode,
        program: &str,
        at: &crate::segment::Source,
        message: impl Into<String>,
    ) -> Alarm {
        Alarm {
            code,
            program: program.to_string(),
            line: at.line,
            col: at.col,
            block: at.number.map(|n| n.to_string()),
            message: message.into(),
        }
    }

    pub fn number(&self) -> u32 {
        self.code.number()
    }

    /// The alarm as a compiler diagnostic: the message, then the offending line of `source`
    /// with a caret under the column (docs/alarms.md).
    pub fn render(&self, source: &str) -> String {
        render(self, source)
    }
}

impl fmt::Display for Alarm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: alarm {:03}: ",
            self.program,
            self.line,
            self.col,
            self.number()
        )?;
        if let Some(b) = &self.block {
            write!(f, "{b}: ")?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for Alarm {}

/// Renders an alarm like a compiler diagnostic, with the offending source line and a caret
/// under the column.
pub(crate) fn render(alarm: &Alarm, source: &str) -> String {
    let mut out = alarm.to_string();
    if let Some(text) = source.lines().nth(alarm.line.saturating_sub(1) as usize) {
        let text = text.trim_end_matches('\r');
        let gutter = alarm.line.to_string();
        let pad = " ".repeat(gutter.len());
        let caret_at: String = text
            .chars()
            .take(alarm.col.saturating_sub(1) as usize)
            .map(|c| if c == '\t' { '\t' } else { ' ' })
            .collect();
        out.push_str(&format!(
            "\n{pad} |\n{gutter} | {text}\n{pad} | {caret_at}^"
        ));
    }
    out
}
