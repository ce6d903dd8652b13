//! plc-sim: the simulated PLC and axes (src/lib.rs).

use clap::Parser;

fn main() -> std::process::ExitCode {
    nc_runtime::exit(Some("plc-sim"), plc_sim::main(plc_sim::PlcArgs::parse()))
}
