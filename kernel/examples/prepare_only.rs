//! Prepares a program (interpretation, tool length and radius compensation) and prints the
//! block and segment counts: a profiling target for block preparation.
//! `prepare_only PROGRAM [DIALECT] [KEY=VALUE]...` (machine data overrides, e.g.
//! `trc.bottleneck_window=0`)

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("usage: prepare_only PROGRAM [DIALECT]");
    let dialect = args.next().unwrap_or_else(|| "siemens-840c".into());
    let mut md_over = vec![format!("dialect={dialect}")];
    md_over.extend(args);
    let text = std::fs::read_to_string(&path).expect("readable program");
    let md = nc_kernel::MachineData::load(None, &md_over).expect("machine data");
    let tools = nc_kernel::ToolTable::builtin();
    let mut segments = 0usize;
    let mut prep = nc_kernel::Preparation::new(&path, &text, &md, &tools);
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
    println!("{} blocks, {segments} segments", prep.blocks());
}
