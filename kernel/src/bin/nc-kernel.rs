//! nc-kernel: the NC kernel process (kernel/src/process).

fn main() -> std::process::ExitCode {
    nc_kernel::process::main(std::env::args().skip(1).collect())
}
