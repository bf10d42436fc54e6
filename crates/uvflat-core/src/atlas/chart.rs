//! One chart of an atlas: a set of input triangles made into a disk, flattened by the chosen
//! method, and checked against the atlas's validity conditions.
//!
//! **Chart mesh.** The chart's corners are grouped by union–find across every edge whose two
//! triangles both belong to the chart (as `mesh::cut` groups corners across uncut edges), so a
//! vertex where the chart touches itself only at that vertex (a pinch) gets one copy per fan,
//! and the chart mesh is always a manifold. A chart that is genus 0 with at least one boundary
//! loop is flattened as it is (the free-boundary methods handle holes); a closed chart or one
//! with handles is first cut into a disk by the tree–cotree cut of `mesh::cut`.
//!
//! **Validity** (what the atlas guarantees of every accepted chart):
//! 1. every UV triangle has positive signed area and is not degenerate (`metrics`'
//!    scale-invariant degeneracy test) — locally injective;
//! 2. no two boundary edges of the chart cross — with 1., a locally injective map of a disk
//!    whose boundary is a simple curve is globally injective, so the chart does not overlap
//!    itself (for charts with holes the hole boundaries are checked against each other and
//!    against the outer boundary the same way);
//! 3. Sander et al. 2001's L2 stretch of the chart, after scaling its UV area to its 3D area
//!    (the same normalisation as `metrics`), is at most the caller's bound.
//!
//! **Flattening.** The natural conformal map (LSCM) is fast but may flip; mean value (circle
//! boundary) never flips; SLIM and Sander's stretch start from the natural conformal map when
//! it has no flipped triangle, from the mean value map otherwise, and keep the start's local
//! injectivity (flip-free line search, `methods::nonlinear`).
//!
//! The UVs of an accepted chart are scaled so that its UV area equals its 3D area (uniform
//! texel density across charts, what the packer then preserves).

use super::ChartMethod;
use crate::error::{Error, Result};
use crate::mesh::cut::{cut_to_disk, EdgeCost};
use crate::mesh::{next, TriMesh, NONE};
use crate::methods::barycentric::{fixed_boundary_map, FixedBoundaryOptions};
use crate::methods::conformal::natural_conformal_map;
use crate::methods::nonlinear::{nonlinear_map_from, NonlinearMethod, NonlinearOptions};
use crate::metrics::{count_boundary_crossings, signed_uv_area, squared_singular_value_sum, triangle_is_degenerate_2d};
use crate::progress::Progress;
use std::borrow::Cow;
use uvflat_sparse::union_find::{find, union};

/// A chart made into a flattened disk.
#[derive(Debug, Clone)]
pub struct FlatChart {
    /// Input triangles of the chart, sorted.
    pub faces: Vec<u32>,
    /// For each chart face (same order), the chart-vertex of each corner.
    pub corners: Vec<[u32; 3]>,
    /// Input vertex of every chart vertex.
    pub original: Vec<u32>,
    /// UV of every chart vertex, scaled to the chart's 3D area.
    pub uv: Vec<[f64; 2]>,
    /// L2 stretch of the chart.
    pub stretch_l2: f64,
    /// 3D area of the chart.
    pub area: f64,
    /// Whether the chart's stretch has been polished already.
    pub polished: bool,
    /// Whether the method's own flattening was refused and the chart was laid out by the
    /// bijective repair (SLIM with a scaffold from the mean value map) instead.
    pub repaired: bool,
}

/// Why a flattened chart was refused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Refusal {
    /// A triangle is flipped or degenerate in UV.
    Flipped,
    /// Two boundary edges cross.
    Overlaps,
    /// The stretch exceeds the bound.
    Stretch(f64),
    /// The method failed numerically (e.g. a chart too degenerate for LSCM).
    Failed,
}

