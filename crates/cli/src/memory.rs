//! Large freed blocks go back to the system (glibc).
//!
//! glibc raises its mmap threshold each time a large block is freed (up to 32 MB), after
//! which the lists and histories a neighbour rebuild frees and allocates again come from
//! the heap, where freed memory of one thread's arena stays resident: the 3D bench's
//! peak resident memory was 1.8 kB per sphere on the 50 k bed while the live heap never
//! passed 1.1 kB. A fixed threshold keeps every block of 128 kB or more in a mapping of
//! its own, unmapped when it is freed.

/// Fixes the allocator's mmap threshold at its default (which turns off the raising).
#[cfg(target_env = "gnu")]
#[allow(unsafe_code)]
pub fn return_large_blocks() {
    // SAFETY: mallopt sets an allocator parameter; called first thing in main, before
    // any other thread exists.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 128 * 1024);
    }
}

/// Other allocators keep their own policy.
#[cfg(not(target_env = "gnu"))]
pub fn return_large_blocks() {}
