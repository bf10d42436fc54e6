//! Periodic Global Parameterization (Ray et al. 2006): principal curvatures
//! (`uvf_curvature`), the PGP pipeline (`uvf_pgp`) returning per-corner (θ, φ), and a result
//! handle with the singularity lists (`uvf_pgp_*` accessors, `uvf_pgp_free`).

use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::UvfProgressFn;
use super::{borrow_slice, borrow_slice_mut, checked_count, copy_out, guard, progress_closure, read_options};
use std::os::raw::c_void;
use uvflat_core::error::{Error, Result};
use uvflat_core::methods::pgp::charts::{chart_parameterization, ChartKind, ChartParameterization};
use uvflat_core::methods::pgp::curvature::{principal_curvatures, CurvatureOptions, Neighbourhood};
use uvflat_core::methods::pgp::density::DEFAULT_FEATURE_PERIODS;
use uvflat_core::methods::pgp::dislocations::DEFAULT_DISLOCATION_PERIODS;
use uvflat_core::methods::pgp::pairs::DEFAULT_PAIR_PERIODS;
use uvflat_core::methods::pgp::quality::{quality, Quality};
use uvflat_core::methods::pgp::smoothing::{SmoothingOptions, Symmetry};
use uvflat_core::methods::pgp::solver::NewtonOptions;
use uvflat_core::methods::pgp::{pgp, ChartLayout, PgpOptions, PgpResult, PolygonMesh};
use uvflat_core::progress::Progress;
use uvflat_core::TriMesh;

/// Curvature neighbourhood: the triangles around the vertices at most `rings − 1` edges away.
pub const UVF_CURVATURE_RINGS: u32 = 0;
/// Curvature neighbourhood: the triangles around the vertices within `radius` (graph distance).
pub const UVF_CURVATURE_RADIUS: u32 = 1;

/// Options of `uvf_curvature`. Initialise with `uvf_curvature_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfCurvatureOptions {
    /// `sizeof(UvfCurvatureOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// `UVF_CURVATURE_RINGS` (default) or `UVF_CURVATURE_RADIUS`.
    pub neighbourhood: u32,
    /// Rings for `UVF_CURVATURE_RINGS` (default 2; ≥ 1).
    pub rings: u32,
    /// Radius for `UVF_CURVATURE_RADIUS` (finite, > 0; default 0 = unset).
    pub radius: f64,
}

impl Default for UvfCurvatureOptions {
    fn default() -> Self {
        UvfCurvatureOptions {
            struct_size: std::mem::size_of::<Self>(),
            neighbourhood: UVF_CURVATURE_RINGS,
            rings: 2,
            radius: 0.0,
        }
    }
}

const CURVATURE_OPTIONS_V1: usize = std::mem::size_of::<UvfCurvatureOptions>();

/// Fills `options` with defaults (two rings).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_curvature_options_default(options: *mut UvfCurvatureOptions) {
    if !options.is_null() {
        options.write(UvfCurvatureOptions::default());
    }
}

fn curvature_options(neighbourhood: u32, rings: u32, radius: f64) -> Result<CurvatureOptions> {
    let neighbourhood = match neighbourhood {
        UVF_CURVATURE_RINGS => Neighbourhood::Rings(rings),
        UVF_CURVATURE_RADIUS => Neighbourhood::Radius(radius),
        n => return Err(Error::InvalidArgument(format!("unknown curvature neighbourhood {n}; use UVF_CURVATURE_*"))),
    };
    Ok(CurvatureOptions { neighbourhood })
}

