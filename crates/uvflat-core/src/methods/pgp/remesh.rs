//! Quad-dominant remeshing from a PGP parameterization (Ray et al. 2006, §5 "Implicit
//! remeshing"): the iso-θ and iso-φ lines at `density` lines per period ([`super::isolines`])
//! form the initial polygon mesh; its vertices are the line crossings (grid nodes) and the
//! points where lines meet the mesh boundary; its faces are the faces of the line graph on
//! the surface. Faces that are not quadrilaterals (next to singularities, where lines were
//! removed, §3.2–3.3) are split into quads and at most one triangle by a fan from the corner
//! that gives the largest smallest angle ("the polygons which are not quadrilateral are split
//! into a union of quads and triangles"); a T-vertex (a line ending on another) is a corner of
//! the polygon on its flat side, so that polygon is split with a triangle, as the paper does.
//!
//! The output vertices lie on the input surface (inside a triangle or on an edge). Quad sides
//! are about `2π / (ω · density)` long. Cost: O(F + output).

use super::isolines::{iso_graph_of, IsoGraph, NodeKind, PeriodicMap};
use super::PgpResult;
use crate::error::Result;
use crate::geometry::{dot, norm, sub};
use crate::mesh::NONE;
use crate::TriMesh;
use std::collections::{HashMap, HashSet};

/// A polygon mesh: `face_sizes[f]` indices per face, concatenated in `indices`, counter-
/// clockwise seen from outside the surface.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PolygonMesh {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Number of corners of every face.
    pub face_sizes: Vec<u32>,
    /// Vertex indices of the faces, concatenated.
    pub indices: Vec<u32>,
}

impl PolygonMesh {
    /// Number of faces with four corners.
    pub fn quad_count(&self) -> usize {
        self.face_sizes.iter().filter(|&&s| s == 4).count()
    }

    /// The faces as index slices.
    pub fn faces(&self) -> impl Iterator<Item = &[u32]> + '_ {
        let mut start = 0usize;
        self.face_sizes.iter().map(move |&s| {
            let face = &self.indices[start..start + s as usize];
            start += s as usize;
            face
        })
    }
}

/// The quad-dominant remesh of `result` at `density` lines per period (a whole number ≥ 1).
pub fn quad_dominant_remesh(mesh: &TriMesh, result: &PgpResult, density: f64) -> Result<PolygonMesh> {
    quad_dominant_remesh_of(mesh, &PeriodicMap::of_pgp(result), density)
}

/// [`quad_dominant_remesh`] of any [`PeriodicMap`] (e.g. QuadCover's seamless map).
pub fn quad_dominant_remesh_of(mesh: &TriMesh, map: &PeriodicMap, density: f64) -> Result<PolygonMesh> {
    let graph = iso_graph_of(mesh, map, density)?;
    let mut corner = corner_nodes(&graph);
    let faces = graph.faces();
    for v in parallel_side_nodes(&graph, &corner, &faces) {
        corner[v as usize] = true;
    }
    let polygons: Vec<Vec<u32>> = faces
        .into_iter()
        .flat_map(|cycle| {
            simple_polygons(&cycle.into_iter().map(|(v, _)| v).filter(|&v| corner[v as usize]).collect::<Vec<_>>())
        })
        .filter(|p| p.len() >= 3)
        .collect();
    let polygons = without_pillows(polygons);
    let mut edges: HashSet<(u32, u32)> = polygons.iter().flat_map(|p| sides(p)).collect();
    let mut out = PolygonMesh::default();
    let mut index = vec![NONE; graph.position.len()];
    for polygon in &polygons {
        for piece in split_polygon(&graph.position, polygon, &mut edges) {
            let ids: Vec<u32> = piece.iter().map(|&v| vertex_index(&mut out, &mut index, &graph, v)).collect();
            out.face_sizes.push(ids.len() as u32);
            out.indices.extend(ids);
        }
    }
    // Splitting first: a pinched vertex's fan of two faces is a doublet once it has a copy of
    // its own.
    split_pinched_vertices(&mut out);
    merge_doublets(&mut out);
    Ok(out)
}

