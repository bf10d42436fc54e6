//! C ABI for the distortion measures of [`uvflat_core::metrics`] (course notes ch. 4).

use super::status::UvfStatus;
use super::{borrow_slice, checked_count, guard};
use uvflat_core::error::Error;
use uvflat_core::metrics::{distortion, Metrics};

/// Distortion summary of a UV map (see `uvf_metrics`). Distortion fields are NaN when no
/// triangle is measurable.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct UvfMetrics {
    /// `sizeof(UvfMetrics)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Number of triangles measured.
    pub triangles: usize,
    /// Triangles whose UV orientation is opposite to the layout's majority orientation.
    pub flipped: usize,
    /// Triangles with (numerically) zero UV area; they are left out of every distortion figure.
    pub degenerate_uv: usize,
    /// Proper crossings between UV boundary edges (0 for a layout without overlaps of its border).
    pub boundary_intersections: usize,
    /// Sander et al. 2001 L2 stretch after a global scale; 1 is optimal.
    pub stretch_l2: f64,
    /// Sander et al. 2001 L∞ stretch (largest singular value) after the same scale.
    pub stretch_linf: f64,
    /// Area-weighted mean of σmax/σmin; 1 is conformal.
    pub conformal_mean: f64,
    /// Largest σmax/σmin.
    pub conformal_max: f64,
    /// Mean |UV corner angle − surface corner angle|, radians.
    pub angle_mean: f64,
    /// Largest corner angle error, radians.
    pub angle_max: f64,
    /// Area-weighted mean |ln(s·A_uv / A_3d)| with one global scale s; 0 is authalic.
    pub area_mean: f64,
    /// Largest |ln(s·A_uv / A_3d)|.
    pub area_max: f64,
}

impl From<&Metrics> for UvfMetrics {
    fn from(m: &Metrics) -> Self {
        UvfMetrics {
            struct_size: 0,
            triangles: m.triangles,
            flipped: m.flipped,
            degenerate_uv: m.degenerate_uv,
            boundary_intersections: m.boundary_intersections,
            stretch_l2: m.stretch_l2,
            stretch_linf: m.stretch_linf,
            conformal_mean: m.conformal_mean,
            conformal_max: m.conformal_max,
            angle_mean: m.angle_mean,
            angle_max: m.angle_max,
            area_mean: m.area_mean,
            area_max: m.area_max,
        }
    }
}

fn as_points<const N: usize>(flat: &[f64]) -> Vec<[f64; N]> {
    flat.chunks_exact(N).map(|c| std::array::from_fn(|i| c[i])).collect()
}

fn as_triangles(flat: &[u32]) -> Vec<[u32; 3]> {
    flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
}

/// Distortion of a UV map (Hormann, Lévy, Sheffer 2008 course notes §3.3 and ch. 4; Sander et
/// al. 2001 stretch): singular values of each triangle's Jacobian summarised as stretch,
/// conformal, angle and area distortion, plus flipped triangles and UV-boundary crossings.
///
/// `positions`: 3 doubles per vertex; `triangles`: 3 indices per triangle; `uv`: 2 doubles per
/// UV coordinate (`uv_count` of them). `uv_triangles`: 3 indices into `uv` per triangle, or
/// NULL when UVs are per vertex (then `uv_count` must equal `vertex_count` and `triangles`
/// indexes both). Only UVs referenced by a triangle are read, so the NaN UVs that methods give
/// unreferenced vertices are fine. The mesh is not required to be manifold.
///
/// Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (NULL or mis-sized array, index out of range,
/// non-finite coordinate, no triangles) or `UVF_INTERNAL_ERROR`. `out` is untouched on failure.
///
/// # Safety
/// The arrays must hold the stated number of elements; `out` must point to a `UvfMetrics`.
#[no_mangle]
pub unsafe extern "C" fn uvf_metrics(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    uv: *const f64,
    uv_count: usize,
    uv_triangles: *const u32,
    out: *mut UvfMetrics,
) -> UvfStatus {
    guard(|| {
        let out = unsafe { super::SizedOut::required(out, "out", "UvfMetrics") }?;
        let p = borrow_slice(positions, checked_count(vertex_count, 3, "vertex")?, "positions")?;
        let t = borrow_slice(triangles, checked_count(triangle_count, 3, "triangle")?, "triangles")?;
        let q = borrow_slice(uv, checked_count(uv_count, 2, "uv")?, "uv")?;
        let uv_t = if uv_triangles.is_null() {
            if uv_count != vertex_count {
                return Err(Error::InvalidArgument(format!(
                    "uv_triangles is NULL (per-vertex UVs) but uv_count {uv_count} differs from vertex_count {vertex_count}"
                )));
            }
            t
        } else {
            borrow_slice(uv_triangles, checked_count(triangle_count, 3, "triangle")?, "uv_triangles")?
        };
        let tris = as_triangles(t);
        let m = distortion(&as_points::<3>(p), &tris, &as_points::<2>(q), &as_triangles(uv_t))?;
        out.write(UvfMetrics::from(&m));
        Ok(())
    })
}

