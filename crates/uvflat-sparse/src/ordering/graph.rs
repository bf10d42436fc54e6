//! Weighted undirected graph in compressed rows, the working data of nested dissection:
//! vertex weights count the original unknowns a (coarse) vertex stands for, edge weights the
//! original edges between two (coarse) vertices. Also induced subgraphs and connected
//! components, which the dissection needs after every split.

use crate::union_find::{set_labels, union};

/// Marks "no vertex".
pub const NONE: u32 = u32::MAX;

/// Undirected graph without self loops; each edge is stored in both directions.
pub struct Graph {
    /// Row starts (`n + 1` entries).
    pub xadj: Vec<u32>,
    /// Neighbours.
    pub adjncy: Vec<u32>,
    /// Weight of each stored edge (parallel to `adjncy`).
    pub adjwgt: Vec<u32>,
    /// Weight of each vertex.
    pub vwgt: Vec<u32>,
}

impl Graph {
    /// Number of vertices.
    #[inline]
    pub fn n(&self) -> usize {
        self.vwgt.len()
    }

    /// Range of `v`'s neighbours in `adjncy` / `adjwgt`.
    #[inline]
    pub fn range(&self, v: u32) -> std::ops::Range<usize> {
        self.xadj[v as usize] as usize..self.xadj[v as usize + 1] as usize
    }

    /// Neighbours of `v`.
    #[inline]
    pub fn neighbors(&self, v: u32) -> &[u32] {
        &self.adjncy[self.range(v)]
    }

    /// Sum of the vertex weights.
    pub fn total_weight(&self) -> u64 {
        self.vwgt.iter().map(|&w| w as u64).sum()
    }

    /// The subgraph induced by `vertices` (vertex `k` of the result is `vertices[k]`).
    /// `scratch` must hold `NONE` for every vertex of `self`, and does again on return.
    pub fn induced(&self, vertices: &[u32], scratch: &mut [u32]) -> Graph {
        for (k, &v) in vertices.iter().enumerate() {
            scratch[v as usize] = k as u32;
        }
        let mut xadj = Vec::with_capacity(vertices.len() + 1);
        let mut adjncy = Vec::with_capacity(vertices.len() * 6);
        let mut adjwgt = Vec::with_capacity(vertices.len() * 6);
        xadj.push(0);
        for &v in vertices {
            for e in self.range(v) {
                let u = scratch[self.adjncy[e] as usize];
                if u != NONE {
                    adjncy.push(u);
                    adjwgt.push(self.adjwgt[e]);
                }
            }
            xadj.push(adjncy.len() as u32);
        }
        for &v in vertices {
            scratch[v as usize] = NONE;
        }
        let vwgt = vertices.iter().map(|&v| self.vwgt[v as usize]).collect();
        Graph { xadj, adjncy, adjwgt, vwgt }
    }

    /// Component id of every vertex and the number of components. Union–find over the edges
    /// in vertex order (a sequential pass, where a graph search would jump around memory);
    /// ids are numbered in order of each component's lowest vertex.
    pub fn components(&self) -> (Vec<u32>, usize) {
        let n = self.n();
        let mut parent: Vec<u32> = (0..n as u32).collect();
        for v in 0..n as u32 {
            for &u in self.neighbors(v) {
                if u > v {
                    union(&mut parent, v, u);
                }
            }
        }
        set_labels(&mut parent)
    }
}

/// Small deterministic pseudo-random generator (SplitMix64), so orderings are reproducible.
pub struct Rng(u64);

impl Rng {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform integer in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (((self.next_u64() >> 32) * n as u64) >> 32) as usize
    }

    /// `0..n` in random order.
    pub fn permutation(&mut self, n: usize) -> Vec<u32> {
        let mut p: Vec<u32> = (0..n as u32).collect();
        for i in (1..n).rev() {
            p.swap(i, self.below(i + 1));
        }
        p
    }
}
