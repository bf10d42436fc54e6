//! Fiduccia–Mattheyses refinement of a vertex separator (the two-sided node refinement of
//! Karypis–Kumar's METIS, `FM_2WayNodeRefine2Sided`; Hendrickson–Rothberg 1998, "Improving
//! the run time and quality of nested dissection ordering", §4): a separator vertex moves into
//! one side, and its neighbours on the other side join the separator. The gain of moving `v`
//! into side `s` is `w(v) − w(neighbours of v on side 1 − s)`; moves are taken best gain first
//! within the balance limit, every vertex moves at most once per pass, and each pass is rolled
//! back to the smallest separator it went through. An edge-cut separator made minimal by a
//! vertex cover is often still a few vertices thicker than needed in places; this removes
//! them. Cost per pass: O(boundary · degree · log).

use super::graph::Graph;
use super::separator::SEPARATOR;
use std::collections::BinaryHeap;

/// One move: `v` left the separator for `side`, pulling `pulled` from the other side into it.
struct Move {
    v: u32,
    side: u8,
    pulled: Vec<u32>,
}

/// Shrinks the separator of the three-way split `part` (0, 1, or [`SEPARATOR`]) by up to
/// `passes` FM passes, keeping each side's weight within `max_side`.
pub fn refine_separator(g: &Graph, part: &mut [u8], max_side: u64, passes: usize) {
    let n = g.n();
    let mut weight = [0u64; 3];
    for v in 0..n {
        weight[part[v] as usize] += g.vwgt[v] as u64;
    }
    let mut locked = vec![0u32; n];
    let patience = (n / 200).clamp(20, 100);
    for pass in 1..=passes as u32 {
        let start = (weight[2], weight[0].abs_diff(weight[1]));
        let mut heaps = [BinaryHeap::new(), BinaryHeap::new()];
        for v in 0..n as u32 {
            if part[v as usize] == SEPARATOR {
                for s in 0..2u8 {
                    heaps[s as usize].push((gain(g, part, v, s), v));
                }
            }
        }
        let mut moves: Vec<Move> = Vec::new();
        let mut best = start;
        let mut best_len = 0;
        while let Some((v, side)) = next_move(g, part, &weight, &mut heaps, &locked, pass, max_side) {
            let other = 1 - side;
            part[v as usize] = side;
            locked[v as usize] = pass;
            weight[2] -= g.vwgt[v as usize] as u64;
            weight[side as usize] += g.vwgt[v as usize] as u64;
            let mut pulled = Vec::new();
            for &u in g.neighbors(v) {
                if part[u as usize] == other {
                    part[u as usize] = SEPARATOR;
                    weight[other as usize] -= g.vwgt[u as usize] as u64;
                    weight[2] += g.vwgt[u as usize] as u64;
                    pulled.push(u);
                }
            }
            // Gains change for the separator vertices next to v and to the pulled vertices.
            for &u in g.neighbors(v).iter().chain(pulled.iter().flat_map(|&u| g.neighbors(u))).chain(&pulled) {
                if part[u as usize] == SEPARATOR && locked[u as usize] != pass {
                    for s in 0..2u8 {
                        heaps[s as usize].push((gain(g, part, u, s), u));
                    }
                }
            }
            moves.push(Move { v, side, pulled });
            let key = (weight[2], weight[0].abs_diff(weight[1]));
            if key < best {
                best = key;
                best_len = moves.len();
            }
            if moves.len() - best_len > patience {
                break;
            }
        }
        for m in moves.drain(best_len..).rev() {
            let other = 1 - m.side;
            for &u in &m.pulled {
                part[u as usize] = other;
                weight[2] -= g.vwgt[u as usize] as u64;
                weight[other as usize] += g.vwgt[u as usize] as u64;
            }
            part[m.v as usize] = SEPARATOR;
            weight[m.side as usize] -= g.vwgt[m.v as usize] as u64;
            weight[2] += g.vwgt[m.v as usize] as u64;
        }
        if best >= start {
            break;
        }
    }
}

/// Gain of moving separator vertex `v` into side `s`.
fn gain(g: &Graph, part: &[u8], v: u32, s: u8) -> i64 {
    let pulled: i64 =
        g.neighbors(v).iter().filter(|&&u| part[u as usize] == 1 - s).map(|&u| g.vwgt[u as usize] as i64).sum();
    g.vwgt[v as usize] as i64 - pulled
}

/// The best move that keeps the balance: an unlocked separator vertex and the side it joins.
/// Ties go to the lighter side.
fn next_move(
    g: &Graph,
    part: &[u8],
    weight: &[u64; 3],
    heaps: &mut [BinaryHeap<(i64, u32)>; 2],
    locked: &[u32],
    pass: u32,
    max_side: u64,
) -> Option<(u32, u8)> {
    let mut best: Option<(i64, u8)> = None;
    for (s, heap) in heaps.iter_mut().enumerate() {
        // Drop stale entries (moved, locked, or with an outdated gain).
        while let Some(&(g_v, v)) = heap.peek() {
            if part[v as usize] == SEPARATOR && locked[v as usize] != pass && gain(g, part, v, s as u8) == g_v {
                break;
            }
            heap.pop();
        }
        if let Some(&(g_v, v)) = heap.peek() {
            let fits = weight[s] + g.vwgt[v as usize] as u64 <= max_side;
            let better = match best {
                None => true,
                Some((bg, bs)) => g_v > bg || (g_v == bg && weight[s] < weight[bs as usize]),
            };
            if fits && better {
                best = Some((g_v, s as u8));
            }
        }
    }
    best.and_then(|(_, s)| heaps[s as usize].pop().map(|(_, v)| (v, s)))
}
