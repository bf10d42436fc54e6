"""Principal curvatures and the Periodic Global Parameterization: (θ, φ), singularities, charts
and the quad-dominant remesh."""

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
from ._common import ArrayLike, ProgressCallback, _ProgressBridge, _as_points, _check, _code, _f64p, _mesh_arrays, _non_negative_int, _split, _take_quad_mesh, _u32p


@dataclasses.dataclass(frozen=True)
class Curvatures:
    """Principal curvatures per vertex (``uvf_curvature``)."""

    kmin_direction: np.ndarray  #: ``(n, 3)`` unit tangent directions of the minimum curvature
    kmax_direction: np.ndarray  #: ``(n, 3)`` unit tangent directions of the maximum curvature
    kmin: np.ndarray  #: ``(n,)`` signed minimum curvature
    kmax: np.ndarray  #: ``(n,)`` signed maximum curvature (a sphere of radius r: 1/r)


def curvature(positions: ArrayLike, triangles: ArrayLike, rings: int = 2, radius: Optional[float] = None) -> Curvatures:
    """Principal curvatures by the normal-cycle tensor of Cohen-Steiner & Morvan 2003
    (``uvf_curvature``), averaged over the triangles around the vertices at most ``rings − 1``
    edges away, or, with ``radius``, within that graph distance."""
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfCurvatureOptions()
    lib = L.library()
    lib.uvf_curvature_options_default(byref(options))
    if radius is None:
        options.rings = _non_negative_int(rings, "rings")
    else:
        options.neighbourhood = L.UVF_CURVATURE_RADIUS
        options.radius = float(radius)
    n = len(p)
    kmin_d, kmax_d = np.empty((n, 3), dtype=np.float64), np.empty((n, 3), dtype=np.float64)
    kmin, kmax = np.empty(n, dtype=np.float64), np.empty(n, dtype=np.float64)
    _check(
        lib.uvf_curvature(
            _f64p(p), n, _u32p(t), len(t), byref(options), _f64p(kmin_d), _f64p(kmax_d), _f64p(kmin), _f64p(kmax)
        )
    )
    return Curvatures(kmin_d, kmax_d, kmin, kmax)


@dataclasses.dataclass(frozen=True)
class PgpResult:
    """A periodic global parameterization (``uvf_pgp``)."""

    corner_coords: np.ndarray  #: ``(m, 3, 2)`` (θ, φ) at corner k of triangle t, period 2π
    singular_vertices: np.ndarray  #: ``(a,)`` vertices whose (θ, φ) angles do not sum to 2π
    singular_edges: np.ndarray  #: ``(b, 2)`` edges whose transition functions disagree
    singular_triangles: np.ndarray  #: ``(c,)`` open or flipped (θ, φ) triangles
    singular_points: np.ndarray  #: ``(d,)`` vertices with a non-zero index
    indices: np.ndarray  #: ``(d,)`` their indices (multiples of 1/4; they sum to 2 − 2g)
    field: np.ndarray  #: ``(n, 3)`` the field the solve followed
    omega: float
    newton_iterations: int
    converged: bool
    final_gradient: float
    stretch: float  #: L2 stretch of (θ, φ)/ω over the regular triangles
    shear: float  #: mean |cos| of the angle between the parameter directions
    alignment_degrees: float  #: mean angle between the gradients and the field
    #: the quad-dominant remesh when ``quad_mesh`` was given: ``(positions (k, 3), faces)``,
    #: ``faces`` a list of vertex-index arrays (counter-clockwise seen from outside)
    quad_mesh: Optional[Tuple[np.ndarray, List[np.ndarray]]] = None
    #: the chart layout when ``chart_layout`` was set: ``(polylines, chart_corners)``, the chart
    #: boundaries as ``(j, 3)`` point arrays and the number of corners of every chart
    chart_layout: Optional[Tuple[List[np.ndarray], np.ndarray]] = None
    #: the per-chart parameterization when ``charts`` was given
    charts: Optional["PgpCharts"] = None

    @property
    def uv(self) -> np.ndarray:
        """``(m, 3, 2)`` texture coordinates (θ, φ)/2π: one texture tile per period."""
        return self.corner_coords / (2.0 * np.pi)


@dataclasses.dataclass(frozen=True)
class PgpCharts:
    """The per-chart parameterization of a PGP result (``uvf_pgp_charts``, §3.3–3.4): the
    surface cut along the iso-lines, each chart with its own (u, v) in cells (a regular chart
    is the unit square)."""

    positions: np.ndarray  #: ``(k, 3)`` vertices of the cut triangulation (input vertices first)
    triangles: np.ndarray  #: ``(m, 3)`` its triangles, counter-clockwise
    uv: np.ndarray  #: ``(m, 3, 2)`` (u, v) at every corner, in cells
    chart: np.ndarray  #: ``(m,)`` chart of every triangle
    origin: np.ndarray  #: ``(m,)`` input triangle every triangle lies in
    kinds: np.ndarray  #: ``(c,)`` ``UVF_PGP_CHART_*`` of every chart
    corners: np.ndarray  #: ``(c,)`` corners of every chart (0: not a disk)
    layout: np.ndarray  #: ``(c,)`` layout chart it is (or is a quad of)
    sizes: np.ndarray  #: ``(c, 2)`` (u, v) extent of every chart, in cells


