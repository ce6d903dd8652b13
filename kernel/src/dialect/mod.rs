//! Dialects: one table per control, mapping its G codes, M functions and `@` commands onto
//! dialect-free effects and policies, plus the handful of lexical rules in which the controls
//! differ. Nothing outside this module knows a G, M or `@` number: the front end looks codes
//! up here, and the names softnc's outputs give to a stop or a zero offset come from here.

mod fanuc;
mod fanuc_lathe;
mod isg;
mod siemens_808d;
mod siemens_840c;
mod siemens_840d;

use crate::alarm::AlarmCode;
use crate::frontend::block::{
    CornerPolicy, Distance, FeedAdaption, FeedType, LengthComp, MotionMode, Plane, PoleOrigin,
    ProgramStop, SelectionPolicy, SpindleDir, TrcSide,
};
pub use crate::frontend::{CornerKind, CycleKind, SarContour, SarPath, SarSide};
use crate::machine_data::{DialectName, Units};
use crate::trc::TrcRules;
use std::sync::OnceLock;

/// G numbers run from 0 to `G_CODES - 1` in every dialect; the tables are indexed by them.
pub const G_CODES: usize = 1000;

/// A G number with a decimal point (Fanuc G54.1) is `G_CODES` plus ten times its value.
pub const fn point_code(whole: u16, tenth: u16) -> u16 {
    G_CODES as u16 + whole * 10 + tenth
}

/// G`code` as a program writes it: `G54`, `G54.1`.
#[derive(Clone, Copy, Debug)]
pub struct GName(pub u16);

impl std::fmt::Display for GName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let c = self.0 as usize;
        if c < G_CODES {
            write!(f, "G{c}")
        } else {
            write!(f, "G{}.{}", (c - G_CODES) / 10, (c - G_CODES) % 10)
        }
    }
}

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
    /// Inch or mm for lengths and feeds.
    Units(Units),
    /// Inch or mm for lengths only; F is in the basic system, machine data's units
    /// (SINUMERIK G70/G71).
    GeometryUnits(Units),
    Distance(Distance),
    Trc(TrcSide),
    Corner(CornerPolicy),
    /// Block-level selection method (840C G455/G456, ISG G05): non-modal.
    Approach(SelectionPolicy),
    /// Modal selection method (ISG G138…G239; SINUMERIK NORM, KONT).
    Selection(SelectionPolicy),
    FeedAdaption(FeedAdaption),
    /// ISG contour masking G140 (false) / G141 (true).
    Masking(bool),
    /// Working zero offset (modal): 0 = off, 1.. = the dialect's sets selected by a G code
    /// of their own (G54 …), in table order.
    WorkOffset(u8),
    /// A numbered work offset (modal): the set number comes from P (Fanuc G54.1 P1…P48).
    NumberedWorkOffset,
    /// The block's absolute positions are machine positions: no work offset (non-modal:
    /// Fanuc, Siemens G53).
    MachineCoordinates,
    /// Tool length compensation by H register (modal: Fanuc G43/G44/G49).
    ToolLength(LengthComp),
    /// Feed per minute (false) or per spindle revolution (true): G94/G95.
    FeedPerRevolution(bool),
    /// Constant surface speed on (true) or spindle speed in rev/min (false): G96/G97.
    ConstantSurfaceSpeed(bool),
    /// Feed type and constant cutting speed in one group (SINUMERIK G94 … G97).
    FeedType(FeedType),
    /// The block defines the pole of polar coordinates (SINUMERIK G110, G111, G112).
    Pole(PoleOrigin),
    /// The block's S is the spindle speed limit (840C G92).
    SpindleLimit,
    /// Cancels the modal canned cycle (Fanuc G80).
    CycleCancel,
    /// 840C G25 (min) / G26 (max) working area limitation, values from the axis words; the
    /// max block's S is the spindle speed limit (880 program key).
    WorkingArea {
        max: bool,
    },
    /// 880/840C G110: the current position becomes the pole.
    PoleHere,
    /// A canned cycle for holes (modal until canceled: Fanuc G73 G74 G76 G81…G89).
    Cycle(CycleKind),
    /// The canned cycle's return level: the initial level (true, G98) or the R point (G99).
    CycleReturn(bool),
    /// Reference point return through an intermediate point: the first reference (false,
    /// G28) or the second to fourth with P (true, G30).
    ReferenceReturn(bool),
    /// The position now gets the axis words' values: the zero shifts (Fanuc G92).
    PositionSetting,
    /// A local coordinate system: its zero from the axis words (Fanuc G52).
    LocalCoordinates,
    /// Programmable data input: offsets written by the program (Fanuc G10 L P).
    DataSetting,
    /// Programmable mirror image on (true, Fanuc G51.1) or off for the axes written (G50.1).
    Mirror(bool),
    /// Scaling on (true, Fanuc G51) or off (G50).
    Scaling(bool),
    /// Coordinate system rotation on (true, Fanuc G68) or off (G69).
    Rotation(bool),
    /// Polar coordinates on (true, Fanuc G16: the plane's first axis word is the radius,
    /// the second the angle) or off (G15).
    PolarCoordinates(bool),
    /// A macro call (Fanuc G65): the block is a call statement with P, L and arguments.
    MacroCall,
    /// A modal macro call (Fanuc G66): the program runs after every move until canceled.
    ModalMacroCall,
    /// Cancels the modal macro call (Fanuc G67).
    ModalMacroCancel,
    /// Smooth approach (SINUMERIK G147 G247 G347, non-modal): the tool reaches the contour's
    /// start tangentially along a line, a quarter or a half circle (frontend/build/smooth.rs).
    SmoothApproach(SarContour),
    /// Smooth retraction (SINUMERIK G148 G248 G348, non-modal): the tool leaves the contour's
    /// end tangentially.
    SmoothRetraction(SarContour),
    /// The side a smooth approach or retraction takes (modal: SINUMERIK G140 … G143).
    SmoothSide(SarSide),
    /// How a smooth approach or retraction moves along the tool axis (modal: SINUMERIK G340
    /// in space, G341 axis first).
    SmoothPath(SarPath),
    /// A multiple repetitive turning cycle on the contour between the blocks P and Q
    /// (Fanuc lathe G70 … G73): one shot, the contour written once.
    TurningCycle(TurningCycle),
    /// A Fanuc lathe cycle whose blocks are its data (one shot: G74, G75, G76).
    LatheCycle(LatheCycle),
    /// A code the dialect defines that softnc recognises but does not implement.
    Unsupported(&'static str),
}

