//! The PGP pipeline (Ray et al. 2006, §3–4): options, the solve returning per-corner (θ, φ), and the
//! result handle with its singularity lists and field.

use crate::pgp::curvature::{curvature_options, UVF_CURVATURE_RINGS};
use crate::status::UvfStatus;
use crate::MeshSource;
use crate::SizedOut;
use crate::UvfProgressFn;
use crate::{borrow_slice, borrow_slice_mut, checked_count, copy_out, guard, progress_closure, read_options};
use std::os::raw::c_void;
use uvflat_core::error::{Error, Result};
use uvflat_core::fields::block_newton::NewtonOptions;
use uvflat_core::fields::pairs::DEFAULT_PAIR_PERIODS;
use uvflat_core::fields::smoothing::{SmoothingOptions, Symmetry};
use uvflat_core::methods::pgp::density::DEFAULT_FEATURE_PERIODS;
use uvflat_core::methods::pgp::dislocations::DEFAULT_DISLOCATION_PERIODS;
use uvflat_core::methods::pgp::quality::{quality, Quality};
use uvflat_core::methods::pgp::{pgp, PgpOptions, PgpResult};
use uvflat_core::progress::Progress;
use uvflat_core::TriMesh;

/// No field smoothing.
pub const UVF_SMOOTH_NONE: u32 = 0;

/// Field smoothing with directions equal modulo 2π (poles).
pub const UVF_SMOOTH_2PI: u32 = 1;

/// Field smoothing modulo π (half-poles).
pub const UVF_SMOOTH_PI: u32 = 2;

/// Field smoothing modulo π/2 (quarter-poles; the default).
pub const UVF_SMOOTH_HALF_PI: u32 = 4;

/// Options of `uvf_pgp`. Initialise with `uvf_pgp_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfPgpOptions {
    /// `sizeof(UvfPgpOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// ω: θ grows by ω per unit length along the field, so one chart (a 2π period) is 2π/ω
    /// long. 0 (default) = 2π / (10 × mean edge length), Ray et al.'s "ten times the average
    /// edge length" read as ten edges per period.
    pub omega: f64,
    /// Optional field K, 3 doubles per vertex (projected on the tangent plane; its direction
    /// is used). NULL (default) = the maximum principal curvature direction.
    pub field: *const f64,
    /// `UVF_SMOOTH_NONE`, `UVF_SMOOTH_2PI`, `UVF_SMOOTH_PI` or `UVF_SMOOTH_HALF_PI` (default).
    pub smoothing: u32,
    /// Non-zero: curl correction (§4.1; fewer singularities, conformal rather than isometric).
    /// Default 0.
    pub curl_correction: u32,
    /// Smoothing intensity ρ in [0, 1) (default 0.8).
    pub rho: f64,
    /// ε of the smoothing's unit-norm penalty (default 0.1).
    pub smoothing_epsilon: f64,
    /// ε of the unit-norm penalty (default 0.1, the paper's is 1e-3: see docs/methods/pgp.md; 0 = linear
    /// solve only).
    pub epsilon: f64,
    /// Newton stops when ‖∇F**‖ is below this (default 1e-6).
    pub gradient_tolerance: f64,
    /// Newton iteration limit (default 100, a safeguard: Newton stops once ‖∇F**‖ < 1e-6, within
    /// 3–78 iterations in 29 of the 30 runs of the closed-mesh table of docs/methods/pgp.md — the mesh torus
    /// without curl correction reaches the limit, `converged` = 0 — and 62 iterations, about 40 s,
    /// for a 207k-face mesh; 10 is about 3× faster with nearly the same singularities, see the
    /// README).
    pub max_newton_iterations: u32,
    /// Curvature neighbourhood, as in `UvfCurvatureOptions` (default `UVF_CURVATURE_RINGS`).
    pub curvature_neighbourhood: u32,
    /// Rings (default 2).
    pub curvature_rings: u32,
    /// Radius for `UVF_CURVATURE_RADIUS`.
    pub curvature_radius: f64,
    /// Optional progress callback (may be NULL); returning non-zero cancels.
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
    /// Non-zero (default 1): untangle the per-corner (θ, φ) after Algorithm 1 — negative
    /// triangles next to singular points made positive by moving vertex phases, every
    /// transition kept (not in the paper; see docs/methods/pgp.md). 0: Algorithm 1's output as it is.
    /// Added after `progress_user`: callers built before it get the default.
    pub untangle: u32,
    /// Minimum number of periods around a curved feature (default 3): where a curvature radius
    /// r holds fewer than this many periods ω r, the field is scaled up (at most 2.5×) so that
    /// legs, horns and fingers narrower than a period get travelling waves rather than singular
    /// standing ones (not in the paper; see docs/methods/pgp.md). 0: the paper's single ω everywhere.
    /// Added after `untangle`: callers built before it get the default.
    pub feature_periods: f64,
    /// Cancel the ± quarter singularities of the smoothed cross field closer than this many
    /// periods (2π/ω) to each other, re-solving the field around them (default 0.5; not in the
    /// paper, see docs/methods/pgp.md). 0: keep the smoothed field's singularities. Added after
    /// `feature_periods`: callers built before it get the default.
    pub pair_periods: f64,
    /// Annihilate pairs of open triangles of opposite winding where the field is regular
    /// (dislocations of the wave pattern) closer than this many periods (2π/ω), turning the
    /// phases around them (default 1.5; not in the paper, see docs/methods/pgp.md). 0: keep the periodic
    /// solve's phases. Added after `pair_periods`: callers built before it get the default.
    pub dislocation_periods: f64,
    /// Non-zero (default 1): before the untangling, turn every vertex's phases by the
    /// least-squares fit of the (θ, φ) triangles to the field, Algorithm 1's integers (hence
    /// every transition and open triangle) kept, and use it only where it leaves no more
    /// singular triangles (not in the paper; see docs/methods/pgp.md). 0: no relaxation. Added after
    /// `dislocation_periods`: callers built before it get the default.
    pub relax: u32,
}

