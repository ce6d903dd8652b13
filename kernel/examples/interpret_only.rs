//! Interprets a program and prints the block count: a profiling target for the front end.
//! `interpret_only PROGRAM [DIALECT]`

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("usage: interpret_only PROGRAM [DIALECT]");
    let dialect = args.next().unwrap_or_else(|| "siemens-840c".into());
    let text = std::fs::read_to_string(&path).expect("readable program");
    let md = nc_kernel::MachineData::load(None, &[format!("dialect={dialect}")]).expect("machine data");
    let tools = nc_kernel::ToolTable::default();
    let mut n = 0usize;
    for b in nc_kernel::Interpreter::new(&path, &text, &md, &tools) {
        if let Err(a) = b {
            eprintln!("{a}");
            std::process::exit(1);
        }
        n += 1;
    }
    println!("{n} blocks");
}
