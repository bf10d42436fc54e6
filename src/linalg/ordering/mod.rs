//! Geometric nested dissection (George 1973; the vertex-separator form used by METIS-style
//! orderings): a fill-reducing elimination order for sparse systems whose unknowns have 3D
//! positions, as every mesh Laplacian's do.
//!
//! The unknowns are split at the median of their longest bounding-box axis; the unknowns of
//! the lower half that touch the upper half form a separator, numbered last; both halves are
//! ordered recursively (in parallel). On a well-shaped surface mesh of n vertices this yields
//! O(n log n) fill in the Cholesky factor, against the noticeably larger fill of minimum-degree
//! orderings on large meshes. Cost: O(n log n).

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

/// Symmetric adjacency in compressed rows, without the diagonal.
pub struct Adjacency {
    /// Row starts (`n + 1` entries).
    pub start: Vec<usize>,
    /// Neighbours.
    pub neighbors: Vec<u32>,
}

impl Adjacency {
    /// Builds the full symmetric adjacency from the lower-triangular pattern of a matrix in
    /// compressed columns (`col_ptr`, `row_idx`).
    pub fn from_lower(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Self {
        let mut degree = vec![0usize; n + 1];
        for c in 0..n {
            for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
                if r != c {
                    degree[r + 1] += 1;
                    degree[c + 1] += 1;
                }
            }
        }
        for i in 0..n {
            degree[i + 1] += degree[i];
        }
        let start = degree;
        let mut fill = start.clone();
        let mut neighbors = vec![0u32; start[n]];
        for c in 0..n {
            for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
                if r != c {
                    neighbors[fill[r]] = c as u32;
                    fill[r] += 1;
                    neighbors[fill[c]] = r as u32;
                    fill[c] += 1;
                }
            }
        }
        Adjacency { start, neighbors }
    }

    fn of(&self, v: u32) -> &[u32] {
        &self.neighbors[self.start[v as usize]..self.start[v as usize + 1]]
    }
}

/// Subproblems at most this large are ordered as they come.
const LEAF_SIZE: usize = 64;

/// Elimination order (`order[k]` = unknown eliminated k-th) by geometric nested dissection.
pub fn nested_dissection(adjacency: &Adjacency, coords: &[[f64; 3]]) -> Vec<usize> {
    let n = coords.len();
    // stamp[v]: the id of the subproblem whose upper half holds v (written only by the
    // subproblem that owns v, so parallel halves never interfere).
    let stamp: Vec<AtomicU32> = (0..n).map(|_| AtomicU32::new(0)).collect();
    let counter = AtomicU32::new(1);
    let mut all: Vec<u32> = (0..n as u32).collect();
    let mut order = Vec::with_capacity(n);
    dissect(&mut all, &Context { adjacency, coords, stamp: &stamp, counter: &counter }, &mut order);
    order.into_iter().map(|v| v as usize).collect()
}

struct Context<'a> {
    adjacency: &'a Adjacency,
    coords: &'a [[f64; 3]],
    stamp: &'a [AtomicU32],
    counter: &'a AtomicU32,
}

fn dissect(set: &mut [u32], cx: &Context, order: &mut Vec<u32>) {
    let (adjacency, coords) = (cx.adjacency, cx.coords);
    if set.len() <= LEAF_SIZE {
        order.extend_from_slice(set);
        return;
    }
    let axis = longest_axis(set, coords);
    let mid = set.len() / 2;
    set.select_nth_unstable_by(mid, |&a, &b| coords[a as usize][axis].total_cmp(&coords[b as usize][axis]));
    let id = cx.counter.fetch_add(1, Relaxed);
    for &v in &set[mid..] {
        cx.stamp[v as usize].store(id, Relaxed);
    }
    let (lower, upper) = set.split_at_mut(mid);
    let mut separator = Vec::new();
    let mut interior = Vec::with_capacity(lower.len());
    for &v in lower.iter() {
        if adjacency.of(v).iter().any(|&w| cx.stamp[w as usize].load(Relaxed) == id) {
            separator.push(v);
        } else {
            interior.push(v);
        }
    }
    let mut left_order = Vec::with_capacity(interior.len());
    let mut right_order = Vec::with_capacity(upper.len());
    if set_len_is_large(interior.len() + upper.len()) {
        rayon::join(
            || dissect(&mut interior, cx, &mut left_order),
            || dissect(upper, cx, &mut right_order),
        );
    } else {
        dissect(&mut interior, cx, &mut left_order);
        dissect(upper, cx, &mut right_order);
    }
    order.extend_from_slice(&left_order);
    order.extend_from_slice(&right_order);
    order.extend_from_slice(&separator);
}

fn set_len_is_large(n: usize) -> bool {
    n > 20_000
}

fn longest_axis(set: &[u32], coords: &[[f64; 3]]) -> usize {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for &v in set {
        for d in 0..3 {
            lo[d] = lo[d].min(coords[v as usize][d]);
            hi[d] = hi[d].max(coords[v as usize][d]);
        }
    }
    (0..3).max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b]))).unwrap_or(0)
}
