//! The welds and left-out triangles that make a mesh with zero-area triangles solvable
//! (`mesh::snapped`): convert, call, convert back.

use super::status::UvfStatus;
use super::{borrow_slice, borrow_slice_mut, checked_count, guard, SizedOut};
use uvflat_core::mesh::snapped::snapped_repair;

/// What `uvf_snapped_repair` found. The caller sets `struct_size`; the library writes only the
/// fields that fit in that many bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfSnappedRepairInfo {
    /// `sizeof(UvfSnappedRepairInfo)`, set by the caller.
    pub struct_size: usize,
    /// Solve vertices (input vertices after welding).
    pub vertices: usize,
    /// Input vertices welded onto another one.
    pub welded: usize,
    /// Triangles left out of the solve.
    pub left_out: usize,
    /// Solve vertices that only left-out triangles use (a solve gives them no UV).
    pub unreferenced: usize,
}

/// What to weld and what to leave out so that a mesh with zero-area triangles (vertices
/// snapped onto each other but not merged, collinear corners) can be solved, where
/// `uvf_mesh_info` and every method refuse it. In every degenerate triangle (area at most 1e-12
/// of its longest edge squared, or a corner repeated), the two ends of an edge shorter than
/// 1e-6 of that triangle's longest edge are one point and are welded (transitively); every
/// triangle still degenerate over the welded vertices is left out (a slit of zero area becomes
/// a free boundary of the solve).
///
/// `vertex_out` (`vertex_count` entries) receives the solve vertex of every input vertex,
/// numbered in order of their lowest input vertex (a vertex welded to none is its own);
/// `keep_out` (`triangle_count` entries) 1 for the triangles to solve, 0 for the left-out
/// ones. Solve the kept triangles over the solve vertices (each at the position of its lowest
/// input vertex) and give every input vertex its solve vertex's UV; `info_out->unreferenced`
/// counts solve vertices that only left-out triangles use, which a solve gives no UV. A mesh
/// without degenerate triangles welds nothing and keeps everything.
///
/// Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (NULL or mis-sized array) or `UVF_INVALID_MESH`
/// (an index ≥ `vertex_count`, a non-finite coordinate of a used vertex, no triangles); the
/// outputs are untouched on failure. Cost: O(n + m).
///
/// # Safety
/// The arrays must hold the stated number of elements; `info_out` must point to a
/// `UvfSnappedRepairInfo` with its `struct_size` set.
#[no_mangle]
pub unsafe extern "C" fn uvf_snapped_repair(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    vertex_out: *mut u32,
    keep_out: *mut u8,
    info_out: *mut UvfSnappedRepairInfo,
) -> UvfStatus {
    guard(|| {
        let info = unsafe { SizedOut::required(info_out, "info_out", "UvfSnappedRepairInfo") }?;
        let p = borrow_slice(positions, checked_count(vertex_count, 3, "vertex_count")?, "positions")?;
        let t = borrow_slice(triangles, checked_count(triangle_count, 3, "triangle_count")?, "triangles")?;
        let points: Vec<[f64; 3]> = p.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let tris: Vec<[u32; 3]> = t.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let repair = snapped_repair(&points, &tris)?;
        let vertex = borrow_slice_mut(vertex_out, vertex_count, "vertex_out")?;
        let keep = borrow_slice_mut(keep_out, triangle_count, "keep_out")?;
        vertex.copy_from_slice(&repair.vertex);
        for (k, &kept) in keep.iter_mut().zip(&repair.keep) {
            *k = kept as u8;
        }
        info.write(UvfSnappedRepairInfo {
            struct_size: 0,
            vertices: repair.vertex_count,
            welded: repair.welded,
            left_out: repair.left_out,
            unreferenced: repair.unreferenced,
        });
        Ok(())
    })
}
