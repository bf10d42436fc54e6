"""Circle-pattern conformal maps, with free, polygon or convex boundary, and with cones."""

from __future__ import annotations

import ctypes
import dataclasses
import threading
from ctypes import POINTER, byref, c_double, c_uint32
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _library as L
from ._mesh import Mesh
from ._errors import Error, InternalError, InvalidArgument, InvalidMesh, Status, error_for_status
from ._common import ArrayLike, Pins, ProgressCallback, _ProgressBridge, _as_indices, _check, _f64p, _from_struct, _mesh_arrays, _non_negative_int, _set_two_pins, _u32p
from ._pgp import curvature


@dataclasses.dataclass(frozen=True)
class CirclePatternReport:
    """What ``uvf_circle_pattern_map`` reports."""

    #: Iterations of the angle program: primal–dual steps, plus the log-barrier Newton steps
    #: where it fell back.
    angle_iterations: int
    #: Newton steps of the log radii.
    radius_iterations: int
    #: Largest |Σ φ − π| over the circles (radians).
    closure_error: float
    #: Interior edges of the triangulation used (after the intrinsic flips, if any) whose
    #: angles violate the Delaunay condition.
    non_delaunay_edges: int
    #: Largest |α − β| between a planar and a 3D angle (radians).
    max_angle_change: float
    #: Intrinsic edge flips made before the angle program.
    intrinsic_flips: int
    #: Mesh triangles whose uv area is not positive (always 0 without intrinsic flips).
    flipped_triangles: int
    #: log10 of the largest over the smallest circle radius: the orders of magnitude the map's
    #: scale spans (3–4 on typical free maps; beyond about 12 the layout loses the smallest
    #: triangles to double-precision rounding).
    radius_span: float


def _circle_pattern_options(
    p: np.ndarray,
    t: np.ndarray,
    pins: Optional[Pins],
    max_iterations: Optional[int],
    tolerance: Optional[float],
    intrinsic_delaunay: bool,
    boundary_curvature: Optional[ArrayLike],
    corners: Optional[ArrayLike],
    convex_boundary: bool = False,
) -> Tuple[Any, Optional[np.ndarray]]:
    """The C options and the curvature array they point to (keep it alive during the call)."""
    options = L.UvfCirclePatternOptions()
    L.library().uvf_circle_pattern_options_default(byref(options))
    if pins is not None:
        _set_two_pins(options, pins)
    if max_iterations is not None:
        options.max_iterations = _non_negative_int(max_iterations, "max_iterations")
    if tolerance is not None:
        options.tolerance = float(tolerance)
    options.intrinsic_delaunay = 1 if intrinsic_delaunay else 0
    options.convex_boundary = 1 if convex_boundary else 0
    if corners is not None:
        if boundary_curvature is not None:
            raise InvalidArgument("give boundary_curvature or corners, not both")
        boundary_curvature = polygon_boundary_curvature(p, t, corners)
    curvature = None
    if boundary_curvature is not None:
        curvature = np.require(np.asarray(boundary_curvature, dtype=np.float64), requirements=["C", "A"])
        if curvature.shape != (len(p),):
            raise InvalidArgument(f"boundary_curvature must have shape ({len(p)},), not {curvature.shape}")
        options.boundary_curvature = _f64p(curvature)
    return options, curvature


