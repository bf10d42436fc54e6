//! The graph of iso-lines of a PGP parameterization on the surface: Ray et al. 2006 §3.3,
//! Algorithm 2 (iso-2kπ lines of θ and φ: the chart boundaries), generalized as in §5 to
//! `density` lines per period (the quad-dominant remesh).
//!
//! In grid units `g = value · density / 2π` the lines are the integers of both families. In
//! every non-singular triangle (§3.2) each line crossing it is a straight chord between two
//! edges; chords of different families that cross inside the triangle meet at a **grid node**.
//! A chord's end on a mesh edge is a **crossing node**; the two triangles of a regular edge
//! (non-singular edge between non-singular triangles) share their crossing nodes ("merge the
//! segment end-points stored in e", Algorithm 2); on singular edges and next to singular
//! triangles the ends stay apart, and on the mesh boundary consecutive crossings are joined
//! along the boundary. Dangling segments are removed ("nibbled" until a node of valence above
//! two is met).
//!
//! Exactness. Every corner value is `σ·A_v + density·k` with σ = ±1 and A_v one of the two
//! grid-unit angles of its vertex (the quarter-turn transitions of eq. 16 swap and negate θ
//! and φ; the translations are whole periods), so whether a corner lies above a line is
//! decided on `A_v` itself, identically in every triangle around the vertex. Values exactly on
//! a line are treated as if `A_v` were raised by an infinitesimal (simulation of simplicity),
//! which the transitions carry along. Hence both sides of a regular edge see exactly the same
//! lines, identified by the line's value in the chart of the edge's lower vertex. Whether two
//! chords cross inside a triangle is decided combinatorially (their ends interleave along the
//! triangle's boundary, with one order per edge shared by both sides), so every line crossing
//! is counted once and the graph is planar.
//!
//! Rotation system. In a non-singular triangle (θ, φ) is positively oriented, so the four arms
//! of a grid node, towards increasing θ, increasing φ, decreasing θ, decreasing φ, are in
//! counter-clockwise order on the surface; the faces of the graph are traced from it
//! ([`IsoGraph::faces`]).
//!
//! Cost: O(F + output) time and memory.

use super::extraction::{angles, nearest_period, CornerParameterization};
use super::singularities::transition;
use super::PgpResult;
use crate::error::{Error, Result};
use crate::mesh::NONE;
use crate::TriMesh;
use rayon::prelude::*;
use std::collections::HashSet;
use std::f64::consts::TAU;

/// One end of a graph edge: the neighbouring node and the slot of the arm there pointing back.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arm {
    /// Neighbour node, or [`NONE`] for an absent or removed arm.
    pub to: u32,
    /// Slot of the reverse arm at `to`.
    pub back: u8,
    /// Whether the face to the left of this arm is outside the surface (mesh boundary).
    pub outside: bool,
}

const NO_ARM: Arm = Arm { to: NONE, back: 0, outside: false };

/// What a node is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeKind {
    /// Crossing of a θ-line and a φ-line inside a triangle.
    Grid,
    /// A line crossing an interior mesh edge.
    Crossing,
    /// A line reaching the mesh boundary.
    Boundary,
}

/// The iso-line graph: nodes on the surface with their arms in counter-clockwise order.
#[derive(Debug, Clone)]
pub struct IsoGraph {
    /// Position of every node on the surface.
    pub position: Vec<[f64; 3]>,
    /// Kind of every node.
    pub kind: Vec<NodeKind>,
    /// A triangle the node lies in (on the boundary of, for crossings).
    pub triangle: Vec<u32>,
    /// Arms of every node, counter-clockwise (grid nodes: +θ, +φ, −θ, −φ).
    pub arms: Vec<Vec<Arm>>,
    /// Where every node lies in the triangulation.
    pub location: Vec<NodeLocation>,
    /// Every chord as built, before the dangling segments were removed.
    pub chords: Vec<ChordPath>,
}

/// Where a node lies: on a mesh edge or inside a triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NodeLocation {
    /// On half-edge `half_edge` (`3t + k`, from corner k to k + 1), at parameter `t` from its
    /// tail.
    Edge {
        /// The half-edge.
        half_edge: u32,
        /// Parameter along it, in [0, 1].
        t: f64,
    },
    /// Inside triangle `triangle`, at barycentric coordinates `bary`.
    Inside {
        /// The triangle.
        triangle: u32,
        /// Barycentric coordinates (corner order of the triangle).
        bary: [f64; 3],
    },
}

