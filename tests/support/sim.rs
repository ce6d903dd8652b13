//! `softnc simulate` in a test: a program's CSV setpoint stream on the built-in tool table,
//! and its columns by name.

#![allow(dead_code)] // each test file uses a different part

use nc_kernel::simulate::{run, Options, Summary};
use nc_kernel::{MachineData, ToolTable};

/// The CSV (header first) and the run's summary.
pub fn csv(md: &MachineData, text: &str) -> (String, Summary) {
    let mut out = Vec::new();
    let s = run(
        "t.nc",
        text,
        md,
        &ToolTable::builtin(),
        &Options::default(),
        &mut out,
    )
    .expect("simulate");
    (String::from_utf8(out).expect("UTF-8"), s)
}

/// Where the column `name` is in the header line `header`.
pub fn column(header: &str, name: &str) -> usize {
    header
        .split(',')
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no column {name} in {header}"))
}
