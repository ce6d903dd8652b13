//! Wall-clock timing of block preparation on the 1 M-block serpentine of the prep bench:
//! `prep_timing [WINDOW] [RUNS]` prints min and median of RUNS runs (default 3, 7) with the
//! bottleneck window off (interpretation and compensation, the nearest to the front alone),
//! and with WINDOW in one thread and with the front in a thread of its own. Made for comparing two builds on a noisy machine: copy
//! each build's binary aside and alternate single runs of the two (`prep_timing 3 1`), so
//! that both see the same neighbours (docs/benchmarks.md).
use nc_kernel::synthetic::{compensated_program, Header};
use nc_kernel::{MachineData, Preparation, ToolTable};
use std::time::Instant;

fn drain(mut p: Preparation) -> usize {
    let mut n = 0;
    while let Some(s) = p.next_segment().expect("no alarm") {
        n += 1;
        std::hint::black_box(s);
    }
    n
}

fn main() {
    let mut a = std::env::args().skip(1);
    let window: usize = a.next().map_or(3, |s| s.parse().expect("window"));
    let runs: usize = a.next().map_or(7, |s| s.parse().expect("runs"));
    let text = compensated_program(1_000_000, Header::Softnc);
    let md = MachineData::load(None, &[format!("trc.bottleneck_window={window}")]).unwrap();
    let tools = ToolTable::builtin();
    let off = MachineData::load(None, &["trc.bottleneck_window=0".to_string()]).unwrap();
    time("window 0 one thread", runs, || {
        drain(Preparation::new("b", &text, &off, &tools))
    });
    time(&format!("window {window} one thread"), runs, || {
        drain(Preparation::new("b", &text, &md, &tools))
    });
    time(&format!("window {window} threaded"), runs, || {
        std::thread::scope(|s| drain(Preparation::threaded(s, "b", &text, &md, &tools)))
    });
}

/// Runs `f` `runs` times and prints the fastest and the median run.
fn time(label: &str, runs: usize, mut f: impl FnMut() -> usize) {
    let mut t: Vec<f64> = (0..runs)
        .map(|_| {
            let t0 = Instant::now();
            let segments = f();
            assert!(segments > 1_000_000, "{label}: {segments} segments");
            t0.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    t.sort_by(f64::total_cmp);
    println!("{label}: min {:.1} ms median {:.1} ms", t[0], t[runs / 2]);
}