_SMOOTHING = {
    "none": L.UVF_SMOOTH_NONE,
    "2pi": L.UVF_SMOOTH_2PI,
    "pi": L.UVF_SMOOTH_PI,
    "pi/2": L.UVF_SMOOTH_HALF_PI,
}


def pgp(
    positions: ArrayLike,
    triangles: ArrayLike,
    omega: Optional[float] = None,
    field: Optional[ArrayLike] = None,
    smooth: str = "pi/2",
    curl_correction: bool = False,
    rho: float = 0.8,
    epsilon: float = 0.1,
    max_newton_iterations: int = 100,
    progress: Optional[ProgressCallback] = None,
    quad_mesh: Optional[float] = None,
    chart_layout: bool = False,
    charts: Optional[float] = None,
    untangle: bool = True,
    feature_periods: float = 3.0,
    pair_periods: float = 0.5,
    dislocation_periods: float = 1.5,
    relax: bool = True,
) -> PgpResult:
    """Periodic Global Parameterization (Ray, Li, Lévy, Sheffer, Alliez 2006; ``uvf_pgp``) of a
    manifold mesh of any genus, without cutting: principal-curvature field (or ``field``, an
    ``(n, 3)`` array), smoothing modulo ``smooth`` (``"none"``, ``"2pi"``, ``"pi"``,
    ``"pi/2"``), optional curl correction, the periodic solve and the per-corner (θ, φ).
    ``omega`` defaults to 2π / (10 × mean edge length); ``rho`` is the smoothing intensity
    (paper 0.8) and ``epsilon`` the weight of the periodic solve's unit-norm penalty (0.1; the
    paper's 10⁻³ lets every norm collapse on typical meshes, see docs/methods/pgp.md);
    ``max_newton_iterations`` bounds its Newton phase, which stops at the paper's ‖∇F**‖ < 10⁻⁶
    (5–80 iterations on the meshes measured, ``converged`` tells; 10 is about 3× faster with
    nearly the same singularities). ``untangle=False`` keeps Algorithm 1's per-corner (θ, φ) as
    it is; by default the negative triangles next to singular points are made positive by
    moving vertex phases, every transition kept (not in the paper; see docs/methods/pgp.md).
    ``feature_periods`` is the minimum number of periods around a curved feature: where a
    curvature radius r holds fewer (ω r < feature_periods) the frequency is raised there, at
    most 2.5×, so that legs, horns and fingers narrower than a period are not singular standing
    waves (not in the paper; see docs/methods/pgp.md); 0 keeps the paper's single ω everywhere.
    ``pair_periods``: the +¼ and −¼ singularities of the smoothed cross field closer than this
    many periods (2π/ω) are cancelled together and the field re-solved around them (not in the
    paper; see docs/methods/pgp.md); 0 keeps the smoothed field's singularities.
    ``dislocation_periods``: open triangles of opposite winding where the field is regular
    (dislocations of the wave pattern) closer than this many periods are annihilated together by
    turning the phases around them (not in the paper; see docs/methods/pgp.md); 0 keeps the periodic
    solve's phases. ``relax=False`` skips the phase relaxation that by default runs before the
    untangling: every vertex's phases turned by the least-squares fit of the (θ, φ) triangles to
    the field, every transition kept, used only where it leaves no more singular triangles (not
    in the paper; see docs/methods/pgp.md).

    ``quad_mesh`` (a whole number of iso-lines per period, e.g. 8) also returns the quad-dominant
    remesh of §5 (vertices on the surface, non-quads split into quads and triangles; quad sides
    about 2π / (ω · quad_mesh) long); ``chart_layout=True`` returns the chart boundaries along the
    iso-2kπ lines (§3.3); ``charts`` (a whole number of lines per period, 1 for the paper's
    iso-2kπ lines) returns the per-chart parameterization of §3.4 (:class:`PgpCharts`): charts
    without singularity assembled, singular ones re-parameterized by mean-value coordinates
    (N-sided ones split into quads), charts that are not disks flattened by the atlas."""
    p, t = _mesh_arrays(positions, triangles)
    lib = L.library()
    options = L.UvfPgpOptions()
    lib.uvf_pgp_options_default(byref(options))
    if omega is not None:
        options.omega = float(omega)
    options.smoothing = _code(smooth, _SMOOTHING, "smooth")
    options.curl_correction = 1 if curl_correction else 0
    options.untangle = 1 if untangle else 0
    options.feature_periods = float(feature_periods)
    options.pair_periods = float(pair_periods)
    options.dislocation_periods = float(dislocation_periods)
    options.relax = 1 if relax else 0
    options.rho = float(rho)
    options.epsilon = float(epsilon)
    if isinstance(max_newton_iterations, bool) or int(max_newton_iterations) != max_newton_iterations:
        raise InvalidArgument(f"max_newton_iterations must be a whole number (got {max_newton_iterations!r})")
    if not 0 <= max_newton_iterations < 2**32:
        raise InvalidArgument(f"max_newton_iterations must be in [0, 2^32) (got {max_newton_iterations})")
    options.max_newton_iterations = int(max_newton_iterations)
    given = None
    if field is not None:
        given = _as_points(field, 3, "field")
        if len(given) != len(p):
            raise InvalidArgument(f"field has {len(given)} vectors but the mesh has {len(p)} vertices")
        options.field = _f64p(given)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    coords = np.empty((len(t), 3, 2), dtype=np.float64)
    handle = POINTER(L.UvfPgp)()
    bridge.run(lambda: lib.uvf_pgp(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(coords), byref(handle)))
    try:
        remesh = _quad_mesh(lib, handle, quad_mesh) if quad_mesh is not None else None
        layout = _chart_layout(lib, handle) if chart_layout else None
        cut = _charts(lib, handle, charts) if charts is not None else None
        info = L.UvfPgpInfo()
        _check(lib.uvf_pgp_info(handle, byref(info)))
        vertices = np.empty(info.singular_vertex_count, dtype=np.uint32)
        edges = np.empty((info.singular_edge_count, 2), dtype=np.uint32)
        tris = np.empty(info.singular_triangle_count, dtype=np.uint32)
        points = np.empty(info.singular_point_count, dtype=np.uint32)
        indices = np.empty(info.singular_point_count, dtype=np.float64)
        used_field = np.empty((len(p), 3), dtype=np.float64)
        _check(lib.uvf_pgp_copy_singular_vertices(handle, _u32p(vertices), vertices.size))
        _check(lib.uvf_pgp_copy_singular_edges(handle, _u32p(edges), edges.size))
        _check(lib.uvf_pgp_copy_singular_triangles(handle, _u32p(tris), tris.size))
        _check(lib.uvf_pgp_copy_singular_points(handle, _u32p(points), _f64p(indices), points.size))
        _check(lib.uvf_pgp_copy_field(handle, _f64p(used_field), used_field.size))
    finally:
        lib.uvf_pgp_free(handle)
    return PgpResult(
        coords,
        vertices,
        edges,
        tris,
        points,
        indices,
        used_field,
        info.omega,
        info.newton_iterations,
        bool(info.converged),
        info.final_gradient,
        info.stretch,
        info.shear,
        info.alignment_degrees,
        remesh,
        layout,
        cut,
    )


