//! QuadCover, step 2: the covering cut open — every vertex of the cut mesh written as an affine
//! function of a few unknowns, so that the parameterization is the same on the two sides of the
//! cut up to a grid automorphism (Kälberer, Nieser & Polthier 2007; course notes §8.2.1,
//! eq. 8.2: f_j ∘ f_i⁻¹(z) = J^r z + t, and §8.3.1: the gap is constant along a cutting path).
//!
//! The cut graph (through every cone, see [`crate::mesh::cut::cut_to_disk_through`]) splits
//! into *chains*: maximal paths whose inner vertices are regular, interior and of degree 2 in
//! the graph. Across a chain the combed frames differ by one rotation J^r (J(u, v) = (v, −u),
//! [`crate::fields::frames::rotate_coords`]) and the parameterization by one translation
//! t (the paper's gap d_i): `x_B = J^r x_A + t` for the copies A (left of the chain's
//! direction) and B (right) of each of its vertices.
//!
//! Around each input vertex these links join its copies. A breadth-first walk over them
//! writes every copy as `J^k x_rep + Σ M_j z_j` (x_rep the first copy's position, z_j the
//! 2-vector unknowns: chain translations, and cone positions, M_j integer 2 × 2 matrices).
//! A link whose ends are both known closes a loop around the vertex and gives a linear
//! constraint on the z_j; where the rotations around the vertex do not cancel (a cone, layer
//! shift ≠ 0), the constraint involves x_rep, which then becomes a z unknown itself, so that
//! its position can be required to be an integer point.
//!
//! The constraints are eliminated by sparse Gaussian elimination over the scalar components,
//! pivoting on translations with coefficient ±1 where possible (then cone coordinates with
//! ±1, then the largest coefficient): the remaining (free) components are cone coordinates and
//! independent gaps, and every pivot is an integer combination of them whenever only ±1 pivots
//! were needed — rounding the free ones to integers then makes every transition a grid
//! automorphism (§8.3.1 "the grid lines are globally continuous iff all d_i ∈ Z").

use crate::error::{Error, Result};
use crate::mesh::cut::Cut;
use crate::mesh::NONE;
use crate::TriMesh;
use std::collections::{BTreeMap, HashMap};

/// A 2 × 2 integer matrix.
type M2 = [[i64; 2]; 2];

const IDENTITY: M2 = [[1, 0], [0, 1]];

/// J^r with J(u, v) = (v, −u).
fn j_power(r: u8) -> M2 {
    match r % 4 {
        0 => IDENTITY,
        1 => [[0, 1], [-1, 0]],
        2 => [[-1, 0], [0, -1]],
        _ => [[0, -1], [1, 0]],
    }
}

fn mul(a: M2, b: M2) -> M2 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j]))
}

fn sub_m(a: M2, b: M2) -> M2 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][j] - b[i][j]))
}

fn is_zero(a: M2) -> bool {
    a.iter().flatten().all(|&x| x == 0)
}

/// `J^rot x_rep + Σ M_j z_j` (module comment).
#[derive(Clone, Debug, Default)]
struct Affine {
    rot: u8,
    terms: BTreeMap<u32, M2>,
}

impl Affine {
    /// `J^r self + sign · z`.
    fn rotated_plus(&self, r: u8, z: u32, sign: i64) -> Affine {
        let q = j_power(r);
        let mut terms: BTreeMap<u32, M2> = self.terms.iter().map(|(&k, &m)| (k, mul(q, m))).collect();
        let entry = terms.entry(z).or_insert([[0; 2]; 2]);
        for (i, row) in entry.iter_mut().enumerate() {
            row[i] += sign;
        }
        terms.retain(|_, m| !is_zero(*m));
        Affine { rot: (self.rot + r) % 4, terms }
    }
}

/// One chain of the cut graph: its half-edges in order (the triangle of each is side A) and
/// the rotation from side A to side B.
#[derive(Clone, Debug)]
pub struct Chain {
    pub halfedges: Vec<u32>,
    pub rotation: u8,
}

