//! Point constraints and pinned vertices (Desbrun, Meyer & Alliez 2002, §4.1: Lagrange multipliers on
//! the fixed-boundary and natural conformal systems), and the options the interactive tools share.

use super::barycentric::UvfFixedBoundaryOptions;
use super::status::UvfStatus;
use super::MeshSource;
use super::{borrow_slice, checked_count, guard, progress_closure, read_options, write_uv, UvfProgressFn};
use std::os::raw::c_void;
use uvflat_core::error::Result;
use uvflat_core::methods::constraints::{
    constrained_fixed_boundary_map, constrained_natural_conformal_map, pinned_natural_conformal_map, PointConstraint,
};
use uvflat_core::progress::Progress;

/// A point of the surface (triangle index and barycentric coordinates with respect to its
/// three corners, normalized by their sum) and the UV it must map to.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfPointConstraint {
    /// Triangle index (< triangle_count).
    pub triangle: u32,
    /// Barycentric coordinates of the point (must not sum to zero).
    pub barycentric: [f64; 3],
    /// Target UV.
    pub uv: [f64; 2],
}

/// Options of the constrained natural conformal maps and of the boundary editor. Initialise
/// with `uvf_intrinsic_tool_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfIntrinsicToolOptions {
    /// `sizeof(UvfIntrinsicToolOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// Optional progress callback (may be NULL).
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
}

impl Default for UvfIntrinsicToolOptions {
    fn default() -> Self {
        UvfIntrinsicToolOptions {
            struct_size: std::mem::size_of::<Self>(),
            progress: None,
            progress_user: std::ptr::null_mut(),
        }
    }
}

pub(crate) const TOOL_OPTIONS_V1: usize = std::mem::size_of::<UvfIntrinsicToolOptions>();

/// Fills `options` with defaults (no progress callback).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_intrinsic_tool_options_default(options: *mut UvfIntrinsicToolOptions) {
    if !options.is_null() {
        options.write(UvfIntrinsicToolOptions::default());
    }
}

fn constraints_from(ptr: *const UvfPointConstraint, count: usize) -> Result<Vec<PointConstraint>> {
    Ok(borrow_slice(ptr, count, "constraints")?
        .iter()
        .map(|c| PointConstraint { triangle: c.triangle, barycentric: c.barycentric, uv: c.uv })
        .collect())
}

/// Fixed-boundary map with point constraints (Desbrun et al. 2002 §4.1, Lagrange multipliers):
/// the map of `uvf_fixed_boundary_map` (same `options`, any weights and boundary) with each of
/// the `constraint_count` points of `constraints` placed exactly on its target. Already
/// satisfied constraints leave the map unchanged.
///
/// `uv_out` receives 2 doubles per vertex. Returns `UVF_OK`; `UVF_INVALID_ARGUMENT` for a bad
/// pointer, option, triangle index, zero-sum barycentric coordinates, a non-finite target, or
/// conflicting constraints (linearly dependent ones with different targets, or a point whose
/// triangle lies entirely on the fixed boundary given another position — the message names the
/// constraint); `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY`, `UVF_NUMERICAL_FAILURE`,
/// `UVF_CANCELLED`, `UVF_INTERNAL_ERROR`. On failure `uv_out` is untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_constrained_fixed_boundary_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfFixedBoundaryOptions,
    constraints: *const UvfPointConstraint,
    constraint_count: usize,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        constrained_fixed_boundary_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            constraints,
            constraint_count,
            uv_out,
        )
    }
}

/// `uvf_constrained_fixed_boundary_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_constrained_fixed_boundary_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_constrained_fixed_boundary_map(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfFixedBoundaryOptions,
    constraints: *const UvfPointConstraint,
    constraint_count: usize,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        constrained_fixed_boundary_map_from(MeshSource::Handle(mesh), options, constraints, constraint_count, uv_out)
    }
}

/// `uvf_constrained_fixed_boundary_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_constrained_fixed_boundary_map`.
unsafe fn constrained_fixed_boundary_map_from(
    source: MeshSource,
    options: *const UvfFixedBoundaryOptions,
    constraints: *const UvfPointConstraint,
    constraint_count: usize,
    uv_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let o = read_options(
            options,
            UvfFixedBoundaryOptions::default(),
            std::mem::size_of::<UvfFixedBoundaryOptions>(),
            "UvfFixedBoundaryOptions",
        )?;
        let opts = super::barycentric::fixed_options_from(&o)?;
        let c = constraints_from(constraints, constraint_count)?;
        let mesh = unsafe { source.mesh() }?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let uv = constrained_fixed_boundary_map(&mesh, &opts, &c, &mut Progress::new(&mut callback))?;
        write_uv(&uv, uv_out)
    })
}

