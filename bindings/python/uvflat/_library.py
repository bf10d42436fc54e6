"""Finding and loading ``libuvflat``, and the ctypes mirror of ``include/uvflat.h``.

Everything here follows the header line by line: the structs are ``ctypes.Structure``
subclasses with the header's fields in the header's order, and every ``uvf_*`` function gets
its ``argtypes`` and ``restype`` when the library is loaded. Nothing here converts arrays or
raises per-call errors; that is the method modules (:mod:`uvflat._common` and its siblings)'s job.

Where the library comes from, in this order:

1. the path given to :func:`load_library`;
2. the ``UVFLAT_LIBRARY`` environment variable (a path to the shared library);
3. a ``libuvflat.so`` (``.dylib``, ``uvflat.dll``) copied into this package's directory;
4. the system search path (``ctypes.util.find_library("uvflat")``, then plain
   ``libuvflat.so``, which the dynamic loader looks up in ``LD_LIBRARY_PATH`` and the
   ``ldconfig`` cache).

GIL: calls through a ``ctypes.CDLL`` release the GIL for the duration of the C call, so
several Python threads can run uvflat functions at the same time (the library is reentrant and
its error message is thread-local). A progress callback re-acquires the GIL while it runs.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import sys
import threading
from ctypes import (
    CFUNCTYPE,
    POINTER,
    Structure,
    c_char_p,
    c_double,
    c_int,
    c_int32,
    c_int64,
    c_size_t,
    c_uint8,
    c_uint32,
    c_uint64,
    c_void_p,
)
from typing import Optional, Union

from ._errors import LibraryError

#: The ABI version this binding was written for (``UVF_ABI_VERSION`` in ``uvflat.h``).
ABI_VERSION = 1

#: Name of the environment variable that points at the shared library.
LIBRARY_ENV = "UVFLAT_LIBRARY"

# --- constants (uvflat.h) -------------------------------------------------------------------

UVF_WEIGHTS_UNIFORM = 0
UVF_WEIGHTS_FLOATER = 1
UVF_WEIGHTS_AUTHALIC = 2
UVF_WEIGHTS_CONFORMAL = 3
UVF_WEIGHTS_MEAN_VALUE = 4
UVF_WEIGHTS_INTRINSIC = 5

UVF_BOUNDARY_CIRCLE = 0
UVF_BOUNDARY_SQUARE = 1
UVF_BOUNDARY_GIVEN = 2

UVF_DISTRIBUTION_UNIFORM = 0
UVF_DISTRIBUTION_CHORD = 1
UVF_DISTRIBUTION_CENTRIPETAL = 2

UVF_ABF_VARIANT_ABF = 0
UVF_ABF_VARIANT_ABF_PLUS_PLUS = 1
UVF_ABF_WEIGHTS_ANGLE_AND_SUPPLEMENT = 0
UVF_ABF_WEIGHTS_INVERSE_SQUARE = 1
UVF_ABF_WEIGHTS_INVERSE = 2

UVF_PGP_CHART_ASSEMBLED = 0
UVF_PGP_CHART_MEAN_VALUE = 1
UVF_PGP_CHART_SPLIT_QUAD = 2
UVF_PGP_CHART_ATLAS = 3
UVF_PGP_CHART_UNRESOLVED = 4

UVF_NONLINEAR_SLIM = 0
UVF_NONLINEAR_ARAP = 1
UVF_NONLINEAR_MIPS = 2
UVF_NONLINEAR_STRETCH = 3
UVF_NONLINEAR_GREEN_LAGRANGE = 4
UVF_NONLINEAR_DEGENER = 5

UVF_CUT_COST_CURVATURE = 0
UVF_CUT_COST_LENGTH = 1
UVF_CUT_COST_GIVEN = 2

UVF_ENERGY_EDGE_LENGTH = 0
UVF_ENERGY_AREA = 1
UVF_ATLAS_CHART_NATURAL_CONFORMAL = 0
UVF_ATLAS_CHART_MEAN_VALUE = 1
UVF_ATLAS_CHART_SLIM = 2
UVF_ATLAS_CHART_STRETCH = 3

UVF_SPHERE_TUTTE_GNOMONIC = 0
UVF_SPHERE_GAUSS_SEIDEL = 1
UVF_SPHERE_STEREOGRAPHIC = 2
UVF_SPHERE_CIRCLE_PATTERNS = 3

UVF_CURVATURE_RINGS = 0
UVF_CURVATURE_RADIUS = 1

UVF_SCALAR_DOUBLE = 0
UVF_SCALAR_FLOAT = 1
UVF_INDEX_UINT32 = 0
UVF_INDEX_UINT16 = 1

UVF_SMOOTH_NONE = 0
UVF_SMOOTH_2PI = 1
UVF_SMOOTH_PI = 2
UVF_SMOOTH_HALF_PI = 4

# --- types (uvflat.h) -----------------------------------------------------------------------

#: ``enum UvfStatus`` is passed as a C ``int``.
UvfStatus = c_int

#: ``typedef int (*UvfProgressFn)(void *user, double fraction);``
UvfProgressFn = CFUNCTYPE(c_int, c_void_p, c_double)


class _Written(Structure):
    """A struct the library writes into (report, info): ``struct_size`` is set on creation, and
    the library writes only that many bytes."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        super().__init__(*args, **kwargs)
        self.struct_size = ctypes.sizeof(self)