/// A link between two copies of an input vertex: `x_b = J^r x_a + t_chain`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct Link {
    a: u32,
    b: u32,
    chain: u32,
}

/// The cut mesh's vertices as affine functions of the unknowns (module comment).
#[derive(Clone, Debug)]
pub struct Covering {
    /// Real unknowns: 2 per regular input vertex (minus the 2 fixed by the gauge), numbered
    /// first; the lattice scalars follow (2 per chain, then 2 per cone).
    pub vertex_unknowns: usize,
    /// For every cut-mesh vertex, its u and v as sparse rows over the real unknowns and the
    /// lattice scalars.
    pub rows: Vec<[Vec<(u32, f64)>; 2]>,
    /// Every lattice scalar as a row over the free lattice scalars (the integer unknowns).
    pub lattice: Vec<Vec<(u32, f64)>>,
    /// Number of free lattice scalars.
    pub free_lattice: usize,
    /// Which lattice scalars must be integers (gaps always; cone coordinates when on the grid).
    pub integer: Vec<bool>,
    /// Which free lattice scalars are rounded.
    pub free_integer: Vec<bool>,
    /// The cones: the field's singular vertices, plus any vertex whose rotations around do not
    /// cancel.
    pub cones: Vec<u32>,
    /// Number of chains (cutting paths).
    pub chain_count: usize,
    /// Pivots that were not ±1 (their translations are rational, not integer, combinations).
    pub fractional_pivots: usize,
    /// For every cut-mesh vertex, the quarter turns r of `J^r x_rep` in its expression: its
    /// rotation relative to the first copy of its input vertex.
    pub copy_rotation: Vec<u8>,
}

impl Covering {
    /// Number of lattice scalars.
    pub fn lattice_len(&self) -> usize {
        self.lattice.len()
    }
}

/// Builds the covering (module comment) from the cut and the combed matchings.
pub fn build_covering(
    mesh: &TriMesh,
    cut: &Cut,
    combed: &[u8],
    cones: &[u32],
    cones_on_grid: bool,
) -> Result<Covering> {
    let chains = cut_chains(mesh, cut, combed, cones)?;
    let links = chain_links(mesh, cut, &chains);
    let (exprs, cone_of, constraints) = walk_copies(mesh, cut, &chains, &links, cones)?;
    let zcount = 2 * (chains.len() + cone_of.iter().filter(|c| c.is_some()).count());
    let chain_scalars = 2 * chains.len();
    let (pivots, free, fractional_pivots) = eliminate(&constraints, zcount, chain_scalars, cones_on_grid);
    let mut covering = assemble(mesh, cut, &chains, exprs, &cone_of, pivots, free, fractional_pivots)?;
    // Integer lattice scalars: the gaps, and the cone coordinates when they sit on the grid.
    covering.integer = (0..zcount).map(|k| k < chain_scalars || cones_on_grid).collect();
    let mut free_integer = vec![false; covering.free_lattice];
    for (k, row) in covering.lattice.iter().enumerate() {
        if let [(j, x)] = row[..] {
            if x == 1.0 && covering.integer[k] {
                free_integer[j as usize] = true;
            }
        }
    }
    covering.free_integer = free_integer;
    Ok(covering)
}

