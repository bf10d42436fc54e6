//! Fiduccia–Mattheyses refinement of a two-way edge cut (Fiduccia–Mattheyses 1982, "A
//! linear-time heuristic for improving network partitions"; in the boundary form of
//! Karypis–Kumar 1998, §5): boundary vertices move, best gain first, to the other side as long
//! as the balance allows; every vertex moves at most once per pass, and the pass is rolled
//! back to the best cut it went through, so a pass never makes the cut worse. Cost per pass:
//! O(E) to set up, then O(d log n) per move.

use super::graph::Graph;
use std::collections::BinaryHeap;

/// A two-way partition and its bookkeeping.
pub struct Bisection {
    /// Side (0 or 1) of every vertex.
    pub side: Vec<u8>,
    /// Total vertex weight of each side.
    pub weight: [u64; 2],
    /// Total weight of the edges between the sides.
    pub cut: u64,
}

impl Bisection {
    /// Weights and cut of a given assignment of sides.
    pub fn new(g: &Graph, side: Vec<u8>) -> Self {
        let mut weight = [0u64; 2];
        let mut cut = 0u64;
        for v in 0..g.n() as u32 {
            let s = side[v as usize];
            weight[s as usize] += g.vwgt[v as usize] as u64;
            for e in g.range(v) {
                if side[g.adjncy[e] as usize] != s {
                    cut += g.adjwgt[e] as u64;
                }
            }
        }
        Bisection { side, weight, cut: cut / 2 }
    }

    /// How far the heavier side exceeds `max_side` (0 when balanced).
    pub fn overweight(&self, max_side: u64) -> u64 {
        self.weight[0].max(self.weight[1]).saturating_sub(max_side)
    }

    /// Quality key, smaller is better: balance first, then cut, then evenness.
    pub fn key(&self, max_side: u64) -> (u64, u64, u64) {
        (self.overweight(max_side), self.cut, self.weight[0].abs_diff(self.weight[1]))
    }
}

/// Sum of edge weights from each vertex to its own side (`internal`) and to the other side
/// (`external`).
struct Degrees {
    internal: Vec<i64>,
    external: Vec<i64>,
}

impl Degrees {
    fn new(g: &Graph, side: &[u8]) -> Self {
        let n = g.n();
        let (mut internal, mut external) = (vec![0i64; n], vec![0i64; n]);
        for v in 0..n as u32 {
            for e in g.range(v) {
                if side[g.adjncy[e] as usize] == side[v as usize] {
                    internal[v as usize] += g.adjwgt[e] as i64;
                } else {
                    external[v as usize] += g.adjwgt[e] as i64;
                }
            }
        }
        Degrees { internal, external }
    }

    #[inline]
    fn gain(&self, v: u32) -> i64 {
        self.external[v as usize] - self.internal[v as usize]
    }
}

/// Moves `v` to the other side, updating weights, cut and degrees.
fn move_vertex(g: &Graph, b: &mut Bisection, d: &mut Degrees, v: u32) {
    let from = b.side[v as usize];
    let to = 1 - from;
    b.side[v as usize] = to;
    let w = g.vwgt[v as usize] as u64;
    b.weight[from as usize] -= w;
    b.weight[to as usize] += w;
    b.cut = (b.cut as i64 - d.gain(v)) as u64;
    let (i, x) = (d.internal[v as usize], d.external[v as usize]);
    d.internal[v as usize] = x;
    d.external[v as usize] = i;
    for e in g.range(v) {
        let u = g.adjncy[e] as usize;
        let w = g.adjwgt[e] as i64;
        if b.side[u] == to {
            d.internal[u] += w;
            d.external[u] -= w;
        } else {
            d.internal[u] -= w;
            d.external[u] += w;
        }
    }
}

/// Improves the cut of `b` by up to `passes` FM passes keeping each side's weight within
/// `max_side` (a partition that starts unbalanced is first pushed towards balance).
pub fn refine(g: &Graph, b: &mut Bisection, max_side: u64, passes: usize) {
    let n = g.n();
    let mut d = Degrees::new(g, &b.side);
    // locked[v] == pass + 1 once v moved in this pass.
    let mut locked = vec![0u32; n];
    let patience = (n / 100).clamp(25, 150);
    for pass in 1..=passes as u32 {
        let mut heaps = [BinaryHeap::new(), BinaryHeap::new()];
        for v in 0..n as u32 {
            if d.external[v as usize] > 0 {
                heaps[b.side[v as usize] as usize].push((d.gain(v), v));
            }
        }
        let start_key = b.key(max_side);
        let mut best_key = start_key;
        let mut moves: Vec<u32> = Vec::new();
        let mut best_len = 0;
        while let Some(v) = next_move(g, b, &d, &mut heaps, &locked, pass, max_side) {
            move_vertex(g, b, &mut d, v);
            locked[v as usize] = pass;
            moves.push(v);
            for &u in g.neighbors(v) {
                if locked[u as usize] != pass && d.external[u as usize] > 0 {
                    heaps[b.side[u as usize] as usize].push((d.gain(u), u));
                }
            }
            let key = b.key(max_side);
            if key < best_key {
                best_key = key;
                best_len = moves.len();
            }
            if moves.len() - best_len > patience {
                break;
            }
        }
        for &v in moves[best_len..].iter().rev() {
            move_vertex(g, b, &mut d, v);
        }
        if best_key >= start_key {
            break;
        }
    }
}

/// The unlocked boundary vertex to move next: the best gain among the sides it may leave
/// (only the heavy side while the partition is out of balance).
fn next_move(
    g: &Graph,
    b: &Bisection,
    d: &Degrees,
    heaps: &mut [BinaryHeap<(i64, u32)>; 2],
    locked: &[u32],
    pass: u32,
    max_side: u64,
) -> Option<u32> {
    let mut best: Option<(i64, usize)> = None;
    let heavy = if b.weight[0] >= b.weight[1] { 0 } else { 1 };
    let unbalanced = b.weight[heavy] > max_side;
    for (s, heap) in heaps.iter_mut().enumerate() {
        if unbalanced && s != heavy {
            continue;
        }
        // Drop stale entries (moved, locked, or with an outdated gain).
        while let Some(&(gain, v)) = heap.peek() {
            let valid = locked[v as usize] != pass && b.side[v as usize] as usize == s && d.gain(v) == gain;
            if valid {
                break;
            }
            heap.pop();
        }
        if let Some(&(gain, v)) = heap.peek() {
            let fits = b.weight[1 - s] + g.vwgt[v as usize] as u64 <= max_side || unbalanced;
            let better = match best {
                None => true,
                Some((bg, bs)) => gain > bg || (gain == bg && b.weight[s] > b.weight[bs]),
            };
            if fits && better {
                best = Some((gain, s));
            }
        }
    }
    best.and_then(|(_, s)| heaps[s].pop().map(|(_, v)| v))
}