/// One line crossing one triangle: its nodes in order, each with the slot of the arm towards
/// the next node (`out`) and from the previous one (`inward`).
#[derive(Debug, Clone, PartialEq)]
pub struct ChordPath {
    /// The triangle.
    pub triangle: u32,
    /// 0: a θ-line, 1: a φ-line (in the triangle's own chart).
    pub family: u8,
    /// `(node, slot towards the previous node, slot towards the next node)`; the first node's
    /// inward slot and the last node's out slot are unused.
    pub nodes: Vec<(u32, u8, u8)>,
}

impl IsoGraph {
    /// Whether the segment between the `i`-th and `i + 1`-th node of `chord` is still in the
    /// graph (not removed as dangling).
    pub fn segment_present(&self, chord: &ChordPath, i: usize) -> bool {
        let (u, _, out) = chord.nodes[i];
        let (w, inward, _) = chord.nodes[i + 1];
        let arm = self.arms[u as usize][out as usize];
        arm.to == w && arm.back == inward
    }
}

/// A node's slot count by kind: grid 4, crossing 2 (one per side), boundary 3 (along the
/// boundary forwards, into the surface, backwards).
fn slot_count(kind: NodeKind) -> usize {
    match kind {
        NodeKind::Grid => 4,
        NodeKind::Crossing => 2,
        NodeKind::Boundary => 3,
    }
}

/// A corner value in grid units: `sign · A[vertex][comp] + density · period`.
#[derive(Debug, Clone, Copy)]
struct CornerValue {
    sign: f64,
    comp: usize,
    period: i64,
}

/// Where a chord ends: the triangle edge (half-edge `3t + edge`), the parameter along it, and
/// the line's key in the chart of the edge's lower vertex.
#[derive(Debug, Clone, Copy)]
struct ChordEnd {
    edge: u8,
    t: f64,
    /// Infinitesimal offset of `t` (in units of the perturbation) for ends at a corner.
    tie: f64,
    key: (u8, i64),
}

/// A line of family `family` (0: θ, 1: φ) at grid value `value` crossing one triangle.
#[derive(Debug, Clone, Copy)]
struct Chord {
    family: u8,
    value: i64,
    /// The corner alone on its side of the line, and whether it is above it.
    lone: u8,
    lone_above: bool,
    ends: [ChordEnd; 2],
}

/// What the iso-line graph is drawn from: a per-corner (θ, φ) of the form of Algorithm 1 — every
/// corner is its vertex's two angles turned by `param.rotation` quarter turns plus
/// `param.shift` whole periods — and the triangles that carry no lines. PGP's result gives one
/// ([`PeriodicMap::of_pgp`]); so does any seamless map with quarter-turn, whole-period
/// transitions (QuadCover, [`crate::methods::quadcover::quad_mesh`]).
pub struct PeriodicMap<'a> {
    /// Per-corner (θ, φ) with their rotations and shifts.
    pub param: &'a CornerParameterization,
    /// (θ, φ) of every vertex, in (−π, π]; `param.coords` must equal them turned and shifted
    /// up to round-off (well below half a period).
    pub vertex_angles: Vec<[f64; 2]>,
    /// Triangles without lines (singular, §3.2, or otherwise not positively oriented).
    pub singular_triangles: &'a [u32],
}

impl<'a> PeriodicMap<'a> {
    /// The map of a PGP result: the angles of its unknowns, its singular triangles.
    pub fn of_pgp(result: &'a PgpResult) -> Self {
        PeriodicMap {
            param: &result.param,
            vertex_angles: result.unknowns.iter().map(|&x| angles(x)).collect(),
            singular_triangles: &result.singularities.triangles,
        }
    }
}

/// Builds the iso-line graph of `result` at `density` lines per period (1: the chart
/// boundaries of §3.3). Errors: density not a whole number ≥ 1 (the lines must be invariant
/// under whole-period translations).
pub fn iso_graph(mesh: &TriMesh, result: &PgpResult, density: f64) -> Result<IsoGraph> {
    iso_graph_of(mesh, &PeriodicMap::of_pgp(result), density)
}

/// [`iso_graph`] of any [`PeriodicMap`]. Errors: bad density, a map whose sizes do not match
/// `mesh`.
pub fn iso_graph_of(mesh: &TriMesh, map: &PeriodicMap, density: f64) -> Result<IsoGraph> {
    let d = check_density(density)?;
    check_sizes(mesh, map)?;
    check_graph_fits(map, d, available_memory())?;
    let grid = GridValues::new(mesh, map, d);
    let regular = regular_triangles(mesh, map);
    let chords: Vec<Vec<Chord>> = (0..mesh.triangle_count())
        .into_par_iter()
        .with_min_len(1024)
        .map(|t| if regular[t] { triangle_chords(mesh, &grid, t) } else { Vec::new() })
        .collect();
    let mut builder = Builder::default();
    let ends = builder.crossing_nodes(mesh, map.param, &regular, &chords);
    for t in 0..mesh.triangle_count() {
        if regular[t] {
            builder.triangle_grid(mesh, &grid, t, &chords[t], &ends[t]);
        }
    }
    builder.boundary_chains(mesh);
    let mut graph = IsoGraph {
        position: builder.position,
        kind: builder.kind,
        triangle: builder.triangle,
        arms: builder.arms,
        location: builder.location,
        chords: builder.chords,
    };
    graph.nibble();
    graph.keep_largest_components(mesh);
    Ok(graph)
}