class UvfMeshInfo(_Written):
    """``struct UvfMeshInfo``: counts and topological invariants of a mesh."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("vertices", c_size_t),
        ("referenced_vertices", c_size_t),
        ("triangles", c_size_t),
        ("edges", c_size_t),
        ("components", c_size_t),
        ("boundary_loops", c_size_t),
        ("boundary_vertices", c_size_t),
        ("euler_characteristic", c_int64),
        ("genus", c_int64),
    ]


class UvfPolygonIslandsInfo(_Written):
    """``struct UvfPolygonIslandsInfo``: what ``uvf_polygon_islands`` found."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("islands", c_size_t),
        ("island_vertices", c_size_t),
        ("non_manifold_edges", c_size_t),
        ("misoriented_edges", c_size_t),
    ]


class UvfSnappedRepairInfo(_Written):
    """``struct UvfSnappedRepairInfo``: what ``uvf_snapped_repair`` found."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("vertices", c_size_t),
        ("welded", c_size_t),
        ("left_out", c_size_t),
        ("unreferenced", c_size_t),
    ]


class UvfPackOptions(Structure):
    """``struct UvfPackOptions``; fill with ``uvf_pack_options_default``."""

    _fields_ = [("struct_size", c_size_t), ("margin", c_double), ("rotate", c_uint32)]


class UvfPackReport(_Written):
    """``struct UvfPackReport``: what ``uvf_pack_islands`` did."""

    _fields_ = [("struct_size", c_size_t), ("islands", c_size_t), ("utilization", c_double)]


class UvfFixedBoundaryOptions(Structure):
    """``struct UvfFixedBoundaryOptions``; fill with ``uvf_fixed_boundary_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("weights", c_uint32),
        ("boundary", c_uint32),
        ("distribution", c_uint32),
        ("lambda_", c_double),  # `lambda` in C; a Python keyword
        ("mu", c_double),
        ("given_count", c_size_t),
        ("given_vertices", POINTER(c_uint32)),
        ("given_uv", POINTER(c_double)),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfNaturalConformalOptions(Structure):
    """``struct UvfNaturalConformalOptions``; fill with ``uvf_natural_conformal_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("pin_count", c_uint32),
        ("pin_vertices", c_uint32 * 2),
        ("pin_uv", c_double * 4),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfMetrics(_Written):
    """``struct UvfMetrics``: distortion summary of a UV map."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("triangles", c_size_t),
        ("flipped", c_size_t),
        ("degenerate_uv", c_size_t),
        ("boundary_intersections", c_size_t),
        ("stretch_l2", c_double),
        ("stretch_linf", c_double),
        ("conformal_mean", c_double),
        ("conformal_max", c_double),
        ("angle_mean", c_double),
        ("angle_max", c_double),
        ("area_mean", c_double),
        ("area_max", c_double),
    ]


class UvfAbfOptions(Structure):
    """``struct UvfAbfOptions``; fill with ``uvf_abf_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("variant", c_uint32),
        ("max_iterations", c_uint32),
        ("tolerance", c_double),
        ("pin_count", c_uint32),
        ("pin_vertices", c_uint32 * 2),
        ("pin_uv", c_double * 4),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
        ("weights", c_uint32),
        ("barrier", c_double),
    ]


class UvfAbfReport(_Written):
    """``struct UvfAbfReport``: iterations and convergence of an ABF / ABF++ run."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("iterations", c_uint32),
        ("converged", c_uint32),
        ("gradient_norm", c_double),
        ("invalid_angles", c_uint64),
    ]


class UvfIntrinsicToolOptions(Structure):
    """``struct UvfIntrinsicToolOptions``; fill with ``uvf_intrinsic_tool_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfPointConstraint(Structure):
    """``struct UvfPointConstraint``: a point (triangle, barycentric coordinates) and its UV."""

    _fields_ = [
        ("triangle", c_uint32),
        ("barycentric", c_double * 3),
        ("uv", c_double * 2),
    ]


class UvfSpectralOptions(Structure):
    """``struct UvfSpectralOptions``; fill with ``uvf_spectral_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("iterations", c_uint32),
        ("tolerance", c_double),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfSpectralReport(_Written):
    """``struct UvfSpectralReport``: the eigenpair behind a spectral conformal map."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("iterations", c_uint32),
        ("converged", c_uint32),
        ("eigenvalue", c_double),
        ("residual", c_double),
    ]


class UvfCirclePatternOptions(Structure):
    """``struct UvfCirclePatternOptions``; fill with ``uvf_circle_pattern_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("max_iterations", c_uint32),
        ("tolerance", c_double),
        ("pin_count", c_uint32),
        ("pin_vertices", c_uint32 * 2),
        ("pin_uv", c_double * 4),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
        ("intrinsic_delaunay", c_uint32),
        ("boundary_curvature", POINTER(c_double)),
        ("convex_boundary", c_uint32),
    ]


