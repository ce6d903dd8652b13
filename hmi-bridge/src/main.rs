use clap::Parser;

fn main() -> std::process::ExitCode {
    nc_runtime::exit(
        Some("hmi-bridge"),
        hmi_bridge::main(hmi_bridge::BridgeArgs::parse()),
    )
}