/// Errors unless `map` has one entry per triangle (per vertex for the angles) of `mesh`.
fn check_sizes(mesh: &TriMesh, map: &PeriodicMap) -> Result<()> {
    let (t, p) = (mesh.triangle_count(), map.param);
    let sizes = [p.coords.len(), p.rotation.len(), p.shift.len()];
    if sizes.iter().any(|&n| n != t)
        || map.vertex_angles.len() != mesh.vertex_count()
        || map.singular_triangles.iter().any(|&s| s as usize >= t)
    {
        return Err(Error::InvalidArgument(format!(
            "the periodic map does not match the mesh ({t} triangles, {} vertices; the map has {sizes:?} corner \
             triangles and {} vertex angles)",
            mesh.vertex_count(),
            map.vertex_angles.len()
        )));
    }
    Ok(())
}

/// The density as a whole number of lines per period; an error unless a whole number ≥ 1.
pub fn check_density(density: f64) -> Result<i64> {
    if density.is_finite() && density >= 1.0 && density.fract() == 0.0 && density < 1e9 {
        Ok(density as i64)
    } else {
        Err(Error::InvalidArgument(format!(
            "density must be a whole number of lines per period, at least 1 (got {density})"
        )))
    }
}

/// Peak memory per grid cell of the line graph and the polygon mesh built from it, measured:
/// `uvflat pgp closed_g1_bob.obj --quad-mesh … --quad-density 256` made 720,391 faces and
/// peaked at 460 MB (about 640 bytes a face).
const BYTES_PER_CELL: f64 = 640.0;

/// Refuses a density whose line graph would not fit in `available` bytes of memory (None:
/// unknown, not checked). The graph has about one node per grid cell, Σ_T |area of T in
/// (θ, φ)| · (density / 2π)² over the triangles that carry lines; without this check a large
/// density on a small mesh ran the machine out of memory (a process killed, not an error).
pub fn check_graph_fits(map: &PeriodicMap, density: i64, available: Option<f64>) -> Result<()> {
    let singular: HashSet<u32> = map.singular_triangles.iter().copied().collect();
    let area: f64 = (map.param.coords.iter().enumerate())
        .filter(|(t, _)| !singular.contains(&(*t as u32)))
        .map(|(_, [a, b, c])| 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs())
        .sum();
    let cells = area * (density as f64 / TAU).powi(2);
    let needed = cells * BYTES_PER_CELL;
    match available {
        Some(bytes) if needed > bytes => Err(Error::InvalidArgument(format!(
            "density {density} would make about {cells:.3e} grid cells, needing about {:.1} GB of memory; {:.1} GB \
             are available",
            needed / 1e9,
            bytes / 1e9
        ))),
        _ => Ok(()),
    }
}

/// Memory the system can still give (Linux: MemAvailable of /proc/meminfo), in bytes.
fn available_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kilobytes: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kilobytes * 1024.0)
}

/// Triangles that carry lines: not singular (§3.2).
fn regular_triangles(mesh: &TriMesh, map: &PeriodicMap) -> Vec<bool> {
    let mut regular = vec![true; mesh.triangle_count()];
    for &t in map.singular_triangles {
        regular[t as usize] = false;
    }
    regular
}

/// Grid-unit angles per vertex and the signed-permutation form of every corner value.
struct GridValues {
    density: i64,
    angle: Vec<[f64; 2]>,
    corner: Vec<[[CornerValue; 2]; 3]>,
}

impl GridValues {
    fn new(mesh: &TriMesh, map: &PeriodicMap, density: i64) -> Self {
        let scale = density as f64 / TAU;
        let raw = &map.vertex_angles;
        let angle = raw.iter().map(|a| [a[0] * scale, a[1] * scale]).collect();
        let param = map.param;
        let corner = (0..mesh.triangle_count())
            .map(|t| {
                std::array::from_fn(|c| {
                    let v = mesh.triangles()[t][c] as usize;
                    let perm = signed_permutation(param.rotation[t][c]);
                    std::array::from_fn(|f| {
                        let (comp, sign) = perm[f];
                        let k = nearest_period(param.coords[t][c][f] - sign * raw[v][comp]);
                        CornerValue { sign, comp, period: k }
                    })
                })
            })
            .collect();
        GridValues { density, angle, corner }
    }