/// Splits the cut graph into chains (module comment), oriented, with their rotation.
fn cut_chains(mesh: &TriMesh, cut: &Cut, combed: &[u8], cones: &[u32]) -> Result<Vec<Chain>> {
    let n = mesh.vertex_count();
    let mut adjacent: Vec<Vec<(u32, u32)>> = vec![Vec::new(); n];
    for (e, &[a, b]) in cut.edges.iter().enumerate() {
        adjacent[a as usize].push((b, e as u32));
        adjacent[b as usize].push((a, e as u32));
    }
    let mut is_cone = vec![false; n];
    for &c in cones {
        is_cone[c as usize] = true;
    }
    let is_node = |v: u32| adjacent[v as usize].len() != 2 || is_cone[v as usize] || mesh.is_boundary_vertex(v);
    let mut used = vec![false; cut.edges.len()];
    let mut chains = Vec::new();
    let starts: Vec<u32> = (0..n as u32).filter(|&v| !adjacent[v as usize].is_empty() && is_node(v)).collect();
    // Chains from every node, then loops without a node (any vertex starts them).
    for start in starts.iter().copied().chain(cut.edges.iter().map(|e| e[0])) {
        for k in 0..adjacent[start as usize].len() {
            let (mut w, e0) = adjacent[start as usize][k];
            if used[e0 as usize] {
                continue;
            }
            used[e0 as usize] = true;
            let mut path = vec![start, w];
            while !is_node(w) && w != start {
                let Some(&(x, e)) = adjacent[w as usize].iter().find(|&&(_, e)| !used[e as usize]) else { break };
                used[e as usize] = true;
                path.push(x);
                w = x;
            }
            chains.push(oriented_chain(mesh, &path, combed)?);
        }
    }
    Ok(chains)
}

/// The chain along the vertex path `path`: its half-edges (tail p_i, head p_i+1) and their
/// common rotation.
fn oriented_chain(mesh: &TriMesh, path: &[u32], combed: &[u8]) -> Result<Chain> {
    let mut halfedges = Vec::with_capacity(path.len() - 1);
    for w in path.windows(2) {
        let h = mesh
            .outgoing_halfedges(w[0])
            .find(|&h| mesh.head(h) == w[1])
            .ok_or_else(|| Error::Internal(format!("cut edge {}–{} has no half-edge", w[0], w[1])))?;
        halfedges.push(h);
    }
    let rotation = combed[halfedges[0] as usize];
    if let Some(&h) = halfedges.iter().find(|&&h| combed[h as usize] != rotation) {
        return Err(Error::Internal(format!(
            "QuadCover: the rotation changes along a cut path at edge {}–{}",
            mesh.tail(h),
            mesh.head(h)
        )));
    }
    Ok(Chain { halfedges, rotation })
}

/// The links of every input vertex between its copies (duplicates removed).
fn chain_links(mesh: &TriMesh, cut: &Cut, chains: &[Chain]) -> Vec<Vec<Link>> {
    let twin = &mesh.connectivity().twin;
    let copy = |h: u32| cut.triangles[(h / 3) as usize][(h % 3) as usize];
    let mut links: Vec<Vec<Link>> = vec![Vec::new(); mesh.vertex_count()];
    for (c, chain) in chains.iter().enumerate() {
        for &h in &chain.halfedges {
            let g = twin[h as usize];
            let (hn, gn) = (crate::mesh::next(h), crate::mesh::next(g));
            // tail(h) = tail(next(g)), head(h) = tail(next(h)) = tail(g).
            for (v, a, b) in [(mesh.tail(h), copy(h), copy(gn)), (mesh.head(h), copy(hn), copy(g))] {
                let link = Link { a, b, chain: c as u32 };
                if !links[v as usize].contains(&link) {
                    links[v as usize].push(link);
                }
            }
        }
    }
    links
}

/// A linear constraint `Σ M_j z_j = 0` on the 2-vector unknowns.
type Constraint = BTreeMap<u32, M2>;

/// What [`walk_copies`] finds: the copies' expressions, the cones' z indices, the constraints.
type Walk = (Vec<Affine>, Vec<Option<u32>>, Vec<Constraint>);

