//! Circle patterns with cone singularities (Kharevych, Springborn & Schröder 2006, §5 "cone
//! singularities"; course notes 2008 §4.4 and ch. 6: "they use cone-singularities to ..."):
//! a conformal map of a surface of any genus, with or without boundary, to a flat metric with
//! cones at chosen interior vertices, laid out in the plane after cutting through the cones.
//!
//! 1. The cone vertices (curvature κ_v = 2π − cone angle) are joined by a cut graph (through
//!    every cone, plus the handle loops of a closed or higher-genus mesh:
//!    [`crate::mesh::cut::cut_to_disk_through`]).
//! 2. The mesh is flipped to its intrinsic Delaunay triangulation keeping the cut edges, so
//!    that the cut is a graph of both triangulations, and keeping the triangles around every
//!    cone, so that the input's corners at a cone are the pattern's and sum exactly to its
//!    angle. (Without that, a cone of large angle at a vertex of low degree — the coarse
//!    knight's automatic cone of 468° at a vertex of 4 triangles — had its star re-triangulated,
//!    and the input's straight triangle across a flipped-away spoke, spanning more than π in
//!    the pattern, was drawn the short way round: one flipped triangle, a cone 2π short.)
//! 3. The angle program prescribes the angle sum 2π − κ_v at each cone (2π at the other
//!    interior vertices, and the boundary as in the disk map); on a closed mesh every vertex is
//!    prescribed and the values must satisfy Gauss–Bonnet, Σ κ = 2π χ. The radii follow as for
//!    the disk map: the pattern is a flat metric with cones, every circle closed.
//! 4. The flipped triangulation is opened along the cut, a disk whose interior vertices are
//!    flat (every cone is on its boundary), and its pattern laid out exactly; each copy of a cut
//!    vertex gets its own uv. A corner of the input mesh takes the uv of the copy on its side
//!    of the cut: both triangulations open into the same wedges (a copy is identified by its
//!    vertex and the far end of the boundary edge leaving it).
//!
//! Across a seam the two sides are congruent (same edge lengths, a rigid motion apart), the
//! seamless-up-to-rotation structure of a cone metric; the rotation is a multiple of the cone
//! angles, not of π/2 (that would be QuadCover's integer constraint).

use super::{angle_sums, check_tolerance, flipped_triangles_of_corners, solve_pattern, Triangulation};
use super::{CirclePatternOptions, CirclePatternReport};
use crate::error::{Error, Result};
use crate::mesh::cut::{cut_along, cut_to_disk_through, Cut, EdgeCost};
use crate::mesh::{TriMesh, NONE};
use crate::methods::angle_layout::reconstruct_uv;
use crate::methods::conformal::resolve_pins;
use crate::progress::Progress;
use std::collections::HashMap;

/// A cone map: one uv per triangle corner, the seams it is cut along, and the pattern's report.
#[derive(Debug, Clone)]
pub struct ConeMapResult {
    /// uv of corner k of triangle t at `[t][k]`.
    pub corner_uv: Vec<[[f64; 2]; 3]>,
    /// The interior edges the map is cut along (`[a, b]`, a < b): through every cone, and the
    /// handle loops of a closed or higher-genus mesh.
    pub seams: Vec<[u32; 2]>,
    pub report: CirclePatternReport,
}

/// The circle-pattern map of a connected mesh of any genus, with or without boundary, with
/// cones: `cones` lists interior vertices and their curvature κ (2π minus the cone angle; π/2
/// for the corner of a cube, −π/2 for a 450° saddle). The other interior vertices are flat. On a
/// closed mesh Σ κ must be 2π χ (4π on a sphere). `options.pins` must be `None` (the map is
/// placed by the two farthest boundary vertices of the opened mesh).
pub fn circle_pattern_cone_map(
    mesh: &TriMesh,
    cones: &[(u32, f64)],
    options: &CirclePatternOptions,
    progress: &mut Progress,
) -> Result<ConeMapResult> {
    check_tolerance(options)?;
    if options.pins.is_some() {
        return Err(Error::InvalidArgument(
            "a cone map places itself by the two farthest boundary vertices of the opened mesh; pins are not supported"
                .into(),
        ));
    }
    // The same checks on the input mesh first, before any work.
    angle_sums::vertex_sums(mesh, options.boundary_curvature.as_deref(), cones)?;
    let cone_vertices: Vec<u32> = cones.iter().filter(|c| c.1 != 0.0).map(|c| c.0).collect();
    let cut = cut_to_disk_through(mesh, &EdgeCost::default(), &cone_vertices)?;
    let mut fixed = cut.edges.clone();
    fixed.extend(cone_stars(mesh, &cone_vertices));
    let surface = Triangulation::of(mesh, options, &fixed)?;
    let sums = angle_sums::vertex_sums(&surface.mesh, options.boundary_curvature.as_deref(), cones)?;
    let (angles, mut report) = solve_pattern(&surface, &sums, options, progress)?;
    let opened = cut_along(&surface.mesh, &cut.edges)?;
    let uv = reconstruct_uv(&opened.mesh, &angles, resolve_pins(&opened.mesh, None)?)?;
    let corner_uv = corners_on_their_side(&cut, &opened, &uv)?;
    progress.report(1.0)?;
    report.flipped_triangles = flipped_triangles_of_corners(&corner_uv);
    Ok(ConeMapResult { corner_uv, seams: cut.edges, report })
}

/// Every edge of the triangles around the cones (spokes and link), each once per triangle.
fn cone_stars(mesh: &TriMesh, cones: &[u32]) -> Vec<[u32; 2]> {
    let mut is_cone = vec![false; mesh.vertex_count()];
    cones.iter().for_each(|&v| is_cone[v as usize] = true);
    let star = mesh.triangles().iter().filter(|t| t.iter().any(|&v| is_cone[v as usize]));
    star.flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]]).collect()
}

/// The uv of every corner of the input: the copy of its vertex in `opened` (the flipped
/// triangulation cut open) on the same side of the cut as its copy in `cut` (the input cut
/// open along the same edges).
fn corners_on_their_side(cut: &Cut, opened: &Cut, uv: &[[f64; 2]]) -> Result<Vec<[[f64; 2]; 3]>> {
    let copy_of: HashMap<(u32, u32), u32> =
        (0..opened.original.len() as u32).map(|c| (wedge_key(opened, c), c)).collect();
    cut.triangles
        .iter()
        .map(|tri| {
            let mut out = [[0.0; 2]; 3];
            for (k, &c) in tri.iter().enumerate() {
                let copy = copy_of.get(&wedge_key(cut, c)).ok_or_else(|| {
                    Error::Internal("a wedge of the cut input has no copy in the cut triangulation".into())
                })?;
                out[k] = uv[*copy as usize];
            }
            Ok(out)
        })
        .collect()
}

/// A copy of an input vertex in a cut mesh, named by the vertex and the input vertex at the far
/// end of the boundary half-edge leaving the copy (NONE for a vertex off the cut and the
/// boundary, which has one copy).
fn wedge_key(cut: &Cut, copy: u32) -> (u32, u32) {
    let h = cut.mesh.connectivity().vertex_halfedge[copy as usize];
    let far = if h != NONE && cut.mesh.connectivity().is_boundary(h) {
        cut.original[cut.mesh.head(h) as usize]
    } else {
        NONE
    };
    (cut.original[copy as usize], far)
}
