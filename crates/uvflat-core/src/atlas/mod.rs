//! Atlas mode: split any manifold mesh (closed or not, any genus, any number of components)
//! into charts whose flattening keeps the L2 stretch under a caller-given bound, flatten each
//! chart with a chosen method, and pack the charts into the unit square (course notes §6.2:
//! "decompose the shape into a set of charts using a segmentation algorithm (e.g. VSA), then
//! parameterize each chart").
//!
//! **Top-down segmentation, driven by the flattening itself.** Every connected component starts
//! as one chart. A chart is made into a disk (the tree–cotree cut of `mesh::cut` if it is closed
//! or has handles), flattened, and accepted when the result is valid ([`chart`]: no flipped or
//! degenerate UV triangle, no crossing boundary edges, L2 stretch ≤ the bound); otherwise it is
//! split in two by a two-proxy VSA on normals ([`split`], Cohen-Steiner et al. 2004) and both
//! halves are tried again. This is the reverse of bottom-up chart growing (xatlas; Lévy et al.
//! 2002 §5's feature-driven growing; Sander et al. 2001's greedy merging of charts by
//! planarity): instead of guessing from normals how large a chart may grow, the stretch of the
//! actual flattening decides, so nearly developable regions (cylinders, cones) stay whole even
//! when their normals spread widely. Single triangles always flatten validly, so the recursion
//! ends. Charts are processed level by level, the charts of a level in parallel (rayon);
//! progress is reported (and cancellation checked) between levels.
//!
//! **Merging.** Splitting can cut more than needed (a VSA split is only a guess); afterwards,
//! adjacent charts are merged greedily, smallest union first, whenever the merged chart
//! flattens validly under the bound — Sander et al. 2001's chart merging with the validity test
//! as the merge criterion — within a work budget of a few solves of the whole mesh.
//!
//! **Packing**: minimum-area rectangles by skyline bottom-left ([`pack`]) and the charts'
//! rasterized shapes ([`raster_pack`]), the layout with the higher utilization kept; uniform
//! scale into the unit square, margin between charts; every chart keeps its 3D area ratio (uniform texel
//! density), so the whole atlas's L2 stretch is the area-weighted RMS of the charts' stretches.
//!
//! Output: per-corner UVs (atlas vertices: one per chart vertex, each pointing back to its input
//! vertex), the chart of every triangle, the stretch of every chart and the utilization (fraction
//! of the unit square covered by charts).

pub(crate) mod chart;
pub(crate) mod pack;
pub(crate) mod raster_pack;
pub mod repack;
pub(crate) mod split;

use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use crate::progress::Progress;
use chart::{exact_triangle_chart, flatten_chart, polished, ChartSettings, FlatChart, Refusal};
use rayon::prelude::*;
use split::{split_in_two, FaceData};

/// How each chart is flattened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChartMethod {
    /// Natural conformal map / LSCM (fast; may flip, then the chart is split).
    NaturalConformal,
    /// Mean value map with the boundary on a circle (never flips, more stretch).
    MeanValue,
    /// SLIM (symmetric Dirichlet) from the natural conformal map when it does not flip, else
    /// from the mean value map; never flips.
    Slim,
    /// Sander's L2 stretch minimized from the same start; never flips.
    Stretch,
}

/// Options of [`atlas`].
#[derive(Debug, Clone, PartialEq)]
pub struct AtlasOptions {
    /// Largest L2 stretch of a chart (≥ 1; `f64::INFINITY` splits only charts that flip or
    /// overlap themselves). The default, 1.004, is chosen by measurement
    /// (`benches/atlas_vs_xatlas.py`): on every closed and multi-hole mesh of `tests/data/meshes`
    /// it gives a lower L2 stretch than xatlas's default atlas with fewer charts, where 1.02 left
    /// two meshes a few thousandths above xatlas's stretch.
    pub max_stretch: f64,
    /// Gap between charts in the unit square (half of it to the square's sides), in [0, 0.5).
    pub margin: f64,
    /// How charts are flattened.
    pub method: ChartMethod,
    /// Iterations of the non-linear methods per chart.
    pub iterations: usize,
    /// Let the packer rotate charts (to their minimum-area rectangle, and by quarter turns).
    pub rotate: bool,
    /// Merge adjacent charts after splitting when the merged chart is still valid.
    pub merge: bool,
    /// Iterations of L2-stretch polishing per chart (0: none): a chart slightly over the bound
    /// is polished before it is judged, and every accepted chart is polished at the end.
    /// Polishing minimizes Sander's L2 stretch, so it lowers L2 and raises the angle error (a
    /// natural conformal chart is no longer conformal).
    pub polish: usize,
    /// Before a chart whose flattening flips or overlaps itself is split, lay it out by the
    /// bijective repair (`chart::repaired`: SLIM with a
    /// scaffold from the mean value map) and keep it whole when that is valid under the bound.
    pub repair: bool,
}

