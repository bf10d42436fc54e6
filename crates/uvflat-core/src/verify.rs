//! An independent check of a UV layout: does it have flipped triangles, and does any part of it
//! cover another? It knows nothing of the method that made the layout; it reads the UVs and the
//! per-corner UV triangles only, and decides every question with exact predicates (Shewchuk's
//! adaptive orientation test, `robust` crate), so a layout it accepts is valid to the last bit.
//!
//! What it counts:
//! - **flipped**: UV triangles that are not strictly counter-clockwise (zero area included) or
//!   have a non-finite corner;
//! - **overlaps**: pairs of UV boundary edges (edges used by one triangle) that share a point —
//!   a crossing, a touch, or a collinear overlap; edges that share an endpoint index count only
//!   when they fold back onto each other; plus the islands (triangles connected through shared
//!   UV vertices) that lie inside a triangle of another island without any boundary contact.
//!
//! Why that suffices: on a layout without flipped triangles whose boundary curves are simple and
//! pairwise disjoint, every island is embedded (a locally injective, orientation-preserving
//! piecewise-linear map whose boundary image is simple has degree one, so it is injective), and
//! two islands overlap only if one lies inside the other — which the point-in-triangle test of
//! one vertex per island finds.
//!
//! Cost: O(m) for m triangles plus the pairs of edges sharing a cell of a uniform grid (cells
//! about the mean boundary edge length), near-linear on real layouts.

use robust::{orient2d, Coord};

/// What [`check_layout`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Validity {
    /// Triangles not strictly counter-clockwise, or with a non-finite corner.
    pub flipped: usize,
    /// Pairs of boundary edges that touch or cross, plus islands inside another island.
    pub overlaps: usize,
    /// Islands: triangles connected through shared UV vertices.
    pub islands: usize,
}

impl Validity {
    /// No flipped triangle and no overlap.
    pub fn is_valid(&self) -> bool {
        self.flipped == 0 && self.overlaps == 0
    }
}

fn coord(p: [f64; 2]) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}

/// Exact orientation: > 0 counter-clockwise, < 0 clockwise, 0 collinear.
fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    orient2d(coord(a), coord(b), coord(c))
}

fn finite(p: [f64; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}

/// Checks the layout `uv_triangles` (indices into `uv`), see the module docs. Indices out of
/// range count as flipped triangles.
pub fn check_layout(uv: &[[f64; 2]], uv_triangles: &[[u32; 3]]) -> Validity {
    let corner = |t: &[u32; 3]| -> Option<[[f64; 2]; 3]> {
        let q = [uv.get(t[0] as usize)?, uv.get(t[1] as usize)?, uv.get(t[2] as usize)?];
        q.iter().all(|p| finite(**p)).then(|| q.map(|p| *p))
    };
    // Per triangle: (has finite corners in range, is counter-clockwise), in parallel on large
    // layouts (the orientation predicates are a third of the check).
    let state = crate::parallel::map_range(uv_triangles.len(), |t| {
        corner(&uv_triangles[t]).map_or((false, false), |[a, b, c]| (true, orient(a, b, c) > 0.0))
    });
    let flipped = state.iter().filter(|s| !s.1).count();
    let valid: Vec<[u32; 3]> = uv_triangles.iter().zip(&state).filter(|(_, s)| s.0).map(|(t, _)| *t).collect();
    let island = islands(uv.len(), &valid);
    let count = island.iter().max().map_or(0, |&m| m as usize + 1);
    let edges = crate::metrics::uv_edges(&valid).boundary;
    let overlaps = touching_edge_pairs(uv, &edges) + nested_islands(uv, &valid, &island, count);
    Validity { flipped, overlaps, islands: count }
}

/// Island of every triangle (union–find over shared UV vertices), numbered from 0 in order of
/// first triangle.
pub fn islands(vertex_count: usize, tris: &[[u32; 3]]) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..vertex_count as u32).collect();
    fn find(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            parent[v as usize] = parent[parent[v as usize] as usize];
            v = parent[v as usize];
        }
        v
    }
    for t in tris {
        let r = find(&mut parent, t[0]);
        for &v in &t[1..] {
            let s = find(&mut parent, v);
            parent[s as usize] = r;
        }
    }
    let mut number = vec![u32::MAX; vertex_count];
    let mut count = 0;
    tris.iter()
        .map(|t| {
            let root = find(&mut parent, t[0]) as usize;
            if number[root] == u32::MAX {
                number[root] = count;
                count += 1;
            }
            number[root]
        })
        .collect()
}

