//! Cutting a closed or higher-genus mesh into a disk (Hormann, Polthier & Sheffer 2008, §6): a
//! result handle with the cut edges, the cut mesh and its vertex correspondence.

use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{borrow_slice, borrow_slice_mut, checked_count, copy_out, guard, read_options};
use uvflat_core::error::{Error, Result};
use uvflat_core::mesh::cut::{cut_to_disk, total_edge_length, Cut, EdgeCost};

/// Default edge cost: length divided by `1 + 3·θ/π` (θ the dihedral angle).
pub const UVF_CUT_COST_CURVATURE: u32 = 0;

/// Plain edge length.
pub const UVF_CUT_COST_LENGTH: u32 = 1;

/// Caller-given cost per half-edge in `edge_cost`.
pub const UVF_CUT_COST_GIVEN: u32 = 2;

/// Options of `uvf_cut_to_disk`. Initialise with `uvf_cut_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfCutOptions {
    /// `sizeof(UvfCutOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// One of `UVF_CUT_COST_*` (default curvature-weighted length).
    pub cost: u32,
    /// For `UVF_CUT_COST_GIVEN`: 3 doubles per triangle, the cost of half-edge `3t + k` (from
    /// corner k of triangle t to corner k + 1), finite and ≥ 0; an interior edge costs the
    /// mean of its two half-edges. Low cost attracts the cut.
    pub edge_cost: *const f64,
}

impl Default for UvfCutOptions {
    fn default() -> Self {
        UvfCutOptions {
            struct_size: std::mem::size_of::<Self>(),
            cost: UVF_CUT_COST_CURVATURE,
            edge_cost: std::ptr::null(),
        }
    }
}

/// Sizes and lengths of a cut (see `uvf_cut_info`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfCutInfo {
    /// `sizeof(UvfCutInfo)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Vertices of the cut mesh (input vertices duplicated along the cut; unreferenced input
    /// vertices dropped).
    pub vertex_count: usize,
    /// Triangles (the input's, same order).
    pub triangle_count: usize,
    /// Cut edges (interior input edges opened by the cut).
    pub edge_count: usize,
    /// Total 3D length of the cut edges.
    pub seam_length: f64,
    /// Total 3D length of all input edges.
    pub total_edge_length: f64,
}

/// A mesh cut into a disk: created by `uvf_cut_to_disk`, read with the `uvf_cut_*` accessors,
/// released with `uvf_cut_free`.
pub struct UvfCut {
    cut: Cut,
    info: UvfCutInfo,
}

/// Fills `options` with defaults (curvature-weighted edge length).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_cut_options_default(options: *mut UvfCutOptions) {
    if !options.is_null() {
        options.write(UvfCutOptions::default());
    }
}

const CUT_OPTIONS_V1: usize = std::mem::size_of::<UvfCutOptions>();

/// Cuts a connected manifold mesh (closed or with boundary loops, any genus) into a topological
/// disk: tree–cotree cut graph (Eppstein 2003) with a shortest-path primal tree and a maximum
/// dual tree by loop length (Erickson & Whittlesey's greedy loops), dangling branches pruned,
/// boundary loops joined; closed genus-0 meshes are cut along a path between two far vertices.
/// The cut is steered by the edge cost (Seamster-like: short edges and sharp creases are cheap).
///
/// On success `*cut_out` receives a handle to free with `uvf_cut_free`. The cut mesh has the
/// input's triangles (same order) over a new vertex set; run any disk method on
/// (`uvf_cut_copy_positions`, `uvf_cut_copy_triangles`) and use the result as per-corner UVs.
/// `options` may be NULL. Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (NULL pointer, bad cost),
/// `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY` (several components), `UVF_INTERNAL_ERROR`.
/// On failure `*cut_out` is untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `cut_out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_cut_to_disk(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfCutOptions,
    cut_out: *mut *mut UvfCut,
) -> UvfStatus {
    unsafe {
        cut_to_disk_from(MeshSource::arrays(positions, vertex_count, triangles, triangle_count), options, cut_out)
    }
}

/// `uvf_cut_to_disk` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_cut_to_disk`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_cut_to_disk(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfCutOptions,
    cut_out: *mut *mut UvfCut,
) -> UvfStatus {
    unsafe { cut_to_disk_from(MeshSource::Handle(mesh), options, cut_out) }
}

