//! QuadCover: a global, seamless parameterization guided by a frame field (Kälberer, Nieser &
//! Polthier 2007, "QuadCover — surface parameterization using branched coverings", Computer
//! Graphics Forum 26(3); course notes ch. 8). One file per step:
//!
//! - [`matching`]: frames per triangle, matchings, layer shifts, combing (§8.2.1–8.2.3);
//! - [`covering`]: the branched covering cut open into the cut mesh, transition functions
//!   `J^r z + t` across the cut, cones as integer points (§8.2.1 eq. 8.2, §8.3.1);
//! - [`integration`]: eq. 8.6 minimized (the Hodge projection, eq. 8.7), gaps rounded, solved
//!   again (§8.3.1);
//! - [`guards`]: triangles the integer unknowns alone would flatten or fold, consulted by the
//!   rounding (not in the notes);
//! - [`untangle`]: folds left by the rounding untangled with every lattice unknown kept
//!   (Garanzha et al. 2021's untangling energy; not in the notes);
//! - [`remesh`]: the quad-dominant mesh of the integer iso-lines (§8.1: "the integer grid
//!   lines ... form a quadrilateral mesh").
//!
//! Pipeline of [`quadcover`]: frame field (the caller's per triangle, or the principal
//! curvature directions smoothed modulo π/2 by [`crate::fields::smoothing`]) →
//! matchings → cones (vertices of non-zero cross-field index) → cut graph through the cones
//! ([`crate::mesh::cut::cut_to_disk_through`]) → combing → covering → continuous solve → gaps
//! and cone positions rounded (guarded against two cones on one grid point) → final solve,
//! stiffening → untangling → per-corner (u, v).
//!
//! What the result guarantees, and tests check: across every interior edge the (u, v) of the
//! two triangles differ by a grid automorphism `J^r z + t` with t integer (so the iso-lines of
//! integer u and v close up over the whole surface), and every cone sits at an integer point.
//! What it does not: the map may fold near cones after rounding (the notes' algorithm
//! rounds all gaps at once); the untangling opens most of those folds that the fixed lattice
//! allows, and the count left is reported.

pub mod cone_pairs;
pub(crate) mod covering;
pub mod field;
pub(crate) mod guards;
pub(crate) mod integration;
pub(crate) mod matching;
pub mod remesh;
pub(crate) mod untangle;

use crate::error::{Error, Result};
use crate::fields::curvature::{principal_curvatures, CurvatureOptions};
use crate::fields::frames::{normalized, tangent_part, triangle_normal};
use crate::fields::indices::face_field_indices;
use crate::fields::smoothing::mean_edge_length;
use crate::mesh::cut::{cut_to_disk_through, EdgeCost};
use crate::metrics::signed_uv_area;
use crate::progress::Progress;
use crate::TriMesh;
use std::collections::HashSet;

/// Default grid spacing in mean edge lengths. Rounding puts every cone on a grid point, so
/// cones closer than a cell or two fold the map between them; measured on the test meshes
/// (README), 3 edges per cell keeps the folds to a few percent of the triangles where 10 (PGP's
/// period) folds up to a quarter of them.
pub const DEFAULT_EDGES_PER_CELL: f64 = 3.0;

/// Options of [`quadcover`].
#[derive(Debug, Clone, PartialEq)]
pub struct QuadCoverOptions {
    /// Surface length of one grid cell (one unit of u or v). `None`: [`DEFAULT_EDGES_PER_CELL`]
    /// mean edge lengths.
    pub grid_spacing: Option<f64>,
    /// The frame field: one tangent vector per triangle (projected on the triangle's plane,
    /// must not vanish). `None`: principal curvature directions, smoothed.
    pub field: Option<Vec<[f64; 3]>>,
    /// Curvature estimation of the default field.
    pub curvature: CurvatureOptions,
    /// Alignment α of the default field to the curvature directions ([`field`]; larger: more
    /// aligned, more cones).
    pub alignment: f64,
    /// Round the gaps (and with `cones_on_grid` the cone positions) to integers (§8.3.1).
    /// `false` returns the first, continuous solve (seamless up to rotation only).
    pub round: bool,
    /// Also require every cone to sit on an integer point (as mixed-integer quadrangulation
    /// does, so that cones become irregular vertices of a quad mesh). `false` (the course
    /// notes' QuadCover): only the gaps are integers; a cone may sit at a half-integer point.
    pub cones_on_grid: bool,
    /// Cone-pair cancellation distance in grid cells ([`cone_pairs`]): ± cone pairs of the
    /// field closer than this are cancelled and cones closer than this to the boundary moved
    /// onto it. 0 keeps the field's cones as they are.
    pub pair_cells: f64,
    /// Untangle the folds left after rounding ([`untangle`]): regular vertices near folds move,
    /// every seam, gap and cone stays. Only with `round`.
    pub untangle: bool,
}

