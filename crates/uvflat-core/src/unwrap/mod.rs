//! The whole unwrap in one call: any manifold mesh in (disk, holes, closed, any genus, several
//! components), UVs out that are valid by construction and checked after the fact: no flipped
//! triangle, no overlap within or between islands, every coordinate finite, and — unless the
//! caller turns the bound off — every island's L2 stretch at most `max_stretch`.
//!
//! The stages, in order:
//! 1. **Islands.** Every connected component starts as one island; a closed one, or one with
//!    handles, is cut into a disk by the tree–cotree cut (`mesh::cut`), so a single island
//!    covers it when it can.
//! 2. **Flatten** each island with the chosen method (default: the natural conformal map,
//!    the least angle distortion of the linear methods).
//! 3. **Repair or split**: an island whose flattening flips a triangle or overlaps its own
//!    boundary is laid out again by bijective SLIM (a scaffold around the boundary,
//!    `methods::nonlinear::scaffold`, from the mean value map), which cannot flip or overlap.
//!    An island over the stretch bound (the method's valid map, or the repaired one) is split
//!    in two (a two-proxy VSA on normals, `atlas::split`) and both halves go back to 2, so the
//!    pieces keep the method's distortion. Single triangles are laid out isometrically, so
//!    splitting ends.
//! 4. **Merge** adjacent islands back while the merged island is valid as the method lays it
//!    out (fewer seams; Sander et al. 2001's greedy merging).
//! 5. **Pack** the islands into the unit square at one texel density (`atlas::pack`,
//!    `atlas::raster_pack`), a margin apart.
//! 6. **Verify** the packed layout with the independent checker (`verify`: exact predicates,
//!    nothing of the method's bookkeeping); a layout that fails is an error, never a result.
//!
//! Zero-area triangles (vertices snapped together but not merged), which `TriMesh` refuses, are
//! handled by [`unwrap_arrays`]: snapped vertices welded, zero-area triangles left out of the
//! solve ([`snapped`]).
//!
//! With the stretch bound off (`max_stretch = ∞`) no island is split for stretch: every
//! component stays one island unless it cannot be made valid at all (what an artist's seams ask
//! for: the input's own seam-bounded regions stay whole).
//!
//! Stages 1–5 are the atlas's (`atlas`), run with the repair on and without the L2 polish (the
//! default keeps the method's angles: no island is silently traded from conformal to
//! stretch-minimizing, except the repaired ones, which the report counts).

mod snapped;

pub use snapped::unwrap_arrays;

use crate::atlas::{atlas_with_progress, Atlas, AtlasOptions, ChartMethod};
use crate::error::{Error, Result};
use crate::mesh::{TriMesh, NONE};
use crate::progress::Progress;
use crate::verify::check_layout;

/// Options of [`unwrap`].
#[derive(Debug, Clone, PartialEq)]
pub struct UnwrapOptions {
    /// Largest L2 stretch (Sander et al. 2001) of an island, ≥ 1; `f64::INFINITY` turns the
    /// bound off (islands are then split only where no valid layout is found). Default 1.5.
    pub max_stretch: f64,
    /// Gap between islands in the unit square, in [0, 0.5). Default 0.005.
    pub margin: f64,
    /// How islands are flattened before verification. Default: natural conformal.
    pub method: ChartMethod,
    /// Iteration limit of the non-linear solves (the repair's SLIM included). Default 100.
    pub iterations: usize,
    /// Let the packer rotate islands. Default true.
    pub rotate: bool,
}

impl Default for UnwrapOptions {
    fn default() -> Self {
        UnwrapOptions {
            max_stretch: 1.5,
            margin: 0.005,
            method: ChartMethod::NaturalConformal,
            iterations: 100,
            rotate: true,
        }
    }
}

