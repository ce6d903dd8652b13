//! The JSON Lines formats: interpreted blocks (`softnc parse`, docs/parse-format.md) and the
//! prepared tool path with its alarms (`softnc path`, docs/path-format.md).

pub use crate::frontend::jsonl::write_block;
pub use crate::prep::jsonl::{write_alarm, write_prepared};