/// The one-shot lathe cycles of the Fanuc 0i-TF (G-code system A).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LatheCycle {
    /// End face peck drilling (G74).
    FacePecking,
    /// Outer/inner diameter grooving (G75).
    Grooving,
    /// Multiple threading cycle (G76).
    Threading,
}

/// What a multiple repetitive turning cycle does with its contour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TurningCycle {
    /// Runs the contour as written (Fanuc G70 finishing).
    Finishing,
    /// Removes the stock down to the contour in passes along Z, then one pass along the
    /// contour offset by the allowances (Fanuc G71 type I). A block with only the depth
    /// of cut and the retract (`U R`) stores them.
    StockRemoval,
    /// The same in passes along X, stepping in Z (Fanuc G72); `W R` stores the depth of
    /// cut and the retract.
    Facing,
    /// Runs the whole contour several times, shifted from the escape towards it (Fanuc
    /// G73); `U W R` stores the escape and the number of passes.
    PatternRepeating,
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
            GEffect::Units(_) | GEffect::GeometryUnits(_) => 6,
            GEffect::Distance(_) => 7,
            GEffect::Trc(_) => 8,
            GEffect::Corner(_) => 9,
            GEffect::Approach(_) => 10,
            GEffect::Selection(_) => 11,
            GEffect::FeedAdaption(_) => 12,
            GEffect::Masking(_) => 13,
            GEffect::WorkOffset(_) | GEffect::NumberedWorkOffset => 14,
            GEffect::MachineCoordinates => 18,
            GEffect::ToolLength(_) => 19,
            GEffect::FeedPerRevolution(_) | GEffect::FeedType(_) => 20,
            GEffect::ConstantSurfaceSpeed(_) => 21,
            GEffect::SpindleLimit => 22,
            GEffect::CycleCancel | GEffect::Cycle(_) => 23,
            GEffect::CycleReturn(_) => 25,
            GEffect::ReferenceReturn(_) => 26,
            GEffect::PositionSetting | GEffect::LocalCoordinates | GEffect::DataSetting => 27,
            GEffect::Mirror(_) => 28,
            GEffect::Scaling(_) => 29,
            GEffect::Rotation(_) => 30,
            GEffect::PolarCoordinates(_) => 31,
            GEffect::SmoothApproach(_) | GEffect::SmoothRetraction(_) => 40,
            GEffect::SmoothSide(_) => 41,
            GEffect::SmoothPath(_) => 42,
            GEffect::MacroCall | GEffect::ModalMacroCall | GEffect::ModalMacroCancel => 24,
            GEffect::WorkingArea { .. } => 15,
            GEffect::PoleHere => 16,
            GEffect::Pole(_) => 32,
            GEffect::TurningCycle(_) => 33,
            GEffect::LatheCycle(_) => 34,
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