/// Principal curvatures per vertex by the normal-cycle tensor of Cohen-Steiner & Morvan 2003
/// (the input field of Ray et al. 2006, §4.2), averaged over a neighbourhood of each vertex.
///
/// Outputs (each may be NULL to skip it): `kmin_direction_out` and `kmax_direction_out`, 3
/// doubles per vertex (unit tangent directions, kmax = normal × kmin); `kmin_out` and
/// `kmax_out`, 1 double per vertex (signed curvatures, kmin ≤ kmax; a sphere with outward
/// normals has 1/r). Unreferenced vertices get zeros. `options` may be NULL. Returns `UVF_OK`,
/// `UVF_INVALID_ARGUMENT` (bad neighbourhood, bad pointers), `UVF_INVALID_MESH`,
/// `UVF_INTERNAL_ERROR`. On failure the outputs are untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements or be NULL.
#[no_mangle]
pub unsafe extern "C" fn uvf_curvature(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfCurvatureOptions,
    kmin_direction_out: *mut f64,
    kmax_direction_out: *mut f64,
    kmin_out: *mut f64,
    kmax_out: *mut f64,
) -> UvfStatus {
    unsafe {
        curvature_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            kmin_direction_out,
            kmax_direction_out,
            kmin_out,
            kmax_out,
        )
    }
}

/// `uvf_curvature` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_curvature`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_curvature(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfCurvatureOptions,
    kmin_direction_out: *mut f64,
    kmax_direction_out: *mut f64,
    kmin_out: *mut f64,
    kmax_out: *mut f64,
) -> UvfStatus {
    unsafe {
        curvature_from(MeshSource::Handle(mesh), options, kmin_direction_out, kmax_direction_out, kmin_out, kmax_out)
    }
}

/// `uvf_curvature` on either kind of mesh.
///
/// # Safety
/// As for `uvf_curvature`.
unsafe fn curvature_from(
    source: MeshSource,
    options: *const UvfCurvatureOptions,
    kmin_direction_out: *mut f64,
    kmax_direction_out: *mut f64,
    kmin_out: *mut f64,
    kmax_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, _) = unsafe { source.counts() }?;
        let o = read_options(options, UvfCurvatureOptions::default(), CURVATURE_OPTIONS_V1, "UvfCurvatureOptions")?;
        let opts = curvature_options(o.neighbourhood, o.rings, o.radius)?;
        let mesh = unsafe { source.mesh() }?;
        let n3 = checked_count(vertex_count, 3, "vertex")?;
        let kmin_dir = optional_out(kmin_direction_out, n3, "kmin_direction_out")?;
        let kmax_dir = optional_out(kmax_direction_out, n3, "kmax_direction_out")?;
        let kmin = optional_out(kmin_out, vertex_count, "kmin_out")?;
        let kmax = optional_out(kmax_out, vertex_count, "kmax_out")?;
        let c = principal_curvatures(&mesh, &opts)?;
        if let Some(d) = kmin_dir {
            d.copy_from_slice(c.kmin_direction.as_flattened());
        }
        if let Some(d) = kmax_dir {
            d.copy_from_slice(c.kmax_direction.as_flattened());
        }
        if let Some(d) = kmin {
            d.copy_from_slice(&c.kmin);
        }
        if let Some(d) = kmax {
            d.copy_from_slice(&c.kmax);
        }
        Ok(())
    })
}