impl Default for UvfPgpOptions {
    fn default() -> Self {
        let n = NewtonOptions::default();
        UvfPgpOptions {
            struct_size: std::mem::size_of::<Self>(),
            omega: 0.0,
            field: std::ptr::null(),
            smoothing: UVF_SMOOTH_HALF_PI,
            curl_correction: 0,
            rho: SmoothingOptions::default().rho,
            smoothing_epsilon: SmoothingOptions::default().newton.epsilon,
            epsilon: n.epsilon,
            gradient_tolerance: n.gradient_tolerance,
            max_newton_iterations: n.max_iterations as u32,
            curvature_neighbourhood: UVF_CURVATURE_RINGS,
            curvature_rings: 2,
            curvature_radius: 0.0,
            progress: None,
            progress_user: std::ptr::null_mut(),
            untangle: 1,
            feature_periods: DEFAULT_FEATURE_PERIODS,
            pair_periods: DEFAULT_PAIR_PERIODS,
            dislocation_periods: DEFAULT_DISLOCATION_PERIODS,
            relax: 1,
        }
    }
}

/// The size of the first version of `UvfPgpOptions` (up to `progress_user`).
const PGP_OPTIONS_V1: usize = std::mem::offset_of!(UvfPgpOptions, untangle);

/// Fills `options` with defaults.
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_options_default(options: *mut UvfPgpOptions) {
    if !options.is_null() {
        options.write(UvfPgpOptions::default());
    }
}