/// Table `a` followed by table `b`, as one (the tables are statics, built at compile time).
pub(crate) const fn concat<const N: usize>(a: &[GCodeDef], b: &[GCodeDef]) -> [GCodeDef; N] {
    let mut out = [g(0, GEffect::Dwell); N];
    let mut k = 0;
    while k < N {
        out[k] = if k < a.len() { a[k] } else { b[k - a.len()] };
        k += 1;
    }
    out
}

/// What an M function does, independent of its number. Only the functions the front end acts
/// on have a row; every other M word is an auxiliary function, handed on as written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MEffect {
    /// A program-flow function acting at block end (840C 11.10).
    Stop(ProgramStop),
    /// The spindle's direction, orientation or stop; the word still goes to the PLC.
    Spindle(SpindleDir),
    /// Subprogram call with P (and L) when the block is complete (Fanuc M98).
    Call,
    /// Return from a subprogram, with P to a sequence number (Fanuc M99).
    Return,
    /// End of a subprogram (SINUMERIK M17): back to the caller; in the main program the
    /// program's end. In a dialect that has it, M2/M30 in a called program return too.
    SubprogramEnd,
}

/// One row of a dialect's M-function table.
#[derive(Clone, Copy, Debug)]
pub struct MCodeDef {
    pub code: u16,
    pub effect: MEffect,
}

pub(crate) const fn m(code: u16, effect: MEffect) -> MCodeDef {
    MCodeDef { code, effect }
}

/// What an `@` command does, independent of its number. The commands with operands (all but
/// the preprocessing stop) belong to the 880/840C language (`Dialect::at_language`): their
/// operands are K constants, R parameters and P pointers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AtEffect {
    /// Stop decoding until the block buffer is empty (840C @714).
    PreprocessStop,
    /// Jump to a block number; its sign gives the direction of the search.
    Jump,
    /// Jump if the comparison of an R parameter with a value holds.
    JumpIf(Compare),
    /// Jump to the destination paired with the first value equal to an R parameter; none
    /// equal: on with the next block.
    Case,
    /// An R parameter gets a function of its operands.
    Function(AtFunction),
}

/// A comparison of a conditional jump: R parameter against value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compare {
    NotEqual,
    Equal,
    LessOrEqual,
    Less,
    GreaterOrEqual,
    Greater,
}

impl Compare {
    pub fn holds(self, a: f64, b: f64) -> bool {
        match self {
            Compare::NotEqual => a != b,
            Compare::Equal => a == b,
            Compare::LessOrEqual => a <= b,
            Compare::Less => a < b,
            Compare::GreaterOrEqual => a >= b,
            Compare::Greater => a > b,
        }
    }
}

/// A function an `@` command computes into its first operand, an R parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AtFunction {
    /// |a|
    Abs,
    /// √a
    Sqrt,
    /// √(a² + b²)
    Hypot,
    /// The parameter itself plus 1.
    Increment,
    /// The parameter itself minus 1.
    Decrement,
    /// The parameter's own integer part (toward 0).
    IntegerPart,
    /// Sine of a, a in degrees.
    Sin,
    /// Cosine of a, a in degrees.
    Cos,
}

