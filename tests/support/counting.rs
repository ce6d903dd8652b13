//! A global allocator that counts allocations, reallocations and frees made by the threads
//! that switched counting on: the check that a real-time path never touches the heap.
#![allow(dead_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

pub struct Counting;

static EVENTS: AtomicU64 = AtomicU64::new(0);

thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
}

fn count() {
    if COUNTING.with(|c| c.get()) {
        EVENTS.fetch_add(1, Ordering::Relaxed);
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        count();
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// Runs `f` with counting on in this thread; returns its result and the allocator calls it
/// made.
pub fn counted<R>(f: impl FnOnce() -> R) -> (R, u64) {
    let before = EVENTS.load(Ordering::Relaxed);
    COUNTING.with(|c| c.set(true));
    let r = f();
    COUNTING.with(|c| c.set(false));
    (r, EVENTS.load(Ordering::Relaxed) - before)
}

/// The counter sees this thread's allocations: a check that can fail.
pub fn self_test() {
    let ((), n) = counted(|| drop(std::hint::black_box(vec![1u8; 16])));
    assert_eq!(n, 2, "one allocation and one free");
}