/// Summary of a PGP result (see `uvf_pgp_info`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfPgpInfo {
    /// `sizeof(UvfPgpInfo)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// The ω used.
    pub omega: f64,
    /// Singular vertices (§3.2: corner angles not summing to 2π).
    pub singular_vertex_count: usize,
    /// Singular edges (transition functions disagreeing at the two endpoints).
    pub singular_edge_count: usize,
    /// Singular triangles (open path of Algorithm 1, or non-positive (θ, φ) area).
    pub singular_triangle_count: usize,
    /// Vertices with a non-zero index.
    pub singular_point_count: usize,
    /// Σ of the indices (2 − 2g on a closed surface of genus g).
    pub index_sum: f64,
    /// Newton iterations of the periodic solve.
    pub newton_iterations: u32,
    /// 1 when ‖∇F**‖ reached the tolerance.
    pub converged: u32,
    /// ‖∇F**‖ at the end.
    pub final_gradient: f64,
    /// L2 stretch of (θ, φ)/ω over the non-singular triangles (1 = isometric up to scale).
    pub stretch: f64,
    /// Mean |cos| of the angle between the parameter directions (0 = orthogonal iso-lines).
    pub shear: f64,
    /// Mean angle in degrees between the gradients of θ, φ and the field.
    pub alignment_degrees: f64,
}

/// A PGP result: created by `uvf_pgp`, read with the `uvf_pgp_*` accessors, released with
/// `uvf_pgp_free`.
pub struct UvfPgp {
    pub(super) mesh: TriMesh,
    pub(super) result: PgpResult,
    info: UvfPgpInfo,
}

fn pgp_options(o: &UvfPgpOptions, vertex_count: usize) -> Result<PgpOptions> {
    let symmetry = match o.smoothing {
        UVF_SMOOTH_NONE => None,
        UVF_SMOOTH_2PI => Some(Symmetry::Vector),
        UVF_SMOOTH_PI => Some(Symmetry::Line),
        UVF_SMOOTH_HALF_PI => Some(Symmetry::Cross),
        s => return Err(Error::InvalidArgument(format!("unknown smoothing {s}; use one of UVF_SMOOTH_*"))),
    };
    let newton = NewtonOptions {
        epsilon: o.epsilon,
        gradient_tolerance: o.gradient_tolerance,
        max_iterations: o.max_newton_iterations as usize,
    };
    let field = if o.field.is_null() {
        None
    } else {
        let flat = borrow_slice(o.field, checked_count(vertex_count, 3, "field")?, "field")?;
        Some(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
    };
    Ok(PgpOptions {
        omega: if o.omega == 0.0 { None } else { Some(o.omega) },
        field,
        curvature: curvature_options(o.curvature_neighbourhood, o.curvature_rings, o.curvature_radius)?,
        smoothing: symmetry.map(|symmetry| {
            let d = SmoothingOptions::default();
            SmoothingOptions {
                symmetry,
                rho: o.rho,
                newton: NewtonOptions { epsilon: o.smoothing_epsilon, ..d.newton },
            }
        }),
        curl_correction: o.curl_correction != 0,
        untangle: o.untangle != 0,
        relax: o.relax != 0,
        feature_periods: o.feature_periods,
        pair_periods: o.pair_periods,
        dislocation_periods: o.dislocation_periods,
        newton,
    })
}

fn summary(result: &PgpResult, q: &Quality) -> UvfPgpInfo {
    let s = &result.singularities;
    UvfPgpInfo {
        struct_size: 0,
        omega: result.omega,
        singular_vertex_count: s.vertices.len(),
        singular_edge_count: s.edges.len(),
        singular_triangle_count: s.triangles.len(),
        singular_point_count: s.singular_points().len(),
        index_sum: s.index_sum(),
        newton_iterations: result.solve.iterations as u32,
        converged: result.solve.converged as u32,
        final_gradient: result.solve.final_gradient,
        stretch: q.stretch,
        shear: q.shear,
        alignment_degrees: q.alignment_degrees,
    }
}

/// Periodic Global Parameterization (Ray, Li, Lévy, Sheffer, Alliez 2006) of a manifold mesh of
/// any genus, with or without boundary, without cutting it: principal curvature field
/// (Cohen-Steiner–Morvan), optional smoothing (§4.2, eqs. 21–22) and curl correction (§4.1,
/// eqs. 17–20), the periodic solve of (cos θ, sin θ, cos φ, sin φ) per vertex (§2.3–2.5,
/// eqs. 13–15, 24: linear solve with one vertex locked per component, then Newton on F**), and
/// the per-triangle parameterization of §3.1 (Algorithm 1).
///
/// `corner_coords_out` receives (θ, φ) for every corner: 6 doubles per triangle, corner k of
/// triangle t at `6t + 2k`. θ and φ are in radians with period 2π (use θ/2π, φ/2π as texture
/// coordinates of a periodic texture). If `result_out` is not NULL it receives a handle with
/// the singular vertices, edges, triangles and indices (§3.2) and quality figures; free it
/// with `uvf_pgp_free`. `options` may be NULL for defaults.
///
/// Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (bad options, a field vector that is not finite or
/// normal to the surface — the message names the vertex), `UVF_INVALID_MESH`,
/// `UVF_NUMERICAL_FAILURE`, `UVF_CANCELLED`, `UVF_INTERNAL_ERROR`. On failure the outputs are
/// untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `result_out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfPgpOptions,
    corner_coords_out: *mut f64,
    result_out: *mut *mut UvfPgp,
) -> UvfStatus {
    unsafe {
        pgp_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            corner_coords_out,
            result_out,
        )
    }
}