impl Default for QuadCoverOptions {
    fn default() -> Self {
        QuadCoverOptions {
            grid_spacing: None,
            field: None,
            curvature: CurvatureOptions::default(),
            alignment: field::DEFAULT_ALIGNMENT,
            round: true,
            cones_on_grid: false,
            pair_cells: cone_pairs::DEFAULT_PAIR_CELLS,
            untangle: true,
        }
    }
}

/// Result of [`quadcover`].
#[derive(Debug, Clone)]
pub struct QuadCoverResult {
    /// (u, v) of every triangle corner, in grid units.
    pub uv: Vec<[[f64; 2]; 3]>,
    /// Quarter turns r of every corner: its (u, v) is `J^r x + t` (J(u, v) = (v, −u), t a
    /// translation) where x is the (u, v) of a corner of the same vertex with r = 0.
    pub corner_rotation: Vec<[u8; 3]>,
    /// Cone vertices and their cross-field indices (multiples of 1/4).
    pub cones: Vec<(u32, f64)>,
    /// Edges of the cut graph (`[a, b]`, a < b).
    pub cut_edges: Vec<[u32; 2]>,
    /// Number of chains (cutting paths, each with one gap).
    pub chains: usize,
    /// The grid spacing used.
    pub grid_spacing: f64,
    /// The frame field used (combed), one unit tangent per triangle.
    pub frames: Vec<[f64; 3]>,
    /// Triangles whose (u, v) image has non-positive signed area.
    pub flipped: usize,
    /// Largest distance of a free gap or cone coordinate to its integer before rounding.
    pub rounding_offset: f64,
    /// Largest distance of any gap (and, with `cones_on_grid`, cone coordinate) to an integer
    /// in the result (0 up to round-off when rounding is on, unless `fractional_pivots` > 0).
    pub lattice_error: f64,
    /// Constraint pivots that were not ±1 (see [`covering`]).
    pub fractional_pivots: usize,
    /// Eq. 8.6 relative to the field's energy, after the continuous and the final solve.
    pub energy_continuous: f64,
    pub energy: f64,
    /// What the cone-pair cancellation did.
    pub cone_pairs: cone_pairs::ConePairReport,
    /// What the untangling did (all zero when it did not run).
    pub untangled: untangle::UntangleReport,
}

