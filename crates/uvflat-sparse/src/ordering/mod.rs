//! Nested dissection (George 1973) with multilevel vertex separators (Karypis–Kumar 1998, the
//! scheme of METIS's `METIS_NodeND`): a fill-reducing elimination order for sparse symmetric
//! systems. The unknowns are split by a small vertex separator into two halves with no edge
//! between them; the halves are ordered recursively (in parallel), the separator last. Large
//! subproblems are split by multilevel graph bisection ([`bisection`]), which finds the short
//! separators a surface mesh has even where it is folded (their size decides most of the
//! factorization's flops); middle-sized ones, when the unknowns have 3D positions, by a plane
//! at the median of their longest axis ([`geometric`]), which is much cheaper and nearly as
//! good on small, nearly flat pieces; either way the separator is a minimum vertex cover of the
//! cut edges ([`separator`]). Disconnected subproblems split along their components, for free.
//! Small ones (at most `leaf_size` unknowns) are ordered by approximate minimum degree (faer's
//! AMD on their induced subgraph). The vertices are first renumbered breadth-first so that
//! the graph work stays in cache. On a well-shaped mesh of n vertices this gives O(n log n)
//! fill in the Cholesky factor and O(n^1.5) factorization flops. Cost: O(E log n).

pub mod bisection;
pub mod coarsen;
pub mod geometric;
pub mod graph;
pub mod node_refine;
pub mod refine;
pub mod separator;

use graph::{Graph, Rng};
use separator::SEPARATOR;
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
}

/// Tuning of [`nested_dissection_with`].
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// Subproblems at most this large are ordered by minimum degree.
    pub leaf_size: usize,
    /// Subproblems larger than this are split by multilevel bisection; smaller ones by a plane
    /// when positions are given (otherwise by multilevel bisection too).
    pub graph_split_above: usize,
    /// Subproblems larger than this are split in parallel with their sibling.
    pub parallel_above: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options { leaf_size: 64, graph_split_above: 20_000, parallel_above: 20_000 }
    }
}

impl Options {
    /// Multilevel bisection at every level down to the leaves, never a plane: about 3× the
    /// ordering time of the default (0.40 s instead of 0.12 s on the 103k-vertex graph of the
    /// 207k-face `disk_face_libigl_loop1`; 2.9 s instead of 1.2 s on the 714k vertices of
    /// `disk_bimba_cut_loop2`), but shorter separators where the surface curves: on that 207k-face
    /// disk the Cholesky factor of PGP's 4-unknowns-per-vertex Newton system takes 32 GFLOP and
    /// 72M entries instead of 61 GFLOP and 99M (METIS 5's `METIS_NodeND`, through pymetis: 28
    /// GFLOP, 65M). It pays when one pattern is factored many times; for a single solve of one
    /// unknown per vertex (the 1.43M-face natural conformal map) the numeric factorization
    /// gains 0.15 s and the ordering loses 1.7 s.
    pub fn thorough() -> Self {
        Options { graph_split_above: 0, ..Self::default() }
    }
}

/// Elimination order (`order[k]` = unknown eliminated k-th) by nested dissection, with the
/// default [`Options`].
pub fn nested_dissection(adjacency: &Adjacency, coords: &[[f64; 3]]) -> Vec<usize> {
    nested_dissection_with(adjacency, Some(coords), &Options::default())
}

/// Elimination order by nested dissection; `coords` (one position per unknown) enables plane
/// splits of middle-sized subproblems.
pub fn nested_dissection_with(adjacency: &Adjacency, coords: Option<&[[f64; 3]]>, options: &Options) -> Vec<usize> {
    let ids = breadth_first_order(adjacency);
    let graph = renumbered_graph(adjacency, &ids);
    let n = ids.len();
    let points: Option<Vec<[f64; 3]>> = coords.map(|c| ids.iter().map(|&v| c[v as usize]).collect());
    let cx = Context {
        graph: &graph,
        points: points.as_deref(),
        options,
        stamp: (0..n).map(|_| AtomicU32::new(0)).collect(),
        local: (0..n).map(|_| AtomicU32::new(0)).collect(),
        counter: AtomicU32::new(1),
    };
    let mut all: Vec<u32> = (0..n as u32).collect();
    let mut order = Vec::with_capacity(n);
    dissect(&mut all, &cx, &mut order);
    order.into_iter().map(|v| ids[v as usize] as usize).collect()
}

