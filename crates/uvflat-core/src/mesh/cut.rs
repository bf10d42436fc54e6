//! Cutting any connected manifold mesh (closed or with boundary loops, any genus) into a
//! topological disk, so that every disk method of the library can run on it.
//!
//! **Cut graph** (Eppstein 2003, "Dynamic generators of topologically embedded graphs": the
//! tree–cotree decomposition; Erickson & Whittlesey 2005 / Erickson & Har-Peled 2002 for the
//! greedy, shortest-path variant):
//! 1. A primal shortest-path tree `T` under an edge cost `c(e)`, grown by Dijkstra from a root
//!    vertex (closed meshes) or from all boundary vertices at once (meshes with boundary, so
//!    each tree of the forest hangs from exactly one boundary vertex).
//! 2. A dual spanning tree `D` over the faces, using only interior edges not in `T`, built as a
//!    *maximum* spanning tree by the loop length `σ(e) = d(u) + c(e) + d(v)` (Kruskal). The
//!    edges left over — in neither `T` nor `D` — are the `2g + (b − 1)` generators (b boundary
//!    loops, g genus); since the maximum tree keeps the long loops, the generators are the
//!    shortest ones (Erickson & Whittlesey's greedy system of loops).
//! 3. Cutting along every edge not crossed by `D` opens the surface into the disk of faces
//!    glued along `D` (the complement of a dual spanning tree is a cut graph). Pruning
//!    dangling branches (degree-one vertices, repeatedly) keeps that property and leaves the
//!    `2g` loops through `T` and the paths of `T` joining the boundary loops.
//! 4. A closed genus-0 mesh prunes to nothing; it is cut instead along the cheapest path
//!    between two far-apart vertices (two Dijkstra sweeps), a tree, so the result is a disk.
//!
//! **Steering** (Seamster, Sheffer & Hart 2002: seams through high-curvature, less visible
//! regions): the default cost of an edge is its length divided by `1 + 3·θ/π`, θ the dihedral
//! angle between its two triangles (so a sharp crease is up to 4× cheaper than a flat edge of
//! the same length); the closed-mesh root is the vertex of largest |angle defect|. Callers may
//! give their own non-negative cost per half-edge instead.
//!
//! **Cut mesh**: corners (one per triangle corner) are grouped by union–find across every
//! interior edge that is not cut; each group is one vertex of the cut mesh, so a vertex is
//! duplicated once per side of the cut (an interior vertex with k ≥ 1 incident cut edges gets
//! k copies, a boundary vertex k + 1). The result is validated: one component, one boundary
//! loop, Euler characteristic 1.
//!
//! Cost: O(E log E) (Dijkstra and the Kruskal sort), O(F) memory.

use super::{next, TriMesh, NONE};
use crate::error::{Error, Result};
use crate::geometry::{cross, distance, dot, norm, sub};
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use uvflat_sparse::union_find::find;

/// How the cut graph is steered.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum EdgeCost {
    /// Edge length divided by `1 + 3·θ/π` (θ the dihedral angle): short edges and sharp
    /// creases are cheap.
    #[default]
    CurvatureWeightedLength,
    /// Plain edge length (shortest cut graph in the greedy sense).
    Length,
    /// A caller-given non-negative cost per half-edge (`3·t + k` runs from corner k of
    /// triangle t to corner k + 1); an interior edge costs the mean of its two half-edges.
    PerHalfedge(Vec<f64>),
}

/// A mesh cut into a disk.
#[derive(Debug, Clone)]
pub struct Cut {
    /// Interior edges of the input opened by the cut, as `[a, b]` with `a < b` (original
    /// vertex numbers); the input's own boundary edges are not listed.
    pub edges: Vec<[u32; 2]>,
    /// Triangles of the cut mesh: `triangles[t][k]` is the cut-mesh vertex of corner k of input
    /// triangle t (same triangle order as the input).
    pub triangles: Vec<[u32; 3]>,
    /// The input vertex of every cut-mesh vertex.
    pub original: Vec<u32>,
    /// The cut mesh (positions copied from the input vertices), a validated disk.
    pub mesh: TriMesh,
}

