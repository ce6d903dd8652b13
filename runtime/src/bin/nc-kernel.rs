//! nc-kernel: the NC kernel process (runtime/src/process).

use clap::Parser;

fn main() -> std::process::ExitCode {
    let args = nc_runtime::process::KernelArgs::parse();
    nc_runtime::exit(Some("nc-kernel"), nc_runtime::process::main(args))
}
