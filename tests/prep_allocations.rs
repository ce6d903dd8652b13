//! Block preparation allocates nothing per block: a counting global allocator sees the same
//! number of allocations for a 2 000-block and a 20 000-block program (issue 3: "nothing is
//! allocated per block"; the IPO path of issue 5 relies on it).
//! One test in this file: the counter is process-wide.

use nc_kernel::synthetic::{compensated_program, Header};
use nc_kernel::{MachineData, Preparation, ToolTable};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicU64, Ordering};

struct Counting;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made while preparing the whole program (the text is made before counting).
fn allocations(blocks: usize, dialect: &str) -> (u64, u64) {
    let text = compensated_program(blocks, Header::Softnc);
    let md = MachineData::load(None, &[format!("dialect={dialect}")]).unwrap();
    let tools = ToolTable::builtin();
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    let mut prep = Preparation::new("alloc", &text, &md, &tools);
    let mut segments = 0u64;
    while let Some(_s) = prep.next_segment().expect("no alarm") {
        segments += 1;
    }
    (ALLOCATIONS.load(Ordering::Relaxed) - before, segments)
}

#[test]
fn preparation_does_not_allocate_per_block() {
    for dialect in ["siemens-840c", "isg", "fanuc", "siemens-808d"] {
        // One-time lazy initialisation in std is not the preparation's doing.
        allocations(10, dialect);
        let (small, s1) = allocations(2_000, dialect);
        let (large, s2) = allocations(20_000, dialect);
        assert!(
            s2 > 9 * s1,
            "{dialect}: the larger program really is larger"
        );
        assert!(
            small == large && large <= 2,
            "{dialect}: {small} allocations for 2 000 blocks, {large} for 20 000"
        );
    }
}
