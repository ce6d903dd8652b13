//! Interpreted blocks: what the front end hands to block preparation. Dialect-free: no G
//! numbers here, only the policies the dialect table mapped them onto.

use crate::machine_data::Units;

/// A position in the basic coordinate system: program coordinates plus the active zero offset,
/// in mm, X as a radius on lathes.
pub type Pos = [f64; 3];

pub use crate::machine_data::{ADDITIONAL, AXIS_NAMES};

/// The additional axes' positions (U V W A B C, one slot each; 0 where not configured), in
/// machine coordinates: mm, or degrees for a rotary axis, counted on without wrapping.
pub type Additional = [f64; ADDITIONAL];

/// Where every path axis stands: the geometry axes and the additional ones.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AxisPos {
    pub geo: Pos,
    pub add: Additional,
}

/// The additional axes' move in a block: from where they stand to where the block takes them,
/// linearly with the path's length. It travels beside the block's segment (additional axes
/// move only outside tool radius compensation, where a block is one segment), so the
/// segments of a plain three-axis path stay as small as they were (docs/axes.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisMove {
    pub from: Additional,
    pub to: Additional,
}

impl AxisPos {
    /// Axis `i` of [`AXIS_NAMES`].
    pub fn axis(&self, i: usize) -> f64 {
        match i {
            0..3 => self.geo[i],
            _ => self.add.get(i - 3).copied().unwrap_or(0.0),
        }
    }

    pub fn set_axis(&mut self, i: usize, v: f64) {
        match i {
            0..3 => self.geo[i] = v,
            _ => {
                if let Some(a) = self.add.get_mut(i - 3) {
                    *a = v;
                }
            }
        }
    }
}

/// A working plane as (abscissa, ordinate, normal) axis indices; always right-handed, so
/// counter-clockwise means from abscissa towards ordinate, looking against the normal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plane {
    pub abscissa: u8,
    pub ordinate: u8,
    pub normal: u8,
}

impl Plane {
    /// G17
    pub const XY: Plane = Plane {
        abscissa: 0,
        ordinate: 1,
        normal: 2,
    };
    /// G18: Z abscissa, X ordinate.
    pub const ZX: Plane = Plane {
        abscissa: 2,
        ordinate: 0,
        normal: 1,
    };
    /// G19
    pub const YZ: Plane = Plane {
        abscissa: 1,
        ordinate: 2,
        normal: 0,
    };

    pub fn name(self) -> &'static str {
        match (self.abscissa, self.ordinate) {
            (0, 1) => "XY",
            (2, 0) => "ZX",
            _ => "YZ",
        }
    }

    /// Whether the axis lies in this plane.
    pub fn contains(self, axis: usize) -> bool {
        axis == self.abscissa as usize || axis == self.ordinate as usize
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionMode {
    Rapid,
    Linear,
    ArcCw,
    ArcCcw,
    /// Polar coordinates (840C/880 G10…G13): the same four, end point given by angle and radius
    /// about the pole.
    PolarRapid,
    PolarLinear,
    PolarCw,
    PolarCcw,
    /// SINUMERIK CIP: a circle through an intermediate point; its direction follows from
    /// the three points.
    ArcThrough,
    /// SINUMERIK CT: a circle tangent to the previous path element.
    ArcTangent,
    /// Thread cutting at a constant lead (Fanuc G32): a straight move at the lead F per
    /// spindle revolution.
    Thread,
    /// A Fanuc lathe cycle of four moves (G90, G92, G94), modal in the group of G00 … G03:
    /// every block with X, Z or R in it cuts the box again.
    BoxCycle(BoxCycle),
}

/// What a lathe box cycle cuts (Fanuc 0i-TF, G-code system A).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoxCycle {
    /// Outer/inner diameter cutting along Z (G90).
    Turning,
    /// One thread cut along Z (G92).
    Threading,
    /// End face cutting along X (G94).
    Facing,
}

