//! All the threading of the tracer: the three schedulers that spread a grid of work over
//! threads ([`for_each_point`]), the thread pool of a render ([`with_threads`]), a
//! parallel loop over a slice ([`for_each_mut`]), a parallel fill ([`filled`]) and the
//! [`Progress`] the workers report to.
//!
//! The schedulers ([`Scheduler`]): rayon's work stealing over rows (like TBB), a static
//! partition into one contiguous block of rows per thread over `std::thread::scope` (like
//! OpenMP `schedule(static)`), or a dynamic queue of square tiles that threads take from
//! an atomic counter. Every point is computed by the same sequential code whatever thread
//! runs it, and ray counts are summed as integers, so the results are identical bit for
//! bit for any thread count and any scheduler.

use crate::settings::{Schedule, Scheduler};
use crate::stats::RayCounts;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Progress of a render, for a front end to show. A render calls
/// [`add_rows`](Progress::add_rows) as each pass over the image begins (a supersampled
/// render makes several passes; packet passes count rows of blocks),
/// [`advance`](Progress::advance) from the worker threads as rows are done, and
/// [`finish`](Progress::finish) at the end. `()` shows nothing.
pub trait Progress: Sync {
    /// `rows` more rows are to be traced.
    fn add_rows(&self, rows: u64);
    /// `rows` more rows are done.
    fn advance(&self, rows: u64);
    /// The render is done.
    fn finish(&self);
}

impl Progress for () {
    fn add_rows(&self, _: u64) {}
    fn advance(&self, _: u64) {}
    fn finish(&self) {}
}

/// The tiles one thread computed (index, values in row-major order) and its ray counts.
type TilesDone<V> = (Vec<(usize, Vec<V>)>, RayCounts);

/// Computes `f(x, y, counts)` for every point of a `w` x `h` grid with `schedule` on
/// `threads` threads (`None`: all cores; rayon uses the current pool), returning the
/// values in row-major order and the summed ray counts, and advancing `progress` by one
/// per row. The value of a point does not depend on the scheduler or the thread that
/// computes it.
pub fn for_each_point<V, F>(
    (w, h): (usize, usize),
    schedule: Schedule,
    threads: Option<usize>,
    progress: &dyn Progress,
    f: F,
) -> (Vec<V>, RayCounts)
where
    V: Copy + Default + Send,
    F: Fn(usize, usize, &mut RayCounts) -> V + Sync,
{
    let mut out: Vec<V> = filled(w * h);
    if w == 0 || h == 0 {
        return (out, RayCounts::default());
    }
    let threads = threads.unwrap_or_else(rayon::current_num_threads).max(1);
    let counts = match schedule.scheduler {
        Scheduler::Rayon => out
            .par_chunks_mut(w)
            .enumerate()
            .map(|(y, row)| {
                let mut counts = RayCounts::default();
                for (x, v) in row.iter_mut().enumerate() {
                    *v = f(x, y, &mut counts);
                }
                progress.advance(1);
                counts
            })
            .reduce(RayCounts::default, |a, b| a + b),
        Scheduler::Static => {
            let rows_per = h.div_ceil(threads);
            std::thread::scope(|s| {
                let handles: Vec<_> = out
                    .chunks_mut(rows_per * w)
                    .enumerate()
                    .map(|(k, block)| {
                        let f = &f;
                        s.spawn(move || {
                            let mut counts = RayCounts::default();
                            for (r, row) in block.chunks_mut(w).enumerate() {
                                let y = k * rows_per + r;
                                for (x, v) in row.iter_mut().enumerate() {
                                    *v = f(x, y, &mut counts);
                                }
                                progress.advance(1);
                            }
                            counts
                        })
                    })
                    .collect();
                handles
                    .into_iter()
                    .map(|t| t.join().expect("a render thread panicked"))
                    .fold(RayCounts::default(), |a, b| a + b)
            })
        }
        Scheduler::Tiles => {
            let t = schedule.tile.max(1) as usize;
            let (tx, ty) = (w.div_ceil(t), h.div_ceil(t));
            let next = AtomicUsize::new(0);
            // Each thread keeps the tiles it computed; they are copied into place after
            // the join, so no two threads ever write the same buffer.
            let done: Vec<TilesDone<V>> = std::thread::scope(|s| {
                let handles: Vec<_> = (0..threads)
                    .map(|_| {
                        let (f, next) = (&f, &next);
                        s.spawn(move || {
                            let mut counts = RayCounts::default();
                            let mut tiles = Vec::new();
                            loop {
                                let k = next.fetch_add(1, Ordering::Relaxed);
                                if k >= tx * ty {
                                    break;
                                }
                                let (x0, y0) = ((k % tx) * t, (k / tx) * t);
                                let (x1, y1) = ((x0 + t).min(w), (y0 + t).min(h));
                                let mut vals = Vec::with_capacity((x1 - x0) * (y1 - y0));
                                for y in y0..y1 {
                                    for x in x0..x1 {
                                        vals.push(f(x, y, &mut counts));
                                    }
                                }
                                tiles.push((k, vals));
                            }
                            (tiles, counts)
                        })
                    })
                    .collect();
                handles
                    .into_iter()
                    .map(|t| t.join().expect("a render thread panicked"))
                    .collect()
            });
            let mut counts = RayCounts::default();
            for (tiles, c) in done {
                counts += c;
                for (k, vals) in tiles {
                    let (x0, y0) = ((k % tx) * t, (k / tx) * t);
                    let tw = (x0 + t).min(w) - x0;
                    for (r, row) in vals.chunks(tw).enumerate() {
                        let at = (y0 + r) * w + x0;
                        out[at..at + tw].copy_from_slice(row);
                    }
                }
            }
            progress.advance(h as u64);
            counts
        }
    };
    (out, counts)
}

/// Runs `run` with the thread count `threads` (`None`: the current pool) on a rayon
/// pool of that many threads: the rayon scheduler traces on it, the others start their
/// own threads for the tracing, and the render's parallel set-up and gathering of the
/// values ([`for_each_mut`], the image's own loops) run on it.
///
/// # Panics
/// If a thread pool with the requested number of threads cannot be created.
pub fn with_threads<R: Send>(threads: Option<usize>, run: impl FnOnce() -> R + Send) -> R {
    match threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .expect("cannot create the rendering thread pool")
            .install(run),
        _ => run(),
    }
}

/// Items of type `V` per parallel task when a large buffer is filled or copied: 256 KiB
/// (64 pages), so that the tasks stay few.
pub fn page_work<V>() -> usize {
    (256 * 1024 / core::mem::size_of::<V>().max(1)).max(1)
}

/// `n` default values, written on the current rayon pool in tasks of [`page_work`]
/// items, so that the pages of a large buffer are first touched on every thread rather
/// than one after the other.
pub fn filled<V: Default + Send>(n: usize) -> Vec<V> {
    (0..n)
        .into_par_iter()
        .with_min_len(page_work::<V>())
        .map(|_| V::default())
        .collect()
}

/// Runs `f(i, &mut items[i])` for every item on the current rayon pool, in tasks of at
/// least `min_len` items.
pub fn for_each_mut<V: Send>(items: &mut [V], min_len: usize, f: impl Fn(usize, &mut V) + Sync) {
    items
        .par_iter_mut()
        .enumerate()
        .with_min_len(min_len.max(1))
        .for_each(|(i, v)| f(i, v));
}