/// `uvf_pgp` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_pgp`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_pgp(
    mesh: *const crate::mesh_handle::UvfMesh,
    options: *const UvfPgpOptions,
    corner_coords_out: *mut f64,
    result_out: *mut *mut UvfPgp,
) -> UvfStatus {
    unsafe { pgp_from(MeshSource::Handle(mesh), options, corner_coords_out, result_out) }
}

/// `uvf_pgp` on either kind of mesh.
///
/// # Safety
/// As for `uvf_pgp`.
unsafe fn pgp_from(
    source: MeshSource,
    options: *const UvfPgpOptions,
    corner_coords_out: *mut f64,
    result_out: *mut *mut UvfPgp,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, triangle_count) = unsafe { source.counts() }?;
        let o = read_options(options, UvfPgpOptions::default(), PGP_OPTIONS_V1, "UvfPgpOptions")?;
        let opts = pgp_options(&o, vertex_count)?;
        let mesh = unsafe { source.mesh() }?;
        let coords =
            borrow_slice_mut(corner_coords_out, checked_count(triangle_count, 6, "corner")?, "corner_coords_out")?;
        let handle_slot =
            if result_out.is_null() { None } else { Some(borrow_slice_mut(result_out, 1, "result_out")?) };
        let mut callback = progress_closure(o.progress, o.progress_user);
        let result = pgp(&mesh, &opts, &mut Progress::new(&mut callback))?;
        let q = quality(&mesh, &result.param, &result.singularities, &result.normals, &result.field, result.omega)?;
        for (d, c) in coords.chunks_exact_mut(6).zip(&result.param.coords) {
            d.copy_from_slice(c.as_flattened());
        }
        if let Some(slot) = handle_slot {
            let info = summary(&result, &q);
            slot[0] = Box::into_raw(Box::new(UvfPgp { mesh: mesh.into_owned(), result, info }));
        }
        Ok(())
    })
}

/// Borrows the handle, rejecting NULL.
pub(crate) unsafe fn handle<'a>(pgp: *const UvfPgp) -> Result<&'a UvfPgp> {
    // SAFETY: the caller passes a handle from `uvf_pgp` not yet freed, or NULL.
    unsafe { pgp.as_ref() }.ok_or_else(|| Error::InvalidArgument("PGP handle is NULL".into()))
}