impl MotionMode {
    pub fn is_arc(self) -> bool {
        matches!(
            self,
            MotionMode::ArcCw
                | MotionMode::ArcCcw
                | MotionMode::PolarCw
                | MotionMode::PolarCcw
                | MotionMode::ArcThrough
                | MotionMode::ArcTangent
        )
    }
    /// A mode whose block is its end point and, for a circle, its centre words: what the
    /// plain-block fast path builds.
    #[inline(always)]
    pub fn is_plain(self) -> bool {
        matches!(
            self,
            MotionMode::Rapid | MotionMode::Linear | MotionMode::ArcCw | MotionMode::ArcCcw
        )
    }
    pub fn is_polar(self) -> bool {
        matches!(
            self,
            MotionMode::PolarRapid
                | MotionMode::PolarLinear
                | MotionMode::PolarCw
                | MotionMode::PolarCcw
        )
    }
    pub fn kind(self) -> MotionKind {
        match self {
            MotionMode::Rapid | MotionMode::PolarRapid => MotionKind::Rapid,
            MotionMode::Linear
            | MotionMode::PolarLinear
            | MotionMode::Thread
            | MotionMode::BoxCycle(_) => MotionKind::Linear,
            MotionMode::ArcCw | MotionMode::PolarCw => MotionKind::ArcCw,
            // The direction of CIP and CT comes from the geometry (build/circles.rs).
            MotionMode::ArcCcw
            | MotionMode::PolarCcw
            | MotionMode::ArcThrough
            | MotionMode::ArcTangent => MotionKind::ArcCcw,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            MotionMode::Rapid => "rapid",
            MotionMode::Linear => "linear",
            MotionMode::ArcCw => "cw",
            MotionMode::ArcCcw => "ccw",
            MotionMode::PolarRapid => "polar-rapid",
            MotionMode::PolarLinear => "polar-linear",
            MotionMode::PolarCw => "polar-cw",
            MotionMode::PolarCcw => "polar-ccw",
            MotionMode::ArcThrough => "through",
            MotionMode::ArcTangent => "tangent",
            MotionMode::Thread => "thread",
            MotionMode::BoxCycle(BoxCycle::Turning) => "turning-cycle",
            MotionMode::BoxCycle(BoxCycle::Threading) => "threading-cycle",
            MotionMode::BoxCycle(BoxCycle::Facing) => "facing-cycle",
        }
    }
}

/// What the axes do in a block, once coordinates are resolved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionKind {
    Rapid,
    Linear,
    ArcCw,
    ArcCcw,
}

impl MotionKind {
    pub fn name(self) -> &'static str {
        match self {
            MotionKind::Rapid => "rapid",
            MotionKind::Linear => "linear",
            MotionKind::ArcCw => "cw",
            MotionKind::ArcCcw => "ccw",
        }
    }
    pub fn is_arc(self) -> bool {
        matches!(self, MotionKind::ArcCw | MotionKind::ArcCcw)
    }
}

/// A motion block's geometry. For arcs, `center` lies in the plane of `start` (its normal
/// coordinate is the start's) and `start`/`end` are at exactly the same distance from it; an
/// arc with `start == end` in the plane is a full circle. The normal axis moves linearly over
/// the sweep (helix).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    pub kind: MotionKind,
    pub plane: Plane,
    pub start: Pos,
    pub end: Pos,
    pub center: Pos,
    /// Axes programmed in the block (bit i = axis i of [`AXIS_NAMES`]), for "at least one
    /// axis of the plane programmed" (840C 11.3) and the 808D completion rule.
    pub programmed: u16,
}

impl Motion {
    /// True if the block moves the axes of `plane` by more than `eps`.
    pub fn moves_in_plane(&self, eps: f64) -> bool {
        let (a, o) = (self.plane.abscissa as usize, self.plane.ordinate as usize);
        self.kind.is_arc()
            || (self.end[a] - self.start[a]).abs() > eps
            || (self.end[o] - self.start[o]).abs() > eps
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Distance {
    Absolute,
    Incremental,
}

/// Where a pole definition's coordinates are measured from (SINUMERIK G110, G111, G112).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PoleOrigin {
    /// The last programmed position.
    LastPosition,
    /// The workpiece zero.
    WorkZero,
    /// The last pole.
    LastPole,
}

/// The feed's type and the spindle's speed in one group (SINUMERIK G94/G95/G96/G97: group
/// 15 of the 840D, "Feedrate control").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeedType {
    /// Feed per minute, constant cutting speed off.
    PerMinute,
    /// Feed per revolution, constant cutting speed off.
    PerRevolution,
    /// Constant cutting speed on, with feed per revolution.
    CuttingSpeed,
    /// Constant cutting speed off; the feed's type stays.
    CuttingSpeedOff,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrcSide {
    Off,
    Left,
    Right,
}

impl TrcSide {
    pub fn name(self) -> &'static str {
        match self {
            TrcSide::Off => "off",
            TrcSide::Left => "left",
            TrcSide::Right => "right",
        }
    }
}

