//! IPO compute time per cycle on the simulated clock (no sleeping): every `Channel::cycle`
//! (taking input included) timed with the monotonic clock, over a long compensated program.
//! Every 5 000 cycles an operator action (override 60 % ↔ 100 %, NC stop, NC start): those
//! cycles replan, and their times are kept apart. Prints p50/p99/p99.9/max in µs.
//!
//! `ipo_timing [BLOCKS]` (default 4000 blocks of the G41 serpentine, about 1.5 M cycles)

use hdrhistogram::Histogram;
use nc_kernel::ipo::{Channel, ChannelState, Setpoint};
use nc_kernel::{MachineData, ToolTable};
use nc_runtime::os::now_ns;

fn main() {
    let blocks: usize = std::env::args()
        .nth(1)
        .map_or(4000, |s| s.parse().expect("BLOCKS"));
    let md = MachineData::load(None, &[]).expect("machine data");
    let tools = ToolTable::builtin();
    let text =
        nc_kernel::synthetic::compensated_program(blocks, nc_kernel::synthetic::Header::Softnc);
    let job = nc_kernel::handover::Job {
        name: "bench",
        source: &text,
        md: &md,
        tools: &tools,
        at: None,
    };
    let (start, inputs, reports) = nc_kernel::handover::prepare_all(job);
    assert!(
        reports.is_empty(),
        "the bench program prepares without alarms"
    );
    let mut it = inputs.into_iter();
    let mut pending = None;
    let mut ch = Box::new(Channel::new(&md, start));
    let mut sp = Box::new(Setpoint::new(start));
    let mut plain = Histogram::<u64>::new_with_bounds(1, 1_000_000_000, 3).unwrap();
    let mut replan = Histogram::<u64>::new_with_bounds(1, 1_000_000_000, 3).unwrap();
    ch.start();
    let mut k = 0u64;
    loop {
        let action = k % 5000 == 4999;
        let t0 = now_ns();
        if action {
            match (k / 5000) % 4 {
                0 => ch.set_override(0.6),
                1 => ch.set_override(1.0),
                2 => ch.stop(),
                _ => ch.start(),
            }
        }
        ch.fill(&mut pending, || it.next());
        while ch.acks_due() > 0 {
            ch.ack();
        }
        ch.cycle(k, &mut sp);
        let dt = (now_ns() - t0).max(1);
        if action {
            replan.record(dt).unwrap();
        } else {
            plain.record(dt).unwrap();
        }
        if sp.state == ChannelState::End {
            break;
        }
        if sp.state == ChannelState::Stopped && (k / 5000) % 4 == 3 {
            ch.start();
        }
        k += 1;
    }
    let q = |h: &Histogram<u64>, p: f64| h.value_at_quantile(p) as f64 / 1000.0;
    println!(
        "cycles {}: p50 {:.3} µs, p99 {:.3} µs, p99.9 {:.3} µs, max {:.1} µs",
        plain.len(),
        q(&plain, 0.5),
        q(&plain, 0.99),
        q(&plain, 0.999),
        plain.max() as f64 / 1000.0
    );
    println!(
        "replanning cycles {} (override change, NC stop, NC start): p50 {:.3} µs, max {:.1} µs",
        replan.len(),
        q(&replan, 0.5),
        replan.max() as f64 / 1000.0
    );
}