/// Merges the two faces of every doublet: a vertex v with exactly two faces that share both
/// of its edges (b–v and v–d), left where a line of the graph stops one node short of a
/// crossing. The two faces lie on either side of the path b–v–d, so they fold onto each other
/// around v, and a reader that fan-triangulates them (uvflat's own OBJ reader, and most) gets
/// two triangles over the same three vertices. Their union without v is one polygon: two
/// quads make a quad, a quad and a triangle a triangle. Repeated until no doublet is left (a
/// merge can make b or d a doublet); v is dropped from the vertices. Pillows are dropped too
/// (their four corners are all doublets, and no merge can remove them).
fn merge_doublets(out: &mut PolygonMesh) {
    let mut faces: Vec<Option<Vec<u32>>> = out.faces().map(|f| Some(f.to_vec())).collect();
    let mut merged_any = false;
    loop {
        let mut incident: Vec<Vec<usize>> = vec![Vec::new(); out.positions.len()];
        for (f, face) in faces.iter().enumerate() {
            for &v in face.iter().flatten() {
                incident[v as usize].push(f);
            }
        }
        let mut touched = vec![false; faces.len()];
        let mut merged = false;
        for (v, at_v) in incident.iter().enumerate() {
            let &[f, g] = at_v.as_slice() else { continue };
            if touched[f] || touched[g] {
                continue;
            }
            let (Some(a), Some(b)) = (&faces[f], &faces[g]) else { continue };
            if let Some(union) = doublet_union(a, b, v as u32) {
                faces[f] = Some(union);
                faces[g] = None;
                (touched[f], touched[g], merged) = (true, true, true);
            }
        }
        if !merged {
            break;
        }
        merged_any = true;
    }
    // Two faces over one cycle in opposite directions (a pocket the polygon splitting can leave
    // where a small cycle was split twice) are dropped as before the split.
    let count = faces.iter().flatten().count();
    let kept = without_pillows(faces.into_iter().flatten().collect());
    if merged_any || kept.len() != count {
        *out = compacted(&out.positions, kept.into_iter());
    }
}

/// The union of faces `a` and `b` around their doublet vertex `v` (a: … x, v, y …; b: … y, v,
/// x …), without v; None when they do not meet that way or the union repeats a vertex.
fn doublet_union(a: &[u32], b: &[u32], v: u32) -> Option<Vec<u32>> {
    let (i, j) = (a.iter().position(|&w| w == v)?, b.iter().position(|&w| w == v)?);
    let (na, nb) = (a.len(), b.len());
    let (x, y) = (a[(i + na - 1) % na], a[(i + 1) % na]);
    if b[(j + nb - 1) % nb] != y || b[(j + 1) % nb] != x {
        return None;
    }
    // a from y round to x, then b's corners strictly between x and y.
    let mut union: Vec<u32> = (1..na).map(|k| a[(i + k) % na]).collect();
    union.extend((2..nb - 1).map(|k| b[(j + k) % nb]));
    let distinct: HashSet<u32> = union.iter().copied().collect();
    (union.len() >= 3 && distinct.len() == union.len()).then_some(union)
}

/// The polygon mesh of `faces` over the vertices they use, renumbered in order of first use.
fn compacted(positions: &[[f64; 3]], faces: impl Iterator<Item = Vec<u32>>) -> PolygonMesh {
    let mut out = PolygonMesh::default();
    let mut index = vec![NONE; positions.len()];
    for face in faces {
        out.face_sizes.push(face.len() as u32);
        for v in face {
            if index[v as usize] == NONE {
                index[v as usize] = out.positions.len() as u32;
                out.positions.push(positions[v as usize]);
            }
            out.indices.push(index[v as usize]);
        }
    }
    out
}

