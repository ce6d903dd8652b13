//! nc-kernel process. The cyclic kernel (IPO thread, iceoryx2 services) is built in later
//! issues; today the binary checks machine data and a program and says what it would run.

use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--help" || a == "-h") || args.is_empty() {
        eprintln!("usage: nc-kernel PROGRAM [--machine FILE]");
        eprintln!("The cyclic kernel process is not built yet; use `softnc parse` meanwhile.");
        return ExitCode::from(2);
    }
    let program = &args[0];
    let machine = args
        .windows(2)
        .find(|w| w[0] == "--machine")
        .map(|w| std::path::PathBuf::from(&w[1]));
    let md = match nc_kernel::MachineData::load(machine.as_deref(), &[]) {
        Ok(md) => md,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    };
    let source = match std::fs::read_to_string(program) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {program}: {e}");
            return ExitCode::from(2);
        }
    };
    match nc_kernel::interpret(program, &source, &md, &nc_kernel::ToolTable::default()) {
        Ok(blocks) => {
            eprintln!(
                "nc-kernel: {} blocks interpreted; the cyclic kernel is not built yet",
                blocks.len()
            );
            ExitCode::SUCCESS
        }
        Err(a) => {
            eprintln!("{}", nc_kernel::alarm::render(&a, &source));
            ExitCode::from(1)
        }
    }
}
