//! Parse + interpretation throughput on a generated 1 M-block line/arc program
//! (docs/benchmarks.md). Run: `cargo bench -p nc-kernel --bench frontend`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use nc_kernel::{synthetic, Interpreter, MachineData, ToolTable};
use std::hint::black_box;

const BLOCKS: usize = 1_000_000;

fn frontend(c: &mut Criterion) {
    let text = synthetic::line_arc_program(BLOCKS);
    let tools = ToolTable::default();
    let mut group = c.benchmark_group("frontend");
    group.throughput(Throughput::Elements(BLOCKS as u64));
    group.sample_size(20);
    group.measurement_time(std::time::Duration::from_secs(20));
    for dialect in ["siemens-840c", "isg", "fanuc"] {
        let md = MachineData::load(None, &[format!("dialect={dialect}")]).expect("machine data");
        group.bench_function(format!("interpret_1M_{dialect}"), |b| {
            b.iter(|| {
                let mut n = 0usize;
                let mut sum = 0.0;
                let mut interp = Interpreter::new("bench", black_box(&text), &md, &tools);
                while let Some(block) = interp.next_block().expect("no alarm") {
                    if let Some(m) = &block.motion {
                        sum += m.end[0];
                    }
                    n += 1;
                }
                black_box((n, sum))
            })
        });
    }
    group.finish();
}

criterion_group!(benches, frontend);
criterion_main!(benches);
