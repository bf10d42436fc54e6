//! The quad-dominant remesh of a PGP result (Ray et al. 2006, §5) or of a QuadCover map: a polygon
//! mesh handle with its counts and arrays.

use crate::pgp::solve::{handle, UvfPgp};
use crate::pgp::{check_optional, copy_optional};
use crate::status::UvfStatus;
use crate::SizedOut;
use crate::{borrow_slice_mut, guard};
use uvflat_core::error::Error;
use uvflat_core::methods::pgp::PolygonMesh;

/// A quad-dominant remesh of a PGP result (Ray et al. 2006, §5) or of the integer grid lines of
/// a QuadCover map: created by `uvf_pgp_quad_mesh` or `uvf_quadcover_quad_mesh`, read with
/// `uvf_quad_mesh_info` and `uvf_quad_mesh_copy`, released with `uvf_quad_mesh_free`.
pub struct UvfQuadMesh {
    pub(crate) mesh: PolygonMesh,
}

/// Counts of a quad-dominant remesh.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfQuadMeshInfo {
    /// `sizeof(UvfQuadMeshInfo)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Vertices (3 doubles each in `uvf_quad_mesh_copy`).
    pub vertex_count: usize,
    /// Faces (polygons).
    pub face_count: usize,
    /// Sum of the face sizes (length of the index array).
    pub index_count: usize,
    /// Faces with four corners.
    pub quad_count: usize,
}

/// Quad-dominant remesh (§5): the iso-θ and iso-φ lines at `density` lines per period (a whole
/// number ≥ 1; quad sides are about 2π / (ω · density) long) as a polygon mesh whose
/// vertices lie on the input surface; faces that are not quads are split into quads and at
/// most one triangle. Returns `UVF_OK` (a handle in `*mesh_out`, free it with
/// `uvf_quad_mesh_free`) or `UVF_INVALID_ARGUMENT` (NULL handle or output, bad density, or a
/// density whose line graph would not fit in the memory available; `*mesh_out` untouched).
///
/// # Safety
/// `pgp` must be a live handle or NULL; `mesh_out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_quad_mesh(
    pgp: *const UvfPgp,
    density: f64,
    mesh_out: *mut *mut UvfQuadMesh,
) -> UvfStatus {
    guard(|| {
        let p = unsafe { handle(pgp) }?;
        let slot = borrow_slice_mut(mesh_out, 1, "mesh_out")?;
        let mesh = uvflat_core::methods::pgp::quad_dominant_remesh(&p.mesh, &p.result, density)?;
        slot[0] = Box::into_raw(Box::new(UvfQuadMesh { mesh }));
        Ok(())
    })
}

/// Counts of a remesh. Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL).
///
/// # Safety
/// `mesh` must be a live handle or NULL; `info_out` writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_quad_mesh_info(mesh: *const UvfQuadMesh, info_out: *mut UvfQuadMeshInfo) -> UvfStatus {
    guard(|| {
        // SAFETY: the caller passes a handle from `uvf_pgp_quad_mesh` not yet freed, or NULL.
        let m =
            &unsafe { mesh.as_ref() }.ok_or_else(|| Error::InvalidArgument("quad mesh handle is NULL".into()))?.mesh;
        unsafe { SizedOut::required(info_out, "info_out", "UvfQuadMeshInfo") }?.write(UvfQuadMeshInfo {
            struct_size: 0,
            vertex_count: m.positions.len(),
            face_count: m.face_sizes.len(),
            index_count: m.indices.len(),
            quad_count: m.quad_count(),
        });
        Ok(())
    })
}

/// Copies a remesh: `3 × vertex_count` coordinates, `face_count` face sizes and `index_count`
/// vertex indices (faces counter-clockwise seen from outside). Any output may be NULL (with
/// capacity 0) to skip it. Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL handle, a capacity
/// too small; outputs untouched).
///
/// # Safety
/// `mesh` must be a live handle or NULL; each non-NULL output must hold its capacity.
#[no_mangle]
pub unsafe extern "C" fn uvf_quad_mesh_copy(
    mesh: *const UvfQuadMesh,
    positions_out: *mut f64,
    positions_capacity: usize,
    face_sizes_out: *mut u32,
    face_sizes_capacity: usize,
    indices_out: *mut u32,
    indices_capacity: usize,
) -> UvfStatus {
    guard(|| {
        // SAFETY: as in `uvf_quad_mesh_info`.
        let m =
            &unsafe { mesh.as_ref() }.ok_or_else(|| Error::InvalidArgument("quad mesh handle is NULL".into()))?.mesh;
        check_optional(positions_out, positions_capacity, 3 * m.positions.len(), "positions_out")?;
        check_optional(face_sizes_out, face_sizes_capacity, m.face_sizes.len(), "face_sizes_out")?;
        check_optional(indices_out, indices_capacity, m.indices.len(), "indices_out")?;
        copy_optional(m.positions.as_flattened(), positions_out, positions_capacity, "positions_out")?;
        copy_optional(&m.face_sizes, face_sizes_out, face_sizes_capacity, "face_sizes_out")?;
        copy_optional(&m.indices, indices_out, indices_capacity, "indices_out")
    })
}

/// Releases a remesh (NULL is ignored).
///
/// # Safety
/// `mesh` must come from `uvf_pgp_quad_mesh` and not have been freed.
#[no_mangle]
pub unsafe extern "C" fn uvf_quad_mesh_free(mesh: *mut UvfQuadMesh) {
    if !mesh.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            // SAFETY: the pointer came from Box::into_raw in `uvf_pgp_quad_mesh`.
            drop(unsafe { Box::from_raw(mesh) });
        }));
    }
}
