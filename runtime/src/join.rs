//! Two pieces of the kernel's work at once: the runtime's answer to the core's [`Join`] (the
//! core starts no thread of its own).

use nc_kernel::Join;

/// One piece in a thread of its own, the other in the caller's; one after the other where
/// no thread can be started. A panic in the thread goes on in the caller.
pub struct Threads;

impl Join for Threads {
    fn join(&self, a: &mut (dyn FnMut() + Send), b: &mut (dyn FnMut() + Send)) {
        let spawned = std::thread::scope(|s| {
            let Ok(h) = std::thread::Builder::new().spawn_scoped(s, &mut *a) else {
                return false;
            };
            b();
            if let Err(p) = h.join() {
                std::panic::resume_unwind(p);
            }
            true
        });
        if !spawned {
            a();
            b();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicU32, Ordering};

    #[test]
    fn both_pieces_run_once() {
        let (x, y) = (AtomicU32::new(0), AtomicU32::new(0));
        Threads.join(
            &mut || {
                x.fetch_add(1, Ordering::Relaxed);
            },
            &mut || {
                y.fetch_add(1, Ordering::Relaxed);
            },
        );
        assert_eq!((x.into_inner(), y.into_inner()), (1, 1));
    }
}