class UvfCirclePatternReport(_Written):
    """``struct UvfCirclePatternReport``: Newton steps and closure of a circle-pattern map."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("angle_iterations", c_uint32),
        ("radius_iterations", c_uint32),
        ("closure_error", c_double),
        ("non_delaunay_edges", c_uint32),
        ("max_angle_change", c_double),
        ("intrinsic_flips", c_uint32),
        ("flipped_triangles", c_uint32),
        ("radius_span", c_double),
    ]


class UvfConePlacementOptions(Structure):
    """``struct UvfConePlacementOptions``; fill with ``uvf_cone_placement_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("max_cones", c_uint32),
        ("max_log_scale", c_double),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfQuadCoverOptions(Structure):
    """``struct UvfQuadCoverOptions``; fill with ``uvf_quadcover_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("grid_spacing", c_double),
        ("alignment", c_double),
        ("round", c_uint32),
        ("cones_on_grid", c_uint32),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
        ("pair_cells", c_double),
        ("untangle", c_uint32),
    ]


class UvfQuadCoverReport(_Written):
    """``struct UvfQuadCoverReport``: cones, folds and energies of a QuadCover map."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("cone_count", c_uint32),
        ("chain_count", c_uint32),
        ("flipped_count", c_uint32),
        ("grid_spacing", c_double),
        ("rounding_offset", c_double),
        ("lattice_error", c_double),
        ("energy_continuous", c_double),
        ("energy", c_double),
        ("cones_before_cancellation", c_uint32),
        ("cancelled_pairs", c_uint32),
        ("cones_moved_to_boundary", c_uint32),
        ("flipped_before_untangling", c_uint32),
        ("forced_flat_count", c_uint32),
    ]


class UvfIntrinsicOptimalOptions(Structure):
    """``struct UvfIntrinsicOptimalOptions``; fill with ``uvf_intrinsic_optimal_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("energy", c_uint32),
        ("boundary", c_uint32),
        ("distribution", c_uint32),
        ("lambda_min", c_double),
        ("lambda_max", c_double),
        ("given_count", c_size_t),
        ("given_vertices", POINTER(c_uint32)),
        ("given_uv", POINTER(c_double)),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfIntrinsicOptimalReport(_Written):
    """``struct UvfIntrinsicOptimalReport``: the chosen λ and the energies."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("lambda_", c_double),  # `lambda` in C; a Python keyword
        ("energy", c_double),
        ("energy_conformal", c_double),
        ("energy_authalic", c_double),
        ("boundary_scale", c_double),
        ("flipped", c_size_t),
    ]


class UvfBoundaryOptimizationOptions(Structure):
    """``struct UvfBoundaryOptimizationOptions``; fill with
    ``uvf_boundary_optimization_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("energy", c_uint32),
        ("iterations", c_uint32),
        ("lambda_", c_double),  # `lambda` in C; a Python keyword
        ("mu", c_double),
        ("tolerance", c_double),
        ("boundary", c_uint32),
        ("distribution", c_uint32),
        ("given_count", c_size_t),
        ("given_vertices", POINTER(c_uint32)),
        ("given_uv", POINTER(c_double)),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfBoundaryOptimizationReport(_Written):
    """``struct UvfBoundaryOptimizationReport``: iterations and energies of a boundary
    optimization."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("iterations", c_uint32),
        ("converged", c_uint32),
        ("history_length", c_size_t),
        ("initial_energy", c_double),
        ("final_energy", c_double),
        ("boundary_scale", c_double),
        ("flipped", c_size_t),
    ]


class UvfNonlinearOptions(Structure):
    """``struct UvfNonlinearOptions``; fill with ``uvf_nonlinear_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("method", c_uint32),
        ("iterations", c_uint32),
        ("tolerance", c_double),
        ("theta", c_double),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
        ("bijective", c_uint32),
    ]


class UvfNonlinearReport(_Written):
    """``struct UvfNonlinearReport``: iterations and energies of a non-linear run."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("iterations", c_uint32),
        ("converged", c_uint32),
        ("initial_energy", c_double),
        ("final_energy", c_double),
    ]


class UvfCutOptions(Structure):
    """``struct UvfCutOptions``; fill with ``uvf_cut_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("cost", c_uint32),
        ("edge_cost", POINTER(c_double)),
    ]


class UvfCutInfo(_Written):
    """``struct UvfCutInfo``: sizes of a cut's outputs and its seam length."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("vertex_count", c_size_t),
        ("triangle_count", c_size_t),
        ("edge_count", c_size_t),
        ("seam_length", c_double),
        ("total_edge_length", c_double),
    ]