/// Expressions of the copies of every vertex (module comment), the z index of each cone's
/// position, and the loop-closing constraints. z indices: chain c → c, cones after the chains.
fn walk_copies(mesh: &TriMesh, cut: &Cut, chains: &[Chain], links: &[Vec<Link>], cones: &[u32]) -> Result<Walk> {
    let mut exprs: Vec<Option<Affine>> = vec![None; cut.original.len()];
    let mut cone_of: Vec<Option<u32>> = vec![None; mesh.vertex_count()];
    let mut next_z = chains.len() as u32;
    // Every singular vertex of the field is a cone (also those of integer index, around which
    // the rotations cancel): its position is an integer unknown.
    for &v in cones {
        cone_of[v as usize] = Some(next_z);
        next_z += 1;
    }
    let mut constraints = Vec::new();
    let mut copies: Vec<Vec<u32>> = vec![Vec::new(); mesh.vertex_count()];
    for (c, &v) in cut.original.iter().enumerate() {
        copies[v as usize].push(c as u32);
    }
    for v in 0..mesh.vertex_count() {
        let Some(&rep) = copies[v].first() else { continue };
        exprs[rep as usize] = Some(Affine::default());
        let mut done = vec![false; links[v].len()];
        // Relax the links until none adds a copy; the rest close loops.
        let mut progress = true;
        while progress {
            progress = false;
            for (k, l) in links[v].iter().enumerate() {
                if done[k] {
                    continue;
                }
                let r = chains[l.chain as usize].rotation;
                match (exprs[l.a as usize].clone(), exprs[l.b as usize].is_some()) {
                    (Some(a), false) => exprs[l.b as usize] = Some(a.rotated_plus(r, l.chain, 1)),
                    (None, true) => {
                        // x_a = J^{-r} (x_b − t).
                        let b = exprs[l.b as usize].clone().unwrap_or_default();
                        let minus_t = b.rotated_plus(0, l.chain, -1);
                        exprs[l.a as usize] = Some(minus_t.rotated_plus((4 - r) % 4, l.chain, 0));
                    }
                    (Some(a), true) => {
                        let b = exprs[l.b as usize].clone().unwrap_or_default();
                        let lhs = a.rotated_plus(r, l.chain, 1);
                        if let Some(c) = closing(&lhs, &b, v as u32, &mut cone_of, &mut next_z) {
                            constraints.push(c);
                        }
                    }
                    (None, false) => continue,
                }
                done[k] = true;
                progress = true;
            }
        }
    }
    if let Some(c) = exprs.iter().position(Option::is_none) {
        return Err(Error::Internal(format!(
            "QuadCover: copy {c} of vertex {} is not linked to the others across the cut",
            cut.original[c]
        )));
    }
    Ok((exprs.into_iter().map(Option::unwrap_or_default).collect(), cone_of, constraints))
}

/// `lhs − rhs = 0` as a constraint; a rotation left over makes the vertex a cone (its position
/// a z unknown). `None` when the constraint is void.
fn closing(lhs: &Affine, rhs: &Affine, v: u32, cone_of: &mut [Option<u32>], next_z: &mut u32) -> Option<Constraint> {
    let mut c: Constraint = lhs.terms.clone();
    for (&k, &m) in &rhs.terms {
        let e = c.entry(k).or_insert([[0; 2]; 2]);
        *e = sub_m(*e, m);
    }
    let rotation = sub_m(j_power(lhs.rot), j_power(rhs.rot));
    if !is_zero(rotation) {
        let z = *cone_of[v as usize].get_or_insert_with(|| {
            *next_z += 1;
            *next_z - 1
        });
        c.insert(z, rotation);
    }
    c.retain(|_, m| !is_zero(*m));
    (!c.is_empty()).then_some(c)
}

/// A sparse scalar row.
type Row = Vec<(u32, f64)>;

/// Adds `factor · row` into `acc`.
fn axpy(acc: &mut BTreeMap<u32, f64>, factor: f64, row: &Row) {
    for &(k, x) in row {
        *acc.entry(k).or_insert(0.0) += factor * x;
    }
}

