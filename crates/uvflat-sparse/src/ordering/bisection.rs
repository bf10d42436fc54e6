//! Multilevel graph bisection (Karypis–Kumar 1998, "A fast and high quality multilevel scheme
//! for partitioning irregular graphs"): the graph is coarsened by heavy-edge matching until it
//! has about a hundred vertices, bisected there by greedy graph growing (breadth-first regions
//! from several random seeds, each refined, the best kept), and the bisection is projected back
//! level by level with Fiduccia–Mattheyses refinement at each one. The minimum vertex cover of
//! the final cut edges is the vertex separator, which node FM refinement then thins
//! ([`super::node_refine`]). Cost: O(E) per level, O(E) in all.

use super::coarsen::{coarsen, Coarsening};
use super::graph::{Graph, Rng};
use super::node_refine::refine_separator;
use super::refine::{refine, Bisection};
use super::separator::min_cover_separator;

/// Coarsening stops at this many vertices.
const COARSEST: usize = 100;
/// Seeds tried for the initial bisection.
const INITIAL_TRIES: usize = 8;
/// FM passes per level.
const PASSES: usize = 2;
/// Largest fraction of the total weight one side may take.
pub const MAX_SIDE_FRACTION: f64 = 0.55;

/// A three-way split of `g` (0, 1, or [`super::separator::SEPARATOR`] per vertex) with no edge
/// between sides 0 and 1.
pub fn separate(g: &Graph, rng: &mut Rng) -> Vec<u8> {
    let side = multilevel_bisection(g, rng);
    let mut part = min_cover_separator(g, &side);
    let heaviest = g.vwgt.iter().copied().max().unwrap_or(1) as u64;
    refine_separator(g, &mut part, max_side(g.total_weight(), heaviest), PASSES);
    part
}

/// Largest side weight allowed for a graph of total weight `total` whose heaviest vertex
/// weighs `heaviest`.
fn max_side(total: u64, heaviest: u64) -> u64 {
    ((total as f64 * MAX_SIDE_FRACTION) as u64).max(total.div_ceil(2) + heaviest)
}

/// Two-way partition of `g` with a small edge cut.
pub fn multilevel_bisection(g: &Graph, rng: &mut Rng) -> Vec<u8> {
    let total = g.total_weight();
    let max_vertex = ((3 * total) / (2 * COARSEST as u64)).max(1) as u32;
    let mut levels: Vec<Coarsening> = Vec::new();
    loop {
        let current = levels.last().map_or(g, |c| &c.graph);
        if current.n() <= COARSEST {
            break;
        }
        let next = coarsen(current, rng, max_vertex);
        if next.graph.n() * 10 > current.n() * 9 {
            break;
        }
        levels.push(next);
    }
    let coarsest = levels.last().map_or(g, |c| &c.graph);
    let mut side = initial_bisection(coarsest, rng);
    for k in (0..levels.len()).rev() {
        let fine = if k == 0 { g } else { &levels[k - 1].graph };
        let projected: Vec<u8> = levels[k].map.iter().map(|&c| side[c as usize]).collect();
        let mut b = Bisection::new(fine, projected);
        let heaviest = fine.vwgt.iter().copied().max().unwrap_or(1) as u64;
        refine(fine, &mut b, max_side(total, heaviest), PASSES);
        side = b.side;
    }
    side
}

/// Best of several greedy-growing bisections of a small graph.
fn initial_bisection(g: &Graph, rng: &mut Rng) -> Vec<u8> {
    let total = g.total_weight();
    let heaviest = g.vwgt.iter().copied().max().unwrap_or(1) as u64;
    let limit = max_side(total, heaviest);
    let mut best: Option<Bisection> = None;
    for _ in 0..INITIAL_TRIES {
        let mut b = Bisection::new(g, grow_region(g, rng, total / 2));
        refine(g, &mut b, limit, PASSES);
        if best.as_ref().is_none_or(|x| b.key(limit) < x.key(limit)) {
            best = Some(b);
        }
    }
    best.map_or_else(|| vec![0; g.n()], |b| b.side)
}

/// Side 0 = a breadth-first region grown from a random seed until it weighs `target`
/// (restarting from another random vertex when a component runs out); side 1 = the rest.
fn grow_region(g: &Graph, rng: &mut Rng, target: u64) -> Vec<u8> {
    let n = g.n();
    let mut side = vec![1u8; n];
    if n == 0 {
        return side;
    }
    let mut weight = 0u64;
    let mut queue = std::collections::VecDeque::new();
    let mut seed = rng.below(n);
    while weight < target {
        if queue.is_empty() {
            // Next unclaimed vertex from a random start (the seed itself on the first round).
            match (0..n).map(|k| (seed + k) % n).find(|&v| side[v] == 1) {
                Some(v) => {
                    side[v] = 0;
                    weight += g.vwgt[v] as u64;
                    queue.push_back(v as u32);
                }
                None => break,
            }
            seed = rng.below(n);
            continue;
        }
        let Some(v) = queue.pop_front() else { break };
        for &u in g.neighbors(v) {
            if side[u as usize] == 1 && weight < target {
                side[u as usize] = 0;
                weight += g.vwgt[u as usize] as u64;
                queue.push_back(u);
            }
        }
    }
    side
}