class UvfAtlasOptions(Structure):
    """``struct UvfAtlasOptions``; fill with ``uvf_atlas_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("max_stretch", c_double),
        ("margin", c_double),
        ("method", c_uint32),
        ("iterations", c_uint32),
        ("rotate", c_uint32),
        ("merge", c_uint32),
        ("polish_iterations", c_uint32),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfAtlasInfo(_Written):
    """``struct UvfAtlasInfo``: sizes and figures of an atlas."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("vertex_count", c_size_t),
        ("triangle_count", c_size_t),
        ("chart_count", c_size_t),
        ("utilization", c_double),
        ("stretch_l2", c_double),
        ("max_chart_stretch", c_double),
    ]


class UvfUnwrapOptions(Structure):
    """``struct UvfUnwrapOptions``; fill with ``uvf_unwrap_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("max_stretch", c_double),
        ("margin", c_double),
        ("method", c_uint32),
        ("iterations", c_uint32),
        ("rotate", c_uint32),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfUnwrapReport(_Written):
    """``struct UvfUnwrapReport``: what ``uvf_unwrap`` did."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("islands", c_size_t),
        ("repaired_islands", c_size_t),
        ("seam_edges", c_size_t),
        ("uv_vertex_count", c_size_t),
        ("flipped", c_size_t),
        ("overlaps", c_size_t),
        ("stretch_l2", c_double),
        ("max_island_stretch", c_double),
        ("angle_error_mean_deg", c_double),
        ("utilization", c_double),
        ("welded_vertices", c_size_t),
        ("left_out_triangles", c_size_t),
    ]


class UvfLayoutCheck(_Written):
    """``struct UvfLayoutCheck``: what ``uvf_check_layout`` found."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("flipped", c_size_t),
        ("overlaps", c_size_t),
        ("islands", c_size_t),
    ]


class UvfSphereOptions(Structure):
    """``struct UvfSphereOptions``; fill with ``uvf_sphere_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("method", c_uint32),
        ("sweeps", c_uint32),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
    ]


class UvfCurvatureOptions(Structure):
    """``struct UvfCurvatureOptions``; fill with ``uvf_curvature_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("neighbourhood", c_uint32),
        ("rings", c_uint32),
        ("radius", c_double),
    ]


class UvfPgpOptions(Structure):
    """``struct UvfPgpOptions``; fill with ``uvf_pgp_options_default``."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("omega", c_double),
        ("field", POINTER(c_double)),
        ("smoothing", c_uint32),
        ("curl_correction", c_uint32),
        ("rho", c_double),
        ("smoothing_epsilon", c_double),
        ("epsilon", c_double),
        ("gradient_tolerance", c_double),
        ("max_newton_iterations", c_uint32),
        ("curvature_neighbourhood", c_uint32),
        ("curvature_rings", c_uint32),
        ("curvature_radius", c_double),
        ("progress", UvfProgressFn),
        ("progress_user", c_void_p),
        ("untangle", c_uint32),
        ("feature_periods", c_double),
        ("pair_periods", c_double),
        ("dislocation_periods", c_double),
        ("relax", c_uint32),
    ]


class UvfPgpInfo(_Written):
    """``struct UvfPgpInfo``: counts and quality figures of a PGP result."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("omega", c_double),
        ("singular_vertex_count", c_size_t),
        ("singular_edge_count", c_size_t),
        ("singular_triangle_count", c_size_t),
        ("singular_point_count", c_size_t),
        ("index_sum", c_double),
        ("newton_iterations", c_uint32),
        ("converged", c_uint32),
        ("final_gradient", c_double),
        ("stretch", c_double),
        ("shear", c_double),
        ("alignment_degrees", c_double),
    ]


class UvfPgp(Structure):
    """Opaque ``struct UvfPgp`` (only used through pointers)."""


class UvfQuadMesh(Structure):
    """Opaque ``struct UvfQuadMesh`` (only used through pointers)."""


class UvfQuadMeshInfo(_Written):
    """``struct UvfQuadMeshInfo``: counts of a quad-dominant remesh."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("vertex_count", c_size_t),
        ("face_count", c_size_t),
        ("index_count", c_size_t),
        ("quad_count", c_size_t),
    ]


class UvfChartLayout(Structure):
    """Opaque ``struct UvfChartLayout`` (only used through pointers)."""


class UvfChartLayoutInfo(_Written):
    """``struct UvfChartLayoutInfo``: counts of a chart layout."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("polyline_count", c_size_t),
        ("point_count", c_size_t),
        ("chart_count", c_size_t),
        ("four_corner_chart_count", c_size_t),
    ]


class UvfPgpCharts(Structure):
    """Opaque ``struct UvfPgpCharts`` (only used through pointers)."""


class UvfPgpChartsInfo(_Written):
    """``struct UvfPgpChartsInfo``: counts of a per-chart parameterization."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("vertex_count", c_size_t),
        ("triangle_count", c_size_t),
        ("chart_count", c_size_t),
        ("kind_counts", c_size_t * 5),
    ]


