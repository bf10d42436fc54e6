//! From an edge cut to a vertex separator: the smallest set of vertices covering every cut
//! edge is a minimum vertex cover of the bipartite graph of cut edges, which by König's theorem
//! (König 1931) has the size of a maximum matching and is read off the matching (Pothen–Fan
//! 1990, "Computing the block triangular form of a sparse matrix", the cover used by METIS's
//! `ConstructMinCoverSeparator`). Removing it leaves the two sides with no edge between them.
//! Cost: O(V·E) in theory on the cut graph (augmenting paths), near-linear on meshes.

use super::graph::{Graph, NONE};

/// Side 0, side 1, or separator, for every vertex.
pub const SEPARATOR: u8 = 2;

/// Turns a two-way `side` assignment into a three-way one whose separator (marked
/// [`SEPARATOR`]) is a minimum vertex cover of the cut edges.
pub fn min_cover_separator(g: &Graph, side: &[u8]) -> Vec<u8> {
    let crosses = |v: u32| g.neighbors(v).iter().any(|&u| side[u as usize] != side[v as usize]);
    let (mut left, mut right) = (Vec::new(), Vec::new());
    for v in 0..g.n() as u32 {
        if crosses(v) {
            if side[v as usize] == 0 {
                left.push(v)
            } else {
                right.push(v)
            }
        }
    }
    let mut part = side.to_vec();
    for v in min_vertex_cover(&left, &right, |v| g.neighbors(v), |v, u| side[v as usize] != side[u as usize]) {
        part[v as usize] = SEPARATOR;
    }
    part
}

/// Minimum vertex cover of the bipartite graph whose edges are the edges `v–u` of a graph
/// (`neighbors`) with `v` in `left`, `u` in `right` and `across(v, u)`.
pub fn min_vertex_cover<'g>(
    left: &[u32],
    right: &[u32],
    neighbors: impl Fn(u32) -> &'g [u32],
    across: impl Fn(u32, u32) -> bool,
) -> Vec<u32> {
    let cut = CutGraph::new(left, right, neighbors, across);
    let mate = cut.maximum_matching();
    let reached = cut.alternating_reach(&mate);
    // König: cover = (left not reached) ∪ (right reached).
    let mut cover: Vec<u32> = left.iter().zip(&reached).filter(|(_, &r)| !r).map(|(&v, _)| v).collect();
    cover.extend(right.iter().zip(&reached[left.len()..]).filter(|(_, &r)| r).map(|(&v, _)| v));
    cover
}

/// Bipartite graph of the cut edges; vertex `k` is `left[k]` for `k < left.len()`, then
/// `right[k − left.len()]`.
struct CutGraph {
    left_len: usize,
    start: Vec<u32>,
    adj: Vec<u32>,
}

impl CutGraph {
    fn new<'g>(
        left: &[u32],
        right: &[u32],
        neighbors: impl Fn(u32) -> &'g [u32],
        across: impl Fn(u32, u32) -> bool,
    ) -> Self {
        let mut local = std::collections::HashMap::with_capacity(left.len() + right.len());
        for (k, &v) in left.iter().chain(right).enumerate() {
            local.insert(v, k as u32);
        }
        let mut start = Vec::with_capacity(left.len() + right.len() + 1);
        let mut adj = Vec::new();
        start.push(0);
        for &v in left.iter().chain(right) {
            for &u in neighbors(v) {
                if across(v, u) {
                    if let Some(&k) = local.get(&u) {
                        adj.push(k);
                    }
                }
            }
            start.push(adj.len() as u32);
        }
        CutGraph { left_len: left.len(), start, adj }
    }

    fn of(&self, k: u32) -> &[u32] {
        &self.adj[self.start[k as usize] as usize..self.start[k as usize + 1] as usize]
    }

    /// Maximum matching by augmenting paths (greedy start, then one depth-first search per
    /// unmatched left vertex). `mate[k]` is the cut-graph vertex matched with `k`, or NONE.
    fn maximum_matching(&self) -> Vec<u32> {
        let nl = self.left_len as u32;
        let total = self.start.len() - 1;
        let mut mate = vec![NONE; total];
        for a in 0..nl {
            if let Some(&b) = self.of(a).iter().find(|&&b| mate[b as usize] == NONE) {
                mate[a as usize] = b;
                mate[b as usize] = a;
            }
        }
        let mut visited = vec![NONE; total];
        // Stack of (left vertex, next neighbour index).
        let mut stack: Vec<(u32, usize)> = Vec::new();
        for root in 0..nl {
            if mate[root as usize] != NONE {
                continue;
            }
            stack.clear();
            stack.push((root, 0));
            visited[root as usize] = root;
            while let Some(&mut (a, ref mut next)) = stack.last_mut() {
                let neighbors = self.of(a);
                let mut advanced = false;
                while *next < neighbors.len() {
                    let b = neighbors[*next];
                    *next += 1;
                    if visited[b as usize] == root {
                        continue;
                    }
                    visited[b as usize] = root;
                    let m = mate[b as usize];
                    if m == NONE {
                        // Augment along the stack.
                        let mut b = b;
                        while let Some((a, _)) = stack.pop() {
                            let previous = mate[a as usize];
                            mate[a as usize] = b;
                            mate[b as usize] = a;
                            b = previous;
                        }
                        advanced = true;
                        break;
                    }
                    if visited[m as usize] != root {
                        visited[m as usize] = root;
                        stack.push((m, 0));
                        advanced = true;
                        break;
                    }
                }
                if !advanced {
                    stack.pop();
                }
            }
        }
        mate
    }

    /// Cut-graph vertices reachable from unmatched left vertices by alternating paths (any edge
    /// left→right, matching edges right→left).
    fn alternating_reach(&self, mate: &[u32]) -> Vec<bool> {
        let nl = self.left_len as u32;
        let mut reached = vec![false; mate.len()];
        let mut queue: Vec<u32> = (0..nl).filter(|&a| mate[a as usize] == NONE).collect();
        for &a in &queue {
            reached[a as usize] = true;
        }
        while let Some(a) = queue.pop() {
            for &b in self.of(a) {
                if reached[b as usize] {
                    continue;
                }
                reached[b as usize] = true;
                let m = mate[b as usize];
                if m != NONE && !reached[m as usize] {
                    reached[m as usize] = true;
                    queue.push(m);
                }
            }
        }
        reached
    }
}