/// What [`unwrap`] did and what its result is, measured on the result.
#[derive(Debug, Clone, PartialEq)]
pub struct UnwrapReport {
    /// Islands (charts) of the layout.
    pub islands: usize,
    /// Islands the method's own flattening could not give validly, laid out by bijective SLIM.
    pub repaired_islands: usize,
    /// Input edges cut (the two sides have different UV vertices).
    pub seam_edges: usize,
    /// Flipped or degenerate UV triangles, by the independent checker (always 0).
    pub flipped: usize,
    /// Overlapping boundary-edge pairs and nested islands, by the independent checker (always 0).
    pub overlaps: usize,
    /// L2 stretch of the whole layout (area-weighted RMS over islands at one texel density).
    pub stretch_l2: f64,
    /// Largest L2 stretch of one island.
    pub max_island_stretch: f64,
    /// Mean angle distortion |UV angle − surface angle| over corners, in degrees.
    pub angle_error_mean_deg: f64,
    /// Fraction of the unit square covered by islands.
    pub utilization: f64,
    /// Input vertices welded onto another for the solve (snapped together but not merged;
    /// [`unwrap_arrays`] only).
    pub welded_vertices: usize,
    /// Zero-area input triangles left out of the solve and the verification ([`unwrap_arrays`]
    /// only).
    pub left_out_triangles: usize,
}

/// The result of [`unwrap`].
#[derive(Debug, Clone)]
pub struct Unwrapped {
    /// The packed layout: per-corner UVs (`atlas.triangles`), the island of every triangle
    /// (`atlas.chart_of_triangle`), the input vertex of every UV vertex (`atlas.original`).
    pub atlas: Atlas,
    /// Cut input edges as vertex pairs `[a, b]`, `a < b`, sorted.
    pub seams: Vec<[u32; 2]>,
    /// Figures of the result.
    pub report: UnwrapReport,
}

fn check_options(options: &UnwrapOptions) -> Result<()> {
    if !(options.max_stretch >= 1.0) {
        return Err(Error::InvalidArgument(format!(
            "max_stretch must be ≥ 1 (1 = isometric, infinity = no bound; got {})",
            options.max_stretch
        )));
    }
    if options.iterations == 0 {
        return Err(Error::InvalidArgument("iterations must be at least 1".into()));
    }
    Ok(())
}

/// Unwraps `mesh` (see the module docs).
pub fn unwrap(mesh: &TriMesh, options: &UnwrapOptions) -> Result<Unwrapped> {
    unwrap_with_progress(mesh, options, &mut Progress::none())
}

/// [`unwrap`] with progress reporting and cancellation.
pub fn unwrap_with_progress(mesh: &TriMesh, options: &UnwrapOptions, progress: &mut Progress) -> Result<Unwrapped> {
    check_options(options)?;
    let atlas_options = AtlasOptions {
        max_stretch: options.max_stretch,
        margin: options.margin,
        method: options.method,
        iterations: options.iterations,
        rotate: options.rotate,
        merge: true,
        polish: 0,
        repair: true,
    };
    let atlas = atlas_with_progress(mesh, &atlas_options, progress)?;
    // The verification and the report's figures read the layout side by side.
    let (validity, (seams, angle_error)) = crate::parallel::join(
        atlas.triangles.len(),
        || check_layout(&atlas.uv, &atlas.triangles),
        || (seam_edges(mesh, &atlas), mean_angle_error(mesh, &atlas)),
    );
    if !validity.is_valid() {
        return Err(Error::Internal(format!(
            "the unwrap's layout failed verification ({} flipped triangles, {} overlaps); please report this mesh",
            validity.flipped, validity.overlaps
        )));
    }
    let report = UnwrapReport {
        islands: atlas.charts.len(),
        repaired_islands: atlas.charts.iter().filter(|c| c.repaired).count(),
        seam_edges: seams.len(),
        flipped: validity.flipped,
        overlaps: validity.overlaps,
        stretch_l2: atlas.stretch_l2,
        max_island_stretch: atlas.charts.iter().map(|c| c.stretch_l2).fold(0.0, f64::max),
        angle_error_mean_deg: angle_error.to_degrees(),
        utilization: atlas.utilization,
        welded_vertices: 0,
        left_out_triangles: 0,
    };
    Ok(Unwrapped { atlas, seams, report })
}

