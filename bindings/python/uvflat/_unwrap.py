"""The default unwrap: flip-free, overlap-free UVs with bounded stretch, verified."""

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
from ._atlas import _atlas_arrays, _set_layout_options
from ._common import ArrayLike, ProgressCallback, _ProgressBridge, _check, _mesh_source, _on_mesh, _u32p


@dataclasses.dataclass(frozen=True)
class UnwrapReport:
    """What :func:`unwrap` did, measured on its result (``UvfUnwrapReport``)."""

    #: Islands of the layout.
    islands: int
    #: Islands the method could not lay out validly, laid out by bijective SLIM instead.
    repaired_islands: int
    #: Input edges cut.
    seam_edges: int
    #: UV vertices.
    uv_vertex_count: int
    #: Flipped or degenerate UV triangles, by the library's independent exact checker (0).
    flipped: int
    #: Touching boundary-edge pairs and nested islands, by the same checker (0).
    overlaps: int
    #: L2 stretch of the whole layout.
    stretch_l2: float
    #: Largest L2 stretch of one island.
    max_island_stretch: float
    #: Mean angle distortion over corners, in degrees.
    angle_error_mean_deg: float
    #: Fraction of the unit square covered by islands.
    utilization: float
    #: Input vertices welded onto another for the solve (snapped together but not merged).
    welded_vertices: int = 0
    #: Zero-area input triangles left out of the solve and the verification.
    left_out_triangles: int = 0


@dataclasses.dataclass(frozen=True)
class Unwrapped:
    """The result of :func:`unwrap`: a packed, verified layout."""

    uv: np.ndarray  #: ``(k, 2)`` UV of every UV vertex, in [0, 1]
    triangles: np.ndarray  #: ``(m, 3)`` UV vertex of each corner of each input triangle
    original_vertices: np.ndarray  #: ``(k,)`` input vertex of each UV vertex
    islands: np.ndarray  #: ``(m,)`` island of each input triangle
    seams: np.ndarray  #: ``(s, 2)`` cut input edges as vertex pairs ``a < b``
    report: UnwrapReport

    @property
    def corner_uv(self) -> np.ndarray:
        """``(m, 3, 2)`` UV of every corner."""
        return self.uv[self.triangles]


def unwrap(
    positions: ArrayLike,
    triangles: Optional[ArrayLike] = None,
    max_stretch: float = 1.5,
    margin: float = 0.005,
    method: str = "natural_conformal",
    iterations: int = 100,
    rotate: bool = True,
    progress: Optional[ProgressCallback] = None,
) -> Unwrapped:
    """UVs for any manifold mesh in one call (``uvf_unwrap``): every component starts as one
    island (cut into a disk when closed or with handles) flattened by ``method``
    (``natural_conformal``, ``mean_value``, ``slim`` or ``stretch``); an island that flips or
    overlaps is laid out again by bijective SLIM, one over ``max_stretch`` (L2, ≥ 1;
    ``math.inf``: no bound) is split; the islands are packed into the unit square ``margin``
    apart and the layout is verified: no flipped triangle, no overlap. ``progress`` may cancel
    (raises :class:`Cancelled`).

    Example::

        result = uvflat.unwrap(positions, triangles)
        assert result.report.flipped == 0 and result.report.overlaps == 0
        corner_uv = result.corner_uv  # (m, 3, 2)
    """
    p, t = _mesh_source(positions, triangles)
    lib = L.library()
    options = L.UvfUnwrapOptions()
    lib.uvf_unwrap_options_default(byref(options))
    _set_layout_options(options, max_stretch, margin, method, iterations, rotate)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    handle = POINTER(L.UvfUnwrap)()
    bridge.run(lambda: _on_mesh(lib, "unwrap", p, t, byref(options), byref(handle)))
    try:
        report = L.UvfUnwrapReport()
        _check(lib.uvf_unwrap_report(handle, byref(report)))
        layout = POINTER(L.UvfAtlas)()
        _check(lib.uvf_unwrap_atlas(handle, byref(layout)))
        _, uv, uv_triangles, original, islands = _atlas_arrays(lib, layout)
        seams = np.empty((report.seam_edges, 2), dtype=np.uint32)
        _check(lib.uvf_unwrap_copy_seams(handle, _u32p(seams), seams.size))
    finally:
        lib.uvf_unwrap_free(handle)
    fields = {f.name: getattr(report, f.name) for f in dataclasses.fields(UnwrapReport)}
    return Unwrapped(uv, uv_triangles, original, islands, seams, UnwrapReport(**fields))
