//! nc-kernel: the portable core of softnc, a soft NC kernel. No OS beyond std: the runtime
//! around it (clock, real-time threads, shared memory, processes) is the crate nc-runtime.
//!
//! A part program flows one way:
//!
//! ```text
//! text ─► Interpreter (front end, one dialect table per control) ─► Block
//!      ─► Preparation (tool length and radius compensation, bottleneck window,
//!         auxiliary functions at S points) ─► Prepared: Segment, AuxFunction, Stop
//!      ─► handover (the preparation thread, a lock-free queue) ─► ipo::Channel
//!         (lookahead, jerk-limited profiles, channel states) ─► Setpoint per IPO cycle
//! ```
//!
//! [`cycle::Cyclic`] is one IPO cycle of the kernel with its PLC and HMI around it, over a
//! [`cycle::Bus`]; [`simulate`] runs the same channel on a simulated clock. Each stage is
//! named after the NC concept it implements, and the manual sections it follows are cited
//! where each rule lives (docs/ARCHITECTURE.md).

mod alarm;
mod checker;
pub mod cycle;
mod dialect;
mod frontend;
pub mod geometry;
pub mod handover;
pub mod ipo;
mod json;
pub mod jsonl;
mod machine_data;
mod macro_variables;
mod prep;
mod programs;
mod segment;
pub mod simulate;
pub mod synthetic;
mod tools;
mod trc;
mod work_offsets;

pub use alarm::{Alarm, AlarmCode};
pub use frontend::{
    interpret, AuxWord, Block, BlockNo, CornerPolicy, Distance, FeedAdaption, Interpreter,
    ModalState, Motion, MotionKind, MotionMode, Plane, Pos, ProgramStop, SelectionPolicy, TrcSide,
};
pub use frontend::{Additional, AxisPos, LengthComp, SpindleDir, SpindleProgram, Technology};
pub use machine_data::{
    AuxOutput, AxisData, AxisKind, CornerModeSetting, DecimalInput, DialectName, MachineData,
    MachineDataError, MachineKind, PlaneName, ToolPost, Units, ViolationReaction, ADDITIONAL, AXES,
    AXIS_NAMES, BUILTIN_DEFAULTS, MAX_PATH_AXES,
};

pub use dialect::work_offset_key;

/// The dialect table of the machine's control (work-offset names for the HMI).
pub fn dialect_of(md: &MachineData) -> &'static dialect::Dialect {
    dialect::Dialect::get(md.dialect)
}
pub use macro_variables::{format_kept_variables, parse_kept_variables};
pub use prep::{
    prepare, AuxFunction, Interruption, Join, Lent, Preparation, Prepared, Resumed, Stop,
    WholeMode, MAX_WINDOW,
};
pub use programs::{LibraryProgram, ProgramKey, ProgramLibrary, ReadText};
pub use segment::{Role, Segment, Shape, Source};
pub use tools::{
    check_edit, offset_label, write_atomic, LiveEdit, LiveEdits, ToolOffset, ToolTable,
};
pub use work_offsets::{WorkOffsetError, WorkOffsets, MAX_WORK_OFFSET};
