//! IPO compute time per cycle on the simulated clock (no sleeping): every `Channel::cycle`
//! (taking input included) timed with the monotonic clock, over a long compensated program.
//! Every 5 000 cycles an operator action (override 60 % ↔ 100 %, NC stop, NC start): those
//! cycles replan, and their times are kept apart. Prints p50/p99/p99.9/max in µs.
//!
//! `ipo_timing [BLOCKS]` (default 4000 blocks of the G41 serpentine, about 1.5 M cycles)
//! `ipo_timing --axes N [BLOCKS]` (N = 3 or 8): a zig-zag of lines with a corner at every
//! block and helical arcs between, on a machine of X Y Z (3) or X Y Z U V A B C (8) where
//! every additional axis moves in every block; the same X Y Z path both ways.
//! `ipo_timing --lathe [BLOCKS]`: facing passes on the 808D lathe at constant surface speed
//! with feed per revolution (G96 G95): the spindle's setpoint follows X every cycle, a
//! model of its drive follows the setpoint, and the path speed follows the drive's actual
//! speed (replanned whenever it has changed by more than 0.5 %); those cycles count as
//! plain cycles.

use hdrhistogram::Histogram;
use nc_kernel::ipo::{Channel, ChannelState, Setpoint};
use nc_kernel::{MachineData, ToolTable};
use nc_runtime::os::now_ns;

/// Machine data with the geometry axes, and with `eight` five additional axes beside them.
fn machine(eight: bool) -> MachineData {
    let mut text = String::from("dialect = \"fanuc\"\n[program]\ndecimal_input = \"calculator\"\n");
    for (name, rotary) in [("X", false), ("Y", false), ("Z", false)]
        .into_iter()
        .chain(
            [
                ("U", false),
                ("V", false),
                ("A", true),
                ("B", true),
                ("C", true),
            ]
            .into_iter()
            .filter(|_| eight),
        )
    {
        text += &format!(
            "[axes.{name}]\nmax_velocity = 15000\nmax_acceleration = 3000\nmax_jerk = 60000\n{}",
            if rotary { "kind = \"rotary\"\n" } else { "" }
        );
    }
    MachineData::from_toml_str(&text, "ipo_timing").expect("machine data")
}

/// `blocks` moves: zig-zag lines (a corner at each) and every fourth a helical half circle;
/// with `eight`, U V A B C move in every block.
fn zigzag(blocks: usize, eight: bool) -> String {
    let mut text = String::from("G90 G0 X0 Y0 Z0\nG1 F3000\n");
    let (mut x, mut y) = (0.0, 0.0);
    for i in 0..blocks {
        let extra = if eight {
            let s = if i % 2 == 0 { 1.0 } else { -1.0 };
            format!(
                " U{} V{} A{} B{} C{}",
                5.0 * s,
                -5.0 * s,
                10.0 * s,
                4.0 * s,
                i * 7
            )
        } else {
            String::new()
        };
        if i % 4 == 3 {
            // A half circle to the same Y, the helix lead down 1.
            text += &format!("G2 X{:.3} Y{y} Z-1 I5 J0{extra}\n", x + 10.0);
            x += 10.0;
        } else {
            x += 6.0;
            y = if i % 2 == 0 { 8.0 } else { 0.0 };
            text += &format!("G1 X{x:.3} Y{y} Z0{extra}\n");
        }
    }
    text + "M30\n"
}

/// `blocks` / 3 facing passes from X80 (a diameter) to the centre, 0.5 mm deeper each, at
/// 200 m/min (limit 3000 rev/min) and 0.2 mm/rev.
fn facing(blocks: usize) -> String {
    let mut text = String::from("G18 G90 G95 G0 X82 Z0\nG96 S200 LIMS=3000 M3\n");
    for i in 0..blocks / 3 {
        let z = -0.5 * (i + 1) as f64;
        text += &format!("G0 X82 Z{z}\nG1 X0 F0.2\nG0 Z{}\n", z + 1.0);
    }
    text + "M5\nM30\n"
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--lathe") {
        let blocks = args.get(1).map_or(300, |s| s.parse().expect("BLOCKS"));
        let md = MachineData::load(Some(std::path::Path::new("config/siemens-808d.toml")), &[])
            .expect("config/siemens-808d.toml (run from the repository)");
        return time_program(&md, &facing(blocks), true);
    }
    let axes: Option<usize> = match args.first().map(String::as_str) {
        Some("--axes") => Some(
            args.get(1)
                .and_then(|a| a.parse().ok())
                .expect("--axes 3|8"),
        ),
        _ => None,
    };
    let rest = if axes.is_some() {
        &args[2..]
    } else {
        &args[..]
    };
    let blocks: usize = rest.first().map_or(4000, |s| s.parse().expect("BLOCKS"));
    let (md, text) = match axes {
        Some(n) => (machine(n == 8), zigzag(blocks, n == 8)),
        None => (
            MachineData::load(None, &nc_kernel::synthetic::unlimited_travel())
                .expect("machine data"),
            nc_kernel::synthetic::compensated_program(blocks, nc_kernel::synthetic::Header::Softnc),
        ),
    };
    time_program(&md, &text, false);
}

/// Runs `text` through the channel on the simulated clock and prints the cycle times;
/// `spindle`: a model of the spindle drive feeds the actual speed back every cycle.
fn time_program(md: &MachineData, text: &str, spindle: bool) {
    let tools = ToolTable::builtin();
    let job = nc_kernel::handover::Job {
        name: "bench",
        source: text,
        md,
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
    let mut ch = Box::new(Channel::new(md, start));
    let mut drive = nc_kernel::ipo::SpindleModel::new(
        md.plc.spindle_acceleration,
        f64::from(md.ipo.cycle_us) * 1e-6,
    );
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
        if spindle {
            ch.set_spindle_actual(drive.follow(sp.spindle));
        }
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