    /// Corner `c` of triangle `t`, family `f`, in grid units.
    fn value(&self, mesh: &TriMesh, t: usize, c: usize, f: usize) -> f64 {
        let cv = self.corner[t][c][f];
        let v = mesh.triangles()[t][c] as usize;
        cv.sign * self.angle[v][cv.comp] + (self.density * cv.period) as f64
    }

    /// Whether corner `c` of `t` lies above line `n` of family `f` (exact, ties broken by
    /// raising the vertex's angles infinitesimally).
    fn above(&self, mesh: &TriMesh, t: usize, c: usize, f: usize, n: i64) -> bool {
        let cv = self.corner[t][c][f];
        let v = mesh.triangles()[t][c] as usize;
        let x = cv.sign * self.angle[v][cv.comp];
        let m = (n - self.density * cv.period) as f64;
        x > m || (x == m && cv.sign > 0.0)
    }

    /// The vertex component whose value puts corner `c` of `t` exactly on line `n` of family
    /// `f` (before the perturbation), if it is.
    fn on_line(&self, mesh: &TriMesh, t: usize, c: usize, f: usize, n: i64) -> Option<usize> {
        let cv = self.corner[t][c][f];
        let v = mesh.triangles()[t][c] as usize;
        (cv.sign * self.angle[v][cv.comp] == (n - self.density * cv.period) as f64).then_some(cv.comp)
    }

    /// Line `n` of family `f` seen from corner `c` of `t`: (component, value) in the chart of
    /// the corner's vertex.
    fn key(&self, t: usize, c: usize, f: usize, n: i64) -> (u8, i64) {
        let cv = self.corner[t][c][f];
        (cv.comp as u8, cv.sign as i64 * (n - self.density * cv.period))
    }
}

/// The infinitesimal raise of a vertex's two grid-unit angles (simulation of simplicity),
/// relative: different so that two lines through one vertex cross next to it, not on it.
const PERTURBATION: [f64; 2] = [1.0, 2.0];

/// Scale of the geometric offset of a crossing at a corner (see [`chord`]).
const NUDGE: f64 = 1e-7;

/// `(component, sign)` of θ and φ after `r` quarter turns P(θ, φ) = (φ, −θ) (the rotation of
/// the unknowns, [`super::periodic::unknown_rotation`]).
fn signed_permutation(r: u8) -> [(usize, f64); 2] {
    let mut p = [(0, 1.0), (1, 1.0)];
    for _ in 0..(r % 4) {
        p = [p[1], (p[0].0, -p[0].1)];
    }
    p
}

/// The chords of both families in triangle `t`.
fn triangle_chords(mesh: &TriMesh, grid: &GridValues, t: usize) -> Vec<Chord> {
    let mut chords = Vec::new();
    for f in 0..2 {
        let g: [f64; 3] = std::array::from_fn(|c| grid.value(mesh, t, c, f));
        let lo = g.iter().cloned().fold(f64::INFINITY, f64::min).floor() as i64 - 1;
        let hi = g.iter().cloned().fold(f64::NEG_INFINITY, f64::max).ceil() as i64 + 1;
        for n in lo..=hi {
            let above: [bool; 3] = std::array::from_fn(|c| grid.above(mesh, t, c, f, n));
            if let Some(lone) = lone_corner(above) {
                chords.push(chord(mesh, grid, t, f, n, &g, lone));
            }
        }
    }
    chords
}

/// The corner on the other side of a line from the two others, if the line crosses.
fn lone_corner(above: [bool; 3]) -> Option<usize> {
    (0..3).find(|&c| above[c] != above[(c + 1) % 3] && above[c] != above[(c + 2) % 3])
}

/// The chord of line `n` (family `f`) separating corner `lone` from the others: it crosses
/// the half-edges `lone → lone+1` and `lone+2 → lone`.
fn chord(mesh: &TriMesh, grid: &GridValues, t: usize, f: usize, n: i64, g: &[f64; 3], lone: usize) -> Chord {
    let end = |e: usize| {
        let (a, b) = (e, (e + 1) % 3);
        let slope = (g[b] - g[a]).abs().max(f64::MIN_POSITIVE);
        // A corner exactly on the line crosses at its perturbed position, an infinitesimal
        // PERTURBATION[comp] / |slope| away from it (which orders lines meeting there).
        // The node is placed at that perturbed position, NUDGE × tie along the edge, so it
        // does not coincide with the corner (cut triangulations and remeshes stay free of
        // zero-length edges).
        let (along, tie) = if let Some(comp) = grid.on_line(mesh, t, a, f, n) {
            let tie = PERTURBATION[comp] / slope;
            ((NUDGE * tie).min(0.25), tie)
        } else if let Some(comp) = grid.on_line(mesh, t, b, f, n) {
            let tie = -PERTURBATION[comp] / slope;
            ((1.0 + NUDGE * tie).max(0.75), tie)
        } else if g[b] != g[a] {
            (((n as f64 - g[a]) / (g[b] - g[a])).clamp(0.0, 1.0), 0.0)
        } else {
            (0.5, 0.0)
        };
        let tri = mesh.triangles()[t];
        let lower = if tri[a] < tri[b] { a } else { b };
        ChordEnd { edge: e as u8, t: along, tie, key: grid.key(t, lower, f, n) }
    };
    let lone_above = grid.above(mesh, t, lone, f, n);
    Chord { family: f as u8, value: n, lone: lone as u8, lone_above, ends: [end(lone), end((lone + 2) % 3)] }
}