impl Default for AtlasOptions {
    fn default() -> Self {
        AtlasOptions {
            max_stretch: 1.004,
            margin: 0.005,
            method: ChartMethod::NaturalConformal,
            iterations: 20,
            rotate: true,
            merge: true,
            polish: 10,
            repair: false,
        }
    }
}

/// One chart of an atlas.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChartInfo {
    /// Triangles in the chart.
    pub triangles: usize,
    /// L2 stretch of the chart's flattening (before packing; packing scales all charts alike).
    pub stretch_l2: f64,
    /// 3D area of the chart.
    pub area: f64,
    /// Laid out by the bijective repair instead of the chosen method (see
    /// [`AtlasOptions::repair`]).
    pub repaired: bool,
}

/// A packed atlas.
#[derive(Debug, Clone)]
pub struct Atlas {
    /// UV of every atlas vertex, inside the unit square.
    pub uv: Vec<[f64; 2]>,
    /// Atlas vertex of each corner of each input triangle (per-corner UV indices).
    pub triangles: Vec<[u32; 3]>,
    /// Input vertex of every atlas vertex.
    pub original: Vec<u32>,
    /// Chart of every input triangle.
    pub chart_of_triangle: Vec<u32>,
    /// Every chart, in chart-id order.
    pub charts: Vec<ChartInfo>,
    /// Fraction of the unit square covered by charts.
    pub utilization: f64,
    /// L2 stretch of the whole atlas (area-weighted RMS of the charts' stretches).
    pub stretch_l2: f64,
}

impl AtlasOptions {
    fn chart_settings(&self) -> ChartSettings {
        ChartSettings {
            method: self.method,
            iterations: self.iterations,
            polish: self.polish,
            max_stretch: self.max_stretch,
            repair: self.repair,
        }
    }
}

impl Atlas {
    /// Per-corner UVs: 3 per input triangle.
    pub fn corner_uv(&self) -> Vec<[[f64; 2]; 3]> {
        self.triangles.iter().map(|t| t.map(|v| self.uv[v as usize])).collect()
    }
}

fn check_options(options: &AtlasOptions) -> Result<()> {
    if !(options.max_stretch >= 1.0) {
        return Err(Error::InvalidArgument(format!(
            "max_stretch must be ≥ 1 (1 = isometric; got {})",
            options.max_stretch
        )));
    }
    if !(options.margin >= 0.0 && options.margin < 0.5) {
        return Err(Error::InvalidArgument(format!("margin must be in [0, 0.5) (got {})", options.margin)));
    }
    Ok(())
}

/// Share of the unit square that the margins alone may take (each chart needs at least a
/// margin × margin square of gap). Beyond it the charts shrink towards nothing (utilizations of
/// 1e-6 and less were measured: 422 charts at margin 0.05) and the raster packing's padded
/// bitmaps grow without bound (margin 0.3 on the 1000-triangle knight ran for minutes).
const MAX_MARGIN_SHARE: f64 = 0.25;

/// Refuses a margin whose gaps alone would take more than [`MAX_MARGIN_SHARE`] of the square.
fn check_margin_fits(charts: usize, margin: f64) -> Result<()> {
    let share = charts as f64 * margin * margin;
    if share > MAX_MARGIN_SHARE {
        return Err(Error::InvalidArgument(format!(
            "margin {margin} is too large for {charts} charts: the gaps alone would take {:.0}% of the unit \
             square; use at most {:.4}",
            100.0 * share,
            (MAX_MARGIN_SHARE / charts as f64).sqrt()
        )));
    }
    Ok(())
}

