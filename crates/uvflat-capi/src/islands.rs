//! UV islands of a polygon mesh as a DCC tool holds it (`mesh::islands`): which selected faces
//! are laid out together and which face corners share one UV, given seams per corner.

use super::status::UvfStatus;
use super::{borrow_slice, borrow_slice_mut, guard, SizedOut};
use uvflat_core::error::{Error, Result};
use uvflat_core::mesh::islands::{polygon_islands, PolygonFaces, NOT_IN_AN_ISLAND};

const _: () = assert!(UVF_NOT_IN_AN_ISLAND == NOT_IN_AN_ISLAND);

/// `uvf_polygon_islands`: the island of a face that is not selected, and the island vertex of
/// its corners.
pub const UVF_NOT_IN_AN_ISLAND: u32 = u32::MAX;

/// What `uvf_polygon_islands` found. The caller sets `struct_size`; the library writes only the
/// fields that fit in that many bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfPolygonIslandsInfo {
    /// `sizeof(UvfPolygonIslandsInfo)`, set by the caller.
    pub struct_size: usize,
    /// Number of islands.
    pub islands: usize,
    /// Number of island vertices (UVs), all islands together.
    pub island_vertices: usize,
    /// Edges of selected faces used by more than two corners (cut: non-manifold).
    pub non_manifold_edges: usize,
    /// Edges between two selected faces that traverse it in the same direction (cut: the faces'
    /// orientations disagree).
    pub misoriented_edges: usize,
}

/// Splits the selected faces of a polygon mesh into UV islands, the first step of an
/// interactive unwrap (what Blender's Unwrap does with seams and a face selection).
///
/// Faces: `corner_vertices` holds the vertex of every face corner, face after face, each face's
/// corners counter-clockwise; `face_sizes` the corner count of each of `face_count` faces
/// (NULL: every face is a triangle). `face_selected` (NULL: all) has one flag per face, non-zero
/// for the faces to lay out; `corner_seams` (NULL: none) one flag per corner, non-zero when the
/// edge from that corner to the next corner of its face is a seam.
///
/// Two selected faces are in one island when they are joined through edges that are used by
/// exactly two corners of the whole mesh (both in selected faces, traversing the edge in
/// opposite directions) and are not seams; every other edge cuts: seams, the selection border,
/// non-manifold edges, edges between faces of opposite orientation (these two are counted in
/// the info). Corners of one vertex are joined across those edges only, so a seam that ends
/// inside an island slits it open, and each corner gets the island vertex (one UV) it shares
/// with the corners around it.
///
/// Outputs: `face_island_out` (`face_count` entries) the island of each face,
/// `UVF_NOT_IN_AN_ISLAND` where not selected; islands are numbered in order of their lowest
/// face. `corner_vertex_out` (`corner_count` entries) the island vertex of each corner,
/// `UVF_NOT_IN_AN_ISLAND` for corners of unselected faces; island vertices are numbered island
/// by island (all of island 0's, then island 1's, …), so each island's are one contiguous range.
/// `info_out->struct_size` must be set.
///
/// Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL or mis-sized array, a vertex index ≥
/// `vertex_count`, a face of fewer than 3 corners, face sizes not adding up to `corner_count`);
/// the outputs are untouched on failure. Cost: O(c log c) for c corners.
///
/// # Safety
/// The arrays must hold the stated number of elements; `info_out` must point to a
/// `UvfPolygonIslandsInfo` with its `struct_size` set.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_polygon_islands(
    corner_vertices: *const u32,
    corner_count: usize,
    vertex_count: usize,
    face_sizes: *const u32,
    face_count: usize,
    face_selected: *const u8,
    corner_seams: *const u8,
    face_island_out: *mut u32,
    corner_vertex_out: *mut u32,
    info_out: *mut UvfPolygonIslandsInfo,
) -> UvfStatus {
    guard(|| {
        let info = unsafe { SizedOut::required(info_out, "info_out", "UvfPolygonIslandsInfo") }?;
        let corners = borrow_slice(corner_vertices, corner_count, "corner_vertices")?;
        let triangles: Vec<u32>;
        let sizes = if face_sizes.is_null() {
            if face_count.checked_mul(3) != Some(corner_count) {
                return Err(Error::InvalidArgument(format!(
                    "face_sizes is NULL (triangles), so corner_count must be 3 × face_count = 3 × {face_count}, not {corner_count}"
                )));
            }
            triangles = vec![3; face_count];
            &triangles[..]
        } else {
            borrow_slice(face_sizes, face_count, "face_sizes")?
        };
        let selected = flags(face_selected, face_count, "face_selected")?;
        let seams = flags(corner_seams, corner_count, "corner_seams")?;
        let faces = PolygonFaces {
            corner_vertices: corners,
            face_sizes: sizes,
            vertex_count,
            selected: selected.as_deref(),
            seams: seams.as_deref(),
        };
        let islands = polygon_islands(&faces)?;
        let face_out = borrow_slice_mut(face_island_out, face_count, "face_island_out")?;
        let corner_out = borrow_slice_mut(corner_vertex_out, corner_count, "corner_vertex_out")?;
        face_out.copy_from_slice(&islands.face_island);
        corner_out.copy_from_slice(&islands.corner_vertex);
        info.write(UvfPolygonIslandsInfo {
            struct_size: 0,
            islands: islands.island_count,
            island_vertices: *islands.vertex_start.last().unwrap_or(&0) as usize,
            non_manifold_edges: islands.non_manifold_edges,
            misoriented_edges: islands.misoriented_edges,
        });
        Ok(())
    })
}

/// An optional array of byte flags as booleans (None for NULL).
fn flags(ptr: *const u8, count: usize, what: &'static str) -> Result<Option<Vec<bool>>> {
    if ptr.is_null() {
        return Ok(None);
    }
    Ok(Some(borrow_slice(ptr, count, what)?.iter().map(|&f| f != 0).collect()))
}
