//! Interprets a program and prints the block count: a profiling target for the front end.
//! `interpret_only PROGRAM [DIALECT [KEY=VALUE …]]` (machine-data overrides after the dialect)

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .expect("usage: interpret_only PROGRAM [DIALECT]");
    let dialect = args.next().unwrap_or_else(|| "siemens-840c".into());
    let text = std::fs::read_to_string(&path).expect("readable program");
    let mut overrides = vec![format!("dialect={dialect}")];
    overrides.extend(args);
    let md = nc_kernel::MachineData::load(None, &overrides).expect("machine data");
    let tools = nc_kernel::ToolTable::builtin();
    let mut n = 0usize;
    let mut interp = nc_kernel::Interpreter::new(&path, &text, &md, &tools);
    loop {
        match interp.next_block() {
            Ok(Some(_)) => n += 1,
            Ok(None) => break,
            Err(a) => {
                eprintln!("{a}");
                std::process::exit(1);
            }
        }
    }
    println!("{n} blocks");
}