impl Cut {
    /// Total 3D length of the cut edges.
    pub fn seam_length(&self, mesh: &TriMesh) -> f64 {
        self.edges.iter().map(|&[a, b]| distance(mesh.points()[a as usize], mesh.points()[b as usize])).sum()
    }

    /// Per-corner values (e.g. UVs) from values per cut-mesh vertex: 3 per input triangle.
    pub fn corner_values<T: Copy>(&self, per_vertex: &[T]) -> Vec<[T; 3]> {
        self.triangles.iter().map(|tri| tri.map(|v| per_vertex[v as usize])).collect()
    }
}

/// Total 3D length of the edges of a mesh (each undirected edge once).
pub fn total_edge_length(mesh: &TriMesh) -> f64 {
    let twin = &mesh.connectivity().twin;
    (0..twin.len() as u32)
        .filter(|&h| twin[h as usize] == NONE || twin[h as usize] > h)
        .map(|h| distance(mesh.points()[mesh.tail(h) as usize], mesh.points()[mesh.head(h) as usize]))
        .sum()
}

/// Undirected edges of a mesh: `edge_of[h]` for every half-edge, and one half-edge per edge
/// (the boundary one, or the lower of the two).
struct Edges {
    edge_of: Vec<u32>,
    halfedge: Vec<u32>,
}

impl Edges {
    fn new(mesh: &TriMesh) -> Self {
        let twin = &mesh.connectivity().twin;
        let mut edge_of = vec![NONE; twin.len()];
        let mut halfedge = Vec::with_capacity(twin.len() / 2 + 1);
        for h in 0..twin.len() as u32 {
            let t = twin[h as usize];
            if t == NONE || t > h {
                edge_of[h as usize] = halfedge.len() as u32;
                if t != NONE {
                    edge_of[t as usize] = halfedge.len() as u32;
                }
                halfedge.push(h);
            }
        }
        Edges { edge_of, halfedge }
    }

    fn len(&self) -> usize {
        self.halfedge.len()
    }
}

/// Cuts a connected manifold mesh into a topological disk (see the module docs).
pub fn cut_to_disk(mesh: &TriMesh, cost: &EdgeCost) -> Result<Cut> {
    cut_to_disk_through(mesh, cost, &[])
}

