//! Prepares a program (interpretation, tool length and radius compensation) and prints the
//! block and segment counts: a profiling target for block preparation.
//! `prepare_only [--threaded] [--check] PROGRAM [DIALECT] [KEY=VALUE]...` (machine data
//! overrides, e.g. `trc.bottleneck_window=0`; `--threaded`: the front in a thread of its own,
//! as `Preparation::threaded`; `--check`: the software limits and the whole-program check
//! collecting, as `softnc check` prepares, every record taken; with `--threaded` a long run
//! is checked by two workers, as there).

use nc_kernel::{Lent, Preparation, Prepared, WholeMode};

#[path = "../benches/support/join.rs"]
mod join;
use join::Scoped;

fn drain(mut prep: Preparation, check: bool) -> (u64, usize) {
    let mut segments = 0usize;
    loop {
        // Some(true): a segment; Some(false): another record; None: the end.
        let next = if check {
            // As `softnc check` takes them: segments lent.
            let item = prep.next_ref().map(|i| {
                i.map(|i| matches!(i, Lent::Segment(_) | Lent::Item(Prepared::Segment(_))))
            });
            if let Some(v) = prep.take_violations(!matches!(item, Ok(Some(_)))).first() {
                eprintln!("{v}");
                std::process::exit(1);
            }
            item
        } else {
            prep.next_segment().map(|s| s.map(|_| true))
        };
        match next {
            Ok(Some(true)) => segments += 1,
            Ok(Some(false)) => {}
            Ok(None) => break,
            Err(a) => {
                eprintln!("{a}");
                std::process::exit(1);
            }
        }
    }
    (prep.blocks(), segments)
}

fn main() {
    let mut args = std::env::args().skip(1).peekable();
    let threaded = args.next_if(|a| a == "--threaded").is_some();
    let check = args.next_if(|a| a == "--check").is_some();
    let path = args
        .next()
        .expect("usage: prepare_only [--threaded] PROGRAM [DIALECT] [KEY=VALUE]...");
    let dialect = args.next().unwrap_or_else(|| "siemens-840c".into());
    let mut md_over = vec![format!("dialect={dialect}")];
    md_over.extend(args);
    let text = std::fs::read_to_string(&path).expect("readable program");
    let md = nc_kernel::MachineData::load(None, &md_over).expect("machine data");
    let tools = nc_kernel::ToolTable::builtin();
    let (blocks, segments) = if threaded {
        std::thread::scope(|s| {
            let prep = Preparation::threaded(s, &path, &text, &md, &tools);
            drain(checked(prep, &md, check).with_join(&Scoped), check)
        })
    } else {
        let prep = Preparation::new(&path, &text, &md, &tools);
        drain(checked(prep, &md, check), check)
    };
    println!("{blocks} blocks, {segments} segments");
}

/// As `softnc check` prepares: the software limits and the whole-program check collecting.
fn checked<'a>(prep: Preparation<'a>, md: &nc_kernel::MachineData, check: bool) -> Preparation<'a> {
    if check {
        prep.with_soft_limits(md).checking_whole(WholeMode::Collect)
    } else {
        prep
    }
}