class UvfBoundaryEditor(Structure):
    """Opaque ``struct UvfBoundaryEditor`` (only used through pointers)."""


class UvfCut(Structure):
    """Opaque ``struct UvfCut`` (only used through pointers)."""


class UvfAtlas(Structure):
    """Opaque ``struct UvfAtlas`` (only used through pointers)."""


class UvfUnwrap(Structure):
    """Opaque ``struct UvfUnwrap`` (only used through pointers)."""


class UvfMesh(Structure):
    """Opaque ``struct UvfMesh`` (only used through pointers)."""


class UvfMeshDesc(Structure):
    """``struct UvfMeshDesc``: where ``uvf_mesh_new`` reads a mesh from."""

    _fields_ = [
        ("struct_size", c_size_t),
        ("positions", c_void_p),
        ("position_type", c_uint32),
        ("position_stride", c_size_t),
        ("vertex_count", c_size_t),
        ("indices", c_void_p),
        ("index_type", c_uint32),
        ("index_stride", c_size_t),
        ("face_sizes", POINTER(c_uint32)),
        ("face_count", c_size_t),
    ]


_f64p = POINTER(c_double)
_u32p = POINTER(c_uint32)
_u8p = POINTER(c_uint8)

#: Every function of ``uvflat.h``: name -> (restype, argtypes).
PROTOTYPES = {
    "uvf_last_error_message": (c_char_p, []),
    "uvf_last_error": (c_size_t, [ctypes.c_char_p, c_size_t]),
    "uvf_status_string": (c_char_p, [c_int]),
    "uvf_version_number": (c_uint32, []),
    "uvf_set_thread_count": (UvfStatus, [c_uint32]),
    "uvf_thread_count": (c_uint32, []),
    "uvf_version": (c_char_p, []),
    "uvf_abi_version": (c_uint32, []),
    "uvf_mesh_info": (UvfStatus, [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfMeshInfo)]),
    "uvf_boundary_loops": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, _u32p, c_size_t, _u32p, c_size_t],
    ),
    "uvf_triangle_components": (UvfStatus, [_f64p, c_size_t, _u32p, c_size_t, _u32p]),
    "uvf_pack_options_default": (None, [POINTER(UvfPackOptions)]),
    "uvf_snapped_repair": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, _u32p, _u8p, POINTER(UvfSnappedRepairInfo)],
    ),
    "uvf_pack_islands": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, _f64p, POINTER(UvfPackOptions), _f64p, _u32p, POINTER(UvfPackReport)],
    ),
    "uvf_polygon_islands": (
        UvfStatus,
        [_u32p, c_size_t, c_size_t, _u32p, c_size_t, _u8p, _u8p, _u32p, _u32p, POINTER(UvfPolygonIslandsInfo)],
    ),
    "uvf_fixed_boundary_options_default": (None, [POINTER(UvfFixedBoundaryOptions)]),
    "uvf_natural_conformal_options_default": (None, [POINTER(UvfNaturalConformalOptions)]),
    "uvf_fixed_boundary_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfFixedBoundaryOptions), _f64p],
    ),
    "uvf_natural_conformal_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfNaturalConformalOptions), _f64p],
    ),
    "uvf_metrics": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, _f64p, c_size_t, _u32p, POINTER(UvfMetrics)],
    ),
    "uvf_abf_options_default": (None, [POINTER(UvfAbfOptions)]),
    "uvf_abf": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfAbfOptions), _f64p, POINTER(UvfAbfReport)],
    ),
    "uvf_intrinsic_tool_options_default": (None, [POINTER(UvfIntrinsicToolOptions)]),
    "uvf_constrained_fixed_boundary_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfFixedBoundaryOptions), POINTER(UvfPointConstraint), c_size_t, _f64p],
    ),
    "uvf_constrained_natural_conformal_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfPointConstraint), c_size_t, POINTER(UvfIntrinsicToolOptions), _f64p],
    ),
    "uvf_pinned_natural_conformal_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, _u32p, _f64p, c_size_t, POINTER(UvfIntrinsicToolOptions), _f64p],
    ),
    "uvf_boundary_editor_new": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, c_double, c_double, POINTER(UvfIntrinsicToolOptions), POINTER(POINTER(UvfBoundaryEditor))],
    ),
    "uvf_boundary_editor_free": (None, [POINTER(UvfBoundaryEditor)]),
    "uvf_boundary_editor_boundary": (UvfStatus, [POINTER(UvfBoundaryEditor), POINTER(c_size_t), _u32p]),
    "uvf_boundary_editor_solve": (UvfStatus, [POINTER(UvfBoundaryEditor), _f64p, c_size_t, _f64p]),
    "uvf_boundary_editor_basis": (UvfStatus, [POINTER(UvfBoundaryEditor), c_size_t, _f64p]),
    "uvf_spectral_options_default": (None, [POINTER(UvfSpectralOptions)]),
    "uvf_spectral_conformal_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfSpectralOptions), _f64p, POINTER(UvfSpectralReport)],
    ),
    "uvf_circle_pattern_options_default": (None, [POINTER(UvfCirclePatternOptions)]),
    "uvf_circle_pattern_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfCirclePatternOptions), _f64p, POINTER(UvfCirclePatternReport)],
    ),
    "uvf_circle_pattern_polygon_curvature": (UvfStatus, [_f64p, c_size_t, _u32p, c_size_t, _u32p, c_size_t, _f64p]),
    "uvf_circle_pattern_cone_map": (
        UvfStatus,
        [
            _f64p,
            c_size_t,
            _u32p,
            c_size_t,
            _u32p,
            _f64p,
            c_size_t,
            POINTER(UvfCirclePatternOptions),
            _f64p,
            POINTER(UvfCirclePatternReport),
        ],
    ),
    "uvf_cone_placement_options_default": (None, [POINTER(UvfConePlacementOptions)]),
    "uvf_place_cones": (
        UvfStatus,
        [
            _f64p,
            c_size_t,
            _u32p,
            c_size_t,
            POINTER(UvfConePlacementOptions),
            _u32p,
            _f64p,
            POINTER(c_size_t),
            POINTER(c_double),
        ],
    ),
    "uvf_quadcover_options_default": (None, [POINTER(UvfQuadCoverOptions)]),
    "uvf_quadcover": (
        UvfStatus,
        [
            _f64p,
            c_size_t,
            _u32p,
            c_size_t,
            POINTER(UvfQuadCoverOptions),
            _f64p,
            _f64p,
            POINTER(c_int32),
            POINTER(UvfQuadCoverReport),
        ],
    ),
    "uvf_quadcover_quad_mesh": (
        UvfStatus,
        [
            _f64p,
            c_size_t,
            _u32p,
            c_size_t,
            POINTER(UvfQuadCoverOptions),
            _f64p,
            c_double,
            POINTER(POINTER(UvfQuadMesh)),
            POINTER(UvfQuadCoverReport),
        ],
    ),
    "uvf_intrinsic_optimal_options_default": (None, [POINTER(UvfIntrinsicOptimalOptions)]),
    "uvf_intrinsic_optimal_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfIntrinsicOptimalOptions), _f64p, POINTER(UvfIntrinsicOptimalReport)],
    ),
    "uvf_boundary_optimization_options_default": (None, [POINTER(UvfBoundaryOptimizationOptions)]),
    "uvf_boundary_optimized_map": (
        UvfStatus,
        [
            _f64p,
            c_size_t,
            _u32p,
            c_size_t,
            POINTER(UvfBoundaryOptimizationOptions),
            _f64p,
            _f64p,
            c_size_t,
            POINTER(UvfBoundaryOptimizationReport),
        ],
    ),
    "uvf_nonlinear_options_default": (None, [POINTER(UvfNonlinearOptions)]),
    "uvf_nonlinear_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfNonlinearOptions), _f64p, POINTER(UvfNonlinearReport)],
    ),
    "uvf_cut_options_default": (None, [POINTER(UvfCutOptions)]),
    "uvf_cut_to_disk": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfCutOptions), POINTER(POINTER(UvfCut))],
    ),
    "uvf_cut_info": (UvfStatus, [POINTER(UvfCut), POINTER(UvfCutInfo)]),
    "uvf_cut_copy_edges": (UvfStatus, [POINTER(UvfCut), _u32p, c_size_t]),
    "uvf_cut_copy_triangles": (UvfStatus, [POINTER(UvfCut), _u32p, c_size_t]),
    "uvf_cut_copy_original_vertices": (UvfStatus, [POINTER(UvfCut), _u32p, c_size_t]),
    "uvf_cut_copy_positions": (UvfStatus, [POINTER(UvfCut), _f64p, c_size_t]),
    "uvf_cut_free": (None, [POINTER(UvfCut)]),
    "uvf_curvature_options_default": (None, [POINTER(UvfCurvatureOptions)]),
    "uvf_curvature": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfCurvatureOptions), _f64p, _f64p, _f64p, _f64p],
    ),
    "uvf_pgp_options_default": (None, [POINTER(UvfPgpOptions)]),
    "uvf_pgp": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfPgpOptions), _f64p, POINTER(POINTER(UvfPgp))],
    ),
    "uvf_pgp_info": (UvfStatus, [POINTER(UvfPgp), POINTER(UvfPgpInfo)]),
    "uvf_pgp_copy_singular_vertices": (UvfStatus, [POINTER(UvfPgp), _u32p, c_size_t]),
    "uvf_pgp_copy_singular_edges": (UvfStatus, [POINTER(UvfPgp), _u32p, c_size_t]),
    "uvf_pgp_copy_singular_triangles": (UvfStatus, [POINTER(UvfPgp), _u32p, c_size_t]),
    "uvf_pgp_copy_singular_points": (UvfStatus, [POINTER(UvfPgp), _u32p, _f64p, c_size_t]),
    "uvf_pgp_copy_field": (UvfStatus, [POINTER(UvfPgp), _f64p, c_size_t]),
    "uvf_pgp_free": (None, [POINTER(UvfPgp)]),
    "uvf_pgp_quad_mesh": (UvfStatus, [POINTER(UvfPgp), c_double, POINTER(POINTER(UvfQuadMesh))]),
    "uvf_pgp_chart_layout": (UvfStatus, [POINTER(UvfPgp), POINTER(POINTER(UvfChartLayout))]),
    "uvf_quad_mesh_info": (UvfStatus, [POINTER(UvfQuadMesh), POINTER(UvfQuadMeshInfo)]),
    "uvf_quad_mesh_copy": (
        UvfStatus,
        [POINTER(UvfQuadMesh), _f64p, c_size_t, _u32p, c_size_t, _u32p, c_size_t],
    ),
    "uvf_quad_mesh_free": (None, [POINTER(UvfQuadMesh)]),
    "uvf_chart_layout_info": (UvfStatus, [POINTER(UvfChartLayout), POINTER(UvfChartLayoutInfo)]),
    "uvf_chart_layout_copy": (
        UvfStatus,
        [POINTER(UvfChartLayout), _u32p, c_size_t, _f64p, c_size_t, _u32p, c_size_t],
    ),
    "uvf_chart_layout_free": (None, [POINTER(UvfChartLayout)]),
    "uvf_pgp_charts": (UvfStatus, [POINTER(UvfPgp), c_double, POINTER(POINTER(UvfPgpCharts))]),
    "uvf_pgp_charts_info": (UvfStatus, [POINTER(UvfPgpCharts), POINTER(UvfPgpChartsInfo)]),
    "uvf_pgp_charts_copy": (
        UvfStatus,
        [POINTER(UvfPgpCharts), _f64p, c_size_t, _u32p, c_size_t, _f64p, c_size_t, _u32p, c_size_t, _u32p, c_size_t],
    ),
    "uvf_pgp_charts_copy_charts": (
        UvfStatus,
        [POINTER(UvfPgpCharts), _u32p, c_size_t, _u32p, c_size_t, _u32p, c_size_t, _f64p, c_size_t],
    ),
    "uvf_pgp_charts_free": (None, [POINTER(UvfPgpCharts)]),
    "uvf_atlas_options_default": (None, [POINTER(UvfAtlasOptions)]),
    "uvf_atlas": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfAtlasOptions), POINTER(POINTER(UvfAtlas))],
    ),
    "uvf_atlas_info": (UvfStatus, [POINTER(UvfAtlas), POINTER(UvfAtlasInfo)]),
    "uvf_atlas_copy_uv": (UvfStatus, [POINTER(UvfAtlas), _f64p, c_size_t]),
    "uvf_atlas_copy_triangles": (UvfStatus, [POINTER(UvfAtlas), _u32p, c_size_t]),
    "uvf_atlas_copy_corner_uv": (UvfStatus, [POINTER(UvfAtlas), _f64p, c_size_t]),
    "uvf_atlas_copy_charts": (UvfStatus, [POINTER(UvfAtlas), _u32p, c_size_t]),
    "uvf_atlas_copy_original_vertices": (UvfStatus, [POINTER(UvfAtlas), _u32p, c_size_t]),
    "uvf_atlas_free": (None, [POINTER(UvfAtlas)]),
    "uvf_check_layout": (UvfStatus, [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfLayoutCheck)]),
    "uvf_unwrap_options_default": (None, [POINTER(UvfUnwrapOptions)]),
    "uvf_unwrap": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfUnwrapOptions), POINTER(POINTER(UvfUnwrap))],
    ),
    "uvf_unwrap_report": (UvfStatus, [POINTER(UvfUnwrap), POINTER(UvfUnwrapReport)]),
    "uvf_unwrap_atlas": (UvfStatus, [POINTER(UvfUnwrap), POINTER(POINTER(UvfAtlas))]),
    "uvf_unwrap_copy_seams": (UvfStatus, [POINTER(UvfUnwrap), _u32p, c_size_t]),
    "uvf_unwrap_free": (None, [POINTER(UvfUnwrap)]),
    "uvf_mesh_desc_default": (None, [POINTER(UvfMeshDesc)]),
    "uvf_mesh_new": (UvfStatus, [POINTER(UvfMeshDesc), POINTER(POINTER(UvfMesh))]),
    "uvf_mesh_free": (None, [POINTER(UvfMesh)]),
    "uvf_mesh_handle_info": (UvfStatus, [POINTER(UvfMesh), POINTER(UvfMeshInfo)]),
    "uvf_mesh_copy_triangles": (UvfStatus, [POINTER(UvfMesh), _u32p, c_size_t]),
    "uvf_mesh_copy_triangle_faces": (UvfStatus, [POINTER(UvfMesh), _u32p, c_size_t]),
    "uvf_mesh_face_corner_uv": (UvfStatus, [POINTER(UvfMesh), _f64p, c_size_t, _f64p, c_size_t]),
    "uvf_sphere_options_default": (None, [POINTER(UvfSphereOptions)]),
    "uvf_spherical_map": (
        UvfStatus,
        [_f64p, c_size_t, _u32p, c_size_t, POINTER(UvfSphereOptions), _f64p, POINTER(c_size_t)],
    ),
}