impl AtFunction {
    /// Operands after the result parameter (0: the function works on the result itself).
    pub fn sources(self) -> usize {
        match self {
            AtFunction::Increment | AtFunction::Decrement | AtFunction::IntegerPart => 0,
            AtFunction::Hypot => 2,
            _ => 1,
        }
    }
}

/// One row of a dialect's `@`-command table.
#[derive(Clone, Copy, Debug)]
pub struct AtCommandDef {
    pub code: u32,
    pub effect: AtEffect,
    /// Not allowed while TRC is active (840C 11.4).
    pub forbidden_with_trc: bool,
}

/// A word that asks for a chamfer or a rounding between its block's move and the next
/// (Fanuc `,C` `,R`), as the program writes it (case ignored).
#[derive(Clone, Copy, Debug)]
pub struct CornerWordDef {
    pub text: &'static str,
    pub kind: CornerKind,
}

/// A G function the program writes as a name (SINUMERIK `NORM`, `KONT`), with its effect.
/// The whole name must match: `KONT` is not the start of `KONTC`.
#[derive(Clone, Copy, Debug)]
pub struct NamedCodeDef {
    pub text: &'static str,
    pub effect: GEffect,
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

/// Where the tool length comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LengthOffset {
    /// The D offset gives radius and length (840C, Sinumerik T/D, ISG).
    WithD,
    /// An H register selected with the length compensation codes (Fanuc memory C: offset
    /// number n holds H n's length and D n's radius, each geometry + wear).
    HRegister,
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
    /// Spindle revolutions under S (SINUMERIK `G4 S…`).
    pub s_revolutions: bool,
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
    /// The M functions the front end acts on.
    pub mcodes: &'static [MCodeDef],
    /// `@` commands (840C); empty where `@` starts no word.
    pub at_commands: &'static [AtCommandDef],
    /// The 880/840C language: R parameters assigned among a block's words (`R1=R2+5`) and read
    /// by an address (`X R1`), the `@` commands' operands, jumps to block numbers
    /// (frontend/statements/siemens_840c.rs).
    pub at_language: bool,
    /// 880/840C main blocks: `:` instead of `N` before the block number.
    pub main_block_colon: bool,
    /// Chamfer and corner words; empty where the control has none (here).
    pub corner_words: &'static [CornerWordDef],
    /// G functions written as names (SINUMERIK NORM, KONT …); empty elsewhere.
    pub named_codes: &'static [NamedCodeDef],
    /// 880/840C polar coordinates: A (angle), U or B (radius).
    pub polar_words: bool,
    /// 808D `DIAMON`/`DIAMOF`.
    pub diameter_words: bool,
    /// Siemens `LIMS=`: the spindle speed limit under constant surface speed.
    pub lims_word: bool,
    /// Fanuc `O` program numbers.
    pub o_numbers: bool,
    /// The most full turns a helix takes before its end point (SINUMERIK `TURN=`).
    pub helix_turns: u16,
    /// Fanuc Custom Macro B: `#` variables, `[…]` expressions, IF/WHILE/GOTO, L repeats.
    pub macro_b: bool,
    /// The SINUMERIK language (808D/828D/840D sl): R parameters, `X=expr`, DEF, IF/WHILE/FOR/
    /// REPEAT/LOOP, labels and GOTOF/GOTOB, subprograms by name with PROC, MCALL, RET
    /// (frontend/sinumerik).
    pub sinumerik: bool,
    /// 840C: `L123 P3` in a block of its own calls subprogram L123 (three times).
    pub l_calls: bool,
    /// Program levels open at once, the main program included: a call that would open one
    /// more is alarm 14012 (840D sl: 16, 808D: 8).
    pub program_levels: u8,
    /// Fanuc lathe (G-code system A): U and W are the incremental words of X and Z.
    pub incremental_words: bool,
    /// Fanuc lathe: T aabb selects tool aa and its offset bb (00: none).
    pub t_selects_offset: bool,
    /// Fanuc: numbers without a decimal point follow the machine-data switch.
    pub decimal_switch: bool,
    /// Tools carry several cutting edges: D is looked up under the active T (808D).
    pub tool_edges: bool,
    /// Work offsets numbered after a G code with P (Fanuc G54.1 P1…P48): how many.
    pub numbered_work_offsets: u8,
    /// The work offset in force at program start (Fanuc: G54; elsewhere none).
    pub initial_work_offset: u8,
    pub length_offset: LengthOffset,
    pub dwell: DwellWords,
    /// Alarm for TRC selection/deselection in a circular block.
    pub trc_not_linear: AlarmCode,
    /// G40/G41/G42 in circular mode is refused even in a block that moves nothing (Fanuc
    /// 026); elsewhere only in a block that moves on a circle.
    pub trc_codes_need_linear_mode: bool,
    /// D0 deselects TRC (840C 11.5: "D0 corresponds to TRC deselection").
    pub d0_deselects: bool,
    pub initial_motion: MotionMode,
    pub initial_corner_intersection: CornerPolicy,
    pub initial_selection: SelectionPolicy,
    /// The control's TRC rules in dialect-free terms.
    pub trc: TrcRules,
}

