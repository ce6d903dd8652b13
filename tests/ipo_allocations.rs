//! The IPO path allocates nothing (issue 5 c): a counting global allocator sees no
//! allocation, reallocation or free in the thread that runs the channel — taking the prepared
//! records into the lookahead, and every cycle from NC start to the program end, with
//! auxiliary functions, acknowledgements, an override change and an NC stop and restart on
//! the way. The records are prepared before counting (preparation runs in its own thread in
//! the kernel and may allocate).

#[path = "support/counting.rs"]
mod counting;

use nc_kernel::handover::{prepare_all, Job};
use nc_kernel::ipo::Input;
use nc_kernel::ipo::{Channel, ChannelState, Setpoint};
use nc_kernel::{AxisPos, MachineData, ToolTable};

#[global_allocator]
static GLOBAL: counting::Counting = counting::Counting;

fn inputs(text: &str, md: &MachineData) -> (Vec<Input>, AxisPos) {
    let tools = ToolTable::builtin();
    let job = Job {
        name: "alloc",
        source: text,
        md,
        tools: &tools,
        at: None,
    };
    let (start, inputs, reports) = prepare_all(job);
    assert!(reports.is_empty(), "no alarm, no warning: {reports:?}");
    (inputs, start)
}

/// Runs the channel over `inputs` and returns the allocator events in this thread and the
/// cycles run.
fn run(inputs: Vec<Input>, start: AxisPos, md: &MachineData) -> (u64, u64) {
    let mut ch = Box::new(Channel::new(md, start));
    let mut sp = Box::new(Setpoint::new(start));
    let mut it = inputs.into_iter();
    let mut pending: Option<Input> = None;
    let (k, events) = counting::counted(|| {
        ch.start();
        let mut k = 0u64;
        let mut acks = 0u32;
        loop {
            ch.fill(&mut pending, || it.next());
            for _ in 0..acks {
                ch.ack();
            }
            ch.cycle(k, &mut sp);
            acks = ch.acks_due();
            match k {
                2_000 => ch.set_override(0.5),
                4_000 => ch.stop(),
                _ => {}
            }
            if sp.state == ChannelState::Stopped {
                ch.start();
            }
            if sp.state == ChannelState::End || k > 50_000_000 {
                break;
            }
            k += 1;
        }
        k
    });
    // What is left (an empty iterator, the boxes) is freed after counting.
    drop(pending);
    (events, k)
}

#[test]
fn the_ipo_path_does_not_touch_the_allocator() {
    counting::self_test();
    let mut md = MachineData::load(None, &[]).unwrap();
    // The synthetic program wanders beyond the built-in machine's travel; this test is about
    // the allocator, not the software limits.
    for a in [&mut md.axes.x, &mut md.axes.y, &mut md.axes.z]
        .into_iter()
        .flatten()
    {
        a.software_limits = None;
    }
    let workpiece = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("programs/siemens-840c/11_15_workpiece.mpf"),
    )
    .unwrap();
    let long =
        nc_kernel::synthetic::compensated_program(3_000, nc_kernel::synthetic::Header::Softnc);
    for text in [workpiece.as_str(), long.as_str()] {
        let (inputs, start) = inputs(text, &md);
        let n = inputs.len();
        let (events, cycles) = run(inputs, start, &md);
        assert!(cycles > 10_000, "{cycles}");
        assert_eq!(
            events, 0,
            "{events} allocator calls over {cycles} cycles and {n} records"
        );
    }
}