/// Mean |UV corner angle − surface corner angle| over every corner, in radians (the layout is
/// verified, so every UV triangle is proper; `metrics::distortion` gives the same mean then,
/// up to triangles thinner than its degeneracy tolerance, which it leaves out).
fn mean_angle_error(mesh: &TriMesh, atlas: &Atlas) -> f64 {
    let surface = mesh.corner_angles();
    let errors = crate::parallel::map_range(atlas.triangles.len(), |t| {
        let q = atlas.triangles[t].map(|v| atlas.uv[v as usize]);
        let angle = |k: usize| {
            let (a, b) = (q[(k + 1) % 3], q[(k + 2) % 3]);
            let (e1, e2) = ([a[0] - q[k][0], a[1] - q[k][1]], [b[0] - q[k][0], b[1] - q[k][1]]);
            (e1[0] * e2[1] - e1[1] * e2[0]).abs().atan2(e1[0] * e2[0] + e1[1] * e2[1])
        };
        // Both triangles' angles sum to π, so the third follows from the first two.
        let (a0, a1) = (angle(0), angle(1));
        let a2 = std::f64::consts::PI - a0 - a1;
        let s = surface[t];
        (a0 - s[0]).abs() + (a1 - s[1]).abs() + (a2 - s[2]).abs()
    });
    errors.iter().sum::<f64>() / (3 * errors.len().max(1)) as f64
}

/// Input edges whose two triangles give an endpoint different UV vertices.
fn seam_edges(mesh: &TriMesh, atlas: &Atlas) -> Vec<[u32; 2]> {
    let twin = &mesh.connectivity().twin;
    let corner = |h: usize| atlas.triangles[h / 3][h % 3];
    let next = |h: usize| 3 * (h / 3) + (h + 1) % 3;
    let mut seams: Vec<[u32; 2]> = (0..twin.len())
        .filter(|&h| twin[h] != NONE && twin[h] as usize > h)
        .filter(|&h| {
            let g = twin[h] as usize;
            corner(h) != corner(next(g)) || corner(next(h)) != corner(g)
        })
        .map(|h| {
            let (a, b) = (mesh.tail(h as u32), mesh.head(h as u32));
            [a.min(b), a.max(b)]
        })
        .collect();
    seams.sort_unstable();
    seams
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize, height: impl Fn(f64, f64) -> f64) -> TriMesh {
        let mut p = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
                p.extend([x, y, height(x, y)]);
            }
        }
        let mut t = Vec::new();
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                t.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        TriMesh::new(&p, &t).unwrap()
    }

    #[test]
    fn a_flat_square_is_one_island_without_seams() {
        let result = unwrap(&grid(6, |_, _| 0.0), &UnwrapOptions::default()).unwrap();
        assert_eq!(result.report.islands, 1);
        assert!(result.seams.is_empty());
        assert_eq!((result.report.flipped, result.report.overlaps), (0, 0));
        assert!((result.report.stretch_l2 - 1.0).abs() < 1e-9, "{:?}", result.report);
    }

    #[test]
    fn a_tall_bump_is_split_under_the_bound_and_whole_without_it() {
        let bump = grid(16, |x, y| 4.0 * (-30.0 * ((x - 0.5).powi(2) + (y - 0.5).powi(2))).exp());
        let bounded = unwrap(&bump, &UnwrapOptions { max_stretch: 1.05, ..UnwrapOptions::default() }).unwrap();
        assert!(bounded.report.islands > 1, "{:?}", bounded.report);
        assert!(bounded.report.max_island_stretch <= 1.05 * (1.0 + 1e-9));
        assert!(!bounded.seams.is_empty());
        let free = unwrap(&bump, &UnwrapOptions { max_stretch: f64::INFINITY, ..UnwrapOptions::default() }).unwrap();
        assert_eq!(free.report.islands, 1);
    }

    #[test]
    fn bad_options_are_refused() {
        let mesh = grid(2, |_, _| 0.0);
        for options in [
            UnwrapOptions { max_stretch: 0.5, ..UnwrapOptions::default() },
            UnwrapOptions { max_stretch: f64::NAN, ..UnwrapOptions::default() },
            UnwrapOptions { iterations: 0, ..UnwrapOptions::default() },
            UnwrapOptions { margin: 0.7, ..UnwrapOptions::default() },
        ] {
            assert!(matches!(unwrap(&mesh, &options), Err(Error::InvalidArgument(_))), "{options:?}");
        }
    }
}