/// Cuts a connected manifold mesh into a topological disk whose boundary passes through every
/// vertex of `required` (e.g. the cone singularities of a frame field, which a seamless
/// parameterization can only have on the cut). The cut graph of [`cut_to_disk`] (nothing on a
/// closed genus-0 mesh with two or more required vertices) is joined to the required vertices
/// by the paths of one shortest-path forest grown from it (a forest hanging from the graph, so
/// the complement stays a disk); dangling branches that end at no required vertex are pruned.
pub fn cut_to_disk_through(mesh: &TriMesh, cost: &EdgeCost, required: &[u32]) -> Result<Cut> {
    let topology = mesh.topology();
    if topology.components != 1 {
        return Err(Error::MultipleComponents { components: topology.components });
    }
    if let Some(&v) = required.iter().find(|&&v| !mesh.is_referenced(v)) {
        return Err(Error::InvalidArgument(format!("required cut vertex {v} is not a vertex of a triangle")));
    }
    let edges = Edges::new(mesh);
    let costs = edge_costs(mesh, &edges, cost)?;
    let sphere = topology.boundary_loops == 0 && topology.genus == 0;
    let mut keep = vec![false; mesh.vertex_count()];
    for &v in required {
        keep[v as usize] = true;
    }
    let distinct = keep.iter().filter(|&&k| k).count();
    let mut cut = match (sphere, distinct) {
        (true, 0 | 1) => sphere_cut_path(mesh, &edges, &costs),
        (true, _) => vec![false; edges.len()],
        (false, _) => cut_graph(mesh, &edges, &costs),
    };
    if distinct > 0 {
        join_required(mesh, &edges, &costs, &mut cut, &keep);
    }
    // The cut graph comes pruned; joined paths may leave branches that lead to no required vertex.
    if distinct > 0 && !(sphere && distinct < 2) {
        prune_dangling_keeping(mesh, &edges, &mut cut, &keep);
    }
    if cut.iter().all(|&c| !c) && topology.boundary_loops == 0 {
        return Err(Error::Internal("cut graph of a closed mesh is empty".into()));
    }
    // Boundary edges are already open; `cut` marks interior edges only.
    for (e, &h) in edges.halfedge.iter().enumerate() {
        if mesh.connectivity().is_boundary(h) {
            cut[e] = false;
        }
    }
    if sphere && cut.iter().filter(|&&c| c).count() == 1 {
        // Two required vertices joined by one edge: a one-edge slit does not open the sphere;
        // it is extended by one more edge at one end.
        let e = cut.iter().position(|&c| c).unwrap_or(0);
        let h = edges.halfedge[e];
        let (a, b) = (mesh.tail(h), mesh.head(h));
        if let Some(g) = mesh.outgoing_halfedges(b).find(|&g| mesh.head(g) != a) {
            cut[edges.edge_of[g as usize] as usize] = true;
        }
    }
    build_cut_mesh(mesh, &edges, &cut)
}

/// Adds to `cut` the shortest path from the graph (or, when it is empty, from the first
/// required vertex) to every required vertex off it.
fn join_required(mesh: &TriMesh, edges: &Edges, costs: &[f64], cut: &mut [bool], keep: &[bool]) {
    let mut on_graph = vec![false; mesh.vertex_count()];
    for (e, &h) in edges.halfedge.iter().enumerate() {
        if cut[e] {
            on_graph[mesh.tail(h) as usize] = true;
            on_graph[mesh.head(h) as usize] = true;
        }
    }
    let mut sources: Vec<u32> = (0..mesh.vertex_count() as u32).filter(|&v| on_graph[v as usize]).collect();
    if sources.is_empty() {
        match keep.iter().position(|&k| k) {
            Some(v) => sources.push(v as u32),
            None => return,
        }
    }
    let (_, parent) = shortest_path_tree(mesh, edges, costs, &sources);
    for v in (0..mesh.vertex_count() as u32).filter(|&v| keep[v as usize]) {
        let mut w = v;
        while parent[w as usize] != NONE && !cut[parent[w as usize] as usize] {
            let e = parent[w as usize];
            cut[e as usize] = true;
            let h = edges.halfedge[e as usize];
            w = if mesh.tail(h) == w { mesh.head(h) } else { mesh.tail(h) };
        }
    }
}

