//! Scoped data parallelism for the hot loops (element state determination, block solves):
//! a slice split into contiguous chunks, one scoped thread per chunk, results in order.
//!
//! Results come back in the slice's order whatever the thread count, so callers that
//! reduce them sequentially stay bitwise deterministic.

/// Threads to use when the caller asks for `requested` (`0`: every core).
pub fn threads(requested: usize) -> usize {
    if requested > 0 {
        requested
    } else {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    }
}

/// `f` applied to every item of `items` on up to `nt` threads (contiguous chunks), results
/// in the items' order. One thread (or one item) runs inline without spawning.
pub fn map_mut<T: Send, R: Send>(
    items: &mut [T],
    nt: usize,
    f: impl Fn(&mut T) -> R + Sync,
) -> Vec<R> {
    if nt <= 1 || items.len() <= 1 {
        return items.iter_mut().map(f).collect();
    }
    let chunk = items.len().div_ceil(nt);
    std::thread::scope(|s| {
        let handles: Vec<_> = items
            .chunks_mut(chunk)
            .map(|c| {
                let f = &f;
                s.spawn(move || c.iter_mut().map(f).collect::<Vec<R>>())
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("parallel worker panicked"))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_keep_the_order_for_any_thread_count() {
        for nt in [1, 2, 3, 7] {
            let mut v: Vec<u64> = (0..100).collect();
            let r = map_mut(&mut v, nt, |x| {
                *x += 1;
                *x * 2
            });
            assert_eq!(r, (1..=100).map(|x| x * 2).collect::<Vec<u64>>());
            assert_eq!(v, (1..=100).collect::<Vec<u64>>());
        }
    }
}