/// `uvf_metrics` on a mesh handle of `uvf_mesh_new`: its positions and triangles (the
/// triangulation, `info.triangles` of them), `uv` per vertex (`uv_triangles` NULL, `uv_count`
/// equal to the vertex count) or per corner (`uv_triangles`: 3 indices per triangle).
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_metrics`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_metrics(
    mesh: *const super::mesh_handle::UvfMesh,
    uv: *const f64,
    uv_count: usize,
    uv_triangles: *const u32,
    out: *mut UvfMetrics,
) -> UvfStatus {
    guard(|| {
        let out = unsafe { super::SizedOut::required(out, "out", "UvfMetrics") }?;
        let m = &unsafe { super::mesh_handle::handle(mesh) }?.mesh;
        let q = borrow_slice(uv, checked_count(uv_count, 2, "uv")?, "uv")?;
        let uv_t = if uv_triangles.is_null() {
            if uv_count != m.vertex_count() {
                return Err(Error::InvalidArgument(format!(
                    "uv_triangles is NULL (per-vertex UVs) but uv_count {uv_count} differs from the mesh's {} vertices",
                    m.vertex_count()
                )));
            }
            m.triangles().to_vec()
        } else {
            let flat = borrow_slice(uv_triangles, checked_count(m.triangle_count(), 3, "triangle")?, "uv_triangles")?;
            as_triangles(flat)
        };
        let d = distortion(m.points(), m.triangles(), &as_points::<2>(q), &uv_t)?;
        out.write(UvfMetrics::from(&d));
        Ok(())
    })
}

/// What `uvf_check_layout` found (see there).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfLayoutCheck {
    /// `sizeof(UvfLayoutCheck)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// UV triangles not strictly counter-clockwise (zero area included) or with a non-finite
    /// corner.
    pub flipped: usize,
    /// Pairs of UV boundary edges that cross, touch or overlap, plus islands lying inside a
    /// triangle of another island.
    pub overlaps: usize,
    /// Islands: triangles connected through shared UV vertices.
    pub islands: usize,
}

/// An independent, exact check of any UV layout (exact orientation predicates, nothing of the
/// method that made it): counts flipped triangles (every triangle must be counter-clockwise)
/// and overlaps within and between islands. A layout with neither is one-to-one: no two
/// triangles cover the same point. `uv`: 2 doubles per UV vertex (`uv_count`),
/// `uv_triangles`: 3 indices into `uv` per triangle. Indices out of range count as flipped.
///
/// Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL or mis-sized array); `out` is untouched on
/// failure.
///
/// # Safety
/// The arrays must hold the stated number of elements; `out` must point to a `UvfLayoutCheck`.
#[no_mangle]
pub unsafe extern "C" fn uvf_check_layout(
    uv: *const f64,
    uv_count: usize,
    uv_triangles: *const u32,
    triangle_count: usize,
    out: *mut UvfLayoutCheck,
) -> UvfStatus {
    guard(|| {
        let uv = borrow_slice(uv, checked_count(uv_count, 2, "uv")?, "uv")?;
        let tris = borrow_slice(uv_triangles, checked_count(triangle_count, 3, "triangle")?, "uv_triangles")?;
        let out = unsafe { super::SizedOut::required(out, "out", "UvfLayoutCheck") }?;
        let v = uvflat_core::verify::check_layout(&as_points::<2>(uv), &as_triangles(tris));
        out.write(UvfLayoutCheck { struct_size: 0, flipped: v.flipped, overlaps: v.overlaps, islands: v.islands });
        Ok(())
    })
}