/// Cost of every edge, checked finite and non-negative.
fn edge_costs(mesh: &TriMesh, edges: &Edges, cost: &EdgeCost) -> Result<Vec<f64>> {
    let twin = &mesh.connectivity().twin;
    let length = |h: u32| distance(mesh.points()[mesh.tail(h) as usize], mesh.points()[mesh.head(h) as usize]);
    let costs: Vec<f64> = match cost {
        EdgeCost::Length => edges.halfedge.iter().map(|&h| length(h)).collect(),
        EdgeCost::CurvatureWeightedLength => {
            let normals: Vec<[f64; 3]> = mesh.triangles().iter().map(|t| unit_normal(mesh.points(), *t)).collect();
            edges
                .halfedge
                .iter()
                .map(|&h| {
                    let t = twin[h as usize];
                    if t == NONE {
                        return length(h);
                    }
                    let (n1, n2) = (normals[(h / 3) as usize], normals[(t / 3) as usize]);
                    let theta = norm(cross(n1, n2)).atan2(dot(n1, n2));
                    length(h) / (1.0 + 3.0 * theta / std::f64::consts::PI)
                })
                .collect()
        }
        EdgeCost::PerHalfedge(given) => {
            if given.len() != twin.len() {
                return Err(Error::InvalidArgument(format!(
                    "edge costs have {} entries but the mesh has {} half-edges (3 per triangle)",
                    given.len(),
                    twin.len()
                )));
            }
            if let Some(h) = given.iter().position(|c| !(c.is_finite() && *c >= 0.0)) {
                return Err(Error::InvalidArgument(format!(
                    "edge cost of half-edge {h} is {} (must be finite and ≥ 0)",
                    given[h]
                )));
            }
            edges
                .halfedge
                .iter()
                .map(|&h| match twin[h as usize] {
                    NONE => given[h as usize],
                    t => 0.5 * (given[h as usize] + given[t as usize]),
                })
                .collect()
        }
    };
    Ok(costs)
}

fn unit_normal(points: &[[f64; 3]], t: [u32; 3]) -> [f64; 3] {
    let [a, b, c] = t.map(|v| points[v as usize]);
    let n = cross(sub(b, a), sub(c, a));
    let l = norm(n);
    if l > 0.0 {
        n.map(|x| x / l)
    } else {
        [0.0; 3]
    }
}

/// Vertex with the largest |angle defect| (2π − Σ angles for interior vertices), the root of
/// the closed-mesh trees.
fn most_curved_vertex(mesh: &TriMesh) -> u32 {
    let mut sum = vec![0.0; mesh.vertex_count()];
    for (tri, angles) in mesh.triangles().iter().zip(mesh.corner_angles()) {
        for k in 0..3 {
            sum[tri[k] as usize] += angles[k];
        }
    }
    let tau = 2.0 * std::f64::consts::PI;
    (0..mesh.vertex_count() as u32)
        .filter(|&v| mesh.is_referenced(v))
        .max_by(|&a, &b| (tau - sum[a as usize]).abs().total_cmp(&(tau - sum[b as usize]).abs()))
        .unwrap_or(0)
}

/// A heap entry ordered by smallest distance first.
#[derive(PartialEq)]
struct Entry(f64, u32);
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

/// Shortest-path tree from `sources` under the edge costs: distance of every vertex and the
/// edge to its parent (`NONE` for sources and unreferenced vertices).
fn shortest_path_tree(mesh: &TriMesh, edges: &Edges, costs: &[f64], sources: &[u32]) -> (Vec<f64>, Vec<u32>) {
    let n = mesh.vertex_count();
    let mut dist = vec![f64::INFINITY; n];
    let mut parent = vec![NONE; n];
    let mut heap = BinaryHeap::new();
    for &s in sources {
        dist[s as usize] = 0.0;
        heap.push(Entry(0.0, s));
    }
    let twin = &mesh.connectivity().twin;
    while let Some(Entry(d, v)) = heap.pop() {
        if d > dist[v as usize] {
            continue;
        }
        let first = mesh.connectivity().vertex_halfedge[v as usize];
        // Every neighbour: heads of the outgoing half-edges, plus (at a boundary vertex) the
        // tail of the incoming boundary half-edge, which no outgoing half-edge reaches.
        let mut relax = |w: u32, e: u32| {
            let nd = d + costs[e as usize];
            if nd < dist[w as usize] {
                dist[w as usize] = nd;
                parent[w as usize] = e;
                heap.push(Entry(nd, w));
            }
        };
        let mut last = first;
        for h in mesh.outgoing_halfedges(v) {
            relax(mesh.head(h), edges.edge_of[h as usize]);
            last = h;
        }
        if first != NONE && twin[first as usize] == NONE {
            let incoming = super::prev(last);
            if twin[incoming as usize] == NONE {
                relax(mesh.tail(incoming), edges.edge_of[incoming as usize]);
            }
        }
    }
    (dist, parent)
}