#: Every call on flat mesh arrays has a mesh-handle twin: ``uvf_mesh_<name>(mesh, <the rest>)``.
_HANDLE_TWINS = (
    "abf",
    "atlas",
    "boundary_editor_new",
    "boundary_loops",
    "boundary_optimized_map",
    "circle_pattern_cone_map",
    "circle_pattern_map",
    "circle_pattern_polygon_curvature",
    "constrained_fixed_boundary_map",
    "constrained_natural_conformal_map",
    "curvature",
    "cut_to_disk",
    "fixed_boundary_map",
    "intrinsic_optimal_map",
    "metrics",
    "natural_conformal_map",
    "nonlinear_map",
    "pgp",
    "pinned_natural_conformal_map",
    "place_cones",
    "quadcover",
    "quadcover_quad_mesh",
    "spectral_conformal_map",
    "spherical_map",
    "triangle_components",
    "unwrap",
)
for _name in _HANDLE_TWINS:
    _restype, _argtypes = PROTOTYPES["uvf_" + _name]
    PROTOTYPES["uvf_mesh_" + _name] = (_restype, [POINTER(UvfMesh)] + list(_argtypes[4:]))

# --- loading --------------------------------------------------------------------------------

_lock = threading.Lock()
_loaded: Optional[ctypes.CDLL] = None
_loaded_path: Optional[str] = None

