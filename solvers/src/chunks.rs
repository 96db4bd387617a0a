//! Loops over an index range in fixed chunks on a few threads: the chunks do not depend on
//! the thread count, so sums formed chunk by chunk and added in chunk order are the same
//! on any number of threads. Used by the condensed Newton's passes over the equations
//! ([`crate::condensed`]) and the energy balance ([`crate::energy`]).

/// Chunk length of the parallel loops: fixed, so sums do not depend on the thread count.
const CHUNK: usize = 1 << 15;

/// Runs `f(offset, chunks...)` over fixed chunks of the index range, on `nt` threads, and
/// returns the per-chunk results in order.
pub(crate) fn par_chunks<R: Send>(
    n: usize,
    nt: usize,
    f: impl Fn(usize, usize) -> R + Sync,
) -> Vec<R> {
    let nch = n.div_ceil(CHUNK).max(1);
    let run = |c: usize| f(c * CHUNK, ((c + 1) * CHUNK).min(n));
    if nt <= 1 || nch == 1 {
        return (0..nch).map(run).collect();
    }
    let per = nch.div_ceil(nt);
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..nt)
            .map(|t| {
                let run = &run;
                s.spawn(move || {
                    (t * per..((t + 1) * per).min(nch))
                        .map(run)
                        .collect::<Vec<R>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("parallel worker panicked"))
            .collect()
    })
}

/// A raw view of a vector that parallel chunks write disjoint ranges of.
#[derive(Clone, Copy)]
pub(crate) struct Shared(pub(crate) *mut f64);
// SAFETY: every use writes only indices of its own chunk (disjoint ranges).
unsafe impl Send for Shared {}
unsafe impl Sync for Shared {}
impl Shared {
    /// # Safety
    /// `lo..hi` must be in bounds and written by no other thread at the same time.
    pub(crate) unsafe fn range(self, lo: usize, hi: usize) -> &'static mut [f64] {
        std::slice::from_raw_parts_mut(self.0.add(lo), hi - lo)
    }
}