/// Tree–cotree cut graph, pruned: `true` for every edge of the cut graph (boundary edges
/// included, they are cleared by the caller).
///
/// On a closed mesh every loop passes through the root, so a root off the cheap loops drags
/// in the paths joining them to it. The graph is therefore computed twice: from the most
/// curved vertex, then from the vertex of highest degree in that first cut graph (where
/// loops already meet).
///
/// A third candidate ignores roots altogether: the complement of the maximum dual spanning tree
/// by edge cost (every expensive edge that can be kept uncut is), pruned. The cheapest of the
/// candidates (total cost of the cut edges) is returned.
fn cut_graph(mesh: &TriMesh, edges: &Edges, costs: &[f64]) -> Vec<bool> {
    let cost_of = |cut: &[bool]| -> f64 { cut.iter().zip(costs).filter(|(c, _)| **c).map(|(_, w)| w).sum() };
    let by_cost = cut_graph_by_cost(mesh, edges, costs);
    let rooted = rooted_cut_graph(mesh, edges, costs);
    if cost_of(&by_cost) < cost_of(&rooted) {
        by_cost
    } else {
        rooted
    }
}

/// Complement of the maximum dual spanning tree by edge cost, pruned.
fn cut_graph_by_cost(mesh: &TriMesh, edges: &Edges, costs: &[f64]) -> Vec<bool> {
    let conn = mesh.connectivity();
    let mut order: Vec<u32> =
        (0..edges.len() as u32).filter(|&e| !conn.is_boundary(edges.halfedge[e as usize])).collect();
    order.sort_unstable_by(|&a, &b| costs[b as usize].total_cmp(&costs[a as usize]).then(a.cmp(&b)));
    let mut face_set: Vec<u32> = (0..mesh.triangle_count() as u32).collect();
    let mut cut = vec![true; edges.len()];
    for &e in &order {
        let h = edges.halfedge[e as usize];
        let (a, b) = (find(&mut face_set, h / 3), find(&mut face_set, conn.twin[h as usize] / 3));
        if a != b {
            face_set[a.max(b) as usize] = a.min(b);
            cut[e as usize] = false;
        }
    }
    prune_dangling(mesh, edges, &mut cut);
    cut
}

/// The tree–cotree candidates (from the boundary, or from the most curved vertex and then the
/// hub of that first graph).
fn rooted_cut_graph(mesh: &TriMesh, edges: &Edges, costs: &[f64]) -> Vec<bool> {
    if !mesh.boundary_loops().is_empty() {
        let sources: Vec<u32> = mesh.boundary_loops().iter().flatten().copied().collect();
        return cut_graph_from(mesh, edges, costs, &sources);
    }
    let root = most_curved_vertex(mesh);
    let first = cut_graph_from(mesh, edges, costs, &[root]);
    let mut degree = vec![0u32; mesh.vertex_count()];
    for (e, &h) in edges.halfedge.iter().enumerate() {
        if first[e] {
            degree[mesh.tail(h) as usize] += 1;
            degree[mesh.head(h) as usize] += 1;
        }
    }
    let hub =
        (0..mesh.vertex_count() as u32).max_by_key(|&v| (degree[v as usize], std::cmp::Reverse(v))).unwrap_or(root);
    if hub == root || degree[hub as usize] == 0 {
        return first;
    }
    let second = cut_graph_from(mesh, edges, costs, &[hub]);
    let cost_of = |cut: &[bool]| -> f64 { cut.iter().zip(costs).filter(|(c, _)| **c).map(|(_, w)| w).sum() };
    if cost_of(&second) <= cost_of(&first) {
        second
    } else {
        first
    }
}