/// Behaviour at outer corners (840C 11.1, 808D, ISG G25/G26).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CornerPolicy {
    /// Transition circle of radius R about the corner (840C/808D G450, ISG G26).
    TransitionCircle,
    /// Intersection of the equidistants with up to three linear intermediate blocks where it
    /// runs too far (840C G451).
    Intersection,
    /// Intersection, switching to the transition circle above a limit angle (808D G451).
    IntersectionLimited { limit_deg: f64 },
    /// Intersection with linear transition blocks per the TF5200 table (ISG G25).
    LinearTransition,
    /// Fanuc cutter compensation C: intersection at obtuse corners, extension by the radius
    /// at acute ones.
    ExtendedIntersection,
}

impl CornerPolicy {
    pub fn name(self) -> &'static str {
        match self {
            CornerPolicy::TransitionCircle => "transition-circle",
            CornerPolicy::Intersection => "intersection",
            CornerPolicy::IntersectionLimited { .. } => "intersection-limited",
            CornerPolicy::LinearTransition => "linear-transition",
            CornerPolicy::ExtendedIntersection => "extended-intersection",
        }
    }
}

/// How TRC is selected and deselected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SelectionPolicy {
    /// 840C G455: at α < 180° the corner mode applies (compensated approach/departure).
    Compensated,
    /// 840C G456 and 808D: straight to / from the normal position.
    NormalPosition,
    /// Fanuc type C start-up: the offset vector on the normal at the start of the next block.
    OffsetVector,
    /// ISG G138
    Direct,
    /// ISG G139
    Indirect,
    /// ISG G237
    Perpendicular,
    /// ISG G238
    InnerCorner,
    /// ISG G239
    WithoutBlock,
    /// ISG G05 (non-modal)
    Tangential,
    /// Fanuc C cancel with I J K (block-level, never modal): the last element ends where its
    /// equidistant meets that of a virtual block along the vector, inner corner or outer; in
    /// the normal position where they do not meet.
    ExitVector,
}

impl SelectionPolicy {
    pub fn name(self) -> &'static str {
        match self {
            SelectionPolicy::Compensated => "compensated",
            SelectionPolicy::NormalPosition => "normal-position",
            SelectionPolicy::OffsetVector => "offset-vector",
            SelectionPolicy::Direct => "direct",
            SelectionPolicy::Indirect => "indirect",
            SelectionPolicy::Perpendicular => "perpendicular",
            SelectionPolicy::InnerCorner => "inner-corner",
            SelectionPolicy::WithoutBlock => "without-block",
            SelectionPolicy::Tangential => "tangential",
            SelectionPolicy::ExitVector => "exit-vector",
        }
    }
}

/// ISG G10/G11: which point the programmed feed applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeedAdaption {
    /// Programmed feed at the tool centre.
    Centre,
    /// Programmed feed at the contour engagement point.
    Contour,
}

/// The spindle's direction as programmed (the dialects' M3, M4, M5, M19).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SpindleDir {
    #[default]
    Stop,
    Clockwise,
    CounterClockwise,
    /// Oriented stop: the PLC positions the spindle.
    Orient,
}

impl SpindleDir {
    pub fn name(self) -> &'static str {
        match self {
            SpindleDir::Stop => "stop",
            SpindleDir::Clockwise => "cw",
            SpindleDir::CounterClockwise => "ccw",
            SpindleDir::Orient => "orient",
        }
    }
}

/// The spindle as the program has set it: the channel turns it into a speed setpoint
/// every cycle (docs/spindle.md).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SpindleProgram {
    pub dir: SpindleDir,
    /// rev/min, or under constant surface speed the cutting speed in m/min.
    pub speed: f64,
    /// Constant surface speed: the speed follows the transverse axis (X, a radius).
    pub css: bool,
    /// The program's limit, rev/min (0: none; machine data's maximum always holds).
    pub limit: f64,
}