/// Vertices in breadth-first order (component by component): neighbours get nearby numbers,
/// so the graph algorithms below touch memory locally (mesh vertex numberings are often close
/// to random, and every cache miss counts on a million vertices).
fn breadth_first_order(adjacency: &Adjacency) -> Vec<u32> {
    let n = adjacency.start.len().saturating_sub(1);
    let mut seen = vec![false; n];
    let mut order = Vec::with_capacity(n);
    for seed in 0..n {
        if seen[seed] {
            continue;
        }
        seen[seed] = true;
        let mut head = order.len();
        order.push(seed as u32);
        while head < order.len() {
            let v = order[head] as usize;
            head += 1;
            for &u in &adjacency.neighbors[adjacency.start[v]..adjacency.start[v + 1]] {
                if !seen[u as usize] {
                    seen[u as usize] = true;
                    order.push(u);
                }
            }
        }
    }
    order
}

/// The unit-weight graph of `adjacency` with vertex `k` standing for unknown `ids[k]`.
fn renumbered_graph(adjacency: &Adjacency, ids: &[u32]) -> Graph {
    let n = ids.len();
    let mut new_id = vec![0u32; n];
    for (k, &v) in ids.iter().enumerate() {
        new_id[v as usize] = k as u32;
    }
    let mut xadj = Vec::with_capacity(n + 1);
    let mut adjncy = Vec::with_capacity(adjacency.neighbors.len());
    xadj.push(0u32);
    for &v in ids {
        let row = &adjacency.neighbors[adjacency.start[v as usize]..adjacency.start[v as usize + 1]];
        adjncy.extend(row.iter().map(|&u| new_id[u as usize]));
        xadj.push(adjncy.len() as u32);
    }
    let adjwgt = vec![1; adjncy.len()];
    Graph { xadj, adjncy, adjwgt, vwgt: vec![1; n] }
}

/// Shared state of the recursion. Subproblems own disjoint vertex sets; `stamp[v]` holds the id
/// of the last subproblem that claimed `v` and `local[v]` its number there. A subproblem writes
/// only its own vertices' entries and reads its neighbours' stamps only to compare them with
/// its own id, so parallel siblings never interfere.
struct Context<'a> {
    graph: &'a Graph,
    points: Option<&'a [[f64; 3]]>,
    options: &'a Options,
    stamp: Vec<AtomicU32>,
    local: Vec<AtomicU32>,
    counter: AtomicU32,
}

/// A split of a vertex set: two sides with no edge between them, and the separator.
struct Split {
    sides: [Vec<u32>; 2],
    separator: Vec<u32>,
}

/// Appends to `order` the elimination order of the vertex set `set` (vertices of the
/// breadth-first-numbered graph).
fn dissect(set: &mut [u32], cx: &Context, order: &mut Vec<u32>) {
    let n = set.len();
    if n <= cx.options.leaf_size {
        minimum_degree_leaf(set, cx, order);
        return;
    }
    let split = match cx.points {
        Some(points) if n <= cx.options.graph_split_above => plane_split(set, points, cx),
        _ => graph_split(set, cx),
    };
    let Split { sides: [mut a, mut b], separator } = split;
    if a.len() == n || b.len() == n {
        // No split found (cannot happen on a connected set with an edge; kept as a guard).
        order.extend_from_slice(set);
        return;
    }
    if n > cx.options.parallel_above {
        let mut order_b = Vec::with_capacity(b.len());
        rayon::join(|| dissect(&mut a, cx, order), || dissect(&mut b, cx, &mut order_b));
        order.extend_from_slice(&order_b);
    } else {
        dissect(&mut a, cx, order);
        dissect(&mut b, cx, order);
    }
    order.extend_from_slice(&separator);
}

/// Appends a small vertex set in approximate minimum degree order (faer's AMD on its induced
/// subgraph; METIS orders its small subproblems by minimum degree the same way).
fn minimum_degree_leaf(set: &[u32], cx: &Context, order: &mut Vec<u32>) {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::sparse::linalg::amd;
    let n = set.len();
    if n <= 2 {
        order.extend_from_slice(set);
        return;
    }
    let id = claim(set, cx);
    let mut sub = induced_subgraph(set, id, cx);
    for v in 0..n as u32 {
        let range = sub.range(v);
        sub.adjncy[range].sort_unstable();
    }
    let pattern = faer::sparse::SymbolicSparseColMatRef::new_checked(n, n, &sub.xadj, None, &sub.adjncy);
    let (mut perm, mut inverse) = (vec![0u32; n], vec![0u32; n]);
    let ordered = MemBuffer::try_new(amd::order_scratch::<u32>(n, sub.adjncy.len())).ok().and_then(|mut mem| {
        amd::order(&mut perm, &mut inverse, pattern, Default::default(), MemStack::new(&mut mem)).ok()
    });
    match ordered {
        Some(_) => order.extend(perm.iter().map(|&k| set[k as usize])),
        None => order.extend_from_slice(set),
    }
}