/// Gives every fan of faces around a vertex its own copy of the vertex. Where the line graph
/// pinches (two chains of faces touching only at one node: seen next to the singular regions
/// of the coarse knight with the smoothing at ρ = 0.9), the output would otherwise be
/// non-manifold at that vertex; the copies share its position. Fans are the classes of corners
/// at a vertex linked through shared edges: the corner whose next vertex is x and the corner
/// whose previous vertex is x.
fn split_pinched_vertices(out: &mut PolygonMesh) {
    let starts: Vec<usize> = out
        .face_sizes
        .iter()
        .scan(0usize, |start, &size| {
            let s = *start;
            *start += size as usize;
            Some(s)
        })
        .collect();
    // Corners (positions in `indices`) at each vertex, with their previous and next vertices.
    let mut corners: Vec<Vec<(usize, u32, u32)>> = vec![Vec::new(); out.positions.len()];
    for (f, &size) in out.face_sizes.iter().enumerate() {
        let (start, n) = (starts[f], size as usize);
        for i in 0..n {
            let v = out.indices[start + i];
            let prev = out.indices[start + (i + n - 1) % n];
            let next = out.indices[start + (i + 1) % n];
            corners[v as usize].push((start + i, prev, next));
        }
    }
    for at_v in corners.iter().filter(|c| c.len() > 1) {
        let fans = fan_classes(at_v);
        let mut copy_of: HashMap<usize, u32> = HashMap::new();
        let first = fans[0];
        for (k, &(slot, _, _)) in at_v.iter().enumerate() {
            if fans[k] == first {
                continue;
            }
            let v = out.indices[slot];
            let id = *copy_of.entry(fans[k]).or_insert_with(|| {
                out.positions.push(out.positions[v as usize]);
                (out.positions.len() - 1) as u32
            });
            out.indices[slot] = id;
        }
    }
}