/// What the channel keeps of the modal state besides the path: the spindle, and the tool,
/// cutting edge and work offset the HMI shows (docs/spindle.md).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Technology {
    pub spindle: SpindleProgram,
    /// T (0: none).
    pub tool: u32,
    /// The offset number D (0: none).
    pub d: u32,
    /// The work offset's index in the dialect's sets (0: none).
    pub work_offset: u8,
}

impl ModalState {
    pub fn technology(&self) -> Technology {
        Technology {
            spindle: SpindleProgram {
                dir: self.spindle_dir,
                speed: self.spindle,
                css: self.css,
                limit: self.spindle_limit,
            },
            tool: self.tool.unwrap_or(0),
            d: self.d,
            work_offset: self.work_offset,
        }
    }
}

/// Tool length compensation by H register (Fanuc G43 +, G44 −, G49 off).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LengthComp {
    Off,
    Plus,
    Minus,
}

/// The modal state after a block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModalState {
    pub motion: MotionMode,
    pub plane: Plane,
    pub distance: Distance,
    pub units: Units,
    /// The unit F is written in: `units`, except on SINUMERIK, where G70/G71 switch only
    /// the geometry (F in machine data's units) and G700/G710 the feed as well.
    pub feed_units: Units,
    /// Path feed, mm/min.
    pub feed: f64,
    /// Spindle speed S: rev/min, or under constant surface speed m/min (ft/min in inch).
    pub spindle: f64,
    /// The spindle as programmed: the technology the channel turns into a speed setpoint.
    pub spindle_dir: SpindleDir,
    /// Constant surface speed (G96): S is the cutting speed, the speed follows the
    /// transverse axis (X).
    pub css: bool,
    /// The program's spindle speed limit, rev/min (0: machine data's only).
    pub spindle_limit: f64,
    /// The feed is per spindle revolution (G95): F in mm/rev.
    pub feed_per_rev: bool,
    pub trc: TrcSide,
    pub corner: CornerPolicy,
    /// The modal selection/deselection method (ISG G138…G239; fixed per dialect elsewhere).
    pub selection: SelectionPolicy,
    pub feed_adaption: FeedAdaption,
    /// ISG contour masking (G141).
    pub masking: bool,
    /// Modal exact stop (G60 / G61) instead of continuous path (G64).
    pub exact_stop: bool,
    /// The active work offset: 0 = none, 1.. = the dialect's sets in its order.
    pub work_offset: u8,
    /// X programmed as a diameter.
    pub diameter: bool,
    /// With `diameter`, X is a radius where it is incremental (SINUMERIK DIAM90).
    pub radius_incremental: bool,
    pub tool: Option<u32>,
    /// Active offset number (0 = none).
    pub d: u32,
    /// Effective tool radius of the active offset (geometry + wear, or as the program set it).
    pub radius: f64,
    /// Effective tool length, along the tool axis (the active plane's normal): the active
    /// offset's, or on controls with H registers the active H's, signed by G43/G44.
    pub length: f64,
    /// Tool length compensation by H register (Fanuc G43/G44/G49).
    pub length_comp: LengthComp,
    /// The active H register (0: none).
    pub h: u32,
    /// Cutting edge position 1..=9 of the active offset (turning tools; 0: none).
    pub edge: u8,
    /// Pole for polar coordinates (840C/880).
    pub pole: Pos,
}

/// An auxiliary or technology word as programmed (M3, S2000, H2, T1, D1, F400).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AuxWord {
    pub address: u8,
    pub value: f64,
}

impl std::fmt::Display for AuxWord {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.value.fract() == 0.0 && self.value.abs() < 1e15 {
            write!(f, "{}{}", self.address as char, self.value as i64)
        } else {
            write!(f, "{}{}", self.address as char, self.value)
        }
    }
}

