"""Atlases: charts under a stretch bound, packed into the unit square."""

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
from ._common import ArrayLike, ProgressCallback, _ProgressBridge, _check, _code, _f64p, _mesh_arrays, _u32p


@dataclasses.dataclass(frozen=True)
class Atlas:
    """A packed atlas (``uvf_atlas``): charts under a stretch bound in the unit square."""

    uv: np.ndarray  #: ``(k, 2)`` UV of every atlas vertex, in [0, 1]
    triangles: np.ndarray  #: ``(m, 3)`` atlas vertex of each corner of each input triangle
    original_vertices: np.ndarray  #: ``(k,)`` input vertex of each atlas vertex
    charts: np.ndarray  #: ``(m,)`` chart id of each input triangle
    chart_count: int
    utilization: float  #: fraction of the unit square covered by charts
    stretch_l2: float  #: L2 stretch of the whole atlas
    max_chart_stretch: float

    @property
    def corner_uv(self) -> np.ndarray:
        """``(m, 3, 2)`` UV of every corner."""
        return self.uv[self.triangles]


def _atlas_arrays(lib: Any, handle: Any) -> Tuple[Any, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Info, UVs, per-corner UV indices, input vertices and chart ids of an atlas handle."""
    info = L.UvfAtlasInfo()
    _check(lib.uvf_atlas_info(handle, byref(info)))
    uv = np.empty((info.vertex_count, 2), dtype=np.float64)
    uv_triangles = np.empty((info.triangle_count, 3), dtype=np.uint32)
    original = np.empty(info.vertex_count, dtype=np.uint32)
    charts = np.empty(info.triangle_count, dtype=np.uint32)
    _check(lib.uvf_atlas_copy_uv(handle, _f64p(uv), uv.size))
    _check(lib.uvf_atlas_copy_triangles(handle, _u32p(uv_triangles), uv_triangles.size))
    _check(lib.uvf_atlas_copy_original_vertices(handle, _u32p(original), original.size))
    _check(lib.uvf_atlas_copy_charts(handle, _u32p(charts), charts.size))
    return info, uv, uv_triangles, original, charts


def _set_layout_options(options: Any, max_stretch: float, margin: float, method: str, iterations: int, rotate: bool) -> None:
    """The fields `UvfAtlasOptions` and `UvfUnwrapOptions` share, checked."""
    options.max_stretch = float(max_stretch)
    options.margin = float(margin)
    options.method = _code(method, _ATLAS_METHODS, "method")
    if not (isinstance(iterations, int) and 0 <= iterations < 2**32):
        raise InvalidArgument(f"iterations must be an integer in [0, 2^32), not {iterations!r}")
    options.iterations = iterations
    options.rotate = 1 if rotate else 0


_ATLAS_METHODS = {
    "natural_conformal": L.UVF_ATLAS_CHART_NATURAL_CONFORMAL,
    "lscm": L.UVF_ATLAS_CHART_NATURAL_CONFORMAL,
    "mean_value": L.UVF_ATLAS_CHART_MEAN_VALUE,
    "slim": L.UVF_ATLAS_CHART_SLIM,
    "stretch": L.UVF_ATLAS_CHART_STRETCH,
}


def atlas(
    positions: ArrayLike,
    triangles: ArrayLike,
    max_stretch: float = 1.004,
    margin: float = 0.005,
    method: str = "natural_conformal",
    iterations: int = 20,
    rotate: bool = True,
    merge: bool = True,
    polish_iterations: int = 10,
    progress: Optional[ProgressCallback] = None,
) -> Atlas:
    """Atlas of any manifold mesh (``uvf_atlas``): charts split top-down until each flattens
    (``method``: ``natural_conformal``, ``mean_value``, ``slim`` or ``stretch``) without flips
    or overlaps with L2 stretch ≤ ``max_stretch``, adjacent charts merged while still valid,
    then packed into the unit square with ``margin`` between charts (``rotate``: let the packer
    turn charts). ``polish_iterations`` L2-stretch minimization steps are spent on every chart
    slightly over the bound before it is judged and on every accepted chart before packing (0:
    none). ``progress`` may cancel (raises :class:`Cancelled`)."""
    p, t = _mesh_arrays(positions, triangles)
    lib = L.library()
    options = L.UvfAtlasOptions()
    lib.uvf_atlas_options_default(byref(options))
    _set_layout_options(options, max_stretch, margin, method, iterations, rotate)
    options.merge = 1 if merge else 0
    if not (isinstance(polish_iterations, int) and 0 <= polish_iterations < 2**32):
        raise InvalidArgument(f"polish_iterations must be an integer in [0, 2^32), not {polish_iterations!r}")
    options.polish_iterations = polish_iterations
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    handle = POINTER(L.UvfAtlas)()
    bridge.run(lambda: lib.uvf_atlas(_f64p(p), len(p), _u32p(t), len(t), byref(options), byref(handle)))
    try:
        info, uv, uv_triangles, original, charts = _atlas_arrays(lib, handle)
        corner = np.empty((info.triangle_count, 3, 2), dtype=np.float64)
        _check(lib.uvf_atlas_copy_corner_uv(handle, _f64p(corner), corner.size))
    finally:
        lib.uvf_atlas_free(handle)
    if not np.array_equal(corner, uv[uv_triangles]):
        raise InternalError("uvf_atlas_copy_corner_uv disagrees with the atlas vertices (please report this bug)")
    return Atlas(
        uv, uv_triangles, original, charts, info.chart_count, info.utilization, info.stretch_l2, info.max_chart_stretch
    )
