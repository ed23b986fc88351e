//! Transparent huge pages for the simulator's large arrays (the bodies,
//! the grid's cells, the queue's records).  At 10^5 disks these are tens
//! of megabytes read at random: with 4 KiB pages nearly every body or cell
//! a prediction reads also misses the TLB, and under a hypervisor each
//! such miss walks two page tables.  Linux backs a range with 2 MiB pages
//! when asked (`madvise(MADV_HUGEPAGE)`; the project's machines have
//! THP in "madvise" mode: nothing is backed so unless asked).  A hint
//! only: no value, no order of operations changes, so the trace is the
//! same bytes; elsewhere, or when the kernel refuses, nothing happens.
//! Asked before the pages are first written (a fresh buffer's capacity),
//! the kernel gives huge pages at once instead of collapsing small ones later.

/// Bytes in a huge page (x86-64, aarch64 with 4 KiB base pages).
#[cfg(target_os = "linux")]
const HUGE: usize = 2 << 20;

/// Below this many bytes a buffer is left alone: it holds at most one
/// whole huge page.
const WORTH: usize = 4 << 20;

/// Ask for huge pages behind the whole 2 MiB pages inside `v`'s buffer
/// (its capacity, written or not).
pub fn advise<T>(v: &Vec<T>) {
    let bytes = v.capacity().saturating_mul(std::mem::size_of::<T>());
    if bytes < WORTH {
        return;
    }
    #[cfg(target_os = "linux")]
    {
        extern "C" {
            fn madvise(addr: *mut std::ffi::c_void, len: usize, advice: i32) -> i32;
        }
        const MADV_HUGEPAGE: i32 = 14;
        let start = v.as_ptr() as usize;
        let lo = (start + HUGE - 1) & !(HUGE - 1);
        let hi = (start + bytes) & !(HUGE - 1);
        if hi > lo {
            // SAFETY: [lo, hi) lies inside the vector's own allocation
            // (anonymous memory of this process) and is page aligned;
            // MADV_HUGEPAGE changes neither its contents nor its validity,
            // only how the kernel backs it.  The result is not needed: a
            // kernel without THP answers EINVAL and nothing changes.
            unsafe {
                madvise(lo as *mut std::ffi::c_void, hi - lo, MADV_HUGEPAGE);
            }
        }
    }
}
