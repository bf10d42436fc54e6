//! Fixed-boundary (barycentric) maps: Tutte, Floater, authalic, discrete conformal, mean value
//! and intrinsic weights (Hormann, Polthier & Sheffer 2008, §3; Desbrun, Meyer & Alliez 2002, §3),
//! the boundary shapes and the parameter distributions along the boundary.

use super::status::UvfStatus;
use super::MeshSource;
use super::{borrow_slice, checked_count, guard, progress_closure, read_options, write_uv, UvfProgressFn};
use std::os::raw::c_void;
use uvflat_core::boundary::{BoundaryShape, Distribution};
use uvflat_core::error::{Error, Result};
use uvflat_core::methods::barycentric::{fixed_boundary_map_with_progress, FixedBoundaryOptions, Weights};
use uvflat_core::progress::Progress;

/// Tutte's uniform weights.
pub const UVF_WEIGHTS_UNIFORM: u32 = 0;

/// Floater's shape-preserving weights.
pub const UVF_WEIGHTS_FLOATER: u32 = 1;

/// Wachspress / discrete authalic (DAP, Desbrun et al. 2002 eq. 6).
pub const UVF_WEIGHTS_AUTHALIC: u32 = 2;

/// Discrete harmonic / discrete conformal (DCP, Desbrun et al. 2002 eq. 4).
pub const UVF_WEIGHTS_CONFORMAL: u32 = 3;

/// Floater's mean value weights.
pub const UVF_WEIGHTS_MEAN_VALUE: u32 = 4;

/// λ·DCP + μ·DAP (Desbrun et al. 2002 §3.4); set `lambda` and `mu`.
pub const UVF_WEIGHTS_INTRINSIC: u32 = 5;

/// Boundary on the circle of centre (0.5, 0.5) and radius 0.5.
pub const UVF_BOUNDARY_CIRCLE: u32 = 0;

/// Boundary on the unit square.
pub const UVF_BOUNDARY_SQUARE: u32 = 1;

/// Boundary positions given in `given_vertices` / `given_uv`.
pub const UVF_BOUNDARY_GIVEN: u32 = 2;

/// Equal spacing per boundary edge.
pub const UVF_DISTRIBUTION_UNIFORM: u32 = 0;

/// Spacing proportional to 3D edge length.
pub const UVF_DISTRIBUTION_CHORD: u32 = 1;

/// Spacing proportional to the square root of 3D edge length.
pub const UVF_DISTRIBUTION_CENTRIPETAL: u32 = 2;

/// Options of `uvf_fixed_boundary_map`. Initialise with `uvf_fixed_boundary_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfFixedBoundaryOptions {
    /// `sizeof(UvfFixedBoundaryOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// One of `UVF_WEIGHTS_*` (default mean value).
    pub weights: u32,
    /// One of `UVF_BOUNDARY_*` (default circle).
    pub boundary: u32,
    /// One of `UVF_DISTRIBUTION_*` (default chord length).
    pub distribution: u32,
    /// λ for `UVF_WEIGHTS_INTRINSIC` (default 1).
    pub lambda: f64,
    /// μ for `UVF_WEIGHTS_INTRINSIC` (default 0).
    pub mu: f64,
    /// Number of entries in `given_vertices` (and pairs in `given_uv`) for `UVF_BOUNDARY_GIVEN`.
    pub given_count: usize,
    /// Boundary vertices whose UV is given; must cover whole boundary loops.
    pub given_vertices: *const u32,
    /// 2 doubles per given vertex.
    pub given_uv: *const f64,
    /// Optional progress callback (may be NULL).
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
}

impl Default for UvfFixedBoundaryOptions {
    fn default() -> Self {
        UvfFixedBoundaryOptions {
            struct_size: std::mem::size_of::<Self>(),
            weights: UVF_WEIGHTS_MEAN_VALUE,
            boundary: UVF_BOUNDARY_CIRCLE,
            distribution: UVF_DISTRIBUTION_CHORD,
            lambda: 1.0,
            mu: 0.0,
            given_count: 0,
            given_vertices: std::ptr::null(),
            given_uv: std::ptr::null(),
            progress: None,
            progress_user: std::ptr::null_mut(),
        }
    }
}

/// Fills `options` with defaults (mean value weights, circle, chord-length spacing).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_fixed_boundary_options_default(options: *mut UvfFixedBoundaryOptions) {
    if !options.is_null() {
        options.write(UvfFixedBoundaryOptions::default());
    }
}