/// Natural conformal map (Desbrun et al. 2002 §4.2 eq. 7 = LSCM) with point constraints
/// instead of two pins (§4.1): minimizes the conformal energy subject to every constraint.
/// Needs at least 2 constraints, not all with the same target; two vertex constraints give
/// the 2-pin natural conformal map.
///
/// `uv_out` receives 2 doubles per vertex (NaN for unreferenced vertices); `options` may be
/// NULL. Statuses as `uvf_constrained_fixed_boundary_map`.
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_constrained_natural_conformal_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    constraints: *const UvfPointConstraint,
    constraint_count: usize,
    options: *const UvfIntrinsicToolOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        constrained_natural_conformal_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            constraints,
            constraint_count,
            options,
            uv_out,
        )
    }
}

/// `uvf_constrained_natural_conformal_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_constrained_natural_conformal_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_constrained_natural_conformal_map(
    mesh: *const super::mesh_handle::UvfMesh,
    constraints: *const UvfPointConstraint,
    constraint_count: usize,
    options: *const UvfIntrinsicToolOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        constrained_natural_conformal_map_from(MeshSource::Handle(mesh), constraints, constraint_count, options, uv_out)
    }
}

/// `uvf_constrained_natural_conformal_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_constrained_natural_conformal_map`.
unsafe fn constrained_natural_conformal_map_from(
    source: MeshSource,
    constraints: *const UvfPointConstraint,
    constraint_count: usize,
    options: *const UvfIntrinsicToolOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let o = read_options(options, UvfIntrinsicToolOptions::default(), TOOL_OPTIONS_V1, "UvfIntrinsicToolOptions")?;
        let c = constraints_from(constraints, constraint_count)?;
        let mesh = unsafe { source.mesh() }?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let uv = constrained_natural_conformal_map(&mesh, &c, &mut Progress::new(&mut callback))?;
        write_uv(&uv, uv_out)
    })
}

/// Natural conformal map with any number (≥ 2) of pinned vertices: `pin_vertices[i]` goes to
/// (`pin_uv[2i]`, `pin_uv[2i+1]`) (vertex constraints, Desbrun et al. 2002 §4.1). Pins that
/// conflict (one vertex pinned twice to different places) give `UVF_INVALID_ARGUMENT`.
///
/// `pin_vertices` holds `pin_count` indices, `pin_uv` 2·`pin_count` doubles; `uv_out` 2 doubles
/// per vertex. Statuses as `uvf_constrained_fixed_boundary_map`.
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_pinned_natural_conformal_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    pin_vertices: *const u32,
    pin_uv: *const f64,
    pin_count: usize,
    options: *const UvfIntrinsicToolOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        pinned_natural_conformal_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            pin_vertices,
            pin_uv,
            pin_count,
            options,
            uv_out,
        )
    }
}

/// `uvf_pinned_natural_conformal_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_pinned_natural_conformal_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_pinned_natural_conformal_map(
    mesh: *const super::mesh_handle::UvfMesh,
    pin_vertices: *const u32,
    pin_uv: *const f64,
    pin_count: usize,
    options: *const UvfIntrinsicToolOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        pinned_natural_conformal_map_from(MeshSource::Handle(mesh), pin_vertices, pin_uv, pin_count, options, uv_out)
    }
}

/// `uvf_pinned_natural_conformal_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_pinned_natural_conformal_map`.
unsafe fn pinned_natural_conformal_map_from(
    source: MeshSource,
    pin_vertices: *const u32,
    pin_uv: *const f64,
    pin_count: usize,
    options: *const UvfIntrinsicToolOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let o = read_options(options, UvfIntrinsicToolOptions::default(), TOOL_OPTIONS_V1, "UvfIntrinsicToolOptions")?;
        let v = borrow_slice(pin_vertices, pin_count, "pin_vertices")?;
        let p = borrow_slice(pin_uv, checked_count(pin_count, 2, "pin")?, "pin_uv")?;
        let pins: Vec<(u32, [f64; 2])> = v.iter().zip(p.chunks_exact(2)).map(|(&v, p)| (v, [p[0], p[1]])).collect();
        let mesh = unsafe { source.mesh() }?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let uv = pinned_natural_conformal_map(&mesh, &pins, &mut Progress::new(&mut callback))?;
        write_uv(&uv, uv_out)
    })
}
