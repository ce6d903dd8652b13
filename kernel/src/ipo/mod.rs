//! Interpolation: the prepared path becomes one setpoint per IPO cycle.
//!
//! - [`path`]: a segment as a curve: length, point at a distance, tangents and curvature;
//! - [`limits`]: the axes' velocity, acceleration and jerk limits as the path's limits, and
//!   the corner speeds;
//! - [`profile`]: jerk-limited velocity profiles along the path;
//! - [`planner`]: the lookahead over the queued segments and the interpolator that samples
//!   the plan at every cycle;
//! - [`channel`]: the channel states (RESET, ACTIVE, STOPPED, END) around it;
//! - [`spindle`]: the spindle's speed setpoint, and a model of its drive.
//!
//! Everything the IPO thread runs works in place: no allocation, no lock (docs/ipo.md).

mod channel;
mod limits;
mod path;
mod planner;
mod profile;
mod spindle;

pub use channel::{Channel, ChannelState, Event, Input, Setpoint, MAX_EVENTS};
pub use limits::{AxisLimits, SegmentLimits};
pub use path::Piece;
pub use planner::{Entry, Planner, Progress, Sample, MAX_LOOKAHEAD};
pub use profile::Dynamics;
pub use spindle::{spindle_setpoint, SpindleModel};