/// Program-flow M functions that act at block end (840C 11.10: M00, M01, M02, M18, M30).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgramStop {
    /// M00
    Stop,
    /// M01 (acts only with the optional-stop switch on)
    OptionalStop,
    /// M18 (840C: programmed stop at block end, like M00, listed with the end functions)
    StopAtEnd,
    /// M02
    End,
    /// M30
    EndRewind,
}

impl ProgramStop {
    /// The M function that programs it, as softnc's outputs name the stop.
    pub fn code(self) -> &'static str {
        crate::dialect::stop_name(self)
    }
    pub fn ends_program(self) -> bool {
        matches!(self, ProgramStop::End | ProgramStop::EndRewind)
    }
}

/// Capacity for non-motion words in one block (alarm 14750 beyond it).
pub const MAX_AUX_WORDS: usize = 12;

/// The block number as written: value and digit count (keeps `N05` as `N05`). The count is
/// never 0, which lets `Option<BlockNo>` stay 8 bytes (a `Segment` fits in 128).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockNo {
    pub value: u32,
    pub digits: std::num::NonZeroU8,
}

impl std::fmt::Display for BlockNo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "N{:0width$}",
            self.value,
            width = self.digits.get() as usize
        )
    }
}

/// One interpreted block.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// 1-based source line and column of the block's first character.
    pub line: u32,
    pub col: u32,
    /// The file it is in: 0 the main program's, k a subprogram file of the machine data's
    /// program library.
    pub program: u16,
    pub number: Option<BlockNo>,
    pub motion: Option<Motion>,
    /// Modal state after the block.
    pub modal: ModalState,
    /// Non-motion words in program order (M, H, S, T, D, F, ...).
    pub words: heapless::Vec<AuxWord, MAX_AUX_WORDS>,
    /// G40/G41/G42 as programmed in this block (a repetition of the active side counts).
    pub trc: Option<TrcSide>,
    /// A block-level selection method (840C G455/G456, ISG G05), if programmed.
    pub approach: Option<SelectionPolicy>,
    /// Non-modal exact stop (G09).
    pub exact_stop: bool,
    /// A thread cut (Fanuc G32, the threading cycles' cuts): its path feed per spindle
    /// revolution, the lead along the longer axis scaled to the path.
    pub thread: Option<f64>,
    /// Dwell (G04), seconds.
    pub dwell: Option<f64>,
    /// M00/M01/M02/M18/M30.
    pub stop: Option<ProgramStop>,
    /// A new offset (D or T word, or a write of the active radius) was programmed here.
    pub offset_changed: bool,
    /// The block assigned variables (a calculation block, 840C 11.11).
    pub calculation: bool,
    /// Preprocessing stop (840C @714).
    pub preprocess_stop: bool,
    /// The additional axes move in this block (with `motion`, which may stand still).
    pub axes: Option<AxisMove>,
    /// A message for the operator with the block's stop (Fanuc `#3006 = 1 (MESSAGE)`).
    pub message: Option<Box<str>>,
    /// Fanuc I J K in a compensation cancel block: the direction of the virtual block the
    /// last element's end corner is built against, in basic coordinates. Boxed: rare, and
    /// the plain path copies every block.
    pub exit_vector: Option<Box<Pos>>,
}

impl Block {
    /// A block with nothing programmed yet, at a source position, under a modal state.
    pub fn new(line: u32, col: u32, number: Option<BlockNo>, modal: ModalState) -> Self {
        Block {
            line,
            col,
            program: 0,
            number,
            motion: None,
            modal,
            words: heapless::Vec::new(),
            trc: None,
            approach: None,
            exact_stop: false,
            thread: None,
            dwell: None,
            stop: None,
            offset_changed: false,
            calculation: false,
            preprocess_stop: false,
            axes: None,
            message: None,
            exit_vector: None,
        }
    }

    /// The N word as written, or `L<line>` for a block without one.
    /// The block's place in the program, as the path and alarms carry it (`seq`: its number
    /// in execution order, where the caller counts one).
    #[inline]
    pub fn source(&self, seq: u32) -> crate::segment::Source {
        crate::segment::Source {
            number: self.number,
            line: self.line,
            col: self.col,
            seq,
            program: self.program,
        }
    }

    pub fn label(&self) -> String {
        match self.number {
            Some(n) => n.to_string(),
            None => format!("L{}", self.line),
        }
    }
}