impl Dialect {
    /// The work offsets selected by a G code of their own (G54 …).
    pub(crate) fn coded_work_offsets(&self) -> u8 {
        self.gcodes
            .iter()
            .filter_map(|def| match def.effect {
                GEffect::WorkOffset(i) => Some(i),
                _ => None,
            })
            .max()
            .unwrap_or(0)
    }

    /// How many work offsets the control has: the sets with a G code of their own, then
    /// the numbered ones. Set indices run 1..=this (0: none).
    pub fn work_offset_count(&self) -> u8 {
        self.coded_work_offsets() + self.numbered_work_offsets
    }

    /// The name of work offset `index` as the program selects it (`G54`, `G54.1 P3`);
    /// `None` for 0 (none) or beyond the control's sets.
    pub fn work_offset_name(&self, index: u8) -> Option<String> {
        let coded = self.coded_work_offsets();
        let code_of = |e: GEffect| self.gcodes.iter().find(|def| def.effect == e);
        if index == 0 {
            None
        } else if index <= coded {
            code_of(GEffect::WorkOffset(index)).map(|def| GName(def.code).to_string())
        } else if index - coded <= self.numbered_work_offsets {
            code_of(GEffect::NumberedWorkOffset)
                .map(|def| format!("{} P{}", GName(def.code), index - coded))
        } else {
            None
        }
    }

    /// The index of the work offset named `name` (case and spaces ignored: `g54.1p3`).
    pub fn work_offset_index(&self, name: &str) -> Option<u8> {
        let want = work_offset_key(name);
        (1..=self.work_offset_count()).find(|&i| {
            self.work_offset_name(i)
                .is_some_and(|n| work_offset_key(&n) == want)
        })
    }

    /// The index of numbered work offset P`p`, if the control has it.
    pub fn numbered_work_offset(&self, p: u32) -> Option<u8> {
        let p = u8::try_from(p).ok()?;
        (1..=self.numbered_work_offsets)
            .contains(&p)
            .then(|| self.coded_work_offsets() + p)
    }

