//! Mesh validation and topology queries.

use super::mesh_handle::{handle, UvfMesh};
use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{borrow_slice_mut, guard, mesh_from_raw};
use uvflat_core::error::Error;

/// Counts and topological invariants of a mesh.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfMeshInfo {
    /// `sizeof(UvfMeshInfo)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Vertices in the input arrays (including unreferenced ones).
    pub vertices: usize,
    /// Vertices used by at least one triangle.
    pub referenced_vertices: usize,
    /// Triangles.
    pub triangles: usize,
    /// Undirected edges.
    pub edges: usize,
    /// Connected components.
    pub components: usize,
    /// Boundary loops.
    pub boundary_loops: usize,
    /// Total number of vertices over all boundary loops (size of `uvf_boundary_loops` output).
    pub boundary_vertices: usize,
    /// Euler characteristic V − E + F.
    pub euler_characteristic: i64,
    /// Total genus.
    pub genus: i64,
}

/// Validates a mesh and reports its topology.
///
/// `positions`: 3 doubles per vertex; `triangles`: 3 vertex indices per triangle,
/// counter-clockwise. Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (NULL pointer, overflowing
/// count) or `UVF_INVALID_MESH` (bad index, non-finite coordinate, degenerate, duplicate or
/// non-manifold triangle, inconsistent orientation, no triangles).
///
/// # Safety
/// The arrays must hold the stated number of elements; `info_out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_info(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    info_out: *mut UvfMeshInfo,
) -> UvfStatus {
    guard(|| {
        let out = unsafe { SizedOut::required(info_out, "info_out", "UvfMeshInfo") }?;
        let mesh = mesh_from_raw(positions, vertex_count, triangles, triangle_count)?;
        out.write(info_of(&mesh));
        Ok(())
    })
}

/// Ordered boundary loops (counter-clockwise, surface on the left), concatenated.
///
/// `vertices_out` receives `info.boundary_vertices` indices; `loop_offsets_out` receives
/// `info.boundary_loops + 1` offsets (loop k is `vertices_out[offsets[k] .. offsets[k+1]]`).
/// The capacities say how many elements the arrays hold; too small gives
/// `UVF_INVALID_ARGUMENT` and writes nothing. Other statuses as `uvf_mesh_info`.
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_boundary_loops(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    vertices_out: *mut u32,
    vertices_capacity: usize,
    loop_offsets_out: *mut u32,
    offsets_capacity: usize,
) -> UvfStatus {
    unsafe {
        boundary_loops_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            vertices_out,
            vertices_capacity,
            loop_offsets_out,
            offsets_capacity,
        )
    }
}

/// `uvf_boundary_loops` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_boundary_loops`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_boundary_loops(
    mesh: *const UvfMesh,
    vertices_out: *mut u32,
    vertices_capacity: usize,
    loop_offsets_out: *mut u32,
    offsets_capacity: usize,
) -> UvfStatus {
    unsafe {
        boundary_loops_from(
            MeshSource::Handle(mesh),
            vertices_out,
            vertices_capacity,
            loop_offsets_out,
            offsets_capacity,
        )
    }
}

/// `uvf_boundary_loops` on either kind of mesh.
///
/// # Safety
/// As for `uvf_boundary_loops`.
unsafe fn boundary_loops_from(
    source: MeshSource,
    vertices_out: *mut u32,
    vertices_capacity: usize,
    loop_offsets_out: *mut u32,
    offsets_capacity: usize,
) -> UvfStatus {
    guard(|| {
        let mesh = unsafe { source.mesh() }?;
        let loops = mesh.boundary_loops();
        let total: usize = loops.iter().map(Vec::len).sum();
        if vertices_capacity < total || offsets_capacity < loops.len() + 1 {
            return Err(Error::InvalidArgument(format!(
                "output too small: {total} boundary vertices and {} offsets needed, capacities are {vertices_capacity} and {offsets_capacity}",
                loops.len() + 1
            )));
        }
        let verts = borrow_slice_mut(vertices_out, total, "vertices_out")?;
        let offsets = borrow_slice_mut(loop_offsets_out, loops.len() + 1, "loop_offsets_out")?;
        let mut at = 0;
        for (k, lp) in loops.iter().enumerate() {
            offsets[k] = at as u32;
            verts[at..at + lp.len()].copy_from_slice(lp);
            at += lp.len();
        }
        offsets[loops.len()] = at as u32;
        Ok(())
    })
}

/// Connected component id (0-based) of every triangle; `component_out` holds
/// `triangle_count` entries. Statuses as `uvf_mesh_info`.
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_triangle_components(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    component_out: *mut u32,
) -> UvfStatus {
    unsafe {
        triangle_components_from(MeshSource::arrays(positions, vertex_count, triangles, triangle_count), component_out)
    }
}

/// `uvf_triangle_components` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_triangle_components`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_triangle_components(mesh: *const UvfMesh, component_out: *mut u32) -> UvfStatus {
    unsafe { triangle_components_from(MeshSource::Handle(mesh), component_out) }
}

/// `uvf_triangle_components` on either kind of mesh.
///
/// # Safety
/// As for `uvf_triangle_components`.
unsafe fn triangle_components_from(source: MeshSource, component_out: *mut u32) -> UvfStatus {
    guard(|| {
        let (_, triangle_count) = unsafe { source.counts() }?;
        let mesh = unsafe { source.mesh() }?;
        let out = borrow_slice_mut(component_out, triangle_count, "component_out")?;
        out.copy_from_slice(mesh.triangle_components());
        Ok(())
    })
}

/// The counts and topology of a validated mesh.
pub(crate) fn info_of(mesh: &uvflat_core::TriMesh) -> UvfMeshInfo {
    let t = mesh.topology();
    UvfMeshInfo {
        struct_size: 0,
        vertices: t.vertices,
        referenced_vertices: t.referenced_vertices,
        triangles: t.triangles,
        edges: t.edges,
        components: t.components,
        boundary_loops: t.boundary_loops,
        boundary_vertices: mesh.boundary_loops().iter().map(Vec::len).sum(),
        euler_characteristic: t.euler_characteristic,
        genus: t.genus,
    }
}

/// Counts and topology of a mesh handle, as `uvf_mesh_info` gives them for flat arrays
/// (`triangles` counts the triangles after triangulation). `info_out->struct_size` must be set.
///
/// # Safety
/// `mesh` must be a live handle or NULL; `info_out` writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_handle_info(mesh: *const UvfMesh, info_out: *mut UvfMeshInfo) -> UvfStatus {
    guard(|| {
        let out = unsafe { SizedOut::required(info_out, "info_out", "UvfMeshInfo") }?;
        let m = unsafe { handle(mesh) }?;
        out.write(info_of(&m.mesh));
        Ok(())
    })
}
