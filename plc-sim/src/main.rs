//! plc-sim: the simulated PLC and axes (src/lib.rs).

fn main() -> std::process::ExitCode {
    plc_sim::main(std::env::args().skip(1).collect())
}