    pub fn get(name: DialectName) -> &'static Dialect {
        match name {
            DialectName::Siemens840C => &siemens_840c::DIALECT,
            DialectName::Isg => &isg::DIALECT,
            DialectName::Fanuc => &fanuc::DIALECT,
            DialectName::Siemens808D => &siemens_808d::DIALECT,
            DialectName::FanucLathe => &fanuc_lathe::DIALECT,
            DialectName::Siemens840D => &siemens_840d::DIALECT,
        }
    }

    /// The table row for G`code`, in O(1).
    /// Whether the dialect uses `letter` (upper case) for a word other than an axis: the
    /// radius R, the 840C's polar angle A and radius U/B, the Fanuc dwell P. Machine data
    /// may not name an axis after such a letter.
    pub fn address_taken(&self, letter: u8) -> bool {
        (letter == b'R' && self.radius_word == RadiusWord::R)
            || (matches!(letter, b'A' | b'U' | b'B') && self.polar_words)
            || (letter == b'P' && self.dwell.p_millis)
            || (letter == b'L' && self.macro_b)
            || (matches!(letter, b'U' | b'W') && self.incremental_words)
            || (letter == b'Q' && self.has_cycles())
            || (letter == b'R' && self.at_language)
    }

    /// Some G code switches contour masking on (ISG G141): the bottleneck window may have
    /// to make the path.
    pub fn masks(&self) -> bool {
        self.gcodes
            .iter()
            .any(|g| matches!(g.effect, GEffect::Masking(true)))
    }

    pub fn gcode(&self, code: u16) -> Option<&'static GCodeDef> {
        if code as usize >= G_CODES {
            return self.gcodes.iter().find(|def| def.code == code);
        }
        let index = self.index();
        let slot = *index.get(code as usize)?;
        if slot == 0 {
            None
        } else {
            self.gcodes.get(slot as usize - 1)
        }
    }

    fn index(&self) -> &'static [u16; G_CODES] {
        static INDEX: [OnceLock<Box<[u16; G_CODES]>>; 6] = [
            OnceLock::new(),
            OnceLock::new(),
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
            DialectName::FanucLathe => 4,
            DialectName::Siemens840D => 5,
        };
        INDEX[i].get_or_init(|| {
            let mut t = Box::new([0u16; G_CODES]);
            for (k, def) in self.gcodes.iter().enumerate() {
                if let Some(slot) = t.get_mut(def.code as usize) {
                    *slot = k as u16 + 1;
                }
            }
            t
        })
    }

    pub(crate) fn same_group(a: GEffect, b: GEffect) -> bool {
        a.group() == b.group()
    }

    /// The control ends a subprogram with a function of its own (M17): M2/M30 in a called
    /// program return to the caller as well.
    pub fn has_subprogram_end(&self) -> bool {
        self.mcodes
            .iter()
            .any(|def| def.effect == MEffect::SubprogramEnd)
    }

    /// The row of the M function with value `value`, if the front end acts on it.
    #[inline]
    pub fn mcode(&self, value: f64) -> Option<&'static MCodeDef> {
        self.mcodes.iter().find(|def| def.code as f64 == value)
    }

    /// The dialect has canned cycles (their Q word).
    pub fn has_cycles(&self) -> bool {
        self.gcodes.iter().any(|def| {
            matches!(
                def.effect,
                GEffect::Cycle(_) | GEffect::TurningCycle(_) | GEffect::LatheCycle(_)
            )
        })
    }

    /// The M function with `effect` as a program writes it (`M98`), for messages.
    #[cold]
    pub fn m_name(&self, effect: MEffect) -> String {
        self.mcodes
            .iter()
            .find(|def| def.effect == effect)
            .map_or_else(|| format!("{effect:?}"), |def| format!("M{}", def.code))
    }

    /// The row of `@` command `code`.
    pub fn at_command(&self, code: u32) -> Option<&'static AtCommandDef> {
        self.at_commands.iter().find(|def| def.code == code)
    }

    /// The G codes of `effects` as a program writes them, for messages: `G41/G42`.
    #[cold]
    pub fn codes_of(&self, effects: &[GEffect]) -> String {
        let codes: Vec<String> = effects
            .iter()
            .filter_map(|e| self.gcodes.iter().find(|def| def.effect == *e))
            .map(|def| GName(def.code).to_string())
            .collect();
        codes.join("/")
    }
}

/// A work offset's name as names are compared: case and spaces ignored (`g54.1p3` is
/// `G54.1 P3`).
pub fn work_offset_key(name: &str) -> String {
    name.chars()
        .filter(|c| !c.is_whitespace())
        .collect::<String>()
        .to_ascii_uppercase()
}