/// Runs QuadCover (module comment). Errors: bad options or field (naming the triangle),
/// several components, numerical failures, cancellation.
pub fn quadcover(mesh: &TriMesh, options: &QuadCoverOptions, progress: &mut Progress) -> Result<QuadCoverResult> {
    let spacing = match options.grid_spacing {
        None => DEFAULT_EDGES_PER_CELL * mean_edge_length(mesh),
        Some(h) if h.is_finite() && h > 0.0 => h,
        Some(h) => return Err(Error::InvalidArgument(format!("grid_spacing must be finite and > 0 (got {h})"))),
    };
    if mesh.topology().components != 1 {
        return Err(Error::MultipleComponents { components: mesh.topology().components });
    }
    if !(options.pair_cells.is_finite() && options.pair_cells >= 0.0) {
        return Err(Error::InvalidArgument(format!("pair_cells must be finite and >= 0 (got {})", options.pair_cells)));
    }
    progress.report(0.0)?;
    let field = frame_field(mesh, options, spacing, progress)?;
    progress.report(0.3)?;
    let (directions, pair_report) = cone_pairs::cancel_cone_pairs(mesh, &field, options.pair_cells * spacing, spacing)?;
    progress.report(0.4)?;
    let indices = face_field_indices(mesh, &directions, 4);
    let cone_list: Vec<u32> = (0..mesh.vertex_count() as u32).filter(|&v| indices[v as usize].abs() > 0.125).collect();
    let cut = cut_to_disk_through(mesh, &EdgeCost::CurvatureWeightedLength, &cone_list)?;
    let is_cut = cut_halfedges(mesh, &cut.edges);
    let raw = matching::matchings(mesh, &directions);
    let (frames, combed) = matching::comb(mesh, &directions, &raw, &is_cut)?;
    let cover = covering::build_covering(mesh, &cut, &combed, &cone_list, options.cones_on_grid)?;
    progress.report(0.5)?;
    let scale = 1.0 / spacing;
    let (continuous, mut values, rounding_offset) =
        integration::integrate(mesh, &cut, &frames, scale, &cover, options.round, progress, (0.5, 0.9))?;
    let untangled = if options.round && options.untangle {
        untangle::untangle(mesh, &cut, scale, &cover, &mut values)?
    } else {
        untangle::UntangleReport::default()
    };
    let energy_continuous =
        integration::relative_energy(mesh, &frames, scale, &integration::corner_uv(&cut, &cover, &continuous));
    progress.report(0.95)?;
    let uv = integration::corner_uv(&cut, &cover, &values);
    let lattice_error = values[cover.vertex_unknowns..]
        .iter()
        .zip(&cover.integer)
        .filter(|(_, &integer)| integer)
        .map(|(x, _)| (x - x.round()).abs())
        .fold(0.0, f64::max);
    let flipped = uv.iter().filter(|q| signed_uv_area(**q) <= 0.0).count();
    let energy = integration::relative_energy(mesh, &frames, scale, &uv);
    progress.report(1.0)?;
    Ok(QuadCoverResult {
        cones: cover.cones.iter().map(|&v| (v, indices[v as usize])).collect(),
        cut_edges: cut.edges.clone(),
        chains: cover.chain_count,
        grid_spacing: spacing,
        frames,
        flipped,
        rounding_offset,
        lattice_error,
        fractional_pivots: cover.fractional_pivots,
        energy_continuous,
        energy,
        cone_pairs: pair_report,
        untangled,
        uv,
        corner_rotation: cut.triangles.iter().map(|tri| tri.map(|c| cover.copy_rotation[c as usize])).collect(),
    })
}

/// The frame field per triangle: the caller's (checked, projected, normalized) or the smoothed
/// principal directions.
fn frame_field(
    mesh: &TriMesh,
    options: &QuadCoverOptions,
    spacing: f64,
    progress: &mut Progress,
) -> Result<Vec<[f64; 3]>> {
    if let Some(field) = &options.field {
        if field.len() != mesh.triangle_count() {
            return Err(Error::InvalidArgument(format!(
                "the frame field has {} vectors but the mesh has {} triangles",
                field.len(),
                mesh.triangle_count()
            )));
        }
        return field
            .iter()
            .enumerate()
            .map(|(t, &x)| {
                let d = tangent_part(x, triangle_normal(mesh, t));
                let len = crate::geometry::norm(d);
                if !(len.is_finite() && len > 1e-300) {
                    return Err(Error::InvalidArgument(format!(
                        "the frame field vector of triangle {t} is not finite or has no component in its plane"
                    )));
                }
                Ok(normalized(d))
            })
            .collect();
    }
    let curvatures = principal_curvatures(mesh, &options.curvature)?;
    progress.report(0.2)?;
    field::curvature_cross_field(mesh, &curvatures, spacing, options.alignment)
}

/// Marks both half-edges of every cut edge.
fn cut_halfedges(mesh: &TriMesh, edges: &[[u32; 2]]) -> Vec<bool> {
    let set: HashSet<[u32; 2]> = edges.iter().copied().collect();
    (0..3 * mesh.triangle_count() as u32)
        .map(|h| {
            let (a, b) = (mesh.tail(h), mesh.head(h));
            set.contains(&[a.min(b), a.max(b)])
        })
        .collect()
}
pub use remesh::quad_mesh;