/// The pruned tree–cotree cut graph with the primal tree grown from `sources`.
fn cut_graph_from(mesh: &TriMesh, edges: &Edges, costs: &[f64], sources: &[u32]) -> Vec<bool> {
    let conn = mesh.connectivity();
    let (dist, parent) = shortest_path_tree(mesh, edges, costs, sources);
    let mut in_tree = vec![false; edges.len()];
    for &e in parent.iter().filter(|&&e| e != NONE) {
        in_tree[e as usize] = true;
    }
    // Dual maximum spanning tree by loop length over interior non-tree edges.
    let mut candidates: Vec<(f64, u32)> = (0..edges.len() as u32)
        .filter(|&e| !in_tree[e as usize] && !conn.is_boundary(edges.halfedge[e as usize]))
        .map(|e| {
            let h = edges.halfedge[e as usize];
            (dist[mesh.tail(h) as usize] + costs[e as usize] + dist[mesh.head(h) as usize], e)
        })
        .collect();
    candidates.sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let mut face_set: Vec<u32> = (0..mesh.triangle_count() as u32).collect();
    let mut cut = vec![true; edges.len()];
    for &(_, e) in &candidates {
        let h = edges.halfedge[e as usize];
        let (a, b) = (find(&mut face_set, h / 3), find(&mut face_set, conn.twin[h as usize] / 3));
        if a != b {
            face_set[a.max(b) as usize] = a.min(b);
            cut[e as usize] = false;
        }
    }
    prune_dangling(mesh, edges, &mut cut);
    cut
}

/// Removes degree-one vertices of the cut graph (and their edge) until none is left.
fn prune_dangling(mesh: &TriMesh, edges: &Edges, cut: &mut [bool]) {
    prune_dangling_keeping(mesh, edges, cut, &vec![false; mesh.vertex_count()]);
}

/// [`prune_dangling`], except that the vertices marked in `keep` stay even at degree one.
fn prune_dangling_keeping(mesh: &TriMesh, edges: &Edges, cut: &mut [bool], keep: &[bool]) {
    let n = mesh.vertex_count();
    let mut degree = vec![0u32; n];
    for (e, &h) in edges.halfedge.iter().enumerate() {
        if cut[e] {
            degree[mesh.tail(h) as usize] += 1;
            degree[mesh.head(h) as usize] += 1;
        }
    }
    let mut stack: Vec<u32> = (0..n as u32).filter(|&v| degree[v as usize] == 1 && !keep[v as usize]).collect();
    while let Some(v) = stack.pop() {
        if degree[v as usize] != 1 || keep[v as usize] {
            continue;
        }
        // A degree-one vertex is interior (boundary vertices have two boundary edges), so its
        // edges are exactly those of its outgoing half-edges.
        let Some(h) = mesh.outgoing_halfedges(v).find(|&h| cut[edges.edge_of[h as usize] as usize]) else { continue };
        cut[edges.edge_of[h as usize] as usize] = false;
        degree[v as usize] = 0;
        let w = mesh.head(h);
        degree[w as usize] -= 1;
        if degree[w as usize] == 1 {
            stack.push(w);
        }
    }
}

/// Closed genus-0 mesh: the cheapest path between two far-apart vertices (from the most curved
/// vertex, the farthest vertex a; from a, the farthest b; the path a → b), with at least two
/// edges so that the cut mesh is a proper disk.
fn sphere_cut_path(mesh: &TriMesh, edges: &Edges, costs: &[f64]) -> Vec<bool> {
    let farthest = |dist: &[f64]| {
        (0..dist.len() as u32)
            .filter(|&v| dist[v as usize].is_finite())
            .max_by(|&a, &b| dist[a as usize].total_cmp(&dist[b as usize]))
    };
    let root = most_curved_vertex(mesh);
    let (d0, _) = shortest_path_tree(mesh, edges, costs, &[root]);
    let a = farthest(&d0).unwrap_or(root);
    let (da, parent) = shortest_path_tree(mesh, edges, costs, &[a]);
    let b = farthest(&da).unwrap_or(a);
    let mut cut = vec![false; edges.len()];
    let mut path_edges = 0;
    let mut v = b;
    while parent[v as usize] != NONE {
        let e = parent[v as usize];
        cut[e as usize] = true;
        path_edges += 1;
        let h = edges.halfedge[e as usize];
        v = if mesh.tail(h) == v { mesh.head(h) } else { mesh.tail(h) };
    }
    if path_edges == 1 {
        // Extend at b by an edge to a vertex other than a.
        if let Some(h) = mesh.outgoing_halfedges(b).find(|&h| mesh.head(h) != a) {
            cut[edges.edge_of[h as usize] as usize] = true;
        }
    }
    cut
}