/// `uvf_cut_to_disk` on either kind of mesh.
///
/// # Safety
/// As for `uvf_cut_to_disk`.
unsafe fn cut_to_disk_from(source: MeshSource, options: *const UvfCutOptions, cut_out: *mut *mut UvfCut) -> UvfStatus {
    guard(|| {
        let (_, triangle_count) = unsafe { source.counts() }?;
        let out = borrow_slice_mut(cut_out, 1, "cut_out")?;
        let o = read_options(options, UvfCutOptions::default(), CUT_OPTIONS_V1, "UvfCutOptions")?;
        let mesh = unsafe { source.mesh() }?;
        let cost = match o.cost {
            UVF_CUT_COST_CURVATURE => EdgeCost::CurvatureWeightedLength,
            UVF_CUT_COST_LENGTH => EdgeCost::Length,
            UVF_CUT_COST_GIVEN => EdgeCost::PerHalfedge(
                borrow_slice(o.edge_cost, checked_count(triangle_count, 3, "edge cost")?, "edge_cost")?.to_vec(),
            ),
            c => return Err(Error::InvalidArgument(format!("unknown cut cost {c}; use one of UVF_CUT_COST_*"))),
        };
        let cut = cut_to_disk(&mesh, &cost)?;
        let info = UvfCutInfo {
            struct_size: 0,
            vertex_count: cut.original.len(),
            triangle_count: cut.triangles.len(),
            edge_count: cut.edges.len(),
            seam_length: cut.seam_length(&mesh),
            total_edge_length: total_edge_length(&mesh),
        };
        out[0] = Box::into_raw(Box::new(UvfCut { cut, info }));
        Ok(())
    })
}

/// Borrows the handle, rejecting NULL.
unsafe fn handle<'a>(cut: *const UvfCut) -> Result<&'a UvfCut> {
    // SAFETY: the caller passes a handle from `uvf_cut_to_disk` not yet freed, or NULL.
    unsafe { cut.as_ref() }.ok_or_else(|| Error::InvalidArgument("cut handle is NULL".into()))
}

/// Sizes and seam length of a cut. Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL).
///
/// # Safety
/// `cut` must be a live handle or NULL; `info_out` writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_cut_info(cut: *const UvfCut, info_out: *mut UvfCutInfo) -> UvfStatus {
    guard(|| {
        let c = unsafe { handle(cut) }?;
        unsafe { SizedOut::required(info_out, "info_out", "UvfCutInfo") }?.write(c.info);
        Ok(())
    })
}

/// The cut edges as pairs of input vertex indices `a < b`: `2 × edge_count` entries written to
/// `edges_out`, whose capacity (in `uint32_t`) is `capacity`. Returns `UVF_OK` or
/// `UVF_INVALID_ARGUMENT` (NULL, capacity too small; output untouched).
///
/// # Safety
/// `cut` must be a live handle or NULL; `edges_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_cut_copy_edges(cut: *const UvfCut, edges_out: *mut u32, capacity: usize) -> UvfStatus {
    guard(|| {
        let c = unsafe { handle(cut) }?;
        let flat: Vec<u32> = c.cut.edges.iter().flatten().copied().collect();
        copy_out(&flat, edges_out, capacity, "edges_out")
    })
}

/// Triangles of the cut mesh: `3 × triangle_count` cut-mesh vertex indices (corner k of input
/// triangle t at `3t + k`), i.e. the per-corner UV indices of any map computed on the cut mesh.
/// Statuses as `uvf_cut_copy_edges`.
///
/// # Safety
/// `cut` must be a live handle or NULL; `triangles_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_cut_copy_triangles(
    cut: *const UvfCut,
    triangles_out: *mut u32,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let c = unsafe { handle(cut) }?;
        let flat: Vec<u32> = c.cut.triangles.iter().flatten().copied().collect();
        copy_out(&flat, triangles_out, capacity, "triangles_out")
    })
}

/// The input vertex of every cut-mesh vertex: `vertex_count` entries. Statuses as
/// `uvf_cut_copy_edges`.
///
/// # Safety
/// `cut` must be a live handle or NULL; `original_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_cut_copy_original_vertices(
    cut: *const UvfCut,
    original_out: *mut u32,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let c = unsafe { handle(cut) }?;
        copy_out(&c.cut.original, original_out, capacity, "original_out")
    })
}

/// Positions of the cut-mesh vertices (copies of their input vertices): `3 × vertex_count`
/// doubles. Statuses as `uvf_cut_copy_edges`.
///
/// # Safety
/// `cut` must be a live handle or NULL; `positions_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_cut_copy_positions(
    cut: *const UvfCut,
    positions_out: *mut f64,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let c = unsafe { handle(cut) }?;
        let flat: Vec<f64> = c.cut.mesh.points().iter().flatten().copied().collect();
        copy_out(&flat, positions_out, capacity, "positions_out")
    })
}

/// Releases a cut handle (NULL is ignored).
///
/// # Safety
/// `cut` must come from `uvf_cut_to_disk` and not have been freed.
#[no_mangle]
pub unsafe extern "C" fn uvf_cut_free(cut: *mut UvfCut) {
    if !cut.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            // SAFETY: the pointer came from Box::into_raw in `uvf_cut_to_disk`.
            drop(unsafe { Box::from_raw(cut) });
        }));
    }
}