/// Class (smallest member) of every corner around one vertex, corners being linked when they
/// share an edge (see [`split_pinched_vertices`]).
fn fan_classes(corners: &[(usize, u32, u32)]) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..corners.len()).collect();
    fn root(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    for a in 0..corners.len() {
        for b in 0..corners.len() {
            if a != b && corners[a].2 == corners[b].1 {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    (0..corners.len()).map(|k| root(&mut parent, k)).collect()
}

/// A side: the graph path from one corner to the next, named by its first arm `(corner,
/// slot)`.
type Side = (u32, u8);

/// The path of side `(u, s)`: its interior nodes, its end corner, and the side naming it from
/// that end.
fn follow(graph: &IsoGraph, corner: &[bool], (u, s): Side) -> (Vec<u32>, Side) {
    let mut interior = Vec::new();
    let mut arm = graph.arms[u as usize][s as usize];
    while !corner[arm.to as usize] && arm.to != u {
        let v = arm.to as usize;
        interior.push(arm.to);
        match graph.other_arm(v, arm.back as usize) {
            Some(k) => arm = graph.arms[v][k],
            None => break,
        }
    }
    (interior, (arm.to, arm.back))
}

/// Nodes to make corners so that no two sides join the same two corners: two such sides
/// would become one edge of the output (non-manifold where, around a handle or a singular
/// region, they are not the two sides of a two-cornered face, which is dropped and whose
/// sides become one edge). The middle node of every such side but one becomes a corner.
fn parallel_side_nodes(graph: &IsoGraph, corner: &[bool], faces: &[Vec<(u32, u8)>]) -> Vec<u32> {
    let mut class: HashMap<Side, Side> = HashMap::new();
    let mut paths: HashMap<Side, (Vec<u32>, (u32, u32))> = HashMap::new();
    for face in faces {
        let mut names = Vec::new();
        for &side in face.iter().filter(|&&(v, _)| corner[v as usize]) {
            let (interior, back) = follow(graph, corner, side);
            let name = side.min(back);
            paths.entry(name).or_insert((interior, undirected(side.0, back.0)));
            class.entry(name).or_insert(name);
            names.push(name);
        }
        if let [a, b] = names[..] {
            let (ra, rb) = (find(&class, a), find(&class, b));
            class.insert(rb, ra);
        }
    }
    let mut by_ends: HashMap<(u32, u32), Vec<Side>> = HashMap::new();
    let mut names: Vec<Side> = paths.keys().copied().collect();
    names.sort_unstable();
    for name in names {
        let ends = paths[&name].1;
        let root = find(&class, name);
        let group = by_ends.entry(ends).or_default();
        if !group.contains(&root) {
            group.push(root);
        }
    }
    let mut promote = Vec::new();
    for (&(a, b), roots) in &by_ends {
        if a == b || roots.len() < 2 {
            continue;
        }
        // Keep the class of a direct edge (no interior node) if any, else the first.
        let keep = roots
            .iter()
            .position(|r| paths.iter().any(|(n, p)| p.1 == (a, b) && p.0.is_empty() && find(&class, *n) == *r))
            .unwrap_or(0);
        for (i, r) in roots.iter().enumerate() {
            if i == keep {
                continue;
            }
            for (n, p) in &paths {
                if p.1 == (a, b) && find(&class, *n) == *r && !p.0.is_empty() {
                    promote.push(p.0[p.0.len() / 2]);
                }
            }
        }
    }
    promote
}

/// Root of `x`'s class.
fn find(class: &HashMap<Side, Side>, x: Side) -> Side {
    let mut r = x;
    while class[&r] != r {
        r = class[&r];
    }
    r
}

/// Drops pairs of polygons that are the same cycle in opposite directions: the two faces on
/// either side of a closed line that meets no other (a loop around a tube, or an island
/// in a singular region), which would form a closed two-faced pocket.
fn without_pillows(polygons: Vec<Vec<u32>>) -> Vec<Vec<u32>> {
    let key = |p: &[u32]| {
        let start = (0..p.len()).min_by_key(|&i| p[i]).unwrap_or(0);
        let n = p.len();
        let forward: Vec<u32> = (0..n).map(|i| p[(start + i) % n]).collect();
        let backward: Vec<u32> = (0..n).map(|i| p[(start + n - i) % n]).collect();
        (forward, backward)
    };
    let forward: HashSet<Vec<u32>> = polygons.iter().map(|p| key(p).0).collect();
    polygons.into_iter().filter(|p| !forward.contains(&key(p).1)).collect()
}

/// The sides of a polygon as undirected edges.
fn sides(polygon: &[u32]) -> impl Iterator<Item = (u32, u32)> + '_ {
    (0..polygon.len()).map(|i| undirected(polygon[i], polygon[(i + 1) % polygon.len()]))
}

fn undirected(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

fn vertex_index(out: &mut PolygonMesh, index: &mut [u32], graph: &IsoGraph, v: u32) -> u32 {
    if index[v as usize] == NONE {
        index[v as usize] = out.positions.len() as u32;
        out.positions.push(graph.position[v as usize]);
    }
    index[v as usize]
}

/// Nodes that are polygon corners: grid nodes except those left with two opposite arms, and
/// boundary nodes where a line arrives. Crossings of mesh edges are interior points of sides.
pub fn corner_nodes(graph: &IsoGraph) -> Vec<bool> {
    (0..graph.position.len())
        .map(|v| {
            let present: Vec<usize> = (0..graph.arms[v].len()).filter(|&s| graph.arms[v][s].to != NONE).collect();
            match graph.kind[v] {
                NodeKind::Grid => present.len() >= 3 || (present.len() == 2 && present[1] - present[0] != 2),
                NodeKind::Boundary => present.len() == 3,
                NodeKind::Crossing => false,
            }
        })
        .collect()
}

/// Splits a closed walk that visits a vertex twice into simple cycles.
fn simple_polygons(walk: &[u32]) -> Vec<Vec<u32>> {
    let mut out = Vec::new();
    let mut stack: Vec<u32> = Vec::new();
    for &v in walk {
        if let Some(pos) = stack.iter().position(|&u| u == v) {
            out.push(stack.split_off(pos));
        }
        stack.push(v);
    }
    out.push(stack);
    out
}

/// A quad, a triangle, or for more corners a fan of quads (and one triangle when the count is
/// odd) from the corner that maximizes the smallest angle of the pieces, among the fans whose
/// diagonals are not edges already (which would make the output non-manifold); the polygon is
/// kept whole when there is none. The chosen diagonals are added to `edges`.
fn split_polygon(position: &[[f64; 3]], polygon: &[u32], edges: &mut HashSet<(u32, u32)>) -> Vec<Vec<u32>> {
    let n = polygon.len();
    if n <= 4 {
        return vec![polygon.to_vec()];
    }
    let fan = |start: usize| -> Vec<Vec<u32>> {
        let at = |i: usize| polygon[(start + i) % n];
        let mut pieces = Vec::new();
        let mut i = 1;
        while i + 2 < n {
            pieces.push(vec![at(0), at(i), at(i + 1), at(i + 2)]);
            i += 2;
        }
        if i + 1 < n {
            pieces.push(vec![at(0), at(i), at(i + 1)]);
        }
        pieces
    };
    let score = |pieces: &[Vec<u32>]| pieces.iter().map(|p| smallest_angle(position, p)).fold(f64::INFINITY, f64::min);
    // A fan's diagonals join its first corner to the last corner of every piece but the last.
    let diagonals = |pieces: &[Vec<u32>]| -> Vec<(u32, u32)> {
        pieces[..pieces.len() - 1].iter().map(|p| undirected(p[0], p[p.len() - 1])).collect()
    };
    let best = (0..n)
        .map(fan)
        .filter(|pieces| diagonals(pieces).iter().all(|d| !edges.contains(d)))
        .max_by(|a, b| score(a).total_cmp(&score(b)));
    match best {
        Some(pieces) => {
            edges.extend(diagonals(&pieces));
            pieces
        }
        None => vec![polygon.to_vec()],
    }
}

/// Smallest corner angle of a polygon in space (radians).
fn smallest_angle(position: &[[f64; 3]], polygon: &[u32]) -> f64 {
    let n = polygon.len();
    (0..n)
        .map(|i| {
            let p = position[polygon[i] as usize];
            let a = sub(position[polygon[(i + n - 1) % n] as usize], p);
            let b = sub(position[polygon[(i + 1) % n] as usize], p);
            let denom = norm(a) * norm(b);
            if denom > 0.0 {
                (dot(a, b) / denom).clamp(-1.0, 1.0).acos()
            } else {
                0.0
            }
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two closed tetrahedra, the second sharing vertex 0 with the first when `pinched`.
    fn two_tetrahedra(pinched: bool) -> PolygonMesh {
        let tetrahedron = |[a, b, c, d]: [u32; 4]| [[a, c, b], [a, b, d], [a, d, c], [b, c, d]];
        let second = if pinched { [0, 4, 5, 6] } else { [7, 4, 5, 6] };
        let faces: Vec<[u32; 3]> = tetrahedron([0, 1, 2, 3]).into_iter().chain(tetrahedron(second)).collect();
        let count = if pinched { 7 } else { 8 };
        PolygonMesh {
            positions: (0..count).map(|i| [i as f64, (i * i) as f64, 0.0]).collect(),
            face_sizes: vec![3; faces.len()],
            indices: faces.concat(),
        }
    }

    #[test]
    fn a_vertex_shared_by_two_fans_gets_one_copy_per_fan() {
        let mut mesh = two_tetrahedra(true);
        split_pinched_vertices(&mut mesh);
        assert_eq!(mesh.positions.len(), 8);
        assert_eq!(mesh.positions[7], mesh.positions[0]);
        let faces: Vec<&[u32]> = mesh.faces().collect();
        assert!(faces[..4].iter().all(|f| !f.contains(&7)) && faces[..3].iter().all(|f| f.contains(&0)));
        assert!(faces[4..].iter().all(|f| !f.contains(&0)) && faces[4..7].iter().all(|f| f.contains(&7)));
    }

    #[test]
    fn manifold_output_is_left_unchanged() {
        let mut mesh = two_tetrahedra(false);
        let before = mesh.clone();
        split_pinched_vertices(&mut mesh);
        assert_eq!(mesh, before);
    }
}
