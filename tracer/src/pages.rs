//! Large buffers on huge pages.
//!
//! A build writes over 100 MB of fresh memory for a scene of 600,000 spheres (the build
//! primitives, the binary and wide node arrays, the reordered primitives). The kernel
//! maps fresh memory one 4 KiB page at a time, a fault each; where it offers transparent
//! huge pages on request (Linux's `madvise` mode), memory advised with `MADV_HUGEPAGE`
//! is mapped 2 MiB at a time instead, 512 times fewer faults. Embree asks for huge pages
//! for its BVH memory the same way (`os_malloc` in its `common/sys/alloc.cpp`). The
//! effect on a first build is in `tracer/JOURNAL.md` ("Builds").
//!
//! The advice covers the 2 MiB-aligned part of a vector's spare capacity, so small
//! vectors get none. It changes how the memory is mapped, never what it holds, and
//! where the kernel refuses it (no THP, another OS) the vector keeps small pages.

/// Bytes of one transparent huge page on x86-64 Linux (and AArch64 with 4 KiB pages).
const HUGE_PAGE: usize = 2 << 20;

/// A vector with room for `capacity` items, whose buffer the kernel is asked to back
/// with huge pages (see the module docs).
pub fn vec_with_capacity<T>(capacity: usize) -> Vec<T> {
    let mut v = Vec::new();
    reserve(&mut v, capacity);
    v
}

/// [`Vec::reserve`], with the new spare capacity advised onto huge pages.
pub fn reserve<T>(v: &mut Vec<T>, additional: usize) {
    v.reserve(additional);
    let spare = v.spare_capacity_mut();
    advise(spare.as_ptr() as usize, core::mem::size_of_val(spare));
}

/// Asks for huge pages over the 2 MiB-aligned part of `[addr, addr + len)`.
#[cfg(target_os = "linux")]
fn advise(addr: usize, len: usize) {
    let start = addr.next_multiple_of(HUGE_PAGE);
    let end = addr.saturating_add(len) / HUGE_PAGE * HUGE_PAGE;
    if end > start {
        // SAFETY: `[start, end)` lies inside a live allocation of the caller's vector and
        // is page-aligned. `MADV_HUGEPAGE` only sets how the kernel maps those pages on
        // their next fault; it neither unmaps them nor changes their contents, so no
        // reference into the buffer is affected. A failure (for example a kernel without
        // transparent huge pages) leaves the small pages, so the result is ignored.
        unsafe {
            libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_addr: usize, _len: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vectors_keep_their_contents_and_capacity() {
        let mut v: Vec<u64> = vec_with_capacity(3 * HUGE_PAGE / 8);
        assert!(v.capacity() >= 3 * HUGE_PAGE / 8);
        v.extend(0..1000);
        reserve(&mut v, 5 * HUGE_PAGE / 8);
        assert!(v.capacity() >= 1000 + 5 * HUGE_PAGE / 8);
        v.extend(1000..(1000 + 5 * HUGE_PAGE as u64 / 8));
        assert!(v.iter().enumerate().all(|(i, &x)| x == i as u64));
        let small: Vec<u8> = vec_with_capacity(10);
        assert!(small.capacity() >= 10 && small.is_empty());
    }
}
