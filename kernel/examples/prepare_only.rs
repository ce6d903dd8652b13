//! Prepares a program (interpretation, tool length and radius compensation) and prints the
//! block and segment counts: a profiling target for block preparation.
//! `prepare_only [--threaded] PROGRAM [DIALECT] [KEY=VALUE]...` (machine data overrides, e.g.
//! `trc.bottleneck_window=0`; `--threaded`: the front in a thread of its own, as
//! `Preparation::threaded`).

use nc_kernel::Preparation;

fn drain(mut prep: Preparation) -> (u64, usize) {
    let mut segments = 0usize;
    loop {
        match prep.next_segment() {
            Ok(Some(_)) => segments += 1,
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
        std::thread::scope(|s| drain(Preparation::threaded(s, &path, &text, &md, &tools)))
    } else {
        drain(Preparation::new(&path, &text, &md, &tools))
    };
    println!("{blocks} blocks, {segments} segments");
}
