//! Distortion of a piecewise-linear parameterization.
//!
//! On each triangle the parameterization is a linear map f|t from the uv triangle t to the
//! surface triangle T. Its Jacobian J (3×2) has singular values σ1 ≥ σ2 ≥ 0, which hold all of
//! the local metric distortion: isometric ⇔ σ1 = σ2 = 1, conformal ⇔ σ1 = σ2, equiareal ⇔
//! σ1·σ2 = 1 (Hormann, Lévy, Sheffer, "Mesh Parameterization: Theory and Practice", SIGGRAPH
//! Asia 2008 course notes, §3.3 "Metric Distortion"; per-triangle aggregation as in ch. 4 §4.1,
//! eqs. 4.2–4.4, where σ1t·σ2t = A(T)/A(t)). From them this file computes:
//!
//! - stretch (Sander, Snyder, Gortler, Hoppe, "Texture Mapping Progressive Meshes", SIGGRAPH
//!   2001): L2 = sqrt(Σ A_3d·(σ1²+σ2²)/2 / Σ A_3d) and L∞ = max σ1, after scaling the uv layout
//!   so that its total area equals the total surface area. Both are ≥ 1 and equal 1 exactly for
//!   an isometry up to one global scale;
//! - conformal distortion σ1/σ2 (1 = angle-preserving): surface-area-weighted mean and max;
//! - angle distortion |uv corner angle − surface corner angle| in radians: mean over corners, max;
//! - area distortion |ln(s·A_uv / A_3d)| with s = Σ A_3d / Σ |A_uv| (one global scale):
//!   surface-area-weighted mean and max;
//! - flipped and degenerate uv triangles, and proper crossings of uv boundary edges.
//!
//! Conventions: uv coordinates are 2D, a uv triangle is counter-clockwise when its signed area is
//! positive, angles are in radians. Orientation is judged against the majority: a map whose
//! triangles are mostly clockwise (by total signed area) is a mirror image, not a map of flips, so
//! a triangle is flipped when its signed uv area has the sign opposite to Σ signed uv area. A
//! triangle is degenerate when twice its area is at most `DEGENERACY_TOLERANCE` times its longest
//! edge squared; degenerate uv triangles are counted in `degenerate_uv` (never as flips) and, like
//! triangles degenerate in 3D (which have no Jacobian, and zero weight), are left out of every
//! distortion average and maximum. Flipped triangles are measured with |A_uv|.
//!
//! Uv corner angles are unsigned (a mirrored triangle keeps its angles; its flip is counted
//! instead). The orientation majority is global, over all charts of a per-corner layout.
//!
//! Cost: O(m log m) for m triangles and O(m) extra memory: a few passes over the triangles, one
//! sort of the 3m uv edges, and a multi-level grid over the boundary edges for the crossing count
//! (see `count_boundary_crossings`). About 1 s for 1.4 M triangles on one core.

use crate::error::Error;
use crate::geometry::cross2;

/// A triangle is degenerate when 2·area ≤ `DEGENERACY_TOLERANCE` · (longest edge)², i.e. its
/// height is below 1e-12 of its longest edge (scale-invariant).
pub const DEGENERACY_TOLERANCE: f64 = 1e-12;

/// Distortion summary of a parameterization; see the module comment for each definition.
/// Distortion fields are NaN when no triangle is measurable (all uv or 3D triangles degenerate).
#[derive(Debug, Clone, PartialEq)]
pub struct Metrics {
    pub triangles: usize,
    pub flipped: usize,
    pub degenerate_uv: usize,
    pub stretch_l2: f64,
    pub stretch_linf: f64,
    pub conformal_mean: f64,
    pub conformal_max: f64,
    pub angle_mean: f64,
    pub angle_max: f64,
    pub area_mean: f64,
    pub area_max: f64,
    pub boundary_intersections: usize,
}

/// How a uv triangle sits relative to the layout's majority orientation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UvOrientation {
    /// Same orientation as the majority (by area).
    Agrees,
    /// Opposite orientation to the majority.
    Flipped,
    /// Zero area up to `DEGENERACY_TOLERANCE`.
    Degenerate,
    /// An index is out of range or a coordinate is not finite.
    Invalid,
}

/// The edges of a uv layout, each once as `[smaller index, larger index]`: `boundary` edges are
/// used by exactly one triangle, `interior` ones by two or more.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct UvEdges {
    pub boundary: Vec<[u32; 2]>,
    pub interior: Vec<[u32; 2]>,
}

/// Singular values (σ1, σ2), σ1 ≥ σ2 > 0, of the Jacobian of the linear map from the uv triangle
/// `q` to the surface triangle `p` (corner i of `q` maps to corner i of `p`). `None` when either
/// triangle is degenerate or a coordinate is not finite.
pub fn per_triangle_singular_values(p: [[f64; 3]; 3], q: [[f64; 2]; 3]) -> Option<(f64, f64)> {
    if !points_are_finite_3d(&p) || !points_are_finite_2d(&q) {
        return None;
    }
    if triangle_is_degenerate_3d(p) || triangle_is_degenerate_2d(q) {
        return None;
    }
    let (ju, jv) = jacobian_columns(p, q);
    let e = dot3(ju, ju);
    let f = dot3(ju, jv);
    let g = dot3(jv, jv);
    // Eigenvalues of the first fundamental form [[E, F], [F, G]] = JᵀJ (course notes §3.3);
    // σ2 from σ1·σ2 = |J_u × J_v| avoids cancellation in the smaller eigenvalue.
    let lambda1 = 0.5 * (e + g + (e - g).hypot(2.0 * f));
    let sigma1 = lambda1.sqrt();
    let sigma2 = norm3(cross3(ju, jv)) / sigma1;
    if !(sigma1.is_finite() && sigma2.is_finite() && sigma2 > 0.0) {
        return None;
    }
    Some((sigma1, sigma2.min(sigma1)))
}

