"""Closed surfaces: spherical maps of genus-0 meshes and cutting a mesh into a disk."""

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


def spherical_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    method: str = "tutte_gnomonic",
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, int]:
    """Spherical parameterization of a closed genus-0 mesh (``uvf_spherical_map``; course notes
    §6.1): ``tutte_gnomonic`` (flip-free construction, default), ``gauss_seidel``,
    ``stereographic`` (Haker et al. 2000) or ``circle_patterns`` (Kharevych et al. 2006:
    conformal; angles kept best, flips counted).

    Returns:
        ``(sphere, flipped)``: ``(n, 3)`` unit vectors and the count of flipped spherical
        triangles.
    """
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfSphereOptions()
    L.library().uvf_sphere_options_default(byref(options))
    options.method = _code(
        method,
        {
            "tutte_gnomonic": L.UVF_SPHERE_TUTTE_GNOMONIC,
            "gauss_seidel": L.UVF_SPHERE_GAUSS_SEIDEL,
            "stereographic": L.UVF_SPHERE_STEREOGRAPHIC,
            "circle_patterns": L.UVF_SPHERE_CIRCLE_PATTERNS,
        },
        "method",
    )
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    out = np.empty((len(p), 3), dtype=np.float64)
    flipped = ctypes.c_size_t(0)
    lib = L.library()
    bridge.run(lambda: lib.uvf_spherical_map(_f64p(p), len(p), _u32p(t), len(t), byref(options), _f64p(out), byref(flipped)))
    return out, int(flipped.value)


@dataclasses.dataclass(frozen=True)
class Cut:
    """A mesh cut into a topological disk (``uvf_cut_to_disk``)."""

    positions: np.ndarray  #: ``(k, 3)`` positions of the cut mesh's vertices
    triangles: np.ndarray  #: ``(m, 3)`` triangles of the cut mesh (same order as the input)
    original_vertices: np.ndarray  #: ``(k,)`` input vertex of each cut-mesh vertex
    edges: np.ndarray  #: ``(e, 2)`` input vertex pairs along the cut
    seam_length: float
    total_edge_length: float


def cut_to_disk(positions: ArrayLike, triangles: ArrayLike, cost: Union[str, ArrayLike] = "curvature") -> Cut:
    """Cuts a manifold mesh of any genus into a topological disk (``uvf_cut_to_disk``:
    tree-cotree cut graph, Erickson & Har-Peled 2002, steered by a ``curvature`` or ``length``
    edge cost, or by a caller-given ``(m, 3)`` array: the cost of half-edge ``k`` of triangle
    ``t`` (corner ``k`` to corner ``k + 1``), finite and ≥ 0, low cost attracting the cut); any
    disk method then runs on ``Cut.positions`` / ``Cut.triangles``."""
    p, t = _mesh_arrays(positions, triangles)
    options = L.UvfCutOptions()
    lib = L.library()
    lib.uvf_cut_options_default(byref(options))
    given = None
    if isinstance(cost, str):
        options.cost = _code(cost, {"curvature": L.UVF_CUT_COST_CURVATURE, "length": L.UVF_CUT_COST_LENGTH}, "cost")
    else:
        try:
            given = np.ascontiguousarray(cost, dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise InvalidArgument(f"cost must be 'curvature', 'length' or an (m, 3) array of numbers: {e}") from None
        if given.shape != (len(t), 3):
            raise InvalidArgument(f"cost array has shape {given.shape}; expected ({len(t)}, 3), one per half-edge")
        options.cost = L.UVF_CUT_COST_GIVEN
        options.edge_cost = _f64p(given)
    handle = POINTER(L.UvfCut)()
    _check(lib.uvf_cut_to_disk(_f64p(p), len(p), _u32p(t), len(t), byref(options), byref(handle)))
    try:
        info = L.UvfCutInfo()
        _check(lib.uvf_cut_info(handle, byref(info)))
        cut_positions = np.empty((info.vertex_count, 3), dtype=np.float64)
        cut_triangles = np.empty((info.triangle_count, 3), dtype=np.uint32)
        original = np.empty(info.vertex_count, dtype=np.uint32)
        edges = np.empty((info.edge_count, 2), dtype=np.uint32)
        _check(lib.uvf_cut_copy_positions(handle, _f64p(cut_positions), cut_positions.size))
        _check(lib.uvf_cut_copy_triangles(handle, _u32p(cut_triangles), cut_triangles.size))
        _check(lib.uvf_cut_copy_original_vertices(handle, _u32p(original), original.size))
        _check(lib.uvf_cut_copy_edges(handle, _u32p(edges), edges.size))
    finally:
        lib.uvf_cut_free(handle)
    return Cut(cut_positions, cut_triangles, original, edges, info.seam_length, info.total_edge_length)
