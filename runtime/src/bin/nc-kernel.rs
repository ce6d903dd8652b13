//! nc-kernel: the NC kernel process (runtime/src/process).

fn main() -> std::process::ExitCode {
    nc_runtime::process::main(std::env::args().skip(1).collect())
}