/// A caller array of `count` elements, or None for NULL.
fn optional_out<'a>(ptr: *mut f64, count: usize, what: &'static str) -> Result<Option<&'a mut [f64]>> {
    if ptr.is_null() {
        Ok(None)
    } else {
        borrow_slice_mut(ptr, count, what).map(Some)
    }
}

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
    mesh: TriMesh,
    result: PgpResult,
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
    mesh: *const super::mesh_handle::UvfMesh,
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
unsafe fn handle<'a>(pgp: *const UvfPgp) -> Result<&'a UvfPgp> {
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

/// A quad-dominant remesh of a PGP result (Ray et al. 2006, §5) or of the integer grid lines of
/// a QuadCover map: created by `uvf_pgp_quad_mesh` or `uvf_quadcover_quad_mesh`, read with
/// `uvf_quad_mesh_info` and `uvf_quad_mesh_copy`, released with `uvf_quad_mesh_free`.
pub struct UvfQuadMesh {
    pub(super) mesh: PolygonMesh,
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

/// The chart layout of a PGP result (Ray et al. 2006, §3.3): created by
/// `uvf_pgp_chart_layout`, read with `uvf_chart_layout_info` and `uvf_chart_layout_copy`,
/// released with `uvf_chart_layout_free`.
pub struct UvfChartLayout {
    layout: ChartLayout,
}

/// Counts of a chart layout.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfChartLayoutInfo {
    /// `sizeof(UvfChartLayoutInfo)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Chart-boundary polylines.
    pub polyline_count: usize,
    /// Points of all polylines (3 doubles each in `uvf_chart_layout_copy`).
    pub point_count: usize,
    /// Charts (faces bounded by the polylines).
    pub chart_count: usize,
    /// Charts with four corners (the regular ones).
    pub four_corner_chart_count: usize,
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

fn check_capacity(capacity: usize, needed: usize, what: &str) -> Result<()> {
    if capacity < needed {
        return Err(Error::InvalidArgument(format!("{what} holds {capacity} elements but {needed} are needed")));
    }
    Ok(())
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

/// Chart layout (§3.3, Algorithm 2): the chart boundaries along the iso-2kπ lines of θ and φ
/// as polylines on the surface between chart corners, and the number of corners of every
/// chart (the per-chart parameterization of §3.4: `uvf_pgp_charts`). Returns `UVF_OK` (a
/// handle in `*layout_out`, free it with `uvf_chart_layout_free`) or `UVF_INVALID_ARGUMENT`
/// (NULL handle or output; `*layout_out` untouched).
///
/// # Safety
/// `pgp` must be a live handle or NULL; `layout_out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_chart_layout(pgp: *const UvfPgp, layout_out: *mut *mut UvfChartLayout) -> UvfStatus {
    guard(|| {
        let p = unsafe { handle(pgp) }?;
        let slot = borrow_slice_mut(layout_out, 1, "layout_out")?;
        let layout = uvflat_core::methods::pgp::chart_layout(&p.mesh, &p.result)?;
        slot[0] = Box::into_raw(Box::new(UvfChartLayout { layout }));
        Ok(())
    })
}

/// Counts of a chart layout. Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL).
///
/// # Safety
/// `layout` must be a live handle or NULL; `info_out` writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_chart_layout_info(
    layout: *const UvfChartLayout,
    info_out: *mut UvfChartLayoutInfo,
) -> UvfStatus {
    guard(|| {
        // SAFETY: the caller passes a handle from `uvf_pgp_chart_layout` not yet freed, or NULL.
        let l = &unsafe { layout.as_ref() }
            .ok_or_else(|| Error::InvalidArgument("chart layout handle is NULL".into()))?
            .layout;
        unsafe { SizedOut::required(info_out, "info_out", "UvfChartLayoutInfo") }?.write(UvfChartLayoutInfo {
            struct_size: 0,
            polyline_count: l.polylines.len(),
            point_count: l.polylines.iter().map(Vec::len).sum(),
            chart_count: l.chart_corners.len(),
            four_corner_chart_count: l.chart_corners.iter().filter(|&&c| c == 4).count(),
        });
        Ok(())
    })
}

/// Copies a chart layout: `polyline_count` polyline sizes (points per polyline),
/// `3 × point_count` coordinates (the polylines concatenated) and `chart_count` corner counts.
/// Any output may be NULL (with capacity 0) to skip it. Statuses as `uvf_quad_mesh_copy`.
///
/// # Safety
/// `layout` must be a live handle or NULL; each non-NULL output must hold its capacity.
#[no_mangle]
pub unsafe extern "C" fn uvf_chart_layout_copy(
    layout: *const UvfChartLayout,
    polyline_sizes_out: *mut u32,
    polyline_sizes_capacity: usize,
    points_out: *mut f64,
    points_capacity: usize,
    chart_corners_out: *mut u32,
    chart_corners_capacity: usize,
) -> UvfStatus {
    guard(|| {
        // SAFETY: as in `uvf_chart_layout_info`.
        let l = &unsafe { layout.as_ref() }
            .ok_or_else(|| Error::InvalidArgument("chart layout handle is NULL".into()))?
            .layout;
        let sizes: Vec<u32> = l.polylines.iter().map(|p| p.len() as u32).collect();
        let points: Vec<f64> = l.polylines.iter().flatten().flatten().copied().collect();
        check_optional(polyline_sizes_out, polyline_sizes_capacity, sizes.len(), "polyline_sizes_out")?;
        check_optional(points_out, points_capacity, points.len(), "points_out")?;
        check_optional(chart_corners_out, chart_corners_capacity, l.chart_corners.len(), "chart_corners_out")?;
        copy_optional(&sizes, polyline_sizes_out, polyline_sizes_capacity, "polyline_sizes_out")?;
        copy_optional(&points, points_out, points_capacity, "points_out")?;
        copy_optional(&l.chart_corners, chart_corners_out, chart_corners_capacity, "chart_corners_out")
    })
}

/// Releases a chart layout (NULL is ignored).
///
/// # Safety
/// `layout` must come from `uvf_pgp_chart_layout` and not have been freed.
#[no_mangle]
pub unsafe extern "C" fn uvf_chart_layout_free(layout: *mut UvfChartLayout) {
    if !layout.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            // SAFETY: the pointer came from Box::into_raw in `uvf_pgp_chart_layout`.
            drop(unsafe { Box::from_raw(layout) });
        }));
    }
}