/// The chart mesh of `faces` (sorted input triangles): its triangles per chart face and the
/// input vertex of every chart vertex (pinches split, see the module docs).
fn chart_mesh<'a>(mesh: &'a TriMesh, faces: &[u32]) -> Result<(Cow<'a, TriMesh>, Vec<u32>)> {
    // The whole mesh is its own chart (a validated mesh has no pinched vertex): borrowed, not
    // built again (a tenth of a small disk's unwrap) nor copied.
    let whole = faces.len() == mesh.triangle_count() && (0..mesh.vertex_count() as u32).all(|v| mesh.is_referenced(v));
    if whole {
        return Ok((Cow::Borrowed(mesh), (0..mesh.vertex_count() as u32).collect()));
    }
    let twin = &mesh.connectivity().twin;
    let local = |f: u32| faces.binary_search(&f).ok();
    let corner_count = 3 * faces.len();
    let mut group: Vec<u32> = (0..corner_count as u32).collect();
    for (i, &f) in faces.iter().enumerate() {
        for k in 0..3u32 {
            let h = 3 * f + k;
            let g = twin[h as usize];
            if g == NONE || g < h {
                continue;
            }
            let Some(j) = local(g / 3) else { continue };
            let (hl, gl) = (3 * i as u32 + k, 3 * j as u32 + g % 3);
            // tail(h) = tail(next(g)); head(h) = tail(next(h)) = tail(g).
            union(&mut group, hl, 3 * j as u32 + next(g) % 3);
            union(&mut group, 3 * i as u32 + next(h) % 3, gl);
        }
    }
    let mut new_id = vec![NONE; corner_count];
    let mut original = Vec::new();
    let mut triangles = vec![[0u32; 3]; faces.len()];
    for c in 0..corner_count as u32 {
        let root = find(&mut group, c) as usize;
        if new_id[root] == NONE {
            new_id[root] = original.len() as u32;
            original.push(mesh.triangles()[faces[(c / 3) as usize] as usize][(c % 3) as usize]);
        }
        triangles[(c / 3) as usize][(c % 3) as usize] = new_id[root];
    }
    let points: Vec<[f64; 3]> = original.iter().map(|&v| mesh.points()[v as usize]).collect();
    let chart = TriMesh::from_checked(points, triangles)
        .map_err(|e| Error::Internal(format!("a chart mesh is invalid: {e}")))?;
    Ok((Cow::Owned(chart), original))
}

/// The chart as a disk (genus 0, ≥ 1 boundary loop): itself, or cut by the tree–cotree cut.
/// Returns the disk and the chart vertex of every disk vertex.
fn as_disk(chart: Cow<'_, TriMesh>) -> Result<(Cow<'_, TriMesh>, Option<Vec<u32>>)> {
    if chart.require_disk_with_holes().is_ok() {
        return Ok((chart, None));
    }
    let cut = cut_to_disk(&chart, &EdgeCost::default())?;
    Ok((Cow::Owned(cut.mesh), Some(cut.original)))
}

/// How charts are flattened and judged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChartSettings {
    /// The flattening method.
    pub method: ChartMethod,
    /// Iterations of the non-linear methods.
    pub iterations: usize,
    /// Iterations of L2-stretch polishing (0: none).
    pub polish: usize,
    /// Largest L2 stretch of an accepted chart.
    pub max_stretch: f64,
    /// Repair a refused flattening before the chart is split: see [`repaired`].
    pub repair: bool,
}

/// A chart whose first flattening has L2 stretch above the bound is polished (and may then be
/// accepted) only when its stretch excess `s − 1` is at most this many times the bound's: the
/// stretch minimization lowers the excess of a valid chart by a factor of about 2–10 within a
/// few iterations, so charts far over the bound are split at once instead.
const POLISH_GATE: f64 = 6.0;

/// Relative round-off allowed on the stretch bound (a few ulps of the stretch's sums).
const STRETCH_ROUND_OFF: f64 = 1e-12;

