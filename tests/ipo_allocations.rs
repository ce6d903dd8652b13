//! The IPO path allocates nothing (issue 5 c): a counting global allocator sees no
//! allocation, reallocation or free in the thread that runs the channel — taking the prepared
//! records into the lookahead, and every cycle from NC start to the program end, with
//! auxiliary functions, acknowledgements, an override change and an NC stop and restart on
//! the way; on a machine of three axes, on one of eight, and on a lathe turning at constant
//! surface speed with feed per revolution (the spindle's setpoint every cycle, a drive model
//! feeding its actual speed back, the path replanned as it changes). The records are prepared before
//! counting (preparation runs in its own thread in the kernel and may allocate).

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

/// Runs the channel over `inputs` and returns the allocator events in this thread, the
/// cycles run and the last setpoint.
fn run(inputs: Vec<Input>, start: AxisPos, md: &MachineData) -> (u64, u64, Setpoint) {
    let mut ch = Box::new(Channel::new(md, start));
    let mut sp = Box::new(Setpoint::new(start));
    let mut it = inputs.into_iter();
    let mut pending: Option<Input> = None;
    let mut drive = nc_kernel::ipo::SpindleModel::new(
        md.plc.spindle_acceleration,
        f64::from(md.ipo.cycle_us) * 1e-6,
    );
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
            ch.set_spindle_actual(drive.follow(sp.spindle));
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
    (events, k, (*sp).clone())
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
        let (events, cycles, _) = run(inputs, start, &md);
        assert!(cycles > 10_000, "{cycles}");
        assert_eq!(
            events, 0,
            "{events} allocator calls over {cycles} cycles and {n} records"
        );
    }
    eight_axes_through_the_ipo_without_the_allocator();
    a_lathe_at_constant_surface_speed_without_the_allocator();
}

/// Facing and turning on the 808D lathe under G96/G95 (docs/spindle.md). Called from the
/// test above, as the eight-axis run.
fn a_lathe_at_constant_surface_speed_without_the_allocator() {
    let md = MachineData::load(
        Some(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("config/siemens-808d.toml")),
        &[],
    )
    .unwrap();
    let text = "G18 G90 G95 G0 X82 Z0\nG96 S200 LIMS=3000 M3\nG1 X0 F0.3\nG0 Z2\n\
                X60\nG1 Z-20 F0.25\nX82\nG97 S800 M4\nG0 Z5\nM5\nM30\n";
    let (inputs, start) = inputs(text, &md);
    let (events, cycles, last) = run(inputs, start, &md);
    assert!(cycles > 5_000, "{cycles}");
    assert_eq!(events, 0, "{events} allocator calls over {cycles} cycles");
    assert_eq!(last.spindle, 0.0, "stopped at the end");
}

/// A machine with eight path axes: X Y Z U V A B C.
const EIGHT_AXES: &str = "dialect = \"fanuc\"\n\
    [program]\ndecimal_input = \"calculator\"\n\
    [axes.X]\nmax_velocity = 15000\nmax_acceleration = 3000\nmax_jerk = 60000\n\
    [axes.Y]\nmax_velocity = 15000\nmax_acceleration = 3000\nmax_jerk = 60000\n\
    [axes.Z]\nmax_velocity = 10000\nmax_acceleration = 2000\nmax_jerk = 50000\n\
    [axes.U]\nmax_velocity = 6000\nmax_acceleration = 1000\nmax_jerk = 20000\n\
    software_limits = [-100.0, 100.0]\n\
    [axes.V]\nmax_velocity = 6000\nmax_acceleration = 1000\nmax_jerk = 20000\n\
    [axes.A]\nkind = \"rotary\"\nmax_velocity = 5400\nmax_acceleration = 600\n\
    max_jerk = 12000\nsoftware_limits = [-120.0, 30.0]\n\
    [axes.B]\nkind = \"rotary\"\nmax_velocity = 5400\nmax_acceleration = 600\n\
    max_jerk = 12000\n\
    [axes.C]\nkind = \"rotary\"\nmodulo = true\nshortest_way = true\nmax_velocity = 7200\n\
    max_acceleration = 900\nmax_jerk = 15000\n";

const PROGRAM: &str = "G90 G0 X0 Y0 Z0 U0 V0 A0 B0 C0\n\
    G1 X40 Y20 Z-5 U10 V-10 A-30 B15 C200 F3000 M8\n\
    G2 X40 Y-20 Z-10 I0 J-20 U20 V0 A-60 B0 C300\n\
    G0 X60 Y0\n\
    G41 D1 G1 X80 Y0 F2000\n\
    Y40\nX60\nY0\n\
    G40 G0 X100 Y0\n\
    G1 X0 Y0 Z0 U0 V0 A0 B0 C0 F4000 M9\n\
    M30\n";

/// Every axis of eight moving together. Called from the test above: the allocator's counter
/// is one for the process, so counted runs may not overlap.
fn eight_axes_through_the_ipo_without_the_allocator() {
    let md = MachineData::from_toml_str(EIGHT_AXES, "eight.toml").unwrap();
    assert_eq!(md.axes.configured().count(), 8);
    let (inputs, start) = inputs(PROGRAM, &md);
    let (events, cycles, last) = run(inputs, start, &md);
    assert!(cycles > 5_000, "{cycles}");
    assert_eq!(events, 0, "{events} allocator calls over {cycles} cycles");
    // Back where it started (Z with D1's tool length). C takes the shorter way each time:
    // 0 → 200 is −160, shown 200 → 300 is +100 (at −60), shown 300 → 0 is +60 (at 0).
    assert_eq!((last.pos[0], last.pos[1]), (0.0, 0.0));
    assert_eq!(last.add, [0.0; 6]);
}