fn weights_from(o: &UvfFixedBoundaryOptions) -> Result<Weights> {
    Ok(match o.weights {
        UVF_WEIGHTS_UNIFORM => Weights::Uniform,
        UVF_WEIGHTS_FLOATER => Weights::Floater,
        UVF_WEIGHTS_AUTHALIC => Weights::Authalic,
        UVF_WEIGHTS_CONFORMAL => Weights::Conformal,
        UVF_WEIGHTS_MEAN_VALUE => Weights::MeanValue,
        UVF_WEIGHTS_INTRINSIC => Weights::Intrinsic { lambda: o.lambda, mu: o.mu },
        w => return Err(Error::InvalidArgument(format!("unknown weights {w}; use one of UVF_WEIGHTS_*"))),
    })
}

fn shape_from(o: &UvfFixedBoundaryOptions) -> Result<BoundaryShape> {
    shape_from_parts(o.boundary, o.given_count, o.given_vertices, o.given_uv)
}

/// The boundary shape of a `UVF_BOUNDARY_*` code and, for `UVF_BOUNDARY_GIVEN`, its arrays.
pub(crate) fn shape_from_parts(
    boundary: u32,
    given_count: usize,
    given_vertices: *const u32,
    given_uv: *const f64,
) -> Result<BoundaryShape> {
    Ok(match boundary {
        UVF_BOUNDARY_CIRCLE => BoundaryShape::Circle,
        UVF_BOUNDARY_SQUARE => BoundaryShape::Square,
        UVF_BOUNDARY_GIVEN => {
            let v = borrow_slice(given_vertices, given_count, "given_vertices")?;
            let uv = borrow_slice(given_uv, checked_count(given_count, 2, "given")?, "given_uv")?;
            BoundaryShape::Given(v.iter().zip(uv.chunks_exact(2)).map(|(&v, p)| (v, [p[0], p[1]])).collect())
        }
        b => return Err(Error::InvalidArgument(format!("unknown boundary {b}; use one of UVF_BOUNDARY_*"))),
    })
}

/// The Rust options of a C `UvfFixedBoundaryOptions`.
pub(crate) fn fixed_options_from(o: &UvfFixedBoundaryOptions) -> Result<FixedBoundaryOptions> {
    Ok(FixedBoundaryOptions { weights: weights_from(o)?, shape: shape_from(o)?, distribution: distribution_from(o)? })
}

fn distribution_from(o: &UvfFixedBoundaryOptions) -> Result<Distribution> {
    distribution_from_code(o.distribution)
}

/// The distribution of a `UVF_DISTRIBUTION_*` code.
pub(crate) fn distribution_from_code(code: u32) -> Result<Distribution> {
    Ok(match code {
        UVF_DISTRIBUTION_UNIFORM => Distribution::Uniform,
        UVF_DISTRIBUTION_CHORD => Distribution::ChordLength,
        UVF_DISTRIBUTION_CENTRIPETAL => Distribution::Centripetal,
        d => return Err(Error::InvalidArgument(format!("unknown distribution {d}; use one of UVF_DISTRIBUTION_*"))),
    })
}

/// Smallest options struct accepted (the first released layout).
const FIXED_OPTIONS_V1: usize = std::mem::size_of::<UvfFixedBoundaryOptions>();

/// Fixed-boundary barycentric map (Tutte, Floater, DAP/Wachspress, DCP/harmonic, mean value,
/// or Desbrun et al.'s λ·DCP + μ·DAP): course notes ch. 2, Desbrun et al. 2002 §3–4.1.
///
/// The longest boundary loop goes to the chosen shape (or the given positions); other loops
/// are holes. `uv_out` receives 2 doubles per vertex (`vertex_count` pairs); unreferenced
/// vertices get NaN. `options` may be NULL for defaults.
/// Returns `UVF_OK`, `UVF_INVALID_ARGUMENT`, `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY`
/// (not a single genus-0 component with a boundary), `UVF_NUMERICAL_FAILURE`,
/// `UVF_CANCELLED`, `UVF_INTERNAL_ERROR`. On failure `uv_out` is untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_fixed_boundary_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfFixedBoundaryOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        fixed_boundary_map_from(MeshSource::arrays(positions, vertex_count, triangles, triangle_count), options, uv_out)
    }
}

/// `uvf_fixed_boundary_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_fixed_boundary_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_fixed_boundary_map(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfFixedBoundaryOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe { fixed_boundary_map_from(MeshSource::Handle(mesh), options, uv_out) }
}

/// `uvf_fixed_boundary_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_fixed_boundary_map`.
unsafe fn fixed_boundary_map_from(
    source: MeshSource,
    options: *const UvfFixedBoundaryOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let o = read_options(options, UvfFixedBoundaryOptions::default(), FIXED_OPTIONS_V1, "UvfFixedBoundaryOptions")?;
        let opts = FixedBoundaryOptions {
            weights: weights_from(&o)?,
            shape: shape_from(&o)?,
            distribution: distribution_from(&o)?,
        };
        let mesh = unsafe { source.mesh() }?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let uv = fixed_boundary_map_with_progress(&mesh, &opts, &mut Progress::new(&mut callback))?;
        write_uv(&uv, uv_out)
    })
}