/// Chart kind: a chart without singularity, its triangles' (θ, φ) assembled (§3.4).
pub const UVF_PGP_CHART_ASSEMBLED: u32 = 0;
/// Chart kind: four corners, equal opposite sides, re-parameterized by mean-value coordinates.
pub const UVF_PGP_CHART_MEAN_VALUE: u32 = 1;
/// Chart kind: one of the quads an N-sided chart was split into, mean-value re-parameterized.
pub const UVF_PGP_CHART_SPLIT_QUAD: u32 = 2;
/// Chart kind: part of a chart that is not a disk with three or more corners, flattened by the
/// atlas segmentation (no quad structure, not continuous with its neighbours, not folded).
pub const UVF_PGP_CHART_ATLAS: u32 = 3;
/// Chart kind: per-triangle (θ, φ) kept (the atlas failed on it).
pub const UVF_PGP_CHART_UNRESOLVED: u32 = 4;

/// The per-chart parameterization of a PGP result (Ray et al. 2006, §3.3–3.4): the surface
/// cut along the chart boundaries, every chart with its own (u, v). Created by
/// `uvf_pgp_charts`, read with `uvf_pgp_charts_info`, `uvf_pgp_charts_copy` and
/// `uvf_pgp_charts_copy_charts`, released with `uvf_pgp_charts_free`.
pub struct UvfPgpCharts {
    charts: ChartParameterization,
}

/// Counts of a per-chart parameterization.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfPgpChartsInfo {
    /// `sizeof(UvfPgpChartsInfo)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Vertices of the cut triangulation (the input's first, in the same order).
    pub vertex_count: usize,
    /// Triangles of the cut triangulation.
    pub triangle_count: usize,
    /// Charts.
    pub chart_count: usize,
    /// Charts of each kind, indexed by `UVF_PGP_CHART_*`.
    pub kind_counts: [usize; 5],
}