/// Builds, flattens and checks the chart of `faces` (sorted). `Ok(Err(refusal))` when the
/// flattening is not valid under `settings.max_stretch`. A valid flattening over the bound but
/// within `POLISH_GATE` is polished (L2 stretch minimized) and judged again.
pub fn flatten_chart(
    mesh: &TriMesh,
    faces: Vec<u32>,
    settings: &ChartSettings,
) -> Result<std::result::Result<FlatChart, Refusal>> {
    let (chart, mut original) = chart_mesh(mesh, &faces)?;
    let (disk, disk_to_chart) = as_disk(chart)?;
    if let Some(map) = disk_to_chart {
        original = map.iter().map(|&v| original[v as usize]).collect();
    }
    let flattened = flatten(&disk, settings.method, settings.iterations);
    let judged = match flattened {
        None => Err(Refusal::Failed),
        Some(mut uv) => checked_and_scaled(&disk, &mut uv).map(|(stretch, area)| (uv, stretch, area)),
    };
    // The bound is met up to round-off: one triangle laid out exactly has a stretch of 1 ± a
    // few ulps, and `max_stretch = 1` (isometric) must accept it.
    let over = |s: f64| !(s <= settings.max_stretch * (1.0 + STRETCH_ROUND_OFF));
    // Only an invalid flattening is repaired: one that is merely over the bound is split, so
    // that its pieces keep the method's distortion (a conformal map stays conformal).
    if settings.repair && judged.is_err() {
        if let Some((uv, stretch, area)) = repaired(&disk, settings.iterations) {
            if over(stretch) {
                return Ok(Err(Refusal::Stretch(stretch)));
            }
            let corners = disk.triangles().to_vec();
            return Ok(Ok(FlatChart {
                faces,
                corners,
                original,
                uv,
                stretch_l2: stretch,
                area,
                polished: true,
                repaired: true,
            }));
        }
    }
    let (mut uv, mut stretch, area) = match judged {
        Ok(j) => j,
        Err(refusal) => return Ok(Err(refusal)),
    };
    let mut polished = false;
    let gate = 1.0 + POLISH_GATE * (settings.max_stretch - 1.0);
    if stretch > settings.max_stretch && stretch <= gate && settings.polish > 0 {
        if let Some((better, s)) = polish(&disk, &uv, settings.polish) {
            (uv, stretch, polished) = (better, s, true);
        }
    }
    if over(stretch) {
        return Ok(Err(Refusal::Stretch(stretch)));
    }
    let corners = disk.triangles().to_vec();
    Ok(Ok(FlatChart { faces, corners, original, uv, stretch_l2: stretch, area, polished, repaired: false }))
}

/// Triangle `t` alone, laid out isometrically (its first edge along u, counter-clockwise):
/// every triangle has such a flattening, whatever the method would make of it (the mean value
/// map puts its corners on a circle, for instance). None for a degenerate triangle.
pub fn exact_triangle_chart(mesh: &TriMesh, t: u32) -> Option<FlatChart> {
    use crate::geometry::{cross, dot, norm, sub};
    let tri = mesh.triangles()[t as usize];
    let [a, b, c] = tri.map(|v| mesh.points()[v as usize]);
    let (ab, ac) = (sub(b, a), sub(c, a));
    let (len, twice_area) = (norm(ab), norm(cross(ab, ac)));
    if !(len > 0.0 && twice_area > 0.0) {
        return None;
    }
    let uv = vec![[0.0, 0.0], [len, 0.0], [dot(ab, ac) / len, twice_area / len]];
    Some(FlatChart {
        faces: vec![t],
        corners: vec![[0, 1, 2]],
        original: tri.to_vec(),
        uv,
        stretch_l2: 1.0,
        area: 0.5 * twice_area,
        polished: true,
        repaired: false,
    })
}

/// The chart polished: its L2 stretch minimized from its current map (see [`polish`]); the
/// chart unchanged when it already was, or when polishing fails or does not lower the stretch.
pub fn polished(mesh: &TriMesh, chart: FlatChart, iterations: usize) -> Result<FlatChart> {
    if chart.polished || iterations == 0 {
        return Ok(chart);
    }
    let points: Vec<[f64; 3]> = chart.original.iter().map(|&v| mesh.points()[v as usize]).collect();
    let disk = TriMesh::from_checked(points, chart.corners.clone())
        .map_err(|e| Error::Internal(format!("a chart disk is invalid: {e}")))?;
    Ok(match polish(&disk, &chart.uv, iterations) {
        Some((uv, stretch)) if stretch < chart.stretch_l2 => {
            FlatChart { uv, stretch_l2: stretch, polished: true, ..chart }
        }
        _ => FlatChart { polished: true, ..chart },
    })
}