/// σ1² + σ2² of the map from the uv triangle `q` to the surface triangle `p`: the squared
/// Frobenius norm |J_u|² + |J_v|² of its Jacobian (the trace of the first fundamental form), the
/// L2 stretch's integrand without the eigen-decomposition of [`per_triangle_singular_values`]
/// and without its degeneracy tests: for a `q` known to be proper (positive, not degenerate).
pub(crate) fn squared_singular_value_sum(p: [[f64; 3]; 3], q: [[f64; 2]; 3]) -> f64 {
    let (ju, jv) = jacobian_columns(p, q);
    dot3(ju, ju) + dot3(jv, jv)
}

/// Distortion of the map sending uv triangle `uv_triangles[t]` (indices into `uv`) onto surface
/// triangle `triangles[t]` (indices into `positions`). Per-vertex uv: pass the same triangles
/// twice. Errors name the offending triangle: length mismatch, no triangles, an index out of
/// range, a non-finite coordinate.
pub fn distortion(
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
    uv: &[[f64; 2]],
    uv_triangles: &[[u32; 3]],
) -> Result<Metrics, Error> {
    validate_inputs(positions, triangles, uv, uv_triangles)?;
    let orientations = uv_orientations(uv, uv_triangles);
    let flipped = count_orientation(&orientations, UvOrientation::Flipped);
    let degenerate_uv = count_orientation(&orientations, UvOrientation::Degenerate);
    let summary = distortion_sums(positions, triangles, uv, uv_triangles, &orientations).summarize();
    Ok(Metrics {
        triangles: triangles.len(),
        flipped,
        degenerate_uv,
        stretch_l2: summary.stretch_l2,
        stretch_linf: summary.stretch_linf,
        conformal_mean: summary.conformal_mean,
        conformal_max: summary.conformal_max,
        angle_mean: summary.angle_mean,
        angle_max: summary.angle_max,
        area_mean: summary.area_mean,
        area_max: summary.area_max,
        boundary_intersections: count_boundary_crossings(uv, &uv_edges(uv_triangles).boundary),
    })
}

/// +1.0 when the layout is counter-clockwise by area (Σ signed area of the valid, non-degenerate
/// uv triangles ≥ 0), −1.0 when it is mirrored. Invalid triangles are ignored.
pub fn majority_orientation(uv: &[[f64; 2]], uv_triangles: &[[u32; 3]]) -> f64 {
    let total: f64 = uv_triangles
        .iter()
        .filter_map(|tri| uv_corners(uv, *tri))
        .filter(|q| !triangle_is_degenerate_2d(*q))
        .map(signed_uv_area)
        .sum();
    if total < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// Orientation of every uv triangle relative to `majority_orientation`. Never panics: triangles
/// with out-of-range indices or non-finite coordinates are `Invalid`.
pub fn uv_orientations(uv: &[[f64; 2]], uv_triangles: &[[u32; 3]]) -> Vec<UvOrientation> {
    let majority = majority_orientation(uv, uv_triangles);
    uv_triangles
        .iter()
        .map(|tri| match uv_corners(uv, *tri) {
            None => UvOrientation::Invalid,
            Some(q) if triangle_is_degenerate_2d(q) => UvOrientation::Degenerate,
            Some(q) if signed_uv_area(q) * majority > 0.0 => UvOrientation::Agrees,
            Some(_) => UvOrientation::Flipped,
        })
        .collect()
}

/// Signed area of a uv triangle, positive when counter-clockwise.
pub fn signed_uv_area(q: [[f64; 2]; 3]) -> f64 {
    0.5 * cross2(sub2(q[1], q[0]), sub2(q[2], q[0]))
}

/// Area of a surface triangle.
pub fn triangle_area_3d(p: [[f64; 3]; 3]) -> f64 {
    0.5 * norm3(cross3(sub3(p[1], p[0]), sub3(p[2], p[0])))
}

/// Whether a uv triangle has (numerically) zero area; true for non-finite input too.
pub fn triangle_is_degenerate_2d(q: [[f64; 2]; 3]) -> bool {
    let twice_area = (2.0 * signed_uv_area(q)).abs();
    let longest_squared =
        [sub2(q[1], q[0]), sub2(q[2], q[1]), sub2(q[0], q[2])].iter().map(|e| dot2(*e, *e)).fold(0.0, f64::max);
    area_is_negligible(twice_area, longest_squared)
}

/// Whether a surface triangle has (numerically) zero area; true for non-finite input too.
pub fn triangle_is_degenerate_3d(p: [[f64; 3]; 3]) -> bool {
    let twice_area = 2.0 * triangle_area_3d(p);
    let longest_squared =
        [sub3(p[1], p[0]), sub3(p[2], p[1]), sub3(p[0], p[2])].iter().map(|e| dot3(*e, *e)).fold(0.0, f64::max);
    area_is_negligible(twice_area, longest_squared)
}

/// True unless 2·area is strictly above the tolerance (so NaN counts as degenerate).
fn area_is_negligible(twice_area: f64, longest_squared: f64) -> bool {
    let threshold = DEGENERACY_TOLERANCE * longest_squared;
    !matches!(twice_area.partial_cmp(&threshold), Some(std::cmp::Ordering::Greater))
}

/// Edges of the uv layout, split into boundary (used once) and interior (used twice or more).
/// Edges whose two indices are equal are dropped. O(m + n) for m edges over n indices, plus
/// the sort of each index's few edges.
pub fn uv_edges(uv_triangles: &[[u32; 3]]) -> UvEdges {
    // Bucketed by the smaller index (a counting sort: linear), each bucket sorted by the larger
    // index: the order of sorting every edge key, without that O(m log m) sort (a third of the
    // layout check of a large chart was the sort).
    let n = uv_triangles.iter().flatten().max().map_or(0, |&m| m as usize + 1);
    let mut start = vec![0usize; n + 1];
    for t in uv_triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if a != b {
                start[a.min(b) as usize + 1] += 1;
            }
        }
    }
    for v in 0..n {
        start[v + 1] += start[v];
    }
    let mut larger = vec![0u32; start[n]];
    let mut fill = start.clone();
    for t in uv_triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if a != b {
                let smaller = a.min(b) as usize;
                larger[fill[smaller]] = a.max(b);
                fill[smaller] += 1;
            }
        }
    }
    let mut edges = UvEdges::default();
    for v in 0..n {
        let bucket = &mut larger[start[v]..start[v + 1]];
        bucket.sort_unstable();
        for run in bucket.chunk_by(|x, y| x == y) {
            let edge = [v as u32, run[0]];
            if run.len() == 1 {
                edges.boundary.push(edge);
            } else {
                edges.interior.push(edge);
            }
        }
    }
    edges
}