/// Computes a packed atlas of any manifold mesh (see the module docs).
pub fn atlas(mesh: &TriMesh, options: &AtlasOptions) -> Result<Atlas> {
    atlas_with_progress(mesh, options, &mut Progress::none())
}

/// [`atlas`] with progress reporting and cancellation (between levels of the segmentation).
pub fn atlas_with_progress(mesh: &TriMesh, options: &AtlasOptions, progress: &mut Progress) -> Result<Atlas> {
    check_options(options)?;
    if mesh.triangle_count() == 0 {
        return Err(Error::InvalidArgument("the mesh has no triangles".into()));
    }
    progress.report(0.0)?;
    let mut charts = segment(mesh, options, progress)?;
    if options.merge && charts.len() > 1 {
        charts = merge_charts(mesh, charts, options)?;
    }
    progress.report(0.9)?;
    if options.polish > 0 {
        charts = charts.into_par_iter().map(|c| polished(mesh, c, options.polish)).collect::<Result<_>>()?;
    }
    progress.report(0.95)?;
    check_margin_fits(charts.len(), options.margin)?;
    let result = assemble(mesh, charts, options);
    progress.report(1.0)?;
    Ok(result)
}

/// Sorted triangle lists of the connected components.
fn components(mesh: &TriMesh) -> Vec<Vec<u32>> {
    let count = mesh.topology().components;
    let mut parts = vec![Vec::new(); count];
    for (t, &c) in mesh.triangle_components().iter().enumerate() {
        parts[c as usize].push(t as u32);
    }
    parts.retain(|p| !p.is_empty());
    parts
}

/// Top-down: flatten, accept or split, level by level.
fn segment(mesh: &TriMesh, options: &AtlasOptions, progress: &mut Progress) -> Result<Vec<FlatChart>> {
    // The splits' face normals and areas, computed at the first split (a mesh whose components
    // are accepted whole never needs them).
    let data = std::sync::OnceLock::new();
    let total = mesh.triangle_count() as f64;
    let mut pending = components(mesh);
    let mut accepted: Vec<FlatChart> = Vec::new();
    let mut done = 0usize;
    let mut settings = options.chart_settings();
    while !pending.is_empty() {
        let attempt = |faces: Vec<u32>| {
            let keep = faces.clone();
            match flatten_chart(mesh, faces, &settings)? {
                Ok(chart) => Ok(Ok(chart)),
                Err(_) if keep.len() >= 2 => {
                    Ok(Err(split_in_two(mesh, data.get_or_init(|| FaceData::new(mesh)), &keep)))
                }
                Err(refusal) => {
                    exact_triangle_chart(mesh, keep[0]).map(Ok).ok_or_else(|| single_triangle_failure(&keep, refusal))
                }
            }
        };
        // One chart (a whole component at the first level) is flattened on this thread: the
        // pool's hand-over would cost more than it gives (its solver runs in parallel anyway).
        let outcomes: Vec<Result<std::result::Result<FlatChart, (Vec<u32>, Vec<u32>)>>> = if pending.len() == 1 {
            pending.into_iter().map(attempt).collect()
        } else {
            pending.into_par_iter().map(attempt).collect()
        };
        pending = Vec::new();
        for outcome in outcomes {
            match outcome? {
                Ok(chart) => {
                    done += chart.faces.len();
                    accepted.push(chart);
                }
                Err((a, b)) => {
                    pending.push(a);
                    pending.push(b);
                }
            }
        }
        progress.report(0.8 * done as f64 / total)?;
        // The repair is for whole components; the halves of a split made for the stretch bound
        // are split further instead, so they keep the method's distortion. Without a bound,
        // only invalid maps are split, and the halves are repaired as well.
        settings.repair = options.repair && options.max_stretch == f64::INFINITY;
    }
    Ok(accepted)
}

fn single_triangle_failure(faces: &[u32], refusal: Refusal) -> Error {
    let why = match refusal {
        Refusal::Flipped => "it is flipped or degenerate in UV".to_string(),
        Refusal::Overlaps => "its boundary crosses itself in UV".to_string(),
        Refusal::Stretch(s) => {
            format!("its L2 stretch {s:.4} exceeds the bound (the method does not lay it out isometrically)")
        }
        Refusal::Failed => "the method failed on it".to_string(),
    };
    Error::Numerical(format!(
        "triangle {} cannot be flattened validly on its own: {why}",
        faces.first().copied().unwrap_or(0)
    ))
}