/// A uniform grid over boxes: the cells each box overlaps, as (cell, box) pairs sorted by cell
/// (a sort instead of a hash map of cells: the map's hashing took a third of the check).
struct Grid {
    origin: [f64; 2],
    cell: f64,
    entries: Vec<(u64, u32)>,
}

impl Grid {
    fn new(boxes: &[([f64; 2], [f64; 2])]) -> Grid {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let mut size = 0.0;
        for (a, b) in boxes {
            for d in 0..2 {
                lo[d] = lo[d].min(a[d]);
                hi[d] = hi[d].max(b[d]);
            }
            size += (b[0] - a[0]).max(b[1] - a[1]);
        }
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        // About the mean box size, and at least 1/1024 of the layout's extent.
        let mean = size / boxes.len().max(1) as f64;
        let cell = mean.max(extent / 1024.0).max(f64::MIN_POSITIVE);
        let mut grid = Grid { origin: lo, cell, entries: Vec::with_capacity(boxes.len()) };
        for (i, (a, b)) in boxes.iter().enumerate() {
            let (p, q) = (grid.cell_of(*a), grid.cell_of(*b));
            for x in p.0..=q.0 {
                for y in p.1..=q.1 {
                    grid.entries.push((Grid::key(x, y), i as u32));
                }
            }
        }
        grid.entries.sort_unstable();
        grid
    }

    /// Cell coordinates of a point inside the boxes' bounds (never negative: the origin is
    /// their lower corner).
    fn cell_of(&self, p: [f64; 2]) -> (u64, u64) {
        let c = |d: usize| ((p[d] - self.origin[d]) / self.cell).floor().max(0.0) as u64;
        (c(0), c(1))
    }

    fn key(x: u64, y: u64) -> u64 {
        (x << 32) | y
    }

    fn key_of(&self, p: [f64; 2]) -> u64 {
        let (x, y) = self.cell_of(p);
        Grid::key(x, y)
    }

    /// Every non-empty cell: its (cell, box) entries.
    fn cells(&self) -> impl Iterator<Item = &[(u64, u32)]> + '_ {
        self.entries.chunk_by(|a, b| a.0 == b.0)
    }

    /// The boxes in the cell of `p`.
    fn members(&self, p: [f64; 2]) -> impl Iterator<Item = u32> + '_ {
        let key = self.key_of(p);
        let start = self.entries.partition_point(|e| e.0 < key);
        self.entries[start..].iter().take_while(move |e| e.0 == key).map(|e| e.1)
    }
}

fn bounds(points: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in points {
        for d in 0..2 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    (lo, hi)
}

/// Pairs of boundary edges that share a point (see the module docs). Each pair is tested in
/// the one cell that holds the lower-left corner of the intersection of their boxes.
fn touching_edge_pairs(uv: &[[f64; 2]], edges: &[[u32; 2]]) -> usize {
    if edges.len() < 2 {
        return 0;
    }
    let boxes: Vec<([f64; 2], [f64; 2])> =
        edges.iter().map(|e| bounds(&[uv[e[0] as usize], uv[e[1] as usize]])).collect();
    let grid = Grid::new(&boxes);
    let mut count = 0;
    for members in grid.cells() {
        let key = members[0].0;
        for (k, &(_, i)) in members.iter().enumerate() {
            for &(_, j) in &members[k + 1..] {
                let (bi, bj) = (boxes[i as usize], boxes[j as usize]);
                let corner = [bi.0[0].max(bj.0[0]), bi.0[1].max(bj.0[1])];
                if corner[0] > bi.1[0].min(bj.1[0]) || corner[1] > bi.1[1].min(bj.1[1]) {
                    continue; // the boxes are apart
                }
                if grid.key_of(corner) == key && edges_touch(uv, edges[i as usize], edges[j as usize]) {
                    count += 1;
                }
            }
        }
    }
    count
}

/// Whether two boundary edges share a point; edges with a common endpoint index only when they
/// fold onto each other (collinear, pointing the same way from the common vertex).
fn edges_touch(uv: &[[f64; 2]], e: [u32; 2], f: [u32; 2]) -> bool {
    let p = |v: u32| uv[v as usize];
    let shared: Vec<u32> = e.iter().filter(|v| f.contains(v)).copied().collect();
    match shared.len() {
        0 => segments_intersect(p(e[0]), p(e[1]), p(f[0]), p(f[1])),
        1 => {
            let s = shared[0];
            let a = if e[0] == s { e[1] } else { e[0] };
            let b = if f[0] == s { f[1] } else { f[0] };
            let (o, pa, pb) = (p(s), p(a), p(b));
            orient(o, pa, pb) == 0.0 && (pa[0] - o[0]) * (pb[0] - o[0]) + (pa[1] - o[1]) * (pb[1] - o[1]) > 0.0
        }
        _ => false, // the same edge listed twice cannot happen: boundary edges are distinct
    }
}

/// Closed segments `ab` and `cd` share a point (exact).
fn segments_intersect(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (o1, o2) = (orient(a, b, c), orient(a, b, d));
    let (o3, o4) = (orient(c, d, a), orient(c, d, b));
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    let on = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        r[0] >= p[0].min(q[0]) && r[0] <= p[0].max(q[0]) && r[1] >= p[1].min(q[1]) && r[1] <= p[1].max(q[1])
    };
    (o1 == 0.0 && on(a, b, c)) || (o2 == 0.0 && on(a, b, d)) || (o3 == 0.0 && on(c, d, a)) || (o4 == 0.0 && on(c, d, b))
}