/// Number of pairs of `edges` (indices into `uv`) that share no endpoint index and cross at a
/// point interior to both (touching and collinear overlap do not count). Edges with an index out
/// of range or a non-finite coordinate are ignored.
///
/// Near-linear whatever the spread of edge lengths (a vertex flung far away included): each edge
/// goes to the level of a multi-level grid whose cells are at least as large as its bounding box
/// (cell sizes h0·2^level), listed in the ≤ 2×2 cells its box overlaps. An edge is tested against
/// the edges of its own level and of coarser ones in the cells its box overlaps there, and a pair
/// is counted only in the cell holding the lower-left corner of the intersection of the two boxes.
pub fn count_boundary_crossings(uv: &[[f64; 2]], edges: &[[u32; 2]]) -> usize {
    let segments = scaled_to_safe_range(edges.iter().filter_map(|e| segment(uv, *e)).collect());
    let Some(grid) = LevelGrid::build(&segments) else {
        return 0;
    };
    let mut crossings = 0;
    for (i, s) in segments.iter().enumerate() {
        let own_level = grid.level_of[i];
        for &level in grid.levels.iter().filter(|&&l| l >= own_level) {
            let (lo, hi) = (grid.cell_of(level, s.min), grid.cell_of(level, s.max));
            for cy in lo[1]..=hi[1] {
                for cx in lo[0]..=hi[0] {
                    let cell = (level, cx, cy);
                    for &j in grid.members(cell) {
                        let t = &segments[j as usize];
                        let once = level > own_level || j as usize > i;
                        if once && grid.pair_owner(level, s, t) == Some(cell) && segments_cross_properly(s, t) {
                            crossings += 1;
                        }
                    }
                }
            }
        }
    }
    crossings
}

// ---------------------------------------------------------------------------------------------
// Validation and per-triangle measurement

fn validate_inputs(
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
    uv: &[[f64; 2]],
    uv_triangles: &[[u32; 3]],
) -> Result<(), Error> {
    if triangles.len() != uv_triangles.len() {
        return Err(Error::InvalidArgument(format!(
            "{} triangles but {} uv triangles; there must be one uv triangle per triangle",
            triangles.len(),
            uv_triangles.len()
        )));
    }
    if triangles.is_empty() {
        return Err(Error::InvalidArgument("the mesh has no triangles".into()));
    }
    for (t, (tri, uv_tri)) in triangles.iter().zip(uv_triangles).enumerate() {
        for &v in tri {
            match positions.get(v as usize) {
                None => {
                    return Err(Error::InvalidArgument(format!(
                        "triangle {t} references vertex {v} but there are {} vertices",
                        positions.len()
                    )))
                }
                Some(p) if !p.iter().all(|x| x.is_finite()) => {
                    return Err(Error::InvalidArgument(format!(
                        "triangle {t}: position of vertex {v} is not finite ({p:?})"
                    )))
                }
                Some(_) => {}
            }
        }
        for &i in uv_tri {
            match uv.get(i as usize) {
                None => {
                    return Err(Error::InvalidArgument(format!(
                        "triangle {t} references uv {i} but there are {} uv coordinates",
                        uv.len()
                    )))
                }
                Some(q) if !q.iter().all(|x| x.is_finite()) => {
                    return Err(Error::InvalidArgument(format!("triangle {t}: uv {i} is not finite ({q:?})")))
                }
                Some(_) => {}
            }
        }
    }
    Ok(())
}

