fn main() -> std::process::ExitCode {
    hmi_bridge::main(std::env::args().skip(1).collect())
}