def _quad_mesh(lib, handle, density: float) -> Tuple[np.ndarray, List[np.ndarray]]:
    quad = POINTER(L.UvfQuadMesh)()
    _check(lib.uvf_pgp_quad_mesh(handle, float(density), byref(quad)))
    return _take_quad_mesh(lib, quad)


def _chart_layout(lib, handle) -> Tuple[List[np.ndarray], np.ndarray]:
    layout = POINTER(L.UvfChartLayout)()
    _check(lib.uvf_pgp_chart_layout(handle, byref(layout)))
    try:
        info = L.UvfChartLayoutInfo()
        _check(lib.uvf_chart_layout_info(layout, byref(info)))
        sizes = np.empty(info.polyline_count, dtype=np.uint32)
        points = np.empty((info.point_count, 3), dtype=np.float64)
        corners = np.empty(info.chart_count, dtype=np.uint32)
        _check(
            lib.uvf_chart_layout_copy(
                layout, _u32p(sizes), sizes.size, _f64p(points), points.size, _u32p(corners), corners.size
            )
        )
    finally:
        lib.uvf_chart_layout_free(layout)
    return _split(points, sizes), corners


def _charts(lib, handle, density: float) -> PgpCharts:
    charts = POINTER(L.UvfPgpCharts)()
    _check(lib.uvf_pgp_charts(handle, float(density), byref(charts)))
    try:
        info = L.UvfPgpChartsInfo()
        _check(lib.uvf_pgp_charts_info(charts, byref(info)))
        m, c = info.triangle_count, info.chart_count
        positions = np.empty((info.vertex_count, 3), dtype=np.float64)
        triangles = np.empty((m, 3), dtype=np.uint32)
        uv = np.empty((m, 3, 2), dtype=np.float64)
        chart = np.empty(m, dtype=np.uint32)
        origin = np.empty(m, dtype=np.uint32)
        _check(
            lib.uvf_pgp_charts_copy(
                charts,
                _f64p(positions),
                positions.size,
                _u32p(triangles),
                triangles.size,
                _f64p(uv),
                uv.size,
                _u32p(chart),
                chart.size,
                _u32p(origin),
                origin.size,
            )
        )
        kinds, corners, layout = (np.empty(c, dtype=np.uint32) for _ in range(3))
        sizes = np.empty((c, 2), dtype=np.float64)
        _check(
            lib.uvf_pgp_charts_copy_charts(
                charts, _u32p(kinds), c, _u32p(corners), c, _u32p(layout), c, _f64p(sizes), sizes.size
            )
        )
    finally:
        lib.uvf_pgp_charts_free(charts)
    return PgpCharts(positions, triangles, uv, chart, origin, kinds, corners, layout, sizes)