/// Sums and maxima over the measurable triangles (uv and surface triangle both non-degenerate),
/// gathered in one pass before the global uv scale is known: σ scales by 1/k, so the L2 sum and
/// σ1 max are rescaled at the end; the area measure needs k², so it keeps ln(A_uv/A_3d) per
/// triangle (16 bytes each) for a second, light pass.
#[derive(Default)]
struct DistortionSums {
    triangles: usize,
    area_3d: f64,
    area_uv: f64,
    dirichlet: f64,
    sigma1_max: f64,
    conformal: f64,
    conformal_max: f64,
    angle: f64,
    angle_max: f64,
    log_area_ratios: Vec<(f64, f64)>,
}

impl DistortionSums {
    fn add(&mut self, p: [[f64; 3]; 3], q: [[f64; 2]; 3]) {
        let Some((sigma1, sigma2)) = per_triangle_singular_values(p, q) else {
            return;
        };
        let area_3d = triangle_area_3d(p);
        let area_uv = signed_uv_area(q).abs();
        self.triangles += 1;
        self.area_3d += area_3d;
        self.area_uv += area_uv;
        self.dirichlet += area_3d * 0.5 * (sigma1 * sigma1 + sigma2 * sigma2);
        self.sigma1_max = self.sigma1_max.max(sigma1);
        let conformal = sigma1 / sigma2;
        self.conformal += area_3d * conformal;
        self.conformal_max = self.conformal_max.max(conformal);
        for (a_uv, a_3d) in corner_angles_2d(q).iter().zip(&corner_angles_3d(p)) {
            let d = (a_uv - a_3d).abs();
            self.angle += d;
            self.angle_max = self.angle_max.max(d);
        }
        self.log_area_ratios.push((area_3d, (area_uv / area_3d).ln()));
    }

    /// Adds the sums of the triangles after this one's.
    fn merge(&mut self, o: DistortionSums) {
        self.triangles += o.triangles;
        self.area_3d += o.area_3d;
        self.area_uv += o.area_uv;
        self.dirichlet += o.dirichlet;
        self.sigma1_max = self.sigma1_max.max(o.sigma1_max);
        self.conformal += o.conformal;
        self.conformal_max = self.conformal_max.max(o.conformal_max);
        self.angle += o.angle;
        self.angle_max = self.angle_max.max(o.angle_max);
        self.log_area_ratios.extend(o.log_area_ratios);
    }

    /// Final measures, after scaling uv by k = sqrt(Σ A_3d / Σ A_uv): every σ is divided by k
    /// and every uv area multiplied by s = k².
    fn summarize(&self) -> DistortionSummary {
        if self.triangles == 0 || !(self.area_3d > 0.0 && self.area_uv > 0.0) {
            return DistortionSummary::undefined();
        }
        let area_scale = self.area_3d / self.area_uv;
        let log_scale = area_scale.ln();
        let (mut area_sum, mut area_max) = (0.0, 0.0f64);
        for &(area_3d, log_ratio) in &self.log_area_ratios {
            let area = (log_scale + log_ratio).abs();
            area_sum += area_3d * area;
            area_max = area_max.max(area);
        }
        DistortionSummary {
            stretch_l2: (self.dirichlet / area_scale / self.area_3d).sqrt(),
            stretch_linf: self.sigma1_max / area_scale.sqrt(),
            conformal_mean: self.conformal / self.area_3d,
            conformal_max: self.conformal_max,
            angle_mean: self.angle / (3 * self.triangles) as f64,
            angle_max: self.angle_max,
            area_mean: area_sum / self.area_3d,
            area_max,
        }
    }
}

fn distortion_sums(
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
    uv: &[[f64; 2]],
    uv_triangles: &[[u32; 3]],
    orientations: &[UvOrientation],
) -> DistortionSums {
    // Fixed chunks summed in order: the same sums whatever the thread count.
    let chunk = |range: std::ops::Range<usize>| {
        let mut sums = DistortionSums::default();
        for t in range {
            if matches!(orientations[t], UvOrientation::Agrees | UvOrientation::Flipped) {
                sums.add(triangles[t].map(|v| positions[v as usize]), uv_triangles[t].map(|i| uv[i as usize]));
            }
        }
        sums
    };
    let n = triangles.len();
    let range = |c: usize| c * SUM_CHUNK..((c + 1) * SUM_CHUNK).min(n);
    let parts: Vec<DistortionSums> = if n < crate::parallel::SEQUENTIAL_BELOW {
        vec![chunk(0..n)]
    } else {
        use rayon::prelude::*;
        (0..n.div_ceil(SUM_CHUNK)).into_par_iter().map(|c| chunk(range(c))).collect()
    };
    let mut sums = DistortionSums::default();
    for part in parts {
        sums.merge(part);
    }
    sums
}

/// Triangles per partial sum of [`distortion_sums`].
const SUM_CHUNK: usize = 4096;

struct DistortionSummary {
    stretch_l2: f64,
    stretch_linf: f64,
    conformal_mean: f64,
    conformal_max: f64,
    angle_mean: f64,
    angle_max: f64,
    area_mean: f64,
    area_max: f64,
}

impl DistortionSummary {
    fn undefined() -> DistortionSummary {
        DistortionSummary {
            stretch_l2: f64::NAN,
            stretch_linf: f64::NAN,
            conformal_mean: f64::NAN,
            conformal_max: f64::NAN,
            angle_mean: f64::NAN,
            angle_max: f64::NAN,
            area_mean: f64::NAN,
            area_max: f64::NAN,
        }
    }
}

fn count_orientation(orientations: &[UvOrientation], which: UvOrientation) -> usize {
    orientations.iter().filter(|&&o| o == which).count()
}

