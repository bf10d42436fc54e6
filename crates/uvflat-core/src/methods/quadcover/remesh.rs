//! QuadCover, step 4: the quad-dominant mesh of the integer grid lines (course notes ch. 8,
//! "parameterizations whose grid lines form a global closed quadrilateral grid", Table 8.1 and
//! Figs. 8.9–8.10: the remeshed hand and bunny).
//!
//! QuadCover's map has exactly the structure Ray et al. 2006 (§3.1, Algorithm 1) give PGP's:
//! every corner is its vertex's (u, v) turned by a quarter turn J^r and moved by a whole
//! translation (eq. 8.2 with integer gaps). Written in PGP's form — (θ, φ) = 2π (u, v), each
//! vertex's angles the fractional part of one of its corners, the other corners that turned by
//! [`super::QuadCoverResult::corner_rotation`] plus whole periods — the iso-line graph and the
//! polygon splitting of PGP's remesh ([`crate::methods::pgp::quad_dominant_remesh_of`], §5)
//! apply unchanged: at `density` lines per grid unit the lines u, v ∈ ℤ / density are traced
//! exactly, shared across every edge whose transition is the same seen from both endpoints, and
//! the faces of the line graph split into quads and at most one triangle.
//!
//! Triangles without lines: folded ones (non-positive (u, v) area), and any whose corner is not
//! its vertex's turned (u, v) plus an integer to 10⁻⁶ (a translation left fractional by a
//! non-±1 pivot, see [`super::covering`]). Around a cone the quarter turns do not close, so one
//! edge there is singular in PGP's sense and the lines end on it.
//!
//! Cost: O(F + output).

use super::QuadCoverResult;
use crate::error::{Error, Result};
use crate::fields::frames::rotate_coords;
use crate::methods::pgp::extraction::CornerParameterization;
use crate::methods::pgp::{quad_dominant_remesh_of, PeriodicMap, PolygonMesh};
use crate::metrics::signed_uv_area;
use crate::TriMesh;
use std::f64::consts::TAU;

/// Largest distance of a corner's translation to an integer still read as that integer.
const SHIFT_TOLERANCE: f64 = 1e-6;

/// The quad-dominant mesh of `result`'s iso-lines at `density` lines per grid unit (a whole
/// number ≥ 1; 1 gives one quad per grid cell). Empty when no line survives (folded triangles
/// and cones everywhere, as on the 1000-triangle knight at the default spacing). Errors: bad
/// density, a result that does not belong to `mesh`.
pub fn quad_mesh(mesh: &TriMesh, result: &QuadCoverResult, density: f64) -> Result<PolygonMesh> {
    if result.uv.len() != mesh.triangle_count() || result.corner_rotation.len() != mesh.triangle_count() {
        return Err(Error::InvalidArgument(format!(
            "the QuadCover result has {} triangles but the mesh has {}",
            result.uv.len(),
            mesh.triangle_count()
        )));
    }
    let (param, vertex_angles, singular) = periodic_form(mesh, result);
    quad_dominant_remesh_of(mesh, &PeriodicMap { param: &param, vertex_angles, singular_triangles: &singular }, density)
}

/// PGP's form of the map (module comment): per-corner (θ, φ), rotations and whole periods, the
/// vertices' angles, and the triangles that carry no lines.
pub fn periodic_form(mesh: &TriMesh, result: &QuadCoverResult) -> (CornerParameterization, Vec<[f64; 2]>, Vec<u32>) {
    let fraction = vertex_fractions(mesh, result);
    let n = mesh.triangle_count();
    let mut param = CornerParameterization {
        coords: Vec::with_capacity(n),
        rotation: result.corner_rotation.clone(),
        shift: Vec::with_capacity(n),
        open: vec![false; n],
    };
    let mut singular = Vec::new();
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let uv = result.uv[t];
        let mut whole = signed_uv_area(uv) > 0.0;
        let shift: [[i64; 2]; 3] = std::array::from_fn(|c| {
            let turned = rotate_coords(result.corner_rotation[t][c], fraction[tri[c] as usize]);
            std::array::from_fn(|k| {
                let d = uv[c][k] - turned[k];
                whole &= (d - d.round()).abs() <= SHIFT_TOLERANCE;
                d.round() as i64
            })
        });
        if !whole {
            singular.push(t as u32);
        }
        param.coords.push(uv.map(|p| [TAU * p[0], TAU * p[1]]));
        param.shift.push(shift);
    }
    let angles = fraction.iter().map(|f| [TAU * f[0], TAU * f[1]]).collect();
    (param, angles, singular)
}

/// Per vertex, the fractional part (in [−½, ½]) of the (u, v) of its first corner of rotation
/// 0 (the first copy's; every copy is the corner of some triangle).
fn vertex_fractions(mesh: &TriMesh, result: &QuadCoverResult) -> Vec<[f64; 2]> {
    let mut fraction: Vec<Option<[f64; 2]>> = vec![None; mesh.vertex_count()];
    for (t, tri) in mesh.triangles().iter().enumerate() {
        for c in 0..3 {
            let slot = &mut fraction[tri[c] as usize];
            if slot.is_none() && result.corner_rotation[t][c] == 0 {
                *slot = Some(result.uv[t][c].map(|x| x - x.round()));
            }
        }
    }
    fraction.into_iter().map(Option::unwrap_or_default).collect()
}