/// Claims `set` under a fresh subproblem id and returns it.
fn claim(set: &[u32], cx: &Context) -> u32 {
    let id = cx.counter.fetch_add(1, Relaxed);
    for (k, &v) in set.iter().enumerate() {
        cx.stamp[v as usize].store(id, Relaxed);
        cx.local[v as usize].store(k as u32, Relaxed);
    }
    id
}

/// Splits by multilevel bisection of the induced subgraph, or along its components when it has
/// several (no separator needed).
fn graph_split(set: &[u32], cx: &Context) -> Split {
    let id = claim(set, cx);
    let sub = induced_subgraph(set, id, cx);
    let (comp, count) = sub.components();
    let part = if count > 1 {
        split_components(&sub, &comp, count)
    } else {
        let mut rng = Rng::new(0x5EED ^ ((set.len() as u64) << 32) ^ set[0] as u64);
        bisection::separate(&sub, &mut rng)
    };
    let mut split = Split { sides: [Vec::new(), Vec::new()], separator: Vec::new() };
    for (k, &p) in part.iter().enumerate() {
        match p {
            SEPARATOR => split.separator.push(set[k]),
            p => split.sides[p as usize].push(set[k]),
        }
    }
    split
}

/// The subgraph induced by `set`, claimed under `id` (vertex `k` is `set[k]`).
fn induced_subgraph(set: &[u32], id: u32, cx: &Context) -> Graph {
    let g = cx.graph;
    let mut xadj = Vec::with_capacity(set.len() + 1);
    let mut adjncy = Vec::with_capacity(set.len() * 6);
    xadj.push(0u32);
    for &v in set {
        for &u in g.neighbors(v) {
            if cx.stamp[u as usize].load(Relaxed) == id {
                adjncy.push(cx.local[u as usize].load(Relaxed));
            }
        }
        xadj.push(adjncy.len() as u32);
    }
    let adjwgt = vec![1; adjncy.len()];
    Graph { xadj, adjncy, adjwgt, vwgt: vec![1; set.len()] }
}

/// Splits at the median of the longest axis; the separator is a minimum vertex cover of the
/// edges crossing the plane.
fn plane_split(set: &mut [u32], points: &[[f64; 3]], cx: &Context) -> Split {
    let mid = geometric::median_split(set, points);
    let (lower, upper) = set.split_at(mid);
    let lower_id = claim(lower, cx);
    let upper_id = claim(upper, cx);
    let g = cx.graph;
    let side_of = |u: u32| {
        let s = cx.stamp[u as usize].load(Relaxed);
        if s == lower_id {
            0
        } else if s == upper_id {
            1
        } else {
            2
        }
    };
    let touches = |v: u32, other: u8| g.neighbors(v).iter().any(|&u| side_of(u) == other);
    let left: Vec<u32> = lower.iter().copied().filter(|&v| touches(v, 1)).collect();
    let right: Vec<u32> = upper.iter().copied().filter(|&v| touches(v, 0)).collect();
    let cover = separator::min_vertex_cover(
        &left,
        &right,
        |v| g.neighbors(v),
        |v, u| {
            let (a, b) = (side_of(v), side_of(u));
            a != b && a < 2 && b < 2
        },
    );
    // Mark the cover with a third id so the sides can be read off the stamps.
    let cover_id = claim(&cover, cx);
    let mut split = Split { sides: [Vec::new(), Vec::new()], separator: cover };
    for (s, half) in [lower, upper].into_iter().enumerate() {
        split.sides[s] = half.iter().copied().filter(|&v| cx.stamp[v as usize].load(Relaxed) != cover_id).collect();
    }
    split
}

/// Assigns whole components to two sides of nearly equal weight (largest first, each to the
/// lighter side).
fn split_components(g: &Graph, comp: &[u32], count: usize) -> Vec<u8> {
    let mut weight = vec![0u64; count];
    for (v, &c) in comp.iter().enumerate() {
        weight[c as usize] += g.vwgt[v] as u64;
    }
    let mut by_weight: Vec<usize> = (0..count).collect();
    by_weight.sort_by_key(|&c| std::cmp::Reverse(weight[c]));
    let mut side_of = vec![0u8; count];
    let mut totals = [0u64; 2];
    for c in by_weight {
        let s = if totals[0] <= totals[1] { 0 } else { 1 };
        side_of[c] = s as u8;
        totals[s] += weight[c];
    }
    comp.iter().map(|&c| side_of[c as usize]).collect()
}