def circle_pattern_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    pins: Optional[Pins] = None,
    max_iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    intrinsic_delaunay: bool = True,
    boundary_curvature: Optional[ArrayLike] = None,
    corners: Optional[ArrayLike] = None,
    convex_boundary: bool = False,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, CirclePatternReport]:
    """Conformal map by circle patterns (Kharevych, Springborn & Schröder 2006;
    ``uvf_circle_pattern_map``), free boundary: the edges flipped to the intrinsic Delaunay
    triangulation of the mesh's metric (as in the paper), planar angles from the paper's
    quadratic program, the circumcircles' intersection angles, the log radii minimizing the
    paper's convex energy, and their layout. The mesh's triangles take their vertices' uv, so
    a few may flip after intrinsic flips (``report.flipped_triangles``); with
    ``intrinsic_delaunay=False`` none does, but the angles at non-Delaunay edges are distorted.
    May raise :class:`NumericalFailure` where the barrier or the radii do not converge.

    Args:
        pins: ``None`` (default: the two boundary vertices farthest apart at (0, 0) and (d, 0),
            d their 3D distance)
            or ``((v0, (u0, v0_)), (v1, (u1, v1_)))`` as for :func:`natural_conformal_map`.
        intrinsic_delaunay: flip to the intrinsic Delaunay triangulation first (default).
        boundary_curvature: ``None`` (free boundary, default) or ``(n,)`` floats: the turning
            angle of the uv boundary at each boundary vertex (its uv angle sum is π − κ; 0 keeps
            the boundary straight), NaN where it is free; ignored at interior vertices. A fully
            prescribed boundary must sum to 2π (1 − holes).
        corners: instead of ``boundary_curvature``, the corner vertices of a convex polygon
            with straight sides (see :func:`polygon_boundary_curvature`; 4 give a rectangle).
        convex_boundary: keep the uv boundary convex (the paper's inequality constraints on
            the boundary angles): every boundary vertex whose curvature is not prescribed turns
            by at least 0, so the pattern embeds its triangulation (no overlap). Costs angle
            distortion where the boundary is concave (``report.radius_span`` tells how far the
            scale then spreads).

    Returns:
        ``(uv, report)``: ``(n, 2)`` UVs and a :class:`CirclePatternReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    options, _curvature = _circle_pattern_options(
        p, t, pins, max_iterations, tolerance, intrinsic_delaunay, boundary_curvature, corners, convex_boundary
    )
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    report = L.UvfCirclePatternReport()
    lib = L.library()
    bridge.run(lambda: lib.uvf_circle_pattern_map(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(uv), byref(report)))
    return uv, _from_struct(CirclePatternReport, report)


@dataclasses.dataclass(frozen=True)
class ConePlacement:
    """What :func:`place_cones` returns: the cones in the order placed."""

    #: ``(k,)`` uint32 interior vertices.
    vertices: np.ndarray
    #: ``(k,)`` float64 curvatures (2π minus the cone angle, radians); Σ = 2π χ on a closed mesh.
    curvatures: np.ndarray
    #: Largest |log scale| of the conformal flattening with these cones.
    max_log_scale: float

    def cones(self) -> Tuple[np.ndarray, np.ndarray]:
        """``(vertices, curvatures)``, as :func:`circle_pattern_cone_map` takes them."""
        return self.vertices, self.curvatures


def place_cones(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    max_cones: int = 64,
    max_log_scale: float = 0.7,
    progress: Optional[ProgressCallback] = None,
) -> ConePlacement:
    """Cone singularities for a conformal map, placed greedily (Ben-Chen, Gotsman & Bunin 2008;
    ``uvf_place_cones``): each new cone goes where the flattening's log scale |u| is largest,
    until |u| ≤ ``max_log_scale`` everywhere or ``max_cones`` are placed; each cone's curvature
    is the one that flattening gives it. Feed the result to :func:`circle_pattern_cone_map`::

        placement = uvflat.place_cones(p, t)
        corner_uv, report = uvflat.circle_pattern_cone_map(p, t, placement)

    A closed surface of genus g needs at least 2g − 2 cones (raises :class:`InvalidArgument`
    naming the cone that ``max_cones`` leave overloaded; 4 per unit of −χ is ample).
    """
    p, t = _mesh_arrays(positions, triangles)
    if not (isinstance(max_cones, (int, np.integer)) and 0 <= max_cones < 2**32):
        raise InvalidArgument(f"max_cones must be an integer in [0, 2^32), not {max_cones!r}")
    options = L.UvfConePlacementOptions()
    L.library().uvf_cone_placement_options_default(byref(options))
    options.max_cones = int(max_cones)
    options.max_log_scale = float(max_log_scale)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    capacity = max(min(int(max_cones), len(p)), 1)  # a vertex is a cone at most once
    vertices = np.zeros(capacity, dtype=np.uint32)
    curvatures = np.zeros(capacity, dtype=np.float64)
    count, largest = ctypes.c_size_t(0), ctypes.c_double(0.0)
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_place_cones(
            _f64p(p), len(p), _u32p(t), len(t), byref(options), _u32p(vertices), _f64p(curvatures), byref(count), byref(largest)
        )
    )
    k = count.value
    return ConePlacement(vertices[:k].copy(), curvatures[:k].copy(), largest.value)


def circle_pattern_cone_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    cones: Any,
    *,
    max_iterations: Optional[int] = None,
    tolerance: Optional[float] = None,
    intrinsic_delaunay: bool = True,
    boundary_curvature: Optional[ArrayLike] = None,
    corners: Optional[ArrayLike] = None,
    convex_boundary: bool = False,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, CirclePatternReport]:
    """Conformal map with cone singularities by circle patterns (Kharevych, Springborn &
    Schröder 2006 §5; ``uvf_circle_pattern_cone_map``) of a connected mesh of any genus, closed
    or with boundary. The mesh is cut through the cones (and its handles) and laid out per
    corner: both sides of every seam are congruent, and the uv angles around each cone sum to
    its cone angle.

    Args:
        cones: ``{vertex: curvature}``, ``(vertices, curvatures)`` or a :class:`ConePlacement`
            from :func:`place_cones`: interior vertices and their curvature in radians (2π minus the cone angle; π/2 for a cube corner). On a
            closed mesh the curvatures must sum to 2π χ (4π on a sphere, 0 on a torus: ``{}``).
        boundary_curvature, corners, convex_boundary, intrinsic_delaunay: as for
            :func:`circle_pattern_map`.

    Returns:
        ``(corner_uv, report)``: ``(m, 3, 2)`` uv per triangle corner and a
        :class:`CirclePatternReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    if isinstance(cones, ConePlacement):
        cones = cones.cones()
    if isinstance(cones, Mapping):
        vertices: Any = list(cones.keys())
        curvatures: Any = [cones[v] for v in vertices]
    elif isinstance(cones, tuple) and len(cones) == 2:
        vertices, curvatures = cones
    else:
        raise InvalidArgument(f"cones must be a mapping {{vertex: curvature}} or (vertices, curvatures), not {type(cones).__name__}")
    if np.size(vertices) == 0:
        vertices = np.zeros(0, dtype=np.uint32)
    v = _as_indices(vertices, "cone vertices", InvalidArgument, None, "cone vertex {value} (entry {row}) {reason}")
    k = np.require(np.asarray(curvatures, dtype=np.float64).reshape(-1), requirements=["C", "A"])
    if len(k) != len(v):
        raise InvalidArgument(f"{len(v)} cone vertices but {len(k)} curvatures")
    options, _curvature = _circle_pattern_options(
        p, t, None, max_iterations, tolerance, intrinsic_delaunay, boundary_curvature, corners, convex_boundary
    )
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    corner_uv = np.empty((len(t), 3, 2), dtype=np.float64)
    report = L.UvfCirclePatternReport()
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_circle_pattern_cone_map(
            _f64p(p), len(p), _u32p(t), len(t), _u32p(v), _f64p(k), len(v), byref(options), _f64p(corner_uv), byref(report)
        )
    )
    return corner_uv, _from_struct(CirclePatternReport, report)


def polygon_boundary_curvature(positions: ArrayLike, triangles: ArrayLike, corners: ArrayLike) -> np.ndarray:
    """Boundary curvature (``uvf_circle_pattern_polygon_curvature``) that makes the longest
    boundary loop a convex polygon with the given k ≥ 3 corner vertices: turning 2π / k at each
    corner, 0 (straight) at the loop's other vertices, NaN (free) elsewhere. For the
    ``boundary_curvature`` of :func:`circle_pattern_map`. Raises :class:`InvalidArgument` when a
    corner is not on that loop or is given twice, or when a boundary vertex in a single
    triangle is not a corner (no straight side can pass through it).
    """
    p, t = _mesh_arrays(positions, triangles)
    c = _as_indices(corners, "corners", InvalidArgument, None, "corner {value} (entry {row}) {reason}")
    out = np.empty(len(p), dtype=np.float64)
    _check(L.library().uvf_circle_pattern_polygon_curvature(_f64p(p), len(p), _u32p(t), len(t), _u32p(c), len(c), _f64p(out)))
    return out