/// Gaussian elimination of the scalar constraints (module comment): the expression of every
/// pivot over free scalars, the free scalars, and the number of pivots that were not ±1. The
/// pivots' expressions are kept over free scalars only; `users[k]` lists the pivots whose
/// expression holds the free scalar k, so a new pivot is substituted where it occurs only.
fn eliminate(
    constraints: &[Constraint],
    zcount: usize,
    chain_scalars: usize,
    cones_on_grid: bool,
) -> (HashMap<u32, Row>, Vec<u32>, usize) {
    let mut pivots: HashMap<u32, Row> = HashMap::new();
    let mut users: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut fractional = 0;
    for c in constraints {
        for i in 0..2 {
            let mut reduced: BTreeMap<u32, f64> = BTreeMap::new();
            for (&z, m) in c {
                for (j, &x) in m[i].iter().enumerate() {
                    if x == 0 {
                        continue;
                    }
                    let k = 2 * z + j as u32;
                    match pivots.get(&k) {
                        Some(expr) => axpy(&mut reduced, x as f64, expr),
                        None => *reduced.entry(k).or_insert(0.0) += x as f64,
                    }
                }
            }
            reduced.retain(|_, x| x.abs() > 1e-9);
            let Some(p) = choose_pivot(&reduced, chain_scalars, cones_on_grid) else { continue };
            let a = reduced[&p];
            if (a.abs() - 1.0).abs() > 1e-9 && ((p as usize) < chain_scalars || cones_on_grid) {
                fractional += 1;
            }
            let expr: Row = reduced.iter().filter(|&(&k, _)| k != p).map(|(&k, &x)| (k, -x / a)).collect();
            for q in users.remove(&p).unwrap_or_default() {
                let Some(e) = pivots.get_mut(&q) else { continue };
                let Some(pos) = e.iter().position(|&(k, _)| k == p) else { continue };
                let (_, x) = e.remove(pos);
                let mut acc: BTreeMap<u32, f64> = e.iter().copied().collect();
                axpy(&mut acc, x, &expr);
                acc.retain(|_, x| x.abs() > 1e-9);
                *e = acc.into_iter().collect();
                for &(k, _) in &expr {
                    users.entry(k).or_default().push(q);
                }
            }
            for &(k, _) in &expr {
                users.entry(k).or_default().push(p);
            }
            pivots.insert(p, expr);
        }
    }
    let free = (0..zcount as u32).filter(|k| !pivots.contains_key(k)).collect();
    (pivots, free, fractional)
}

/// Pivot of a reduced row: a translation with coefficient ±1, else a cone coordinate with ±1,
/// else the largest coefficient.
/// With `cones_on_grid` false, a cone coordinate (largest coefficient) comes first: the cones
/// are then functions of the gaps and only the gaps need be integers.
fn choose_pivot(row: &BTreeMap<u32, f64>, chain_scalars: usize, cones_on_grid: bool) -> Option<u32> {
    let unit = |&(&k, &x): &(&u32, &f64)| (x.abs() - 1.0).abs() < 1e-9 && (k as usize) < chain_scalars;
    let unit_cone = |&(_, &x): &(&u32, &f64)| (x.abs() - 1.0).abs() < 1e-9;
    let largest = |a: &(&u32, &f64), b: &(&u32, &f64)| a.1.abs().total_cmp(&b.1.abs());
    let cone =
        if cones_on_grid { None } else { row.iter().filter(|&(&k, _)| k as usize >= chain_scalars).max_by(largest) };
    cone.or_else(|| row.iter().find(unit))
        .or_else(|| row.iter().find(unit_cone))
        .or_else(|| row.iter().max_by(largest))
        .map(|(&k, _)| k)
}