/// Minimizes Sander et al. 2001's L2 stretch (scale-normalized, `methods::nonlinear`'s
/// `Energy::Stretch`) over `iterations` preconditioned L-BFGS steps from the valid map `uv`
/// (scaled to the 3D area). The flip-free line search keeps every triangle positively oriented;
/// a free boundary may still run into itself, so the result is checked again. Returns the map
/// scaled to the 3D area and its stretch, or `None` when it is not valid.
fn polish(disk: &TriMesh, uv: &[[f64; 2]], iterations: usize) -> Option<(Vec<[f64; 2]>, f64)> {
    let mut options = NonlinearOptions::new(NonlinearMethod::Stretch);
    options.iterations = iterations;
    options.tolerance = 1e-6;
    let mut out = nonlinear_map_from(disk, &options, uv, &mut Progress::none()).ok()?.uv;
    let (stretch, _) = checked_and_scaled(disk, &mut out).ok()?;
    Some((out, stretch))
}

/// The bijective repair: the mean value map with the outer boundary on a circle (an embedding,
/// the holes filled temporarily: Tutte–Floater), then SLIM with a scaffold around the boundary
/// (`methods::nonlinear::scaffold`), which keeps the map bijective while it frees the boundary
/// and minimizes the symmetric Dirichlet energy. Returns the map scaled to the 3D area, its L2
/// stretch and the 3D area; `None` when a step fails (a nearly degenerate chart).
pub fn repaired(disk: &TriMesh, iterations: usize) -> Option<(Vec<[f64; 2]>, f64, f64)> {
    let start = fixed_boundary_map(disk, &FixedBoundaryOptions::default()).ok()?;
    let mut options = NonlinearOptions::new(NonlinearMethod::Slim);
    options.iterations = iterations;
    options.tolerance = 1e-5;
    options.bijective = true;
    let mut uv = nonlinear_map_from(disk, &options, &start, &mut Progress::none()).ok()?.uv;
    let (stretch, area) = checked_and_scaled(disk, &mut uv).ok()?;
    Some((uv, stretch, area))
}

/// UVs of the disk by `method`; `None` when the method fails (numerically or otherwise).
fn flatten(disk: &TriMesh, method: ChartMethod, iterations: usize) -> Option<Vec<[f64; 2]>> {
    let mean_value = || fixed_boundary_map(disk, &FixedBoundaryOptions::default()).ok();
    let nonlinear = |which: NonlinearMethod| {
        let start =
            natural_conformal_map(disk, None).ok().filter(|uv| is_locally_injective(disk, uv)).or_else(mean_value)?;
        let mut options = NonlinearOptions::new(which);
        options.iterations = iterations;
        options.tolerance = 1e-5;
        match nonlinear_map_from(disk, &options, &start, &mut Progress::none()) {
            Ok(result) => Some(result.uv),
            Err(_) => Some(start),
        }
    };
    match method {
        ChartMethod::NaturalConformal => natural_conformal_map(disk, None).ok(),
        ChartMethod::MeanValue => mean_value(),
        ChartMethod::Slim => nonlinear(NonlinearMethod::Slim),
        ChartMethod::Stretch => nonlinear(NonlinearMethod::Stretch),
    }
}

/// UV triangle of input triangle `tri` of `disk`.
fn uv_triangle(uv: &[[f64; 2]], tri: [u32; 3]) -> [[f64; 2]; 3] {
    tri.map(|v| uv[v as usize])
}

/// Whether every triangle has the same orientation (either) and none is degenerate.
fn is_locally_injective(disk: &TriMesh, uv: &[[f64; 2]]) -> bool {
    let mut sign = 0.0;
    disk.triangles().iter().all(|t| {
        let q = uv_triangle(uv, *t);
        if triangle_is_degenerate_2d(q) {
            return false;
        }
        let s = signed_uv_area(q).signum();
        if sign == 0.0 {
            sign = s;
        }
        s == sign
    })
}