/// Faces flattened while merging, as a multiple of the mesh's faces: a deterministic work
/// budget that bounds merging to a few solves of the whole mesh.
const MERGE_BUDGET: usize = 4;

/// Greedy merging of adjacent charts (see the module docs), in rounds: each round takes the
/// adjacent pairs from the smallest union up (cheap merges of small fragments first; ties by
/// longer shared boundary), keeps a matching (no chart in two pairs), flattens the merged charts
/// in parallel and keeps the valid ones. A pair is tried again only after one of its charts has
/// grown. Merging stops when no pair is left or the work budget (`MERGE_BUDGET` × the mesh's
/// triangles flattened) is spent.
fn merge_charts(mesh: &TriMesh, charts: Vec<FlatChart>, options: &AtlasOptions) -> Result<Vec<FlatChart>> {
    let mut charts: Vec<Option<FlatChart>> = charts.into_iter().map(Some).collect();
    let mut version = vec![0u32; charts.len()];
    let mut owner = vec![0u32; mesh.triangle_count()];
    for (c, chart) in charts.iter().enumerate() {
        for &f in chart.iter().flat_map(|c| &c.faces) {
            owner[f as usize] = c as u32;
        }
    }
    let size = |charts: &[Option<FlatChart>], c: u32| charts[c as usize].as_ref().map_or(0, |c| c.faces.len());
    let mut budget = MERGE_BUDGET * mesh.triangle_count();
    let mut tried = std::collections::HashSet::new();
    // A merged chart must be valid as the method lays it out: repairing every candidate would
    // cost a bijective solve per merge.
    let settings = ChartSettings { repair: false, ..options.chart_settings() };
    while budget > 0 {
        let mut pairs = shared_boundaries(mesh, &owner);
        pairs.sort_by(|x, y| {
            let (sx, sy) =
                (size(&charts, x.0 .0) + size(&charts, x.0 .1), size(&charts, y.0 .0) + size(&charts, y.0 .1));
            sx.cmp(&sy).then(y.1.total_cmp(&x.1)).then(x.0.cmp(&y.0))
        });
        let mut used = vec![false; charts.len()];
        let mut candidates = Vec::new();
        for ((a, b), _) in pairs {
            let key = (a, version[a as usize], b, version[b as usize]);
            let cost = size(&charts, a) + size(&charts, b);
            if used[a as usize] || used[b as usize] || tried.contains(&key) || cost > budget {
                continue;
            }
            budget -= cost;
            tried.insert(key);
            used[a as usize] = true;
            used[b as usize] = true;
            candidates.push((a, b));
        }
        if candidates.is_empty() {
            break;
        }
        let merged: Vec<Result<Option<FlatChart>>> = candidates
            .par_iter()
            .map(|&(a, b)| {
                let (Some(ca), Some(cb)) = (&charts[a as usize], &charts[b as usize]) else { return Ok(None) };
                let mut faces: Vec<u32> = ca.faces.iter().chain(&cb.faces).copied().collect();
                faces.sort_unstable();
                Ok(flatten_chart(mesh, faces, &settings)?.ok())
            })
            .collect();
        for (&(a, b), chart) in candidates.iter().zip(merged) {
            let Some(chart) = chart? else { continue };
            for &f in &chart.faces {
                owner[f as usize] = a;
            }
            charts[a as usize] = Some(chart);
            charts[b as usize] = None;
            version[a as usize] += 1;
        }
    }
    Ok(charts.into_iter().flatten().collect())
}