/// Per-chart parameterization (§3.3–3.4): cuts the surface along the iso-lines at `density`
/// lines per period (1: the paper's iso-2kπ chart boundaries; a whole number) and
/// parameterizes every chart in cells (a regular chart is the unit square): charts without
/// singularity are assembled from the per-triangle (θ, φ), four-sided charts with
/// singularities are re-parameterized by mean-value coordinates, N-sided ones split into N
/// quads; the (u, v) of two charts agree along their common side. Returns `UVF_OK` (a handle
/// in `*charts_out`, free it with `uvf_pgp_charts_free`) or `UVF_INVALID_ARGUMENT` (NULL handle
/// or output, bad density, or one whose line graph would not fit in the memory available;
/// `*charts_out` untouched).
///
/// # Safety
/// `pgp` must be a live handle or NULL; `charts_out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_charts(
    pgp: *const UvfPgp,
    density: f64,
    charts_out: *mut *mut UvfPgpCharts,
) -> UvfStatus {
    guard(|| {
        let p = unsafe { handle(pgp) }?;
        let slot = borrow_slice_mut(charts_out, 1, "charts_out")?;
        let charts = chart_parameterization(&p.mesh, &p.result, density)?;
        slot[0] = Box::into_raw(Box::new(UvfPgpCharts { charts }));
        Ok(())
    })
}

/// The parameterization behind a charts handle.
///
/// # Safety
/// `charts` must be a live handle or NULL.
unsafe fn charts_ref<'a>(charts: *const UvfPgpCharts) -> Result<&'a ChartParameterization> {
    // SAFETY: the caller passes a handle from `uvf_pgp_charts` not yet freed, or NULL.
    Ok(&unsafe { charts.as_ref() }.ok_or_else(|| Error::InvalidArgument("charts handle is NULL".into()))?.charts)
}

fn kind_code(kind: ChartKind) -> u32 {
    match kind {
        ChartKind::Assembled => UVF_PGP_CHART_ASSEMBLED,
        ChartKind::MeanValue => UVF_PGP_CHART_MEAN_VALUE,
        ChartKind::SplitQuad => UVF_PGP_CHART_SPLIT_QUAD,
        ChartKind::Atlas => UVF_PGP_CHART_ATLAS,
        ChartKind::Unresolved => UVF_PGP_CHART_UNRESOLVED,
    }
}

/// Counts of a per-chart parameterization. Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL).
///
/// # Safety
/// `charts` must be a live handle or NULL; `info_out` writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_charts_info(
    charts: *const UvfPgpCharts,
    info_out: *mut UvfPgpChartsInfo,
) -> UvfStatus {
    guard(|| {
        let c = unsafe { charts_ref(charts) }?;
        let mut kind_counts = [0usize; 5];
        for ch in &c.charts {
            kind_counts[kind_code(ch.kind) as usize] += 1;
        }
        unsafe { SizedOut::required(info_out, "info_out", "UvfPgpChartsInfo") }?.write(UvfPgpChartsInfo {
            struct_size: 0,
            vertex_count: c.positions.len(),
            triangle_count: c.triangles.len(),
            chart_count: c.charts.len(),
            kind_counts,
        });
        Ok(())
    })
}

/// Copies the cut triangulation and its parameterization: `3 × vertex_count` coordinates,
/// `3 × triangle_count` vertex indices (counter-clockwise like the input), `6 × triangle_count`
/// (u, v) values (per corner, in cells), the chart of every triangle and the input triangle it
/// lies in (`triangle_count` each). Any output may be NULL (with capacity 0) to skip it.
/// Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL handle, a capacity too small; outputs
/// untouched).
///
/// # Safety
/// `charts` must be a live handle or NULL; each non-NULL output must hold its capacity.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_pgp_charts_copy(
    charts: *const UvfPgpCharts,
    positions_out: *mut f64,
    positions_capacity: usize,
    triangles_out: *mut u32,
    triangles_capacity: usize,
    uv_out: *mut f64,
    uv_capacity: usize,
    chart_out: *mut u32,
    chart_capacity: usize,
    origin_out: *mut u32,
    origin_capacity: usize,
) -> UvfStatus {
    guard(|| {
        let c = unsafe { charts_ref(charts) }?;
        let uv: Vec<f64> = c.uv.iter().flatten().flatten().copied().collect();
        check_optional(positions_out, positions_capacity, 3 * c.positions.len(), "positions_out")?;
        check_optional(triangles_out, triangles_capacity, 3 * c.triangles.len(), "triangles_out")?;
        check_optional(uv_out, uv_capacity, uv.len(), "uv_out")?;
        check_optional(chart_out, chart_capacity, c.chart.len(), "chart_out")?;
        check_optional(origin_out, origin_capacity, c.origin.len(), "origin_out")?;
        copy_optional(c.positions.as_flattened(), positions_out, positions_capacity, "positions_out")?;
        copy_optional(c.triangles.as_flattened(), triangles_out, triangles_capacity, "triangles_out")?;
        copy_optional(&uv, uv_out, uv_capacity, "uv_out")?;
        copy_optional(&c.chart, chart_out, chart_capacity, "chart_out")?;
        copy_optional(&c.origin, origin_out, origin_capacity, "origin_out")
    })
}