/// Mirrors a clockwise layout, then checks condition 1 of the module docs.
fn orient_and_check(disk: &TriMesh, uv: &mut [[f64; 2]]) -> std::result::Result<(), Refusal> {
    if uv.iter().any(|p| !(p[0].is_finite() && p[1].is_finite())) {
        // Unreferenced chart vertices do not exist (charts are built from corners).
        return Err(Refusal::Failed);
    }
    let total: f64 = disk.triangles().iter().map(|t| signed_uv_area(uv_triangle(uv, *t))).sum();
    if total < 0.0 {
        for p in uv.iter_mut() {
            p[0] = -p[0];
        }
    }
    let uv_ref: &[[f64; 2]] = uv;
    let bad = crate::parallel::position_first(disk.triangles(), |t| {
        let q = uv_triangle(uv_ref, *t);
        triangle_is_degenerate_2d(q) || !(signed_uv_area(q) > 0.0)
    })
    .is_some();
    if bad {
        return Err(Refusal::Flipped);
    }
    Ok(())
}

/// Whether two boundary edges of the disk's layout cross (condition 2 of the module docs).
fn boundary_crosses(disk: &TriMesh, uv: &[[f64; 2]]) -> bool {
    // The disk's UV boundary is its mesh boundary: the loops the mesh already holds (sorting
    // every edge to find them took most of this check on large charts).
    let boundary: Vec<[u32; 2]> =
        disk.boundary_loops().iter().flat_map(|l| (0..l.len()).map(move |k| [l[k], l[(k + 1) % l.len()]])).collect();
    count_boundary_crossings(uv, &boundary) > 0
}

/// Mirrors a clockwise layout, checks the three conditions of the module docs but the bound
/// (the crossing test and the stretch sums side by side: neither needs the other) and scales
/// the layout to its 3D area. Returns the L2 stretch and the 3D area.
fn checked_and_scaled(disk: &TriMesh, uv: &mut [[f64; 2]]) -> std::result::Result<(f64, f64), Refusal> {
    orient_and_check(disk, uv)?;
    let (crosses, sums) =
        crate::parallel::join(disk.triangle_count(), || boundary_crosses(disk, uv), || area_and_stretch_sums(disk, uv));
    if crosses {
        return Err(Refusal::Overlaps);
    }
    Ok(scale_to_area(uv, sums))
}

/// (3D area, UV area, Σ A (σ1² + σ2²)/2) of a layout whose triangles are proper.
fn area_and_stretch_sums(disk: &TriMesh, uv: &[[f64; 2]]) -> [f64; 3] {
    // (3D area, UV area, Σ A (σ1² + σ2²)/2) in fixed chunks summed in order: the same sums
    // whatever the thread count, in parallel on large charts.
    // The 3D areas are the mesh's own (computed with it).
    let area = &disk.geometry().area;
    let sums = |range: std::ops::Range<usize>| {
        let mut s = [0.0; 3];
        for (t, &a) in disk.triangles()[range.clone()].iter().zip(&area[range]) {
            let p = t.map(|v| disk.points()[v as usize]);
            let q = uv_triangle(uv, *t);
            s[0] += a;
            s[1] += signed_uv_area(q);
            // Every UV triangle is proper here (`orient_and_check`).
            let sum = squared_singular_value_sum(p, q);
            if sum.is_finite() {
                s[2] += a * 0.5 * sum;
            }
        }
        s
    };
    const CHUNK: usize = 4096;
    let n = disk.triangle_count();
    let parts: Vec<[f64; 3]> = if n < crate::parallel::SEQUENTIAL_BELOW {
        vec![sums(0..n)]
    } else {
        use rayon::prelude::*;
        (0..n.div_ceil(CHUNK)).into_par_iter().map(|c| sums(c * CHUNK..((c + 1) * CHUNK).min(n))).collect()
    };
    parts.iter().fold([0.0; 3], |acc, s| [acc[0] + s[0], acc[1] + s[1], acc[2] + s[2]])
}

/// Scales the UVs so that their area equals the 3D area; returns the L2 stretch (Sander et al.
/// 2001, normalised as in `metrics`) and the 3D area, from [`area_and_stretch_sums`].
fn scale_to_area(uv: &mut [[f64; 2]], [area_3d, area_uv, weighted]: [f64; 3]) -> (f64, f64) {
    let k = (area_3d / area_uv).sqrt();
    for p in uv.iter_mut() {
        *p = [p[0] * k, p[1] * k];
    }
    // σ of the uv → surface map scale by 1/k when the uv layout is scaled by k.
    let stretch = (weighted / area_3d / (k * k)).sqrt();
    (stretch, area_3d)
}