/// Columns J_u, J_v of the Jacobian J = [e1 e2]·[d1 d2]⁻¹ (e_i surface edges, d_i uv edges).
fn jacobian_columns(p: [[f64; 3]; 3], q: [[f64; 2]; 3]) -> ([f64; 3], [f64; 3]) {
    let (e1, e2) = (sub3(p[1], p[0]), sub3(p[2], p[0]));
    let (d1, d2) = (sub2(q[1], q[0]), sub2(q[2], q[0]));
    let det = cross2(d1, d2);
    let ju = [0, 1, 2].map(|k| (e1[k] * d2[1] - e2[k] * d1[1]) / det);
    let jv = [0, 1, 2].map(|k| (e2[k] * d1[0] - e1[k] * d2[0]) / det);
    (ju, jv)
}

/// Interior angles at corners 0, 1, 2, in radians (atan2 form, accurate for thin triangles).
fn corner_angles_3d(p: [[f64; 3]; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| {
        let a = sub3(p[(i + 1) % 3], p[i]);
        let b = sub3(p[(i + 2) % 3], p[i]);
        norm3(cross3(a, b)).atan2(dot3(a, b))
    })
}

/// Interior (unsigned) angles at corners 0, 1, 2 of a uv triangle, in radians.
fn corner_angles_2d(q: [[f64; 2]; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| {
        let a = sub2(q[(i + 1) % 3], q[i]);
        let b = sub2(q[(i + 2) % 3], q[i]);
        cross2(a, b).abs().atan2(dot2(a, b))
    })
}

fn uv_corners(uv: &[[f64; 2]], tri: [u32; 3]) -> Option<[[f64; 2]; 3]> {
    let q = [*uv.get(tri[0] as usize)?, *uv.get(tri[1] as usize)?, *uv.get(tri[2] as usize)?];
    points_are_finite_2d(&q).then_some(q)
}

fn points_are_finite_2d(q: &[[f64; 2]]) -> bool {
    q.iter().flatten().all(|x| x.is_finite())
}

fn points_are_finite_3d(p: &[[f64; 3]]) -> bool {
    p.iter().flatten().all(|x| x.is_finite())
}

// ---------------------------------------------------------------------------------------------
// Boundary crossings

struct Segment {
    ends: [u32; 2],
    a: [f64; 2],
    b: [f64; 2],
    min: [f64; 2],
    max: [f64; 2],
}

fn segment(uv: &[[f64; 2]], edge: [u32; 2]) -> Option<Segment> {
    let a = *uv.get(edge[0] as usize)?;
    let b = *uv.get(edge[1] as usize)?;
    if !points_are_finite_2d(&[a, b]) {
        return None;
    }
    Some(Segment { ends: edge, a, b, min: [a[0].min(b[0]), a[1].min(b[1])], max: [a[0].max(b[0]), a[1].max(b[1])] })
}

/// Whether two segments cross at a single point interior to both; segments sharing an endpoint
/// index never do.
fn segments_cross_properly(s: &Segment, t: &Segment) -> bool {
    if s.ends.iter().any(|e| t.ends.contains(e)) {
        return false;
    }
    opposite_signs(orient2(s.a, s.b, t.a), orient2(s.a, s.b, t.b))
        && opposite_signs(orient2(t.a, t.b, s.a), orient2(t.a, t.b, s.b))
}

fn orient2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    cross2(sub2(b, a), sub2(c, a))
}

fn opposite_signs(x: f64, y: f64) -> bool {
    (x > 0.0 && y < 0.0) || (x < 0.0 && y > 0.0)
}

/// Multiplies all coordinates by a power of two (exact, so orientation signs are unchanged) when
/// they are so large that orientation products could overflow.
fn scaled_to_safe_range(mut segments: Vec<Segment>) -> Vec<Segment> {
    const SAFE: f64 = 1e150;
    let largest = segments.iter().flat_map(|s| [s.a, s.b]).flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    if largest <= SAFE {
        return segments;
    }
    let factor = 2f64.powi(-((largest / SAFE).log2().ceil() as i32));
    for s in &mut segments {
        for p in [&mut s.a, &mut s.b, &mut s.min, &mut s.max] {
            *p = [p[0] * factor, p[1] * factor];
        }
    }
    segments
}

/// A cell: (level, column, row).
type Cell = (u32, u64, u64);

/// Multi-level grid: level l has square cells of side h0·2^l from a common origin; a segment
/// lives at the smallest level whose cells are at least its extent, in the cells its box overlaps.
struct LevelGrid {
    origin: [f64; 2],
    base_cell: f64,
    /// Levels that hold at least one segment, ascending.
    levels: Vec<u32>,
    level_of: Vec<u32>,
    /// (cell, segment), sorted.
    entries: Vec<(Cell, u32)>,
}

