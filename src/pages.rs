//! Room for big arrays (a scene file's bytes, the primitives, the BVH builder's
//! records and nodes, the tree's nodes and leaf blocks), backed by 2 MiB pages where the system offers them:
//! far fewer page faults while the arrays are first written, and far fewer TLB
//! misses while rays walk them.
//!
//! On Linux with transparent huge pages in `madvise` mode (a common default), memory
//! gets them only when asked with `madvise(MADV_HUGEPAGE)` before it is touched.
//! Elsewhere, or if the call fails, the memory is ordinary pages: nothing but speed
//! depends on it.
#![allow(unsafe_code)]

/// Arrays smaller than this are left alone: a huge page would not fit in them.
const HUGE_PAGE: usize = 2 << 20;

/// An empty vector with room for `n` items, whose memory is backed by huge pages
/// where possible (see the module's text). Fill it without exceeding `n` (by `push`,
/// `extend`, or rayon's `collect_into_vec`, which keeps the room) for the advice to
/// hold.
pub fn huge_vec<T>(n: usize) -> Vec<T> {
    let v = Vec::with_capacity(n);
    advise(v.as_ptr() as usize, n.saturating_mul(std::mem::size_of::<T>()));
    v
}

/// Asks for huge pages over the whole pages of `[start, start + bytes)`.
#[cfg(target_os = "linux")]
fn advise(start: usize, bytes: usize) {
    if bytes < HUGE_PAGE {
        return;
    }
    // The smallest page size; where pages are bigger, the kernel refuses a range
    // not aligned to them, and the memory keeps ordinary pages.
    let page = 4096;
    let (first, end) = ((start + page - 1) & !(page - 1), (start + bytes) & !(page - 1));
    // SAFETY: the range lies within one allocation this process owns and nothing has
    // been written to it yet; MADV_HUGEPAGE changes how it is backed, not its contents.
    unsafe {
        libc::madvise(first as *mut libc::c_void, end - first, libc::MADV_HUGEPAGE);
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_start: usize, _bytes: usize) {}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    /// The `VmFlags` of the mapping holding address `at`, from `/proc/self/smaps`.
    fn flags_at(at: usize) -> String {
        let smaps = std::fs::read_to_string("/proc/self/smaps").expect("Linux has /proc/self/smaps");
        let mut inside = false;
        for line in smaps.lines() {
            let range = line.split_whitespace().next().and_then(|r| r.split_once('-'));
            if let Some((lo, hi)) = range.filter(|_| !line.starts_with("VmFlags")) {
                if let (Ok(lo), Ok(hi)) = (usize::from_str_radix(lo, 16), usize::from_str_radix(hi, 16)) {
                    inside = (lo..hi).contains(&at);
                    continue;
                }
            }
            if inside && line.starts_with("VmFlags:") {
                return line.to_string();
            }
        }
        panic!("no mapping holds {at:#x}");
    }

    #[test]
    fn a_big_vector_is_advised_to_use_huge_pages() {
        let big: Vec<u64> = huge_vec(1 << 20); // 8 MiB
        let flags = flags_at(big.as_ptr() as usize + (4 << 20));
        // `hg`: the mapping was given MADV_HUGEPAGE. Kernels built without
        // transparent huge pages refuse the advice, and have no such directory.
        let supported = std::path::Path::new("/sys/kernel/mm/transparent_hugepage").exists();
        assert_eq!(flags.split_whitespace().any(|f| f == "hg"), supported, "{flags}");
        assert!(big.capacity() >= 1 << 20 && big.is_empty());
    }
}