/// The name softnc's outputs give a program stop (`"stop": "M30"`): the M function that
/// programs it, the same in every dialect.
pub fn stop_name(stop: ProgramStop) -> &'static str {
    match stop {
        ProgramStop::Stop => "M0",
        ProgramStop::OptionalStop => "M1",
        ProgramStop::StopAtEnd => "M18",
        ProgramStop::End => "M2",
        ProgramStop::EndRewind => "M30",
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
                assert!(a.code < 1000 || a.code > point_code(0, 0));
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

    #[test]
    fn m_functions_and_at_commands_per_dialect() {
        let c = Dialect::get(DialectName::Siemens840C);
        let i = Dialect::get(DialectName::Isg);
        let stop = |d: &Dialect, v: f64| d.mcode(v).map(|def| def.effect);
        assert_eq!(stop(c, 18.0), Some(MEffect::Stop(ProgramStop::StopAtEnd)));
        assert_eq!(stop(i, 18.0), None);
        assert_eq!(stop(i, 30.0), Some(MEffect::Stop(ProgramStop::EndRewind)));
        assert_eq!(stop(i, 3.0), Some(MEffect::Spindle(SpindleDir::Clockwise)));
        assert_eq!(stop(i, 8.0), None, "coolant: the PLC's");
        assert_eq!(stop(i, 0.5), None);
        let at = c.at_command(714).unwrap();
        assert_eq!(
            (at.effect, at.forbidden_with_trc),
            (AtEffect::PreprocessStop, true)
        );
        assert!(c.at_command(715).is_none() && i.at_commands.is_empty());
        let effect = |code| c.at_command(code).map(|def| def.effect);
        assert_eq!(effect(124), Some(AtEffect::JumpIf(Compare::Less)));
        assert_eq!(effect(630), Some(AtEffect::Function(AtFunction::Sin)));
        assert!(!c.at_command(100).unwrap().forbidden_with_trc);
        assert_eq!(AtFunction::Hypot.sources(), 2);
        // Every stop a table maps to is named after the M function that programs it.
        for name in [
            DialectName::Siemens840C,
            DialectName::Isg,
            DialectName::Fanuc,
            DialectName::Siemens808D,
        ] {
            for def in Dialect::get(name).mcodes {
                if let MEffect::Stop(s) = def.effect {
                    assert_eq!(stop_name(s), format!("M{}", def.code));
                }
            }
        }
    }

    #[test]
    fn codes_for_messages_come_from_the_table() {
        let f = Dialect::get(DialectName::Fanuc);
        let trc = [GEffect::Trc(TrcSide::Left), GEffect::Trc(TrcSide::Right)];
        assert_eq!(f.codes_of(&trc), "G41/G42");
        assert_eq!(f.codes_of(&[GEffect::Dwell]), "G4");
    }

    #[test]
    fn work_offsets_are_named_as_the_program_selects_them() {
        let f = Dialect::get(DialectName::Fanuc);
        assert_eq!(f.work_offset_count(), 6 + 48);
        assert_eq!(f.work_offset_name(0), None);
        assert_eq!(f.work_offset_name(2).as_deref(), Some("G55"));
        assert_eq!(f.work_offset_name(6).as_deref(), Some("G59"));
        assert_eq!(f.work_offset_name(7).as_deref(), Some("G54.1 P1"));
        assert_eq!(f.work_offset_name(54).as_deref(), Some("G54.1 P48"));
        assert_eq!(f.work_offset_name(55), None);
        assert_eq!(f.work_offset_index("g54.1p48"), Some(54));
        assert_eq!(f.work_offset_index("G54.1 P49"), None);
        assert_eq!(f.numbered_work_offset(3), Some(9));
        assert_eq!(f.numbered_work_offset(0), None);
        let c = Dialect::get(DialectName::Siemens840C);
        assert_eq!(c.work_offset_count(), 4);
        assert_eq!(c.work_offset_index("G57"), Some(4));
        assert_eq!(c.work_offset_index("G58"), None);
        assert_eq!(
            Dialect::get(DialectName::Siemens808D).work_offset_count(),
            6
        );
        assert_eq!(Dialect::get(DialectName::Isg).work_offset_count(), 6);
        assert_eq!(GName(point_code(54, 1)).to_string(), "G54.1");
    }
}