PathLike = Union[str, "os.PathLike[str]"]


def _library_file_names() -> list:
    if sys.platform == "darwin":
        return ["libuvflat.dylib"]
    if sys.platform == "win32":
        return ["uvflat.dll"]
    return ["libuvflat.so"]


def _candidates(path: Optional[PathLike]) -> list:
    """Where to look, in order, as (description, path or name) pairs."""
    if path is not None:
        return [("explicit path", os.fspath(path))]
    env = os.environ.get(LIBRARY_ENV)
    if env:
        # An explicit setting that is wrong is an error, not a reason to look elsewhere.
        return [(f"${LIBRARY_ENV}", env)]
    found = []
    here = os.path.dirname(os.path.abspath(__file__))
    for name in _library_file_names():
        local = os.path.join(here, name)
        if os.path.exists(local):
            found.append(("package directory", local))
    system = ctypes.util.find_library("uvflat")
    if system:
        found.append(("system search path", system))
    found.extend(("system search path", name) for name in _library_file_names())
    return found


def _declare(lib: ctypes.CDLL) -> None:
    for name, (restype, argtypes) in PROTOTYPES.items():
        try:
            function = getattr(lib, name)
        except AttributeError as e:
            raise LibraryError(f"{lib._name} has no function {name}; is it an older libuvflat?") from e
        function.restype = restype
        function.argtypes = argtypes


