//! Command-line arguments of the control's processes: one clap definition per process, taken
//! by its own binary and by `softnc <process>` alike (nc-kernel's here, plc-sim's and
//! hmi-bridge's in their crates), and the parts they share.

use nc_kernel::{MachineData, ToolTable};
use softnc_protocol::Instance;
use std::path::{Path, PathBuf};

/// `--instance NAME`: a name iceoryx2's files can carry.
pub fn instance(name: &str) -> Result<Instance, String> {
    Instance::new(name).map_err(|e| e.to_string())
}

/// `--priority P`: a SCHED_FIFO priority.
pub fn priority(p: &str) -> Result<i32, String> {
    match p.parse::<i32>() {
        Ok(x) if (1..=99).contains(&x) => Ok(x),
        _ => Err("expected 1 to 99".into()),
    }
}

/// `--machine FILE` over the built-in machine data.
pub fn machine(file: Option<&Path>) -> Result<MachineData, String> {
    MachineData::load(file, &[]).map_err(|e| e.to_string())
}

/// What plc-sim and hmi-bridge take to find their control: its instance and machine data.
#[derive(clap::Args, Clone, Debug)]
pub struct ControlArgs {
    /// The control's instance: the prefix of its services and shared memory.
    #[arg(long, value_name = "NAME", value_parser = instance, default_value = softnc_protocol::DEFAULT_INSTANCE)]
    pub instance: Instance,
    /// Machine data file (TOML); built-in 840C milling machine if not given.
    #[arg(long, value_name = "FILE")]
    pub machine: Option<PathBuf>,
}

/// The NC kernel on the live clock: preparation thread, lock-free queue, cyclic IPO thread
/// (SCHED_FIFO, locked memory, absolute deadlines).
///
/// With --instance it is a process of the control, talking to plc-sim and the HMI over
/// iceoryx2. Without, it runs PROGRAM alone (no PLC: auxiliary functions are acknowledged at
/// once) and prints the IPO thread's wake-up latency and compute time.
#[derive(clap::Parser, Debug)]
#[command(name = "nc-kernel", arg_required_else_help = true)]
pub struct KernelArgs {
    /// The part program: loaded at start-up with --instance, run alone without.
    #[arg(value_name = "PROGRAM")]
    pub program: Option<PathBuf>,
    /// Run as a process of this instance of the control.
    #[arg(long, value_name = "NAME", value_parser = instance)]
    pub instance: Option<Instance>,
    /// NC start once the PLC is there (with --instance).
    #[arg(long)]
    pub start: bool,
    /// Machine data file (TOML); built-in 840C milling machine if not given.
    #[arg(long, value_name = "FILE")]
    pub machine: Option<PathBuf>,
    /// Tool offset file (TOML), where offset edits are also saved; built-in table if not
    /// given.
    #[arg(long, value_name = "FILE")]
    pub tools: Option<PathBuf>,
    /// Override the radius of offset n, e.g. `--set D1=10.0`.
    #[arg(long = "set", value_name = "Dn=R")]
    pub set: Vec<String>,
    /// Work-offset file (TOML), where work-offset edits are also saved; all zero and not
    /// saved if not given.
    #[arg(long, value_name = "FILE")]
    pub offsets: Option<PathBuf>,
    /// Kept macro variables #500 … #999 (TOML, docs/fanuc.md): read at each program load,
    /// written when a program's preparation ends; none and not written if not given.
    #[arg(long, value_name = "FILE")]
    pub macro_variables: Option<PathBuf>,
    /// Record every input the kernel takes, with its cycle, to FILE (with --instance;
    /// docs/interfaces.md, "Record and replay"); `softnc simulate --replay FILE` replays it.
    #[arg(long, value_name = "FILE", requires = "instance")]
    pub record: Option<PathBuf>,
    /// With --record: also write the live setpoints to FILE, as `softnc simulate` writes
    /// them.
    #[arg(long, value_name = "FILE", requires = "record")]
    pub setpoints: Option<PathBuf>,
    /// The IPO thread's SCHED_FIFO priority, 1 to 99.
    #[arg(long, value_name = "P", value_parser = priority, default_value_t = 80)]
    pub priority: i32,
    /// Stop after this many seconds (alone).
    #[arg(long, value_name = "S", value_parser = seconds)]
    pub seconds: Option<f64>,
    /// Write the wake-up latency histogram to FILE, in cyclictest's format (alone).
    #[arg(long, value_name = "FILE")]
    pub histogram: Option<PathBuf>,
}

fn seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        _ => Err("expected a positive number".into()),
    }
}

impl KernelArgs {
    /// `--tools` (or the built-in table) with every `--set` applied.
    pub fn tool_table(&self) -> Result<ToolTable, String> {
        let mut tools = match &self.tools {
            Some(p) => ToolTable::load(p).map_err(|e| e.to_string())?,
            None => ToolTable::builtin(),
        };
        for s in &self.set {
            tools.apply_set(s)?;
        }
        Ok(tools)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[test]
    fn the_kernels_arguments_as_tests_and_scripts_give_them() {
        let a = KernelArgs::try_parse_from([
            "nc-kernel",
            "--instance",
            "shop",
            "prog.mpf",
            "--start",
            "--set",
            "D1=10",
            "--set",
            "D2=5",
            "--priority",
            "80",
        ])
        .unwrap();
        assert_eq!(
            a.instance.map(|i| i.name().to_string()),
            Some("shop".into())
        );
        assert_eq!(a.program, Some(PathBuf::from("prog.mpf")));
        assert!(a.start);
        assert_eq!(a.set, ["D1=10", "D2=5"]);
        assert_eq!(a.priority, 80);
        let a = KernelArgs::try_parse_from(["nc-kernel", "p.nc", "--seconds", "2.5"]).unwrap();
        assert_eq!((a.instance.is_none(), a.seconds), (true, Some(2.5)));
        for bad in [
            &["nc-kernel", "--priority", "0"][..],
            &["nc-kernel", "--seconds", "-1"],
            &["nc-kernel", "--instance", "a/b"],
            &["nc-kernel", "a.mpf", "b.mpf"],
            &["nc-kernel", "--bogus"],
        ] {
            assert!(KernelArgs::try_parse_from(bad).is_err(), "{bad:?}");
        }
    }
}