impl LevelGrid {
    /// `None` when no two segments can cross (fewer than two, or no segment of positive length).
    /// h0 is the smallest positive extent, but at least 2^-40 of the layout's size, so cell
    /// indices stay below 2^41 and there are at most ~41 levels.
    fn build(segments: &[Segment]) -> Option<LevelGrid> {
        if segments.len() < 2 {
            return None;
        }
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        let mut smallest = f64::INFINITY;
        for s in segments {
            for k in 0..2 {
                lo[k] = lo[k].min(s.min[k]);
                hi[k] = hi[k].max(s.max[k]);
            }
            let e = segment_extent(s);
            if e > 0.0 {
                smallest = smallest.min(e);
            }
        }
        let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        if !(smallest.is_finite() && size > 0.0) {
            return None;
        }
        let mut grid = LevelGrid {
            origin: lo,
            base_cell: smallest.max(size * 2f64.powi(-40)),
            levels: Vec::new(),
            level_of: Vec::with_capacity(segments.len()),
            entries: Vec::with_capacity(4 * segments.len()),
        };
        for (i, s) in segments.iter().enumerate() {
            let level = grid.level_for_extent(segment_extent(s));
            grid.level_of.push(level);
            let (c0, c1) = (grid.cell_of(level, s.min), grid.cell_of(level, s.max));
            for cy in c0[1]..=c1[1] {
                for cx in c0[0]..=c1[0] {
                    grid.entries.push(((level, cx, cy), i as u32));
                }
            }
        }
        grid.entries.sort_unstable();
        grid.levels = grid.level_of.clone();
        grid.levels.sort_unstable();
        grid.levels.dedup();
        Some(grid)
    }

    fn cell_size(&self, level: u32) -> f64 {
        self.base_cell * 2f64.powi(level as i32)
    }

    /// Smallest level whose cells are at least `extent` wide (so a box spans ≤ 2×2 cells).
    fn level_for_extent(&self, extent: f64) -> u32 {
        let mut level = 0;
        while level < 64 && self.cell_size(level) < extent {
            level += 1;
        }
        level
    }

    /// Cell of a point at a level; monotone in each coordinate.
    fn cell_of(&self, level: u32, point: [f64; 2]) -> [u64; 2] {
        let h = self.cell_size(level);
        // `as` saturates: a negative rounding error gives 0, never a wrap.
        [0, 1].map(|k| ((point[k] - self.origin[k]) / h).floor() as u64)
    }

    fn members(&self, cell: Cell) -> impl Iterator<Item = &u32> {
        let start = self.entries.partition_point(|(c, _)| *c < cell);
        self.entries[start..].iter().take_while(move |(c, _)| *c == cell).map(|(_, s)| s)
    }

    /// The one cell (at `level`) where a pair of segments is counted: the cell of the lower-left
    /// corner of the intersection of their boxes. `None` if the boxes are apart.
    fn pair_owner(&self, level: u32, s: &Segment, t: &Segment) -> Option<Cell> {
        let lower = [s.min[0].max(t.min[0]), s.min[1].max(t.min[1])];
        let upper = [s.max[0].min(t.max[0]), s.max[1].min(t.max[1])];
        if lower[0] <= upper[0] && lower[1] <= upper[1] {
            let [cx, cy] = self.cell_of(level, lower);
            Some((level, cx, cy))
        } else {
            None
        }
    }
}

fn segment_extent(s: &Segment) -> f64 {
    (s.max[0] - s.min[0]).max(s.max[1] - s.min[1])
}

// ---------------------------------------------------------------------------------------------
// Small vector helpers

