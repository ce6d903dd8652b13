//! nc-runtime: what the portable NC core (crate `nc-kernel`) needs of an operating system
//! to run a machine.
//!
//! - [`os`]: every OS call of every process (clock, absolute sleep, SCHED_FIFO, locked
//!   memory, timer slack, signals);
//! - [`CycleClock`]: the IPO cycle's clock on absolute deadlines;
//! - [`live`]: the kernel alone on the live clock (the latency bench);
//! - [`process`]: the nc-kernel process of the control over iceoryx2, and the arguments of
//!   the control's processes;
//! - [`Failure`] and [`exit`]: how every softnc program ends without success, and its exit
//!   status.

mod clock;
mod failure;
mod join;
pub mod live;
pub mod os;
pub mod process;
mod program_files;
pub mod record;
mod wire_axes;
mod wire_tools;

pub use clock::{CycleClock, Tick};
pub use failure::{exit, Failure};
pub use join::Threads;
pub use program_files::{program_library, read_program};
pub use wire_axes::WireAxes;
pub use wire_tools::{tool_table, tool_table_msg};

/// A latency histogram (ns) in cyclictest's format, so that scripts sum rounds of either
/// alike: `# title`, `# name value` comment lines, then "`<µs> <count>`" per 1 µs bucket.
pub fn histogram_text(
    title: &str,
    h: &hdrhistogram::Histogram<u64>,
    extra: &[(&str, u64)],
) -> String {
    use std::fmt::Write;
    let mut text = format!("# {title} histogram, µs\n");
    for (k, v) in extra {
        let _ = writeln!(text, "# {k} {v}");
    }
    let mut buckets = std::collections::BTreeMap::<u64, u64>::new();
    for v in h.iter_recorded() {
        *buckets.entry(v.value_iterated_to() / 1000).or_default() += v.count_at_value();
    }
    for (us, n) in buckets {
        let _ = writeln!(text, "{us:06} {n:06}");
    }
    text
}
