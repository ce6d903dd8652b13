//! Two pieces of the kernel's work at once for the benches and examples, as the runtime's
//! `Threads` joins them (the kernel's own targets cannot use the runtime crate).

/// One piece in a scoped thread, the other in the caller's.
pub struct Scoped;

impl nc_kernel::Join for Scoped {
    fn join(&self, a: &mut (dyn FnMut() + Send), b: &mut (dyn FnMut() + Send)) {
        std::thread::scope(|s| {
            s.spawn(a);
            b();
        });
    }
}
