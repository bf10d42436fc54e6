//! Closed and higher-genus surfaces: cutting a mesh into a disk (result handle with accessors)
//! and spherical parameterization of closed genus-0 meshes.

use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{
    borrow_slice, borrow_slice_mut, checked_count, copy_out, guard, progress_closure, read_options, UvfProgressFn,
};
use std::os::raw::c_void;
use uvflat_core::error::{Error, Result};
use uvflat_core::mesh::cut::{cut_to_disk, total_edge_length, Cut, EdgeCost};
use uvflat_core::methods::sphere::{spherical_map_with_progress, SphereMethod, SphereOptions};
use uvflat_core::progress::Progress;

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

/// Tutte embedding of the mesh minus one vertex star, gnomonic lift, flip-guarded relaxation:
/// never flips (the default).
pub const UVF_SPHERE_TUTTE_GNOMONIC: u32 = 0;
/// Projected Gauss–Seidel barycentric iteration (course notes §6.1; no guarantee).
pub const UVF_SPHERE_GAUSS_SEIDEL: u32 = 1;
/// Haker et al. 2000: harmonic map of the mesh minus one triangle + inverse stereographic
/// projection (no guarantee).
pub const UVF_SPHERE_STEREOGRAPHIC: u32 = 2;
/// Kharevych, Springborn & Schröder 2006: the planar circle pattern of the mesh minus one vertex
/// star (its link on a convex polygon whose corners are the removed spokes' intersection
/// angles), balanced so the vertex areas' centroid is the sphere's centre, inverse
/// stereographic projection: conformal (no guarantee against flips; they are counted).
pub const UVF_SPHERE_CIRCLE_PATTERNS: u32 = 3;

/// Options of `uvf_spherical_map`. Initialise with `uvf_sphere_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfSphereOptions {
    /// `sizeof(UvfSphereOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// One of `UVF_SPHERE_*` (default `UVF_SPHERE_TUTTE_GNOMONIC`).
    pub method: u32,
    /// Relaxation sweeps (default 100); ignored by the stereographic and circle-pattern methods.
    pub sweeps: u32,
    /// Optional progress callback (may be NULL); a non-zero return cancels (`UVF_CANCELLED`).
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
}

impl Default for UvfSphereOptions {
    fn default() -> Self {
        UvfSphereOptions {
            struct_size: std::mem::size_of::<Self>(),
            method: UVF_SPHERE_TUTTE_GNOMONIC,
            sweeps: 100,
            progress: None,
            progress_user: std::ptr::null_mut(),
        }
    }
}

/// Fills `options` with defaults (Tutte–gnomonic, 100 sweeps).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_sphere_options_default(options: *mut UvfSphereOptions) {
    if !options.is_null() {
        options.write(UvfSphereOptions::default());
    }
}

/// Size of the first version of `UvfSphereOptions` (without the progress callback).
const SPHERE_OPTIONS_V1: usize = std::mem::offset_of!(UvfSphereOptions, progress);

/// Spherical parameterization of a closed genus-0 mesh (course notes §6.1): unit-sphere
/// positions, 3 doubles per vertex in `sphere_out` (`vertex_count` triples; NaN for
/// unreferenced vertices), and in `*flipped_out` the number of triangles with
/// `det[p0, p1, p2] ≤ 0` (0 for `UVF_SPHERE_TUTTE_GNOMONIC` by construction). `options` may be
/// NULL. Returns `UVF_OK`, `UVF_INVALID_ARGUMENT`, `UVF_INVALID_MESH`,
/// `UVF_UNSUPPORTED_TOPOLOGY` (not one closed genus-0 surface), `UVF_NUMERICAL_FAILURE`,
/// `UVF_CANCELLED` (the progress callback returned non-zero), `UVF_INTERNAL_ERROR`. On failure
/// the outputs are untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `flipped_out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_spherical_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfSphereOptions,
    sphere_out: *mut f64,
    flipped_out: *mut usize,
) -> UvfStatus {
    unsafe {
        spherical_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            sphere_out,
            flipped_out,
        )
    }
}

/// `uvf_spherical_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_spherical_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_spherical_map(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfSphereOptions,
    sphere_out: *mut f64,
    flipped_out: *mut usize,
) -> UvfStatus {
    unsafe { spherical_map_from(MeshSource::Handle(mesh), options, sphere_out, flipped_out) }
}

/// `uvf_spherical_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_spherical_map`.
unsafe fn spherical_map_from(
    source: MeshSource,
    options: *const UvfSphereOptions,
    sphere_out: *mut f64,
    flipped_out: *mut usize,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, _) = unsafe { source.counts() }?;
        let o = read_options(options, UvfSphereOptions::default(), SPHERE_OPTIONS_V1, "UvfSphereOptions")?;
        let method = match o.method {
            UVF_SPHERE_TUTTE_GNOMONIC => SphereMethod::TutteGnomonic,
            UVF_SPHERE_GAUSS_SEIDEL => SphereMethod::GaussSeidel,
            UVF_SPHERE_STEREOGRAPHIC => SphereMethod::Stereographic,
            UVF_SPHERE_CIRCLE_PATTERNS => SphereMethod::CirclePatterns,
            m => return Err(Error::InvalidArgument(format!("unknown sphere method {m}; use one of UVF_SPHERE_*"))),
        };
        let mesh = unsafe { source.mesh() }?;
        let flipped = borrow_slice_mut(flipped_out, 1, "flipped_out")?;
        let out = borrow_slice_mut(sphere_out, checked_count(vertex_count, 3, "sphere")?, "sphere_out")?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let options = SphereOptions { method, sweeps: o.sweeps as usize };
        let map = spherical_map_with_progress(&mesh, &options, &mut Progress::new(&mut callback))?;
        for (d, p) in out.chunks_exact_mut(3).zip(&map.positions) {
            d.copy_from_slice(p);
        }
        flipped[0] = map.flipped;
        Ok(())
    })
}
