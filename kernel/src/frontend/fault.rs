//! The front end's one error type: what went wrong and the byte offset in the program text
//! where. Every part of the front end (word loop, expressions, statements, the block build)
//! returns it; the interpreter, which knows the block's line and number, turns it into an
//! [`Alarm`](crate::alarm::Alarm) in one place.

use crate::alarm::AlarmCode;

/// An alarm before it has a line and column: its code, the byte offset into the program text
/// it points at, and the message.
#[derive(Clone, Debug, PartialEq)]
pub struct Fault {
    pub code: AlarmCode,
    pub at: usize,
    pub message: String,
}

/// Boxed, so that the `Result`s on the hot path stay one word wide; a fault is built only on
/// the way to an alarm.
pub type R<T> = Result<T, Box<Fault>>;

/// Byte offsets come as usize (cursor) or u32 (stored words).
pub trait Offset {
    fn offset(self) -> usize;
}

impl Offset for usize {
    fn offset(self) -> usize {
        self
    }
}

impl Offset for u32 {
    fn offset(self) -> usize {
        self as usize
    }
}

#[cold]
pub fn fault(code: AlarmCode, at: impl Offset, message: impl Into<String>) -> Box<Fault> {
    Box::new(Fault {
        code,
        at: at.offset(),
        message: message.into(),
    })
}