def _check(lib: ctypes.CDLL, where: str) -> ctypes.CDLL:
    _declare(lib)
    abi = lib.uvf_abi_version()
    if abi != ABI_VERSION:
        raise LibraryError(
            f"{where} has ABI version {abi} but this uvflat binding was written for ABI version "
            f"{ABI_VERSION}; install matching versions of the library and the binding"
        )
    return lib


def load_library(path: Optional[PathLike] = None) -> ctypes.CDLL:
    """Loads ``libuvflat`` and makes it the library every uvflat function calls.

    With ``path``, loads exactly that file. Without, looks in ``$UVFLAT_LIBRARY``, then for a
    copy in the package directory, then on the system search path (see the module docs).
    Declares every function's prototype and checks that the library's
    ``uvf_abi_version()`` equals :data:`ABI_VERSION`.

    Returns the ``ctypes.CDLL``. Raises :class:`uvflat.LibraryError` when no library can be
    loaded, a function is missing, or the ABI version differs; the previously loaded library,
    if any, stays in use.
    """
    global _loaded, _loaded_path
    failures = []
    for description, where in _candidates(path):
        try:
            lib = ctypes.CDLL(where)
        except OSError as e:
            failures.append(f"{where} ({description}): {e}")
            continue
        lib = _check(lib, where)  # a library that loads but does not fit is an error at once
        with _lock:
            _loaded, _loaded_path = lib, where
        return lib
    raise LibraryError(
        "cannot load libuvflat: pass its path to uvflat.load_library(), set "
        f"{LIBRARY_ENV}, copy it into {os.path.dirname(os.path.abspath(__file__))}, or put it "
        "on the system library path; tried:" + "".join("\n  " + f for f in failures)
    )


def library() -> ctypes.CDLL:
    """The loaded library, loading it on first use with :func:`load_library`'s search order."""
    lib = _loaded
    return lib if lib is not None else load_library()


def library_path() -> str:
    """The path (or name given to the dynamic loader) of the library in use; loads it if needed."""
    library()
    assert _loaded_path is not None
    return _loaded_path
