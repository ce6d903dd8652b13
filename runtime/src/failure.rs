//! How every softnc program ends when it does not succeed: one error type, and the one
//! function that makes it an exit status (docs/alarms.md, "Exit status": 0 success, 1 an
//! alarm or a failed run, 2 a usage or configuration error).

use std::process::ExitCode;

/// Why a command of `softnc`, or a process of the control, ends without success.
#[derive(Debug, PartialEq)]
pub enum Failure {
    /// Exit status 2: bad arguments, machine data, a tool table or a file; a control that
    /// cannot be set up or reached, or that fails under the command.
    Error(String),
    /// Exit status 1: the work was refused or did not get to its end, for this reason.
    Failed(String),
    /// Exit status 1: the work stopped with an alarm, and the diagnostics (or a summary)
    /// have said so already.
    Reported,
}

impl From<String> for Failure {
    fn from(m: String) -> Failure {
        Failure::Error(m)
    }
}

impl From<&str> for Failure {
    fn from(m: &str) -> Failure {
        Failure::Error(m.to_string())
    }
}

/// The exit status of a program's outcome; the reason, if any, goes to stderr as
/// `error: …`, after `who: ` for a process of the control (its log may be one of several).
pub fn exit(who: Option<&str>, outcome: Result<(), Failure>) -> ExitCode {
    let say = |m: &str| match who {
        Some(w) => eprintln!("{w}: error: {m}"),
        None => eprintln!("error: {m}"),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Error(m)) => {
            say(&m);
            ExitCode::from(2)
        }
        Err(Failure::Failed(m)) => {
            say(&m);
            ExitCode::from(1)
        }
        Err(Failure::Reported) => ExitCode::from(1),
    }
}