/// Incremental graph construction.
#[derive(Default)]
struct Builder {
    position: Vec<[f64; 3]>,
    kind: Vec<NodeKind>,
    triangle: Vec<u32>,
    arms: Vec<Vec<Arm>>,
    location: Vec<NodeLocation>,
    chords: Vec<ChordPath>,
    /// Boundary crossing nodes per boundary half-edge, in the half-edge's direction.
    boundary: std::collections::HashMap<u32, Vec<u32>>,
}

/// A chord end resolved to its node: `(node, slot, position along the triangle boundary)`.
type ResolvedEnd = (u32, u8, u64);

impl Builder {
    fn add_node(&mut self, position: [f64; 3], kind: NodeKind, triangle: usize, location: NodeLocation) -> u32 {
        self.location.push(location);
        self.position.push(position);
        self.kind.push(kind);
        self.triangle.push(triangle as u32);
        self.arms.push(vec![NO_ARM; slot_count(kind)]);
        (self.position.len() - 1) as u32
    }

    fn link(&mut self, (u, su): (u32, u8), (v, sv): (u32, u8)) {
        self.arms[u as usize][su as usize] = Arm { to: v, back: sv, outside: false };
        self.arms[v as usize][sv as usize] = Arm { to: u, back: su, outside: false };
    }

    /// Crossing nodes for every chord end, shared across regular edges; returns each chord's
    /// two ends resolved, per triangle.
    fn crossing_nodes(
        &mut self,
        mesh: &TriMesh,
        param: &CornerParameterization,
        regular: &[bool],
        chords: &[Vec<Chord>],
    ) -> Vec<Vec<[ResolvedEnd; 2]>> {
        let mut ends: Vec<Vec<[ResolvedEnd; 2]>> = chords.iter().map(|c| vec![[(NONE, 0, 0); 2]; c.len()]).collect();
        let twin = &mesh.connectivity().twin;
        for h in 0..twin.len() {
            let t = h / 3;
            if !regular[t] {
                continue;
            }
            let g = twin[h];
            let shared = g != NONE && regular[g as usize / 3] && edge_is_regular(param, h, g as usize);
            if shared && (g as usize) < h {
                continue; // resolved with g
            }
            let mine = edge_crossings(&chords[t], (h % 3) as u8);
            let theirs = if shared { edge_crossings(&chords[g as usize / 3], (g % 3) as u8) } else { Vec::new() };
            self.resolve_edge(mesh, h, shared.then_some(g as usize), chords, &mine, &theirs, &mut ends);
        }
        ends
    }

