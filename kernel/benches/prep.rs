//! Block preparation throughput on a generated 1 M-block G41 line/arc serpentine
//! (docs/benchmarks.md). Run: `cargo bench -p nc-kernel --bench prep`.
//!
//! - `compensate_1M_<dialect>`: parse + interpretation + tool length and radius
//!   compensation, bottleneck window off.
//! - `bottleneck_1M_window_<n>`: the same with the bottleneck check over n blocks.
//! - `..._threaded`: the same with the interpreter in a thread of its own
//!   (`Preparation::threaded`): two cores busy.
//! - `corners/<contour>_1M_...`: the contours with a non-tangent corner at every block
//!   (roughing rows, a row of bars; `synthetic`), with the window of 64 blocks (threaded or
//!   not) and with the whole-program check as `softnc check` runs it (`WholeMode::Collect`).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use nc_kernel::synthetic::{bars_program, compensated_program, roughing_program, Header};
use nc_kernel::{MachineData, Preparation, Shape, ToolTable, WholeMode};
use std::hint::black_box;

#[path = "support/join.rs"]
mod join;
use join::Scoped;

const BLOCKS: usize = 1_000_000;

fn run(text: &str, md: &MachineData, tools: &ToolTable) -> (usize, f64) {
    drain(Preparation::new("bench", black_box(text), md, tools))
}

fn run_threaded(text: &str, md: &MachineData, tools: &ToolTable) -> (usize, f64) {
    std::thread::scope(|s| {
        drain(Preparation::threaded(
            s,
            "bench",
            black_box(text),
            md,
            tools,
        ))
    })
}

fn drain(mut prep: Preparation) -> (usize, f64) {
    let mut n = 0usize;
    let mut sum = 0.0;
    while let Some(s) = prep.next_segment().expect("no alarm") {
        sum += s.to[0];
        if let Shape::Arc { r1, .. } = s.shape {
            sum += r1;
        }
        n += 1;
    }
    (n, sum)
}

fn prep(c: &mut Criterion) {
    let text = compensated_program(BLOCKS, Header::Softnc);
    let tools = ToolTable::builtin();
    let mut group = c.benchmark_group("prep");
    group.throughput(Throughput::Elements(BLOCKS as u64));
    group.sample_size(10);
    group.measurement_time(std::time::Duration::from_secs(20));
    for dialect in ["siemens-840c", "isg", "fanuc"] {
        let md = MachineData::load(
            None,
            &[
                format!("dialect={dialect}"),
                "trc.bottleneck_window=0".into(),
            ],
        )
        .expect("machine data");
        group.bench_function(format!("compensate_1M_{dialect}"), |b| {
            b.iter(|| black_box(run(&text, &md, &tools)))
        });
    }
    for window in [0, 3, 64] {
        let md = MachineData::load(None, &[format!("trc.bottleneck_window={window}")])
            .expect("machine data");
        group.bench_function(format!("bottleneck_1M_window_{window}"), |b| {
            b.iter(|| black_box(run(&text, &md, &tools)))
        });
        group.bench_function(format!("bottleneck_1M_window_{window}_threaded"), |b| {
            b.iter(|| black_box(run_threaded(&text, &md, &tools)))
        });
    }
    group.finish();
}

/// The whole-program check as `softnc check` runs it: interpreter threaded, a long run
/// checked by two workers at once (as nc_runtime::Threads joins them).
fn run_checked(text: &str, md: &MachineData, tools: &ToolTable) -> (usize, f64) {
    std::thread::scope(|s| {
        let prep = Preparation::threaded(s, "bench", black_box(text), md, tools);
        drain(prep.checking_whole(WholeMode::Collect).with_join(&Scoped))
    })
}

fn corners(c: &mut Criterion) {
    let tools = ToolTable::builtin();
    let mut group = c.benchmark_group("corners");
    group.throughput(Throughput::Elements(BLOCKS as u64));
    group.sample_size(10);
    group.measurement_time(std::time::Duration::from_secs(20));
    let window = MachineData::load(None, &["trc.bottleneck_window=64".into()]).unwrap();
    for (name, text) in [
        ("roughing", roughing_program(BLOCKS, Header::Softnc)),
        ("bars", bars_program(BLOCKS, Header::Softnc)),
    ] {
        group.bench_function(format!("{name}_1M_window_64"), |b| {
            b.iter(|| black_box(run(&text, &window, &tools)))
        });
        group.bench_function(format!("{name}_1M_window_64_threaded"), |b| {
            b.iter(|| black_box(run_threaded(&text, &window, &tools)))
        });
        group.bench_function(format!("{name}_1M_whole_check"), |b| {
            b.iter(|| black_box(run_checked(&text, &window, &tools)))
        });
    }
    group.finish();
}

criterion_group!(benches, prep, corners);
criterion_main!(benches);