/// Counts and quality figures of a PGP result. Returns `UVF_OK` or `UVF_INVALID_ARGUMENT`.
///
/// # Safety
/// `pgp` must be a live handle or NULL; `info_out` writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_info(pgp: *const UvfPgp, info_out: *mut UvfPgpInfo) -> UvfStatus {
    guard(|| {
        let p = unsafe { handle(pgp) }?;
        unsafe { SizedOut::required(info_out, "info_out", "UvfPgpInfo") }?.write(p.info);
        Ok(())
    })
}

/// The singular vertices (`singular_vertex_count` indices, ascending). Returns `UVF_OK` or
/// `UVF_INVALID_ARGUMENT` (NULL, capacity too small; output untouched).
///
/// # Safety
/// `pgp` must be a live handle or NULL; `vertices_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_copy_singular_vertices(
    pgp: *const UvfPgp,
    vertices_out: *mut u32,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let p = unsafe { handle(pgp) }?;
        copy_out(&p.result.singularities.vertices, vertices_out, capacity, "vertices_out")
    })
}

/// The singular edges as vertex pairs a < b (`2 × singular_edge_count` entries, sorted).
/// Statuses as `uvf_pgp_copy_singular_vertices`.
///
/// # Safety
/// `pgp` must be a live handle or NULL; `edges_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_copy_singular_edges(
    pgp: *const UvfPgp,
    edges_out: *mut u32,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let p = unsafe { handle(pgp) }?;
        copy_out(p.result.singularities.edges.as_flattened(), edges_out, capacity, "edges_out")
    })
}

/// The singular triangles (`singular_triangle_count` indices, ascending). Statuses as
/// `uvf_pgp_copy_singular_vertices`.
///
/// # Safety
/// `pgp` must be a live handle or NULL; `triangles_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_copy_singular_triangles(
    pgp: *const UvfPgp,
    triangles_out: *mut u32,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let p = unsafe { handle(pgp) }?;
        copy_out(&p.result.singularities.triangles, triangles_out, capacity, "triangles_out")
    })
}

/// The singular points: `singular_point_count` vertices with a non-zero index of the gradient
/// cross field (multiples of 1/4, summing to 2 − 2g on a closed surface), in `vertices_out` and
/// `indices_out` (each of `capacity` elements). Statuses as `uvf_pgp_copy_singular_vertices`.
///
/// # Safety
/// `pgp` must be a live handle or NULL; both arrays must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_copy_singular_points(
    pgp: *const UvfPgp,
    vertices_out: *mut u32,
    indices_out: *mut f64,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let p = unsafe { handle(pgp) }?;
        let points = p.result.singularities.singular_points();
        let (v, i): (Vec<u32>, Vec<f64>) = points.into_iter().unzip();
        if capacity < v.len() {
            return Err(Error::InvalidArgument(format!(
                "the outputs hold {capacity} elements but {} are needed",
                v.len()
            )));
        }
        copy_out(&v, vertices_out, capacity, "vertices_out")?;
        copy_out(&i, indices_out, capacity, "indices_out")
    })
}

/// The field K the periodic solve followed (after smoothing, scaled by the curl correction
/// when enabled): 3 doubles per vertex (`vertex_count` triples). Statuses as
/// `uvf_pgp_copy_singular_vertices`.
///
/// # Safety
/// `pgp` must be a live handle or NULL; `field_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_copy_field(pgp: *const UvfPgp, field_out: *mut f64, capacity: usize) -> UvfStatus {
    guard(|| {
        let p = unsafe { handle(pgp) }?;
        copy_out(p.result.field.as_flattened(), field_out, capacity, "field_out")
    })
}

/// Releases a PGP handle (NULL is ignored).
///
/// # Safety
/// `pgp` must come from `uvf_pgp` and not have been freed.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_free(pgp: *mut UvfPgp) {
    if !pgp.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            // SAFETY: the pointer came from Box::into_raw in `uvf_pgp`.
            drop(unsafe { Box::from_raw(pgp) });
        }));
    }
}