    /// Nodes for the crossings on half-edge `h` (and its twin `g` when shared), ordered along
    /// `h` by parameter (ties by key), the order both triangles use.
    #[allow(clippy::too_many_arguments)]
    fn resolve_edge(
        &mut self,
        mesh: &TriMesh,
        h: usize,
        g: Option<usize>,
        chords: &[Vec<Chord>],
        mine: &[(usize, usize)],
        theirs: &[(usize, usize)],
        ends: &mut [Vec<[ResolvedEnd; 2]>],
    ) {
        let t = h / 3;
        let end_of = |tt: usize, (ci, ei): (usize, usize)| chords[tt][ci].ends[ei];
        let mut order: Vec<(usize, usize)> = mine.to_vec();
        order.sort_by(|&a, &b| {
            let (ea, eb) = (end_of(t, a), end_of(t, b));
            ea.t.total_cmp(&eb.t).then(ea.tie.total_cmp(&eb.tie)).then(ea.key.cmp(&eb.key))
        });
        let mut partner: std::collections::HashMap<(u8, i64), (usize, usize)> = std::collections::HashMap::new();
        if let Some(g) = g {
            for &x in theirs {
                partner.insert(end_of(g / 3, x).key, x);
            }
        }
        let count = order.len() as u64;
        let (a, b) = (mesh.tail(h as u32), mesh.head(h as u32));
        let (pa, pb) = (mesh.points()[a as usize], mesh.points()[b as usize]);
        for (rank, &(ci, ei)) in order.iter().enumerate() {
            let end = chords[t][ci].ends[ei];
            let other = g.and_then(|_| partner.remove(&end.key));
            let kind = if g.is_none() && mesh.connectivity().twin[h] == NONE {
                NodeKind::Boundary
            } else {
                NodeKind::Crossing
            };
            let mut s = end.t;
            if let (Some(g), Some(x)) = (g, other) {
                s = 0.5 * (s + 1.0 - end_of(g / 3, x).t);
            }
            let at = NodeLocation::Edge { half_edge: h as u32, t: s };
            let node = self.add_node(lerp(pa, pb, s), kind, t, at);
            let slot = if kind == NodeKind::Boundary { 1 } else { 0 };
            ends[t][ci][ei] = (node, slot, boundary_position(h % 3, rank as u64));
            if let (Some(g), Some((cj, ej))) = (g, other) {
                ends[g / 3][cj][ej] = (node, 1, boundary_position(g % 3, count - 1 - rank as u64));
            }
            if kind == NodeKind::Boundary {
                self.boundary.entry(h as u32).or_default().push(node);
            }
        }
        if let Some(g) = g {
            // Lines seen on g's side only (a mismatch the exact tests rule out): own nodes.
            let mut leftover: Vec<((u8, i64), (usize, usize))> = partner.into_iter().collect();
            leftover.sort_unstable();
            for (_, (cj, ej)) in leftover {
                let end = chords[g / 3][cj].ends[ej];
                let at = NodeLocation::Edge { half_edge: g as u32, t: end.t };
                let node = self.add_node(lerp(pb, pa, end.t), NodeKind::Crossing, g / 3, at);
                ends[g / 3][cj][ej] = (node, 0, boundary_position(g % 3, 0));
            }
        }
    }

    /// The grid nodes of triangle `t` and the chord segments between them.
    fn triangle_grid(
        &mut self,
        mesh: &TriMesh,
        grid: &GridValues,
        t: usize,
        chords: &[Chord],
        ends: &[[ResolvedEnd; 2]],
    ) {
        let g: [[f64; 3]; 2] = std::array::from_fn(|f| std::array::from_fn(|c| grid.value(mesh, t, c, f)));
        let tri = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
        // Grid nodes on each chord: (other family's value, node).
        let mut on_chord: Vec<Vec<(i64, u32, usize)>> = vec![Vec::new(); chords.len()];
        for i in 0..chords.len() {
            for j in 0..chords.len() {
                if chords[i].family != 0 || chords[j].family != 1 || !interleave(ends[i], ends[j]) {
                    continue;
                }
                let bary = grid_point(&g, chords[i].value as f64, chords[j].value as f64);
                let p = std::array::from_fn(|k| bary[0] * tri[0][k] + bary[1] * tri[1][k] + bary[2] * tri[2][k]);
                let at = NodeLocation::Inside { triangle: t as u32, bary };
                let node = self.add_node(p, NodeKind::Grid, t, at);
                on_chord[i].push((chords[j].value, node, j));
                on_chord[j].push((chords[i].value, node, i));
            }
        }
        for (i, nodes) in on_chord.iter_mut().enumerate() {
            let rising = match nodes.first() {
                Some(&(_, _, j)) => !end_above(ends[i][0], &chords[j], ends[j]),
                None => true,
            };
            self.link_chord(t, chords[i].family, ends[i], rising, nodes);
        }
    }

    /// Links a chord's ends and grid nodes in order of the other family's value; `rising`:
    /// that value increases from end 0 to end 1 (decided exactly, [`end_above`]).
    fn link_chord(
        &mut self,
        t: usize,
        family: u8,
        ends: [ResolvedEnd; 2],
        rising: bool,
        nodes: &mut [(i64, u32, usize)],
    ) {
        let (low, high) = if rising { (ends[0], ends[1]) } else { (ends[1], ends[0]) };
        nodes.sort_unstable_by_key(|&(v, _, _)| v);
        // θ-chord (family 0): moving up in φ leaves a node by arm 1 (+φ), enters by arm 3 (−φ);
        // φ-chord: by arm 0 (+θ), enters by arm 2 (−θ).
        let (out_slot, in_slot) = if family == 0 { (1u8, 3u8) } else { (0u8, 2u8) };
        let mut path = vec![(low.0, 0, low.1)];
        let mut prev = (low.0, low.1);
        for &(_, node, _) in nodes.iter() {
            self.link(prev, (node, in_slot));
            path.push((node, in_slot, out_slot));
            prev = (node, out_slot);
        }
        self.link(prev, (high.0, high.1));
        path.push((high.0, high.1, 0));
        self.chords.push(ChordPath { triangle: t as u32, family, nodes: path });
    }