/// Islands one of whose vertices lies in (or on) a triangle of another island.
fn nested_islands(uv: &[[f64; 2]], tris: &[[u32; 3]], island: &[u32], count: usize) -> usize {
    if count < 2 {
        return 0;
    }
    let mut probe = vec![None; count];
    for (t, &i) in tris.iter().zip(island) {
        probe[i as usize].get_or_insert(uv[t[0] as usize]);
    }
    let boxes: Vec<([f64; 2], [f64; 2])> = tris.iter().map(|t| bounds(&t.map(|v| uv[v as usize]))).collect();
    let grid = Grid::new(&boxes);
    probe
        .iter()
        .enumerate()
        .filter(|(i, p)| {
            let Some(p) = p else { return false };
            grid.members(*p).any(|t| {
                let tri = tris[t as usize];
                island[t as usize] as usize != *i && inside_or_on(tri.map(|v| uv[v as usize]), *p)
            })
        })
        .count()
}

fn inside_or_on([a, b, c]: [[f64; 2]; 3], p: [f64; 2]) -> bool {
    let (x, y, z) = (orient(a, b, p), orient(b, c, p), orient(c, a, p));
    (x >= 0.0 && y >= 0.0 && z >= 0.0) || (x <= 0.0 && y <= 0.0 && z <= 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: [[f64; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];

    #[test]
    fn a_square_of_two_triangles_is_valid() {
        let v = check_layout(&SQUARE, &[[0, 1, 2], [0, 2, 3]]);
        assert_eq!(v, Validity { flipped: 0, overlaps: 0, islands: 1 });
    }

    #[test]
    fn clockwise_and_degenerate_triangles_are_flipped() {
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [2.0, 0.0]];
        assert_eq!(check_layout(&uv, &[[0, 2, 1]]).flipped, 1);
        assert_eq!(check_layout(&uv, &[[0, 1, 3]]).flipped, 1);
        assert_eq!(check_layout(&[[0.0, 0.0], [1.0, 0.0], [f64::NAN, 1.0]], &[[0, 1, 2]]).flipped, 1);
    }

    #[test]
    fn two_islands_crossing_overlap() {
        let uv = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [1.0, 1.0], [3.0, 1.0], [1.0, 3.0]];
        let v = check_layout(&uv, &[[0, 1, 2], [3, 4, 5]]);
        assert_eq!(v.islands, 2);
        assert!(v.overlaps > 0);
    }

    #[test]
    fn an_island_inside_another_overlaps_and_touching_islands_too() {
        let uv = [[0.0, 0.0], [10.0, 0.0], [0.0, 10.0], [1.0, 1.0], [2.0, 1.0], [1.0, 2.0]];
        assert_eq!(check_layout(&uv, &[[0, 1, 2], [3, 4, 5]]).overlaps, 1);
        // Sharing one point (different UV vertices at the same place) is a touch.
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0], [2.0, 0.0], [2.0, 1.0]];
        // Four pairs of edges meet at (1, 0), and island 1's first vertex lies on island 0.
        assert_eq!(check_layout(&uv, &[[0, 1, 2], [3, 4, 5]]).overlaps, 5);
        // Apart: valid.
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.5, 0.0], [2.0, 0.0], [2.0, 1.0]];
        assert!(check_layout(&uv, &[[0, 1, 2], [3, 4, 5]]).is_valid());
    }

    #[test]
    fn a_boundary_folding_back_at_a_vertex_overlaps() {
        // Two triangles sharing vertex 0 only, their edges 0-1 and 0-3 on one ray.
        let uv = [[0.0, 0.0], [2.0, 0.0], [1.0, 1.0], [1.0, 0.0], [1.0, -1.0]];
        let v = check_layout(&uv, &[[0, 1, 2], [0, 4, 3]]);
        assert_eq!(v.flipped, 0);
        assert!(v.overlaps > 0, "{v:?}");
    }
}