/// Adjacent chart pairs `(a, b)`, `a < b`, with the 3D length of their shared boundary, longest
/// first.
fn shared_boundaries(mesh: &TriMesh, owner: &[u32]) -> Vec<((u32, u32), f64)> {
    let twin = &mesh.connectivity().twin;
    let mut length: std::collections::HashMap<(u32, u32), f64> = std::collections::HashMap::new();
    for h in 0..twin.len() as u32 {
        let g = twin[h as usize];
        if g == crate::mesh::NONE || g < h {
            continue;
        }
        let (a, b) = (owner[(h / 3) as usize], owner[(g / 3) as usize]);
        if a != b {
            let l =
                crate::geometry::distance(mesh.points()[mesh.tail(h) as usize], mesh.points()[mesh.head(h) as usize]);
            *length.entry((a.min(b), a.max(b))).or_default() += l;
        }
    }
    let mut pairs: Vec<((u32, u32), f64)> = length.into_iter().collect();
    pairs.sort_by(|x, y| y.1.total_cmp(&x.1).then(x.0.cmp(&y.0)));
    pairs
}

/// Packs the charts (flattened, at one texel density) into the unit square ([`pack_layouts`]).
fn pack_best(
    layouts: &mut [Vec<[f64; 2]>],
    charts: &[FlatChart],
    areas: &[f64],
    options: &AtlasOptions,
) -> pack::Packing {
    let triangles: Vec<&[[u32; 3]]> = charts.iter().map(|c| c.corners.as_slice()).collect();
    pack_layouts(layouts, &triangles, areas, options.margin, options.rotate)
}

/// Packs charts (UV points modified in place, their triangles, their UV areas) by the skyline
/// of their rectangles ([`pack::pack`]) and by their rasterized shapes
/// ([`raster_pack::pack_raster`]) and keeps the layout with the higher utilization (the raster
/// one wins on most meshes with several charts; the rectangles can win for one or two nearly
/// rectangular charts, which the raster's pixels pad more).
pub(crate) fn pack_layouts(
    layouts: &mut [Vec<[f64; 2]>],
    triangles: &[&[[u32; 3]]],
    areas: &[f64],
    margin: f64,
    rotate: bool,
) -> pack::Packing {
    if layouts.len() == 1 {
        // One chart: placed in its minimum-area rectangle (the raster packing of one chart
        // rasterizes every triangle to place one shape; see docs/benchmarks.md for utilizations).
        return pack::pack(layouts, areas, margin, rotate);
    }
    let mut raster = layouts.to_vec();
    let shaped = raster_pack::pack_raster(&mut raster, triangles, areas, margin, rotate);
    let skyline = pack::pack(layouts, areas, margin, rotate);
    match shaped {
        Some(p) if p.utilization > skyline.utilization => {
            layouts.clone_from_slice(&raster);
            p
        }
        _ => skyline,
    }
}

/// Packs the charts and numbers the atlas vertices.
fn assemble(mesh: &TriMesh, mut charts: Vec<FlatChart>, options: &AtlasOptions) -> Atlas {
    // Deterministic chart order: by first triangle.
    charts.sort_by_key(|c| c.faces[0]);
    let mut layouts: Vec<Vec<[f64; 2]>> = charts.iter().map(|c| c.uv.clone()).collect();
    let areas: Vec<f64> = charts.iter().map(|c| c.area).collect();
    let packing = pack_best(&mut layouts, &charts, &areas, options);
    let mut uv = Vec::new();
    let mut original = Vec::new();
    let mut triangles = vec![[0u32; 3]; mesh.triangle_count()];
    let mut chart_of_triangle = vec![0u32; mesh.triangle_count()];
    let mut infos = Vec::with_capacity(charts.len());
    let (mut weighted, mut area) = (0.0, 0.0);
    for (c, (chart, layout)) in charts.iter().zip(layouts).enumerate() {
        let offset = uv.len() as u32;
        uv.extend(layout);
        original.extend(&chart.original);
        for (&f, corners) in chart.faces.iter().zip(&chart.corners) {
            triangles[f as usize] = corners.map(|v| v + offset);
            chart_of_triangle[f as usize] = c as u32;
        }
        infos.push(ChartInfo {
            triangles: chart.faces.len(),
            stretch_l2: chart.stretch_l2,
            area: chart.area,
            repaired: chart.repaired,
        });
        weighted += chart.area * chart.stretch_l2 * chart.stretch_l2;
        area += chart.area;
    }
    Atlas {
        uv,
        triangles,
        original,
        chart_of_triangle,
        charts: infos,
        utilization: packing.utilization,
        stretch_l2: (weighted / area).sqrt(),
    }
}