    /// Joins consecutive boundary crossings along every boundary loop (the interior on the
    /// left of the forward arms).
    fn boundary_chains(&mut self, mesh: &TriMesh) {
        let conn = mesh.connectivity();
        let mut out_of = vec![NONE; mesh.vertex_count()];
        for (h, &g) in conn.twin.iter().enumerate() {
            if g == NONE {
                out_of[mesh.tail(h as u32) as usize] = h as u32;
            }
        }
        let mut seen = vec![false; conn.twin.len()];
        for start in 0..conn.twin.len() {
            if conn.twin[start] != NONE || seen[start] {
                continue;
            }
            let mut loop_nodes = Vec::new();
            let mut h = start as u32;
            while !seen[h as usize] {
                seen[h as usize] = true;
                if let Some(nodes) = self.boundary.get(&h) {
                    loop_nodes.extend_from_slice(nodes);
                }
                h = out_of[mesh.head(h) as usize];
            }
            if loop_nodes.len() >= 2 {
                for i in 0..loop_nodes.len() {
                    let (p, q) = (loop_nodes[i], loop_nodes[(i + 1) % loop_nodes.len()]);
                    self.link((p, 0), (q, 2));
                    self.arms[q as usize][2].outside = true;
                }
            }
        }
    }
}

/// The chord ends `(chord, end)` on triangle edge `edge`.
fn edge_crossings(chords: &[Chord], edge: u8) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for (ci, c) in chords.iter().enumerate() {
        for (ei, e) in c.ends.iter().enumerate() {
            if e.edge == edge {
                out.push((ci, ei));
            }
        }
    }
    out
}

/// Whether the transitions of eq. 16 across the edge of half-edges `h` (in T1) and `g` (in T2)
/// agree at both endpoints (the edge is not singular, §3.2).
fn edge_is_regular(param: &CornerParameterization, h: usize, g: usize) -> bool {
    let (t1, k1, t2, k2) = (h / 3, h % 3, g / 3, g % 3);
    transition(param, (t1, k1), (t2, (k2 + 1) % 3)) == transition(param, (t1, (k1 + 1) % 3), (t2, k2))
}

/// Position along a triangle's boundary: edges in order, `rank` along the edge; corner c sits
/// at `c << 40`, before the crossings of edge c.
fn boundary_position(edge: usize, rank: u64) -> u64 {
    ((edge as u64) << 40) + rank + 1
}

/// Whether boundary position `x` lies strictly between the two ends of a chord.
fn between(ends: [ResolvedEnd; 2], x: u64) -> bool {
    let (lo, hi) = (ends[0].2.min(ends[1].2), ends[0].2.max(ends[1].2));
    lo < x && x < hi
}

/// Whether the end `end` of a chord lies above the line of `other` (a crossing chord of the
/// other family): on the side of `other`'s lone corner exactly when that corner is above.
fn end_above(end: ResolvedEnd, other: &Chord, other_ends: [ResolvedEnd; 2]) -> bool {
    let corner = (other.lone as u64) << 40;
    let same_side = between(other_ends, end.2) == between(other_ends, corner);
    same_side == other.lone_above
}

/// Whether two chords' ends alternate along the triangle boundary.
fn interleave(a: [ResolvedEnd; 2], b: [ResolvedEnd; 2]) -> bool {
    between(a, b[0].2) != between(a, b[1].2)
}

/// Barycentric coordinates of the point where θ = `u` and φ = `w` in a triangle with corner
/// values `g`, clamped into the triangle.
fn grid_point(g: &[[f64; 3]; 2], u: f64, w: f64) -> [f64; 3] {
    // λ1 (g1 − g0) + λ2 (g2 − g0) = target − g0 for both families.
    let (a11, a12) = (g[0][1] - g[0][0], g[0][2] - g[0][0]);
    let (a21, a22) = (g[1][1] - g[1][0], g[1][2] - g[1][0]);
    let (r1, r2) = (u - g[0][0], w - g[1][0]);
    let det = a11 * a22 - a12 * a21;
    let (l1, l2) =
        if det != 0.0 { ((r1 * a22 - a12 * r2) / det, (a11 * r2 - a21 * r1) / det) } else { (1.0 / 3.0, 1.0 / 3.0) };
    let mut l = [1.0 - l1 - l2, l1, l2].map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 });
    let sum: f64 = l.iter().sum();
    if sum > 0.0 {
        l.iter_mut().for_each(|x| *x /= sum);
    } else {
        l = [1.0 / 3.0; 3];
    }
    l
}

fn lerp(a: [f64; 3], b: [f64; 3], s: f64) -> [f64; 3] {
    std::array::from_fn(|k| a[k] + s * (b[k] - a[k]))
}

