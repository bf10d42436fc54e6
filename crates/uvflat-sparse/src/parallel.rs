//! Parallel loops that run on the calling thread when the input is small. A rayon call made
//! from outside rayon's pool hands its job to a pool thread and sleeps until it is done: a
//! thread wake-up each way, 10–20 µs, more than a small input's work. Measured on a
//! 2-triangle mesh: `uvf_mesh_info` took 58 µs, nearly all of it in four such hand-overs
//! (`perf`: futex waits in rayon's `LockLatch`), and the Blender add-on makes a few calls per
//! island — thousands of islands when every edge is a seam.

use rayon::prelude::*;

/// Inputs with fewer items than this run sequentially (rayon's splitting would not give them
/// more than one task of this size anyway).
pub const SEQUENTIAL_BELOW: usize = 4096;

/// `rayon::join(a, b)` for `items` items of work, or `a` then `b` on this thread below
/// [`SEQUENTIAL_BELOW`].
pub fn join<RA: Send, RB: Send>(
    items: usize,
    a: impl FnOnce() -> RA + Send,
    b: impl FnOnce() -> RB + Send,
) -> (RA, RB) {
    if items < SEQUENTIAL_BELOW {
        (a(), b())
    } else {
        rayon::join(a, b)
    }
}

/// `f(0), …, f(n − 1)`, in parallel from [`SEQUENTIAL_BELOW`] on.
pub fn map_range<R: Send>(n: usize, f: impl Fn(usize) -> R + Sync + Send) -> Vec<R> {
    if n < SEQUENTIAL_BELOW {
        (0..n).map(f).collect()
    } else {
        (0..n).into_par_iter().with_min_len(SEQUENTIAL_BELOW).map(f).collect()
    }
}

/// The first index whose item satisfies `f`, in parallel from [`SEQUENTIAL_BELOW`] items on.
pub fn position_first<T: Sync>(items: &[T], f: impl Fn(&T) -> bool + Sync + Send) -> Option<usize> {
    if items.len() < SEQUENTIAL_BELOW {
        items.iter().position(f)
    } else {
        items.par_iter().with_min_len(SEQUENTIAL_BELOW).position_first(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_and_large_inputs_give_the_same_results() {
        for n in [0, 5, SEQUENTIAL_BELOW + 7] {
            let squares = map_range(n, |i| i * i);
            assert_eq!(squares, (0..n).map(|i| i * i).collect::<Vec<_>>());
            let items: Vec<usize> = (0..n).collect();
            assert_eq!(position_first(&items, |&x| x == n / 2 && n > 0), (n > 0).then_some(n / 2));
            assert_eq!(join(n, || n + 1, || n + 2), (n + 1, n + 2));
        }
    }
}