/// Checks the capacity of an output that may be NULL (skipped).
fn check_optional<T>(out: *mut T, capacity: usize, needed: usize, what: &str) -> Result<()> {
    if out.is_null() {
        Ok(())
    } else {
        check_capacity(capacity, needed, what)
    }
}

/// Copies `src` into an output that may be NULL (skipped).
fn copy_optional<T: Copy>(src: &[T], out: *mut T, capacity: usize, what: &'static str) -> Result<()> {
    if out.is_null() {
        Ok(())
    } else {
        copy_out(src, out, capacity, what)
    }
}

/// Copies, per chart (`chart_count` entries each): its kind (`UVF_PGP_CHART_*`), its number of
/// corners (0 when it is not a disk), the layout chart it comes from (the same for the quads
/// of one split chart) and its (u, v) extent in cells (2 doubles). Outputs may be NULL (with
/// capacity 0). Statuses as `uvf_pgp_charts_copy`.
///
/// # Safety
/// `charts` must be a live handle or NULL; each non-NULL output must hold its capacity.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_pgp_charts_copy_charts(
    charts: *const UvfPgpCharts,
    kinds_out: *mut u32,
    kinds_capacity: usize,
    corners_out: *mut u32,
    corners_capacity: usize,
    layout_out: *mut u32,
    layout_capacity: usize,
    sizes_out: *mut f64,
    sizes_capacity: usize,
) -> UvfStatus {
    guard(|| {
        let c = unsafe { charts_ref(charts) }?;
        let kinds: Vec<u32> = c.charts.iter().map(|ch| kind_code(ch.kind)).collect();
        let corners: Vec<u32> = c.charts.iter().map(|ch| ch.corners).collect();
        let layout: Vec<u32> = c.charts.iter().map(|ch| ch.layout).collect();
        let sizes: Vec<f64> = c.charts.iter().flat_map(|ch| ch.size).collect();
        check_optional(kinds_out, kinds_capacity, kinds.len(), "kinds_out")?;
        check_optional(corners_out, corners_capacity, corners.len(), "corners_out")?;
        check_optional(layout_out, layout_capacity, layout.len(), "layout_out")?;
        check_optional(sizes_out, sizes_capacity, sizes.len(), "sizes_out")?;
        copy_optional(&kinds, kinds_out, kinds_capacity, "kinds_out")?;
        copy_optional(&corners, corners_out, corners_capacity, "corners_out")?;
        copy_optional(&layout, layout_out, layout_capacity, "layout_out")?;
        copy_optional(&sizes, sizes_out, sizes_capacity, "sizes_out")
    })
}

/// Releases a per-chart parameterization (NULL is ignored).
///
/// # Safety
/// `charts` must come from `uvf_pgp_charts` and not have been freed.
#[no_mangle]
pub unsafe extern "C" fn uvf_pgp_charts_free(charts: *mut UvfPgpCharts) {
    if !charts.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            // SAFETY: the pointer came from Box::into_raw in `uvf_pgp_charts`.
            drop(unsafe { Box::from_raw(charts) });
        }));
    }
}
