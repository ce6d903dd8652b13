//! Command-line arguments of the control's processes (nc-kernel, plc-sim, hmi-bridge), read
//! the same way by all of them.

/// The value after `flag`, if given.
pub fn value<'a>(args: &'a [String], flag: &str) -> Option<&'a str> {
    args.windows(2)
        .find(|w| w[0] == flag)
        .map(|w| w[1].as_str())
}

/// Every argument is one of `known` followed by its value.
pub fn only_flags(args: &[String], known: &[&str], usage: &str) -> Result<(), String> {
    let mut i = 0;
    while i < args.len() {
        if !known.contains(&args[i].as_str()) || i + 1 >= args.len() {
            return Err(format!("unexpected argument {}\n{usage}", args[i]));
        }
        i += 2;
    }
    Ok(())
}

/// `--priority P`: a SCHED_FIFO priority, 1 to 99.
pub fn priority(args: &[String]) -> Result<Option<i32>, String> {
    value(args, "--priority")
        .map(|p| match p.parse::<i32>() {
            Ok(x) if (1..=99).contains(&x) => Ok(x),
            _ => Err(format!("--priority {p}: expected 1 to 99")),
        })
        .transpose()
}

/// `--instance NAME`, the default instance without it.
pub fn instance(args: &[String]) -> Result<softnc_protocol::Instance, String> {
    softnc_protocol::Instance::new(
        value(args, "--instance").unwrap_or(softnc_protocol::DEFAULT_INSTANCE),
    )
    .map_err(|e| e.to_string())
}

/// `--machine FILE` over the built-in machine data.
pub fn machine(args: &[String]) -> Result<nc_kernel::MachineData, String> {
    nc_kernel::MachineData::load(value(args, "--machine").map(std::path::Path::new), &[])
        .map_err(|e| e.to_string())
}
