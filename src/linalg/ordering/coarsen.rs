//! Graph coarsening by heavy-edge matching (Karypis–Kumar 1998, "A fast and high quality
//! multilevel scheme for partitioning irregular graphs", §3.1): vertices are visited in random
//! order and each unmatched vertex is matched with the unmatched neighbour joined by the
//! heaviest edge; every matched pair (or single vertex) becomes one coarse vertex. Vertex
//! weights add up, parallel edges merge into one edge with the summed weight, so a partition of
//! the coarse graph has exactly the balance and edge cut of its projection. Cost: O(E).

use super::graph::{Graph, Rng, NONE};

/// A coarser graph and the coarse vertex of every fine vertex.
pub struct Coarsening {
    /// The coarse graph.
    pub graph: Graph,
    /// `map[v]`: coarse vertex containing fine vertex `v`.
    pub map: Vec<u32>,
}

/// One level of heavy-edge matching. Pairs heavier than `max_weight` are not formed, so no
/// coarse vertex outweighs what a balanced split can absorb.
pub fn coarsen(g: &Graph, rng: &mut Rng, max_weight: u32) -> Coarsening {
    let mate = heavy_edge_matching(g, rng, max_weight);
    let n = g.n();
    let mut map = vec![NONE; n];
    let mut members: Vec<[u32; 2]> = Vec::with_capacity(n / 2 + 1);
    for v in 0..n as u32 {
        if map[v as usize] != NONE {
            continue;
        }
        let u = mate[v as usize];
        let c = members.len() as u32;
        map[v as usize] = c;
        map[u as usize] = c;
        members.push([v, u]);
    }
    let graph = contract(g, &map, &members);
    Coarsening { graph, map }
}

/// `mate[v]`: the vertex matched with `v` (itself when unmatched).
fn heavy_edge_matching(g: &Graph, rng: &mut Rng, max_weight: u32) -> Vec<u32> {
    let n = g.n();
    let mut mate = vec![NONE; n];
    for v in local_shuffle(n, rng) {
        if mate[v as usize] != NONE {
            continue;
        }
        let mut best = v;
        let mut best_weight = 0;
        let room = max_weight.saturating_sub(g.vwgt[v as usize]);
        for e in g.range(v) {
            let u = g.adjncy[e];
            if mate[u as usize] == NONE && g.adjwgt[e] > best_weight && g.vwgt[u as usize] <= room {
                best = u;
                best_weight = g.adjwgt[e];
            }
        }
        mate[v as usize] = best;
        mate[best as usize] = v;
    }
    mate
}

/// `0..n` shuffled within consecutive blocks: random enough for the matching to avoid the
/// stripes a fixed visiting order produces, local enough to stay in cache.
fn local_shuffle(n: usize, rng: &mut Rng) -> Vec<u32> {
    const BLOCK: usize = 512;
    let mut p: Vec<u32> = (0..n as u32).collect();
    for block in p.chunks_mut(BLOCK) {
        for i in (1..block.len()).rev() {
            block.swap(i, rng.below(i + 1));
        }
    }
    p
}

/// The graph of the coarse vertices `members` (fine pairs, `[v, v]` for a single vertex).
fn contract(g: &Graph, map: &[u32], members: &[[u32; 2]]) -> Graph {
    let nc = members.len();
    let mut xadj = Vec::with_capacity(nc + 1);
    let mut adjncy = Vec::with_capacity(g.adjncy.len() * 3 / 5);
    let mut adjwgt = Vec::with_capacity(g.adjncy.len() * 3 / 5);
    let mut vwgt = Vec::with_capacity(nc);
    // slot[c]: position of the edge to coarse vertex c in the row being built.
    let mut slot = vec![NONE; nc];
    xadj.push(0u32);
    for (c, &[v, u]) in members.iter().enumerate() {
        let row_start = adjncy.len();
        let pair = [v, u];
        let fine = if v == u { &pair[..1] } else { &pair[..] };
        for &x in fine {
            for e in g.range(x) {
                let cy = map[g.adjncy[e] as usize];
                if cy as usize == c {
                    continue;
                }
                match slot[cy as usize] {
                    NONE => {
                        slot[cy as usize] = adjncy.len() as u32;
                        adjncy.push(cy);
                        adjwgt.push(g.adjwgt[e]);
                    }
                    k => adjwgt[k as usize] += g.adjwgt[e],
                }
            }
        }
        for &cy in &adjncy[row_start..] {
            slot[cy as usize] = NONE;
        }
        xadj.push(adjncy.len() as u32);
        vwgt.push(fine.iter().map(|&x| g.vwgt[x as usize]).sum());
    }
    Graph { xadj, adjncy, adjwgt, vwgt }
}
