//! Half-edge connectivity of a triangle soup, built in linear time, with the manifoldness and
//! orientation checks that every method relies on.
//!
//! Conventions: half-edge `h = 3·t + k` runs from corner `k` of triangle `t` to corner
//! `(k + 1) % 3`; `twin[h]` is the opposite half-edge or [`NONE`] on the boundary. Boundary
//! half-edges therefore run counter-clockwise around the surface (the interior on their left).

use crate::error::{Error, Result};

/// Marks "no half-edge" (boundary twin, unreferenced vertex).
pub const NONE: u32 = u32::MAX;

/// Next half-edge inside the same triangle.
#[inline]
pub fn next(h: u32) -> u32 {
    if h % 3 == 2 { h - 2 } else { h + 1 }
}

/// Previous half-edge inside the same triangle.
#[inline]
pub fn prev(h: u32) -> u32 {
    if h % 3 == 0 { h + 2 } else { h - 1 }
}

/// Half-edge connectivity: twins and one outgoing half-edge per vertex.
#[derive(Debug, Clone)]
pub struct Connectivity {
    /// Opposite half-edge, or [`NONE`] for a boundary half-edge.
    pub twin: Vec<u32>,
    /// For each vertex an outgoing half-edge; for a boundary vertex the boundary one;
    /// [`NONE`] for unreferenced vertices.
    pub vertex_halfedge: Vec<u32>,
}

/// Outgoing half-edges of every vertex in compressed rows (`start[v]..start[v+1]`).
struct OutgoingHalfedges {
    start: Vec<u32>,
    halfedges: Vec<u32>,
}

impl OutgoingHalfedges {
    fn new(vertex_count: usize, triangles: &[[u32; 3]]) -> Self {
        let mut start = vec![0u32; vertex_count + 1];
        for tri in triangles {
            for &v in tri {
                start[v as usize + 1] += 1;
            }
        }
        for v in 0..vertex_count {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut halfedges = vec![0u32; triangles.len() * 3];
        for (t, tri) in triangles.iter().enumerate() {
            for (k, &v) in tri.iter().enumerate() {
                halfedges[fill[v as usize] as usize] = (3 * t + k) as u32;
                fill[v as usize] += 1;
            }
        }
        OutgoingHalfedges { start, halfedges }
    }

    fn of(&self, v: u32) -> &[u32] {
        &self.halfedges[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }
}

fn head(triangles: &[[u32; 3]], h: u32) -> u32 {
    triangles[(h / 3) as usize][((h % 3 + 1) % 3) as usize]
}

fn tail(triangles: &[[u32; 3]], h: u32) -> u32 {
    triangles[(h / 3) as usize][(h % 3) as usize]
}

impl Connectivity {
    /// Builds twins and checks that every edge has at most two consistently oriented triangles
    /// and every vertex a single fan. Triangle indices must already be in range and distinct.
    pub fn new(vertex_count: usize, triangles: &[[u32; 3]]) -> Result<Self> {
        let out = OutgoingHalfedges::new(vertex_count, triangles);
        let twin = match_twins(triangles, &out)?;
        let vertex_halfedge = check_single_fans(vertex_count, &twin, &out)?;
        Ok(Connectivity { twin, vertex_halfedge })
    }

    /// Rotates around the tail vertex of `h` to the next outgoing half-edge
    /// (counter-clockwise), or [`NONE`] at a boundary.
    #[inline]
    pub fn rotate_ccw(&self, h: u32) -> u32 {
        let t = self.twin[prev(h) as usize];
        if t == NONE { NONE } else { t }
    }

    /// Whether half-edge `h` lies on the boundary.
    #[inline]
    pub fn is_boundary(&self, h: u32) -> bool {
        self.twin[h as usize] == NONE
    }
}

/// How many of `candidates` end at `b`, and the first and last of them.
struct Matches {
    count: usize,
    first: u32,
    last: u32,
}

fn halfedges_to(triangles: &[[u32; 3]], candidates: &[u32], b: u32) -> Matches {
    let mut m = Matches { count: 0, first: NONE, last: NONE };
    for &g in candidates {
        if head(triangles, g) == b {
            if m.count == 0 {
                m.first = g;
            }
            m.last = g;
            m.count += 1;
        }
    }
    m
}

/// Pairs every half-edge a→b with the half-edge b→a, rejecting edges with more than two
/// triangles and pairs that run the same way.
fn match_twins(triangles: &[[u32; 3]], out: &OutgoingHalfedges) -> Result<Vec<u32>> {
    let mut twin = vec![NONE; triangles.len() * 3];
    for h in 0..twin.len() as u32 {
        let (a, b) = (tail(triangles, h), head(triangles, h));
        let same = halfedges_to(triangles, out.of(a), b);
        let opposite = halfedges_to(triangles, out.of(b), a);
        if same.count + opposite.count > 2 {
            let mut tris: Vec<usize> = out.of(a).iter().chain(out.of(b))
                .filter(|&&g| { let hd = head(triangles, g); (tail(triangles, g) == a && hd == b) || (tail(triangles, g) == b && hd == a) })
                .map(|&g| (g / 3) as usize)
                .collect();
            tris.sort_unstable();
            return Err(Error::NonManifoldEdge { a: a.min(b), b: a.max(b), triangles: tris });
        }
        if same.count == 2 {
            let (first, second) = ((same.first / 3) as usize, (same.last / 3) as usize);
            return Err(Error::InconsistentOrientation { a, b, first: first.min(second), second: first.max(second) });
        }
        if opposite.count == 1 {
            twin[h as usize] = opposite.first;
        }
    }
    Ok(twin)
}

/// Walks the fan of every vertex; a vertex whose outgoing half-edges form more than one fan is
/// a non-manifold ("bow-tie") vertex. Returns one outgoing half-edge per vertex, the boundary
/// one for boundary vertices.
fn check_single_fans(vertex_count: usize, twin: &[u32], out: &OutgoingHalfedges) -> Result<Vec<u32>> {
    let mut visited = vec![false; twin.len()];
    let mut vertex_halfedge = vec![NONE; vertex_count];
    for v in 0..vertex_count as u32 {
        let mut fans = 0;
        for &h in out.of(v) {
            if visited[h as usize] {
                continue;
            }
            fans += 1;
            let first = walk_fan(h, twin, &mut visited);
            vertex_halfedge[v as usize] = first;
        }
        if fans > 1 {
            return Err(Error::NonManifoldVertex { vertex: v, fans });
        }
    }
    Ok(vertex_halfedge)
}

/// Marks every outgoing half-edge of the fan containing `h`; returns the fan's first
/// half-edge in counter-clockwise order (the boundary one for an open fan, `h` otherwise).
fn walk_fan(h: u32, twin: &[u32], visited: &mut [bool]) -> u32 {
    // Clockwise: from outgoing g, the previous outgoing half-edge is next(twin(g)).
    let mut first = h;
    loop {
        let t = twin[first as usize];
        if t == NONE {
            break;
        }
        let g = next(t);
        if g == h {
            break;
        }
        first = g;
    }
    let mut g = first;
    loop {
        visited[g as usize] = true;
        let t = twin[prev(g) as usize];
        if t == NONE || t == first {
            break;
        }
        g = t;
    }
    first
}