/// Splits the vertices along the cut edges (union–find over corners) and validates the disk.
/// Opens `mesh` along the given interior edges (vertex pairs, either order; every one must be
/// an edge of `mesh`), which must form a cut graph (the result is checked to be a disk).
pub fn cut_along(mesh: &TriMesh, cut_edges: &[[u32; 2]]) -> Result<Cut> {
    let edges = Edges::new(mesh);
    let wanted: std::collections::HashSet<[u32; 2]> = cut_edges.iter().map(|&[a, b]| [a.min(b), a.max(b)]).collect();
    let cut: Vec<bool> = edges
        .halfedge
        .iter()
        .map(|&h| {
            let (a, b) = (mesh.tail(h), mesh.head(h));
            wanted.contains(&[a.min(b), a.max(b)])
        })
        .collect();
    let found = cut.iter().filter(|&&c| c).count();
    if found != wanted.len() {
        return Err(Error::InvalidArgument(format!(
            "{} of the {} cut edges are not edges of the mesh",
            wanted.len() - found,
            wanted.len()
        )));
    }
    build_cut_mesh(mesh, &edges, &cut)
}

fn build_cut_mesh(mesh: &TriMesh, edges: &Edges, cut: &[bool]) -> Result<Cut> {
    let twin = &mesh.connectivity().twin;
    // Corner ids are half-edge ids: corner k of triangle t is the tail of half-edge 3t + k.
    let mut group: Vec<u32> = (0..twin.len() as u32).collect();
    let union = |x: u32, y: u32, group: &mut Vec<u32>| {
        let (a, b) = (find(group, x), find(group, y));
        if a != b {
            group[a.max(b) as usize] = a.min(b);
        }
    };
    for (e, &h) in edges.halfedge.iter().enumerate() {
        let g = twin[h as usize];
        if g == NONE || cut[e] {
            continue;
        }
        // tail(h) = head(g) = tail(next(g)); head(h) = tail(next(h)) = tail(g).
        union(h, next(g), &mut group);
        union(next(h), g, &mut group);
    }
    let mut new_id = vec![NONE; twin.len()];
    let mut original = Vec::new();
    let mut triangles = vec![[0u32; 3]; mesh.triangle_count()];
    for h in 0..twin.len() as u32 {
        let root = find(&mut group, h) as usize;
        if new_id[root] == NONE {
            new_id[root] = original.len() as u32;
            original.push(mesh.tail(h));
        }
        triangles[(h / 3) as usize][(h % 3) as usize] = new_id[root];
    }
    let points: Vec<[f64; 3]> = original.iter().map(|&v| mesh.points()[v as usize]).collect();
    let cut_mesh = TriMesh::from_checked(points, triangles.clone())
        .map_err(|e| Error::Internal(format!("the cut mesh is invalid: {e}")))?;
    let t = cut_mesh.topology();
    if t.components != 1 || t.boundary_loops != 1 || t.euler_characteristic != 1 {
        return Err(Error::Internal(format!(
            "cutting did not give a disk: {} component(s), {} boundary loop(s), Euler characteristic {}",
            t.components, t.boundary_loops, t.euler_characteristic
        )));
    }
    let mut cut_edges: Vec<[u32; 2]> = edges
        .halfedge
        .iter()
        .enumerate()
        .filter(|&(e, _)| cut[e])
        .map(|(_, &h)| {
            let (a, b) = (mesh.tail(h), mesh.head(h));
            [a.min(b), a.max(b)]
        })
        .collect();
    cut_edges.sort_unstable();
    Ok(Cut { edges: cut_edges, triangles, original, mesh: cut_mesh })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A torus of `n × m` quads split into triangles.
    fn torus(n: u32, m: u32) -> TriMesh {
        let mut positions = Vec::new();
        for i in 0..n {
            for j in 0..m {
                let (u, v) = (i as f64 / n as f64 * std::f64::consts::TAU, j as f64 / m as f64 * std::f64::consts::TAU);
                let r = 2.0 + v.cos();
                positions.extend([r * u.cos(), r * u.sin(), v.sin()]);
            }
        }
        let id = |i: u32, j: u32| (i % n) * m + (j % m);
        let mut tris = Vec::new();
        for i in 0..n {
            for j in 0..m {
                tris.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        TriMesh::new(&positions, &tris).expect("torus")
    }

    /// An octahedron (closed, genus 0).
    fn octahedron() -> TriMesh {
        let p = [1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0];
        let t = [0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5];
        TriMesh::new(&p, &t).expect("octahedron")
    }

    fn assert_disk(mesh: &TriMesh, cut: &Cut) {
        let t = cut.mesh.topology();
        assert_eq!((t.components, t.boundary_loops, t.euler_characteristic), (1, 1, 1));
        for (tri, cut_tri) in mesh.triangles().iter().zip(&cut.triangles) {
            assert_eq!(*tri, cut_tri.map(|v| cut.original[v as usize]));
        }
    }

    #[test]
    fn torus_is_cut_along_two_loops_into_a_disk() {
        let mesh = torus(12, 8);
        let cut = cut_to_disk(&mesh, &EdgeCost::default()).expect("cut");
        assert_disk(&mesh, &cut);
        // Two loops through one vertex: that vertex has 4 copies, other cut vertices 2.
        let copies = cut.original.len() - mesh.vertex_count();
        assert_eq!(copies, cut.edges.len() - 1 + 2, "a two-loop cut graph has E − 1 + 2 extra copies");
    }

    #[test]
    fn octahedron_is_cut_along_a_path() {
        let mesh = octahedron();
        let cut = cut_to_disk(&mesh, &EdgeCost::Length).expect("cut");
        assert_disk(&mesh, &cut);
        assert!(cut.edges.len() >= 2);
        // A path of k edges duplicates its k − 1 inner vertices.
        assert_eq!(cut.original.len(), mesh.vertex_count() + cut.edges.len() - 1);
    }

    #[test]
    fn caller_costs_steer_the_cut() {
        let mesh = torus(12, 8);
        let twin = &mesh.connectivity().twin;
        // Make every edge expensive except those on the ring j = 0 and the ring i = 0.
        let costs: Vec<f64> = (0..twin.len() as u32)
            .map(|h| {
                let (a, b) = (mesh.tail(h), mesh.head(h));
                let same_ring = (a / 8 == 0 && b / 8 == 0) || (a % 8 == 0 && b % 8 == 0);
                if same_ring {
                    0.01
                } else {
                    10.0
                }
            })
            .collect();
        let cut = cut_to_disk(&mesh, &EdgeCost::PerHalfedge(costs)).expect("cut");
        assert_disk(&mesh, &cut);
        assert_eq!(cut.edges.len(), 12 + 8, "the cut is the two cheap rings");
        assert!(
            cut.edges.iter().all(|&[a, b]| (a / 8 == 0 && b / 8 == 0) || (a % 8 == 0 && b % 8 == 0)),
            "{:?}",
            cut.edges
        );
    }
}
