//! nc-kernel: the softnc NC kernel library.
//!
//! Data flows one way: [`frontend`] (part program → interpreted blocks) → block preparation →
//! interpolation → IPC. Each stage is named after the NC concept it implements; the manual
//! sections it follows are cited where each rule lives.

pub mod alarm;
pub mod cycle;
pub mod dialect;
pub mod frontend;
pub mod handover;
pub mod ipo;
pub(crate) mod json;
pub mod machine_data;
pub mod prep;
pub mod segment;
pub mod simulate;
pub mod synthetic;
pub mod tools;
pub mod trc;

pub use alarm::{Alarm, AlarmCode};
pub use frontend::{interpret, Block, Interpreter};
pub use machine_data::MachineData;
pub use prep::{prepare, Preparation};
pub use segment::{Role, Segment, Shape, Source};
pub use tools::{ToolOffset, ToolTable};