impl IsoGraph {
    /// Number of arms still present at node `v`.
    pub fn valence(&self, v: usize) -> usize {
        self.arms[v].iter().filter(|a| a.to != NONE).count()
    }

    /// The present arm of `v` other than `slot` (the way on through a node of valence two).
    pub fn other_arm(&self, v: usize, slot: usize) -> Option<usize> {
        (0..self.arms[v].len()).find(|&k| k != slot && self.arms[v][k].to != NONE)
    }

    /// Removes dangling segments: nodes of valence 1, repeatedly (Algorithm 2, last step).
    fn nibble(&mut self) {
        let mut stack: Vec<u32> = (0..self.arms.len() as u32).filter(|&v| self.valence(v as usize) == 1).collect();
        while let Some(v) = stack.pop() {
            let v = v as usize;
            if self.valence(v) != 1 {
                continue;
            }
            let slot = self.arms[v].iter().position(|a| a.to != NONE).expect("valence 1");
            let arm = self.arms[v][slot];
            self.arms[v][slot] = NO_ARM;
            self.arms[arm.to as usize][arm.back as usize] = NO_ARM;
            if self.valence(arm.to as usize) == 1 {
                stack.push(arm.to);
            }
        }
    }

    /// Keeps, on every connected part of the surface, only the largest connected part of the
    /// graph: smaller parts are islands of lines inside a face of the largest (within a
    /// singular region where the lines were removed), and that face would overlap them.
    fn keep_largest_components(&mut self, mesh: &TriMesh) {
        let (label, sizes) = self.connected_parts();
        let surface = mesh.triangle_components();
        let mut best: std::collections::HashMap<u32, u32> = std::collections::HashMap::new();
        for v in 0..label.len() {
            if label[v] == NONE {
                continue;
            }
            let part = surface[self.triangle[v] as usize];
            let entry = best.entry(part).or_insert(label[v]);
            if sizes[label[v] as usize] > sizes[*entry as usize] {
                *entry = label[v];
            }
        }
        for v in 0..label.len() {
            if label[v] != NONE && best[&surface[self.triangle[v] as usize]] != label[v] {
                self.arms[v].iter_mut().for_each(|a| *a = NO_ARM);
            }
        }
    }

    /// Connected part of every node with arms (NONE for isolated nodes) and the part sizes.
    fn connected_parts(&self) -> (Vec<u32>, Vec<u32>) {
        let mut label = vec![NONE; self.arms.len()];
        let mut sizes = Vec::new();
        for start in 0..self.arms.len() {
            if label[start] != NONE || self.valence(start) == 0 {
                continue;
            }
            let id = sizes.len() as u32;
            let mut count = 0;
            let mut stack = vec![start as u32];
            label[start] = id;
            while let Some(v) = stack.pop() {
                count += 1;
                for a in &self.arms[v as usize] {
                    if a.to != NONE && label[a.to as usize] == NONE {
                        label[a.to as usize] = id;
                        stack.push(a.to);
                    }
                }
            }
            sizes.push(count);
        }
        (label, sizes)
    }

    /// The arm of `v` before `slot` in counter-clockwise order (the next arm of the face on the
    /// left of an arm arriving at `v` through `slot`).
    fn previous_arm(&self, v: usize, slot: usize) -> usize {
        let n = self.arms[v].len();
        (1..=n).map(|i| (slot + n - i) % n).find(|&s| self.arms[v][s].to != NONE).unwrap_or(slot)
    }

    /// The faces of the graph on the surface, as cycles of `(node, outgoing arm)`, without the
    /// faces outside the mesh boundary.
    pub fn faces(&self) -> Vec<Vec<(u32, u8)>> {
        let mut visited: Vec<Vec<bool>> = self.arms.iter().map(|a| vec![false; a.len()]).collect();
        let mut faces = Vec::new();
        for v in 0..self.arms.len() {
            for s in 0..self.arms[v].len() {
                if self.arms[v][s].to == NONE || visited[v][s] {
                    continue;
                }
                let (cycle, outside) = self.trace(v, s, &mut visited);
                if !outside {
                    faces.push(cycle);
                }
            }
        }
        faces
    }

    fn trace(&self, v0: usize, s0: usize, visited: &mut [Vec<bool>]) -> (Vec<(u32, u8)>, bool) {
        let (mut v, mut s) = (v0, s0);
        let mut cycle = Vec::new();
        let mut outside = false;
        while !visited[v][s] {
            visited[v][s] = true;
            cycle.push((v as u32, s as u8));
            let arm = self.arms[v][s];
            outside |= arm.outside;
            v = arm.to as usize;
            s = self.previous_arm(v, arm.back as usize);
        }
        (cycle, outside)
    }
}