/// Numbers the unknowns — 2 per regular vertex (gauge removed), then every lattice scalar
/// (gap and cone coordinates) — writes every copy as short rows over them, and every lattice
/// scalar as a row over the free ones (the elimination's D).
#[allow(clippy::too_many_arguments)]
fn assemble(
    mesh: &TriMesh,
    cut: &Cut,
    chains: &[Chain],
    exprs: Vec<Affine>,
    cone_of: &[Option<u32>],
    pivots: HashMap<u32, Row>,
    free: Vec<u32>,
    fractional_pivots: usize,
) -> Result<Covering> {
    let zscalars = 2 * (chains.len() + cone_of.iter().filter(|c| c.is_some()).count());
    // Gauge: a cone whose two coordinates are free, else the first regular vertex.
    let gauge_cone = cone_of
        .iter()
        .flatten()
        .find(|&&z| !pivots.contains_key(&(2 * z)) && !pivots.contains_key(&(2 * z + 1)))
        .copied();
    let gauge_vertex = match gauge_cone {
        Some(_) => None,
        None => cut.original.iter().map(|&v| v as usize).find(|&v| cone_of[v].is_none()),
    };
    // Regular vertices other than the gauge vertex (fixed at the origin): 2 unknowns each.
    let mut vertex_id = vec![NONE; mesh.vertex_count()];
    let mut nv = 0u32;
    for &v in &cut.original {
        let v = v as usize;
        if cone_of[v].is_some() || vertex_id[v] != NONE || Some(v) == gauge_vertex {
            continue;
        }
        vertex_id[v] = nv;
        nv += 2;
    }
    let z_id = |k: u32| nv + k;
    let mut rows = Vec::with_capacity(exprs.len());
    for (c, e) in exprs.iter().enumerate() {
        let v = cut.original[c] as usize;
        let rep: [Row; 2] = match cone_of[v] {
            Some(z) => [vec![(z_id(2 * z), 1.0)], vec![(z_id(2 * z + 1), 1.0)]],
            None if Some(v) == gauge_vertex => [Vec::new(), Vec::new()],
            None => [vec![(vertex_id[v], 1.0)], vec![(vertex_id[v] + 1, 1.0)]],
        };
        let q = j_power(e.rot);
        let mut out: [BTreeMap<u32, f64>; 2] = Default::default();
        for i in 0..2 {
            for j in 0..2 {
                if q[i][j] != 0 {
                    axpy(&mut out[i], q[i][j] as f64, &rep[j]);
                }
            }
            for (&z, m) in &e.terms {
                for (j, &x) in m[i].iter().enumerate() {
                    if x != 0 {
                        *out[i].entry(z_id(2 * z + j as u32)).or_insert(0.0) += x as f64;
                    }
                }
            }
            out[i].retain(|_, x| *x != 0.0);
        }
        rows.push(out.map(|m| m.into_iter().collect()));
    }
    // Free lattice scalars (the gauge cone's excluded: 0) numbered in order.
    let mut free_id = vec![NONE; zscalars];
    let mut nw = 0u32;
    for &k in &free {
        if gauge_cone.is_some_and(|z| k / 2 == z) {
            continue;
        }
        free_id[k as usize] = nw;
        nw += 1;
    }
    let to_free = |r: &Row| -> Row {
        r.iter().filter(|&&(k, _)| free_id[k as usize] != NONE).map(|&(k, x)| (free_id[k as usize], x)).collect()
    };
    let lattice = (0..zscalars as u32)
        .map(|k| match pivots.get(&k) {
            Some(expr) => to_free(expr),
            None if free_id[k as usize] != NONE => vec![(free_id[k as usize], 1.0)],
            None => Vec::new(),
        })
        .collect();
    let mut cones: Vec<u32> = (0..mesh.vertex_count() as u32).filter(|&v| cone_of[v as usize].is_some()).collect();
    cones.sort_unstable();
    Ok(Covering {
        vertex_unknowns: nv as usize,
        rows,
        lattice,
        free_lattice: nw as usize,
        integer: Vec::new(),
        free_integer: Vec::new(),
        cones,
        chain_count: chains.len(),
        fractional_pivots,
        copy_rotation: exprs.iter().map(|e| e.rot).collect(),
    })
}
