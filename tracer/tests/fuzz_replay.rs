//! Replays the fuzzing corpora (`tracer/fuzz/corpus/`) and every input the fuzzer ever
//! found a fault with (`tracer/fuzz/regressions/`) through the scene readers, as the
//! fuzz targets feed them (`tracer/fuzz/src/lib.rs`): no input may panic, take more
//! than a second, or allocate more than a fixed amount plus a multiple of its size.

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use tracer::scene::{parse_nff_for, parse_obj, ObjOptions, Precision};

/// The system allocator, keeping the bytes in use and their peak.
struct Counting;

static IN_USE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

impl Counting {
    fn add(size: usize) {
        let now = IN_USE.fetch_add(size, Ordering::Relaxed) + size;
        PEAK.fetch_max(now, Ordering::Relaxed);
    }
}

// SAFETY: every method forwards to `System` with the caller's arguments, so `System`'s
// guarantees hold; the counters do not affect the memory handed out.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        Self::add(layout.size());
        // SAFETY: the caller upholds `alloc`'s contract, which `System.alloc` shares.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        IN_USE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: `ptr` was allocated by `System` (through `alloc`) with `layout`.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        Self::add(layout.size());
        // SAFETY: as for `alloc`.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // Counted as a new block before the old one goes: the peak `realloc` may need.
        Self::add(new_size);
        // SAFETY: the caller upholds `realloc`'s contract, which `System.realloc` shares.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            IN_USE.fetch_sub(new_size, Ordering::Relaxed);
        } else {
            IN_USE.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// The NFF target: the input read in both precisions.
fn nff(data: &[u8]) {
    for precision in [Precision::F32, Precision::F64] {
        let _ = parse_nff_for(data, "fuzz.nff", precision);
    }
}

/// The OBJ target: the bytes before the first NUL are the OBJ file, those after it the
/// contents of every material library it names.
fn obj(data: &[u8]) {
    let (obj, mtl) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &[][..]),
    };
    for precision in [Precision::F32, Precision::F64] {
        let library = |_: &str| Ok(mtl.to_vec());
        let _ = parse_obj(obj, "fuzz.obj", &ObjOptions::default(), precision, library);
    }
}

/// A fuzz target's entry point.
type Target = fn(&[u8]);

fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = match std::fs::read_dir(dir) {
        Ok(entries) => entries
            .map(|e| e.unwrap().path())
            .filter(|p| p.is_file() && p.file_name().is_some_and(|n| n != "README.md"))
            .collect(),
        Err(_) => Vec::new(),
    };
    out.sort();
    out
}

/// Most bytes an input of `len` bytes may have in use at once: 16 MiB for the tables of
/// a scene, plus what gzip data could inflate to (deflate's ratio is at most about
/// 1032:1) and what the reader keeps per input byte.
fn allocation_bound(len: usize) -> usize {
    (16 << 20) + 1100 * len
}

/// Every corpus and regression input of both targets. One test, so that no other test
/// of this binary allocates while an input is measured.
#[test]
fn fuzz_corpora_replay_without_panic_in_bounded_time_and_memory() {
    let fuzz = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    let targets: [(&str, Target); 2] = [("nff", nff), ("obj", obj)];
    let mut replayed = 0;
    for (name, target) in targets {
        let inputs: Vec<PathBuf> = ["corpus", "regressions"]
            .iter()
            .flat_map(|kind| files(&fuzz.join(kind).join(name)))
            .collect();
        assert!(
            inputs.len() >= 5,
            "{name}: the corpus is missing ({} inputs)",
            inputs.len()
        );
        for path in inputs {
            let data = std::fs::read(&path).unwrap();
            let base = IN_USE.load(Ordering::Relaxed);
            PEAK.store(base, Ordering::Relaxed);
            let start = Instant::now();
            let outcome = std::panic::catch_unwind(|| target(&data));
            let elapsed = start.elapsed();
            let peak = PEAK.load(Ordering::Relaxed) - base;
            assert!(outcome.is_ok(), "{}: panicked", path.display());
            assert!(
                elapsed < Duration::from_secs(1),
                "{}: took {elapsed:?}",
                path.display()
            );
            assert!(
                peak <= allocation_bound(data.len()),
                "{}: {peak} bytes in use for {} input bytes",
                path.display(),
                data.len()
            );
            replayed += 1;
        }
    }
    assert!(replayed >= 10);
}
