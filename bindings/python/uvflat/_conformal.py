"""The natural conformal map (LSCM) and its pinned variant."""

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
from ._common import ArrayLike, Pins, ProgressCallback, _ProgressBridge, _as_indices, _f64p, _mesh_arrays, _mesh_source, _on_mesh, _set_two_pins, _u32p


def natural_conformal_map(
    positions: ArrayLike,
    triangles: Optional[ArrayLike] = None,
    *,
    pins: Optional[Pins] = None,
    progress: Optional[ProgressCallback] = None,
) -> np.ndarray:
    """Natural conformal map = LSCM (``uvf_natural_conformal_map``; Desbrun et al. 2002 §4.2
    eq. 7): free boundary, two pinned vertices.

    Args:
        positions: ``(n, 3)`` vertex positions, or a :class:`Mesh` (then no ``triangles``).
        triangles: ``(m, 3)`` vertex indices, counter-clockwise.
        pins: ``None`` (default) pins the two boundary vertices farthest apart at (0, 0) and
            (d, 0), d their 3D distance; or ``((v0, (u0, v0_)), (v1, (u1, v1_)))``.
        progress: optional callable receiving the fraction done in [0, 1] (called from the
            calling thread, with the GIL held). Return ``True`` or ``None`` to go on,
            ``False`` to cancel (the call then raises :class:`Cancelled`). An exception
            raised by the callback cancels too and is re-raised once the library returns.

    Returns:
        ``(n, 2)`` float64 UVs, NaN for unreferenced vertices.

    Raises:
        InvalidArgument (bad pins), InvalidMesh, UnsupportedTopology, NumericalFailure,
        Cancelled, InternalError; or whatever ``progress`` raised.
    """
    p, t = _mesh_source(positions, triangles)
    options = L.UvfNaturalConformalOptions()
    L.library().uvf_natural_conformal_options_default(byref(options))
    if pins is not None:
        _set_two_pins(options, pins)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    lib = L.library()
    bridge.run(lambda: _on_mesh(lib, "natural_conformal_map", p, t, byref(options), _f64p(uv)))
    return uv


#: Alias: the natural conformal map is LSCM.
lscm = natural_conformal_map


def pinned_natural_conformal_map(
    positions: ArrayLike,
    triangles: ArrayLike,
    pins: Mapping[int, Sequence[float]],
    *,
    progress: Optional[ProgressCallback] = None,
) -> np.ndarray:
    """Natural conformal map with two or more pinned vertices
    (``uvf_pinned_natural_conformal_map``; Desbrun et al. 2002 §4.1–4.2, pins as Lagrange
    point constraints): every pin lands exactly where given, the rest minimises the conformal
    energy.

    Args:
        positions: ``(n, 3)`` vertex positions.
        triangles: ``(m, 3)`` vertex indices, counter-clockwise.
        pins: ``{vertex: (u, v)}`` with at least two entries.
        progress: as for :func:`natural_conformal_map`.

    Returns:
        ``(n, 2)`` float64 UVs, NaN for unreferenced vertices.

    Raises:
        InvalidArgument (fewer than two pins, bad vertices, conflicting pins), InvalidMesh,
        UnsupportedTopology, NumericalFailure, Cancelled.
    """
    p, t = _mesh_arrays(positions, triangles)
    try:
        if any(isinstance(v, bool) or not isinstance(v, (int, np.integer)) for v in dict(pins)):
            raise TypeError  # a float vertex would be truncated to another vertex
        items = sorted((int(v), (float(uv[0]), float(uv[1]))) for v, uv in dict(pins).items())
    except (TypeError, ValueError, IndexError):
        raise InvalidArgument(f"pins must map vertex -> (u, v), not {pins!r}") from None
    vertices = _as_indices(np.array([v for v, _ in items], dtype=np.int64), "pin vertices", InvalidArgument, None,
                           "pin {row} is vertex {value}, which {reason}")
    uvs = np.ascontiguousarray([uv for _, uv in items], dtype=np.float64).reshape(-1, 2)
    options = L.UvfIntrinsicToolOptions()
    L.library().uvf_intrinsic_tool_options_default(byref(options))
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    uv = np.empty((len(p), 2), dtype=np.float64)
    lib = L.library()
    bridge.run(
        lambda: lib.uvf_pinned_natural_conformal_map(
            _f64p(p), len(p), _u32p(t), len(t), _u32p(vertices), _f64p(uvs), len(vertices), byref(options), _f64p(uv)
        )
    )
    return uv