fn sub2(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn dot2(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm3(a: [f64; 3]) -> f64 {
    dot3(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOL: f64 = 1e-12;

    /// An n×n grid of unit squares in the plane z = 0, each split into two counter-clockwise
    /// triangles, with interior vertices moved a little so the triangles are not all alike.
    fn flat_grid(n: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let interior = i > 0 && j > 0 && i < n && j < n;
                let wobble = if interior { 0.2 * ((i * 7 + j * 3) as f64).sin() } else { 0.0 };
                positions.push([i as f64 + wobble, j as f64 - 0.5 * wobble, 0.0]);
            }
        }
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        (positions, triangles)
    }

    fn xy(positions: &[[f64; 3]]) -> Vec<[f64; 2]> {
        positions.iter().map(|p| [p[0], p[1]]).collect()
    }

    fn assert_isometric(m: &Metrics) {
        assert_eq!(m.flipped, 0);
        assert_eq!(m.degenerate_uv, 0);
        assert_eq!(m.boundary_intersections, 0);
        assert!((m.stretch_l2 - 1.0).abs() < TOL, "{m:?}");
        assert!((m.stretch_linf - 1.0).abs() < TOL, "{m:?}");
        assert!((m.conformal_mean - 1.0).abs() < TOL, "{m:?}");
        assert!((m.conformal_max - 1.0).abs() < TOL, "{m:?}");
        assert!(m.angle_mean < TOL && m.angle_max < TOL, "{m:?}");
        assert!(m.area_mean < TOL && m.area_max < TOL, "{m:?}");
    }

    #[test]
    fn flat_mesh_is_its_own_parameterization() {
        let (positions, triangles) = flat_grid(6);
        let m = distortion(&positions, &triangles, &xy(&positions), &triangles).unwrap();
        assert_eq!(m.triangles, 72);
        assert_isometric(&m);
    }

    #[test]
    fn similarity_of_the_layout_or_the_surface_changes_nothing() {
        let (positions, triangles) = flat_grid(5);
        let (c, s, scale) = (0.6f64.cos(), 0.6f64.sin(), 3.7);
        let uv: Vec<[f64; 2]> = positions
            .iter()
            .map(|p| [scale * (c * p[0] - s * p[1]) + 10.0, scale * (s * p[0] + c * p[1]) - 4.0])
            .collect();
        assert_isometric(&distortion(&positions, &triangles, &uv, &triangles).unwrap());
        // The flat surface tilted in space (rotation about the x axis), layout unchanged.
        let tilted: Vec<[f64; 3]> =
            positions.iter().map(|p| [p[0], c * p[1] - s * p[2], s * p[1] + c * p[2]]).collect();
        let m = distortion(&tilted, &triangles, &xy(&positions), &triangles).unwrap();
        assert_isometric(&m);
    }

    #[test]
    fn mirrored_layout_is_not_a_layout_of_flips() {
        let (positions, triangles) = flat_grid(4);
        let uv: Vec<[f64; 2]> = positions.iter().map(|p| [-p[0], p[1]]).collect();
        assert!(majority_orientation(&uv, &triangles) < 0.0);
        assert_isometric(&distortion(&positions, &triangles, &uv, &triangles).unwrap());
    }

    #[test]
    fn one_mirrored_triangle_among_others_is_one_flip() {
        // Per-corner uv so one triangle can be mirrored on its own.
        let (positions, triangles) = flat_grid(4);
        let mut uv = Vec::new();
        let mut uv_triangles = Vec::new();
        for (t, tri) in triangles.iter().enumerate() {
            let base = uv.len() as u32;
            for &v in tri {
                let p = positions[v as usize];
                uv.push(if t == 5 { [-p[0], p[1]] } else { [p[0], p[1]] });
            }
            uv_triangles.push([base, base + 1, base + 2]);
        }
        let m = distortion(&positions, &triangles, &uv, &uv_triangles).unwrap();
        assert_eq!(m.flipped, 1);
        assert_eq!(uv_orientations(&uv, &uv_triangles)[5], UvOrientation::Flipped);
        // A mirror image is still an isometry of that triangle.
        assert!((m.stretch_linf - 1.0).abs() < TOL && m.area_max < TOL);
    }

    #[test]
    fn stretching_u_by_two_halves_one_singular_value() {
        // uv = (2x, y): the map uv → surface is (u/2, v), with σ1 = 1 and σ2 = 1/2.
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let q = [[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]];
        let (s1, s2) = per_triangle_singular_values(p, q).unwrap();
        assert!((s1 - 1.0).abs() < TOL && (s2 - 0.5).abs() < TOL, "{s1} {s2}");

        // After rescaling uv to the surface area (k = 1/√2): σ = (√2, √2/2).
        let m = distortion(&p, &[[0, 1, 2]], &q, &[[0, 1, 2]]).unwrap();
        assert!((m.stretch_l2 - 1.25f64.sqrt()).abs() < TOL, "{m:?}");
        assert!((m.stretch_linf - 2f64.sqrt()).abs() < TOL, "{m:?}");
        assert!((m.conformal_mean - 2.0).abs() < TOL && (m.conformal_max - 2.0).abs() < TOL);
        assert!(m.area_mean < TOL && m.area_max < TOL);
        // Corner angles: uv (π/2, atan ½, atan 2) against surface (π/2, π/4, π/4).
        let d = 2f64.atan() - std::f64::consts::FRAC_PI_4;
        assert!((m.angle_max - d).abs() < TOL && (m.angle_mean - 2.0 * d / 3.0).abs() < TOL);
    }

    #[test]
    fn singular_values_satisfy_the_course_notes_identities() {
        // σ1σ2 = A(T)/A(t) (eq. 4.4), and σ1² + σ2² = |J|²_F = Σ cot θ_i |p_{i+2} − p_{i+1}|² / (2A(t))
        // with θ_i the uv angle at corner i (the cotangent form of the Dirichlet energy).
        let p = [[0.3, -1.2, 0.7], [2.1, 0.4, -0.5], [-0.8, 1.9, 1.3]];
        let q = [[0.1, 0.2], [1.7, -0.4], [0.9, 1.6]];
        let (s1, s2) = per_triangle_singular_values(p, q).unwrap();
        let area_t = signed_uv_area(q);
        assert!((s1 * s2 - triangle_area_3d(p) / area_t).abs() < 1e-12);
        let angles = corner_angles_2d(q);
        let dirichlet: f64 = (0..3)
            .map(|i| {
                let e = sub3(p[(i + 2) % 3], p[(i + 1) % 3]);
                dot3(e, e) / angles[i].tan()
            })
            .sum::<f64>()
            / (2.0 * area_t);
        assert!((s1 * s1 + s2 * s2 - dirichlet).abs() < 1e-10, "{} {dirichlet}", s1 * s1 + s2 * s2);
        assert!(s1 >= s2);
    }

    #[test]
    fn degenerate_triangles_have_no_singular_values() {
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        assert!(per_triangle_singular_values(p, [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]).is_none());
        let flat = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        assert!(per_triangle_singular_values(flat, [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]).is_none());
        let nan = [[0.0, 0.0], [f64::NAN, 0.0], [0.0, 1.0]];
        assert!(per_triangle_singular_values(p, nan).is_none());
    }

    #[test]
    fn collapsed_uv_triangles_are_degenerate_not_flipped() {
        let (positions, triangles) = flat_grid(3);
        let mut uv = xy(&positions);
        let (a, b, c) = (triangles[0][0], triangles[0][1], triangles[0][2]);
        // Move corner b onto the segment a–c's line: triangle 0 collapses (neighbours distort).
        let (pa, pc) = (uv[a as usize], uv[c as usize]);
        uv[b as usize] = [0.5 * (pa[0] + pc[0]), 0.5 * (pa[1] + pc[1])];
        let m = distortion(&positions, &triangles, &uv, &triangles).unwrap();
        assert_eq!(m.degenerate_uv, 1);
        assert_eq!(m.flipped, 0);
        assert!(m.stretch_l2.is_finite());
    }

    #[test]
    fn all_degenerate_layout_has_undefined_distortion() {
        let (positions, triangles) = flat_grid(2);
        let uv = vec![[0.5, 0.5]; positions.len()];
        let m = distortion(&positions, &triangles, &uv, &triangles).unwrap();
        assert_eq!(m.degenerate_uv, triangles.len());
        assert!(m.stretch_l2.is_nan());
    }

    #[test]
    fn folded_quad_boundary_crosses_itself_once() {
        // Quad a b c d with triangles (a b c), (a c d); d is folded across a–c and below a–b, so
        // boundary edge c–d crosses boundary edge a–b, and triangle (a c d) flips.
        let positions = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [2.0, 2.0, 0.0], [0.0, 2.0, 0.0]];
        let triangles = [[0, 1, 2], [0, 2, 3]];
        let uv = [[0.0, 0.0], [4.0, 0.0], [2.0, 2.0], [1.5, -0.5]];
        let m = distortion(&positions, &triangles, &uv, &triangles).unwrap();
        assert_eq!(m.boundary_intersections, 1);
        assert_eq!(m.flipped, 1);
    }

    #[test]
    fn triangle_poking_into_another_crosses_twice() {
        let positions = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let triangles = [[0, 1, 2], [0, 1, 2]];
        let uv = [[0.0, 0.0], [4.0, 0.0], [0.0, 4.0], [1.0, -1.0], [2.0, -1.0], [1.5, 1.0]];
        let m = distortion(&positions, &triangles, &uv, &[[0, 1, 2], [3, 4, 5]]).unwrap();
        assert_eq!(m.boundary_intersections, 2);
        // Touching at a shared coordinate without sharing an index is not a crossing.
        let touching = [[0.0, 0.0], [4.0, 0.0], [0.0, 4.0], [4.0, 0.0], [6.0, 0.0], [5.0, 1.0]];
        let m = distortion(&positions, &triangles, &touching, &[[0, 1, 2], [3, 4, 5]]).unwrap();
        assert_eq!(m.boundary_intersections, 0);
    }

    #[test]
    fn grid_crossing_count_matches_brute_force() {
        // A tangle of boundary edges (a pseudo-random walk) with long and short edges.
        let mut x = 0.37f64;
        let mut next = || {
            x = (x * 97.13 + 0.291).fract();
            x
        };
        let mut uv: Vec<[f64; 2]> = (0..400)
            .map(|i| {
                let r = if i % 17 == 0 { 50.0 } else { 3.0 };
                [r * next(), r * next()]
            })
            .collect();
        // A vertex flung far away, and a cluster of tiny edges.
        uv[200] = [1e7, -3e6];
        for q in uv.iter_mut().skip(300).take(50) {
            *q = [1.0 + 1e-4 * q[0], 1.0 + 1e-4 * q[1]];
        }
        let edges: Vec<[u32; 2]> = (0..399).map(|i| [i, i + 1]).collect();
        let segments: Vec<Segment> = edges.iter().filter_map(|e| segment(&uv, *e)).collect();
        let mut brute = 0;
        for i in 0..segments.len() {
            for j in i + 1..segments.len() {
                brute += usize::from(segments_cross_properly(&segments[i], &segments[j]));
            }
        }
        assert!(brute > 100);
        assert_eq!(count_boundary_crossings(&uv, &edges), brute);
    }

    #[test]
    fn far_outlier_does_not_make_the_crossing_count_quadratic() {
        // A closed polygon of 100 000 short edges around the origin, and one edge from the
        // origin to a point flung 1e9 away, which crosses the polygon once. A single uniform grid
        // would put the whole polygon in one cell here.
        let n = 100_000u32;
        let mut uv: Vec<[f64; 2]> = (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * f64::from(i) / f64::from(n);
                [a.cos(), a.sin()]
            })
            .collect();
        uv.extend([[0.0, 0.0], [1e9, 0.5]]);
        let mut edges: Vec<[u32; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
        edges.push([n, n + 1]);
        let start = std::time::Instant::now();
        assert_eq!(count_boundary_crossings(&uv, &edges), 1);
        assert!(start.elapsed().as_secs_f64() < 5.0, "{:?}", start.elapsed());
    }

    #[test]
    fn boundary_edges_are_the_edges_used_once() {
        let (_, triangles) = flat_grid(3);
        let edges = uv_edges(&triangles);
        assert_eq!(edges.boundary.len(), 12);
        assert_eq!(edges.interior.len(), 3 * 18 / 2 - 6);
    }

    #[test]
    fn invalid_input_is_an_error_naming_the_triangle() {
        let (positions, triangles) = flat_grid(2);
        let uv = xy(&positions);
        let mut bad = triangles.clone();
        bad[3][1] = 999;
        match distortion(&positions, &bad, &uv, &triangles) {
            Err(Error::InvalidArgument(msg)) => assert!(msg.contains("triangle 3"), "{msg}"),
            other => panic!("{other:?}"),
        }
        match distortion(&positions, &triangles, &uv, &bad) {
            Err(Error::InvalidArgument(msg)) => assert!(msg.contains("uv 999"), "{msg}"),
            other => panic!("{other:?}"),
        }
        let mut nan_uv = uv.clone();
        nan_uv[triangles[2][0] as usize][1] = f64::NAN;
        assert!(distortion(&positions, &triangles, &nan_uv, &triangles).is_err());
        assert!(distortion(&positions, &triangles, &uv, &triangles[1..]).is_err());
        assert!(distortion(&positions, &[], &uv, &[]).is_err());
    }
}
