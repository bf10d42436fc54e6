"""Packing existing UV islands into the unit square (``uvf_pack_islands``)."""

from __future__ import annotations

import dataclasses
from ctypes import byref
from typing import Optional

import numpy as np

from . import _library as L
from ._errors import InvalidArgument
from ._common import ArrayLike, _as_indices, _as_points, _check, _f64p, _u32p


@dataclasses.dataclass(frozen=True)
class PackedIslands:
    """The result of :func:`pack_islands`."""

    #: ``(k, 2)`` packed UVs (UVs no triangle uses unchanged).
    uv: np.ndarray
    #: ``(m,)`` uint32 island of every UV triangle, in order of their first triangle.
    island: np.ndarray
    #: Number of islands.
    islands: int
    #: Fraction of the unit square covered by islands.
    utilization: float


def pack_islands(
    uv: ArrayLike,
    uv_triangles: ArrayLike,
    positions: Optional[ArrayLike] = None,
    triangles: Optional[ArrayLike] = None,
    margin: float = 0.005,
    rotate: bool = True,
    surface_areas: Optional[ArrayLike] = None,
) -> PackedIslands:
    """Packs the islands of an existing UV layout into the unit square, as Blender's *Pack
    Islands* does (``uvf_pack_islands``).

    Args:
        uv: ``(k, 2)`` UV coordinates.
        uv_triangles: ``(m, 3)`` indices into ``uv``; islands are the connected components of
            these triangles (triangles sharing a UV).
        positions, triangles: the surface, ``(n, 3)`` vertex positions and ``(m, 3)`` vertex
            indices, one row per UV triangle: each island is then scaled so that its UV area
            equals its surface area (one texel density). Without them islands keep their
            relative sizes.
        margin: gap between islands in the unit square, in [0, 0.5).
        rotate: let islands rotate (off for islands squeezed to a non-square image's aspect).
        surface_areas: ``(m,)`` the surface area of every UV triangle, instead of ``positions``
            and ``triangles``.

    Packed islands never overlap; islands that overlap in the input are moved as they are.
    Raises :class:`InvalidArgument` for mis-sized arrays, out-of-range indices, non-finite UVs,
    an island of zero UV area or a bad margin.
    """
    q = _as_points(uv, 2, "uv")
    t = _as_indices(uv_triangles, "uv_triangles", InvalidArgument, 3, "uv triangle {row} references uv {value}, which {reason}")
    areas = None if surface_areas is None else np.ascontiguousarray(np.asarray(surface_areas, dtype=np.float64).reshape(-1))
    if areas is not None and len(areas) != len(t):
        raise InvalidArgument(f"surface_areas has {len(areas)} entries but uv_triangles {len(t)} rows")
    if areas is not None and positions is not None:
        raise InvalidArgument("give surface_areas or positions and triangles, not both")
    if (positions is None) != (triangles is None):
        raise InvalidArgument("give both positions and triangles, or neither")
    if positions is not None:
        p = _as_points(positions, 3, "positions")
        s = _as_indices(triangles, "triangles", InvalidArgument)
        if len(s) != len(t):
            raise InvalidArgument(f"triangles has {len(s)} rows but uv_triangles {len(t)}: one per UV triangle")
        if len(s) and int(s.max()) >= len(p):
            raise InvalidArgument(f"triangles reference vertex {int(s.max())}, but positions has {len(p)} rows")
        a = p[s.astype(np.int64)]
        areas = np.ascontiguousarray(0.5 * np.linalg.norm(np.cross(a[:, 1] - a[:, 0], a[:, 2] - a[:, 0]), axis=1))
    options = L.UvfPackOptions()
    L.library().uvf_pack_options_default(byref(options))
    options.margin = float(margin)
    options.rotate = 1 if rotate else 0
    out = np.empty_like(q)
    island = np.empty(len(t), dtype=np.uint32)
    report = L.UvfPackReport()
    _check(
        L.library().uvf_pack_islands(
            _f64p(q), len(q), _u32p(t), len(t), None if areas is None else _f64p(areas), byref(options), _f64p(out), _u32p(island), byref(report)
        )
    )
    return PackedIslands(uv=out, island=island, islands=int(report.islands), utilization=float(report.utilization))
