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
        let range = g.range(v);
        for (&u, &w) in g.adjncy[range.clone()].iter().zip(&g.adjwgt[range]) {
            if w > best_weight && mate[u as usize] == NONE && g.vwgt[u as usize] <= room {
                best = u;
                best_weight = w;
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
/// Parallel edges are merged by a search of the row being built: coarse rows are short, so
/// this beats a lookup table, which would miss the cache on large graphs; rows that grow long
/// (hubs) switch to the table.
fn contract(g: &Graph, map: &[u32], members: &[[u32; 2]]) -> Graph {
    const LONG_ROW: usize = 32;
    let nc = members.len();
    // slot[c]: position of the edge to coarse vertex c in a long row being built.
    let mut slot: Vec<u32> = Vec::new();
    let mut xadj = Vec::with_capacity(nc + 1);
    let mut adjncy: Vec<u32> = Vec::with_capacity(g.adjncy.len() * 3 / 5);
    let mut adjwgt: Vec<u32> = Vec::with_capacity(g.adjncy.len() * 3 / 5);
    let mut vwgt = Vec::with_capacity(nc);
    xadj.push(0u32);
    for (c, &[v, u]) in members.iter().enumerate() {
        let row_start = adjncy.len();
        let pair = [v, u];
        let fine = if v == u { &pair[..1] } else { &pair[..] };
        for &x in fine {
            let range = g.range(x);
            for (&y, &w) in g.adjncy[range.clone()].iter().zip(&g.adjwgt[range]) {
                let cy = map[y as usize];
                if cy as usize == c {
                    continue;
                }
                let row_len = adjncy.len() - row_start;
                let found = if row_len < LONG_ROW {
                    adjncy[row_start..].iter().position(|&z| z == cy).map(|k| row_start + k)
                } else {
                    if row_len == LONG_ROW && (slot.is_empty() || slot[adjncy[row_start] as usize] == NONE) {
                        slot.resize(nc, NONE);
                        for k in row_start..adjncy.len() {
                            slot[adjncy[k] as usize] = k as u32;
                        }
                    }
                    Some(slot[cy as usize] as usize).filter(|&k| k != NONE as usize)
                };
                match found {
                    Some(k) => adjwgt[k] += w,
                    None => {
                        if adjncy.len() - row_start >= LONG_ROW {
                            slot[cy as usize] = adjncy.len() as u32;
                        }
                        adjncy.push(cy);
                        adjwgt.push(w);
                    }
                }
            }
        }
        let registered =
            !slot.is_empty() && adjncy.len() - row_start >= LONG_ROW && slot[adjncy[row_start] as usize] != NONE;
        if registered {
            for &cy in &adjncy[row_start..] {
                slot[cy as usize] = NONE;
            }
        }
        xadj.push(adjncy.len() as u32);
        vwgt.push(fine.iter().map(|&x| g.vwgt[x as usize]).sum());
    }
    Graph { xadj, adjncy, adjwgt, vwgt }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sum of the weights of the edges between every pair of coarse vertices, from the fine
    /// graph (what contraction must preserve).
    fn coarse_edge_weights(g: &Graph, map: &[u32]) -> std::collections::BTreeMap<(u32, u32), u32> {
        let mut w = std::collections::BTreeMap::new();
        for v in 0..g.n() as u32 {
            for e in g.range(v) {
                let (a, b) = (map[v as usize], map[g.adjncy[e] as usize]);
                if a != b {
                    *w.entry((a, b)).or_insert(0) += g.adjwgt[e];
                }
            }
        }
        w
    }

    #[test]
    fn contraction_preserves_edge_and_vertex_weights_also_around_hubs() {
        // A wheel: hub 0 joined to a 200-cycle, so the hub's coarse row is long.
        let n = 201u32;
        let mut rows: Vec<Vec<u32>> = vec![Vec::new(); n as usize];
        for k in 1..n {
            let next = if k + 1 == n { 1 } else { k + 1 };
            for (a, b) in [(0, k), (k, next)] {
                rows[a as usize].push(b);
                rows[b as usize].push(a);
            }
        }
        let mut xadj = vec![0u32];
        let mut adjncy = Vec::new();
        for row in &rows {
            adjncy.extend(row);
            xadj.push(adjncy.len() as u32);
        }
        let adjwgt = (0..adjncy.len() as u32).map(|e| 1 + e % 3).collect::<Vec<_>>();
        // Symmetric weights: weight of a–b from the smaller endpoint's listing.
        let mut g = Graph { xadj, adjncy, adjwgt, vwgt: vec![1; n as usize] };
        for v in 0..n {
            for e in g.range(v) {
                let u = g.adjncy[e];
                g.adjwgt[e] = 1 + (v.min(u) * 7 + v.max(u)) % 3;
            }
        }
        let c = coarsen(&g, &mut Rng::new(3), u32::MAX);
        assert!(c.graph.n() < g.n());
        assert_eq!(c.graph.total_weight(), g.total_weight());
        let identity: Vec<u32> = (0..c.graph.n() as u32).collect();
        assert_eq!(coarse_edge_weights(&c.graph, &identity), coarse_edge_weights(&g, &c.map));
        for v in 0..c.graph.n() as u32 {
            let mut row = c.graph.neighbors(v).to_vec();
            row.sort_unstable();
            row.dedup();
            assert_eq!(row.len(), c.graph.neighbors(v).len(), "parallel edges left in row {v}");
        }
    }
}
