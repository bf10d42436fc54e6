"""QuadCover: seamless grid parameterization of a mesh of any genus, and its quad mesh."""

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
from ._common import ArrayLike, ProgressCallback, _ProgressBridge, _as_points, _f64p, _from_struct, _mesh_arrays, _take_quad_mesh, _u32p


@dataclasses.dataclass(frozen=True)
class QuadCoverReport:
    """What ``uvf_quadcover`` reports."""

    #: Cone (singular) vertices of the frame field.
    cone_count: int
    #: Cutting paths, each with one integer gap.
    chain_count: int
    #: Triangles whose (u, v) image has non-positive signed area.
    flipped_count: int
    #: Surface length of one grid cell.
    grid_spacing: float
    #: Largest distance of a free gap or cone coordinate to an integer before rounding.
    rounding_offset: float
    #: Largest distance of any gap or cone coordinate to an integer in the result.
    lattice_error: float
    #: Σ A |∇f − K|² / Σ A |K|² of the continuous solve and of the result.
    energy_continuous: float
    energy: float
    #: Cones of the field before the cone-pair cancellation (``cone_count`` is after it).
    cones_before_cancellation: int
    #: ± pair moves the cancellation kept (re-matching can open cones elsewhere: the net
    #: change is ``cones_before_cancellation - cone_count``).
    cancelled_pairs: int
    #: Cone-to-boundary moves the cancellation kept.
    cones_moved_to_boundary: int
    #: Folded triangles before the untangling (``flipped_count`` is after it).
    flipped_before_untangling: int
    #: Folded triangles no untangling can open (two corners fixed at one grid point by the
    #: integer unknowns); 0 when ``untangle`` is off.
    forced_flat_count: int


def quadcover(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    field: Optional[ArrayLike] = None,
    grid_spacing: Optional[float] = None,
    alignment: Optional[float] = None,
    round: bool = True,
    cones_on_grid: bool = False,
    pair_cells: Optional[float] = None,
    untangle: bool = True,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, np.ndarray, QuadCoverReport]:
    """QuadCover (Kälberer, Nieser & Polthier 2007; course notes ch. 8; ``uvf_quadcover``): a
    global parameterization of a mesh of any genus whose integer iso-lines close up over the
    whole surface. Across every interior edge the two triangles' (u, v) differ by a quarter
    turn and an integer translation (with ``cones_on_grid``, every cone also sits on an integer
    point, as in mixed-integer quadrangulation; otherwise only the gaps are rounded, as in the
    course notes, which folds fewer triangles). The map may fold
    near cones closer than a grid cell or two (``report.flipped_count``).

    Args:
        field: ``(m, 3)`` tangent vectors, one per triangle (projected on its plane); default:
            a smooth cross field aligned with the principal curvature directions.
        grid_spacing: surface length of one grid cell (default: 3 mean edge lengths).
        alignment: curvature alignment of the default field (default 1; > 0).
        round: ``False`` returns the continuous solve (gaps not integer).
        pair_cells: ± cone pairs of the field closer than this many grid cells are cancelled,
            and cones that close to the boundary moved onto it, before the map is computed
            (default 2; 0 keeps the field's cones; not in the paper). Fewer clustered cones fold
            the map less.
        untangle: after rounding, move the regular vertices near folded triangles to open them,
            keeping every gap, seam and cone position (default ``True``; not in the paper).

    Returns:
        ``(corner_uv, cone_index, report)``: ``(m, 3, 2)`` (u, v) per triangle corner in grid
        units, ``(n,)`` int32 array of 4 × the field's index per vertex (0 off the cones), and a
        :class:`QuadCoverReport`.
    """
    p, t = _mesh_arrays(positions, triangles)
    options, f = _quadcover_options(t, field, grid_spacing, alignment, round, cones_on_grid, pair_cells, untangle)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    corner_uv = np.empty((len(t), 3, 2), dtype=np.float64)
    cones = np.zeros(len(p), dtype=np.int32)
    report = L.UvfQuadCoverReport()
    lib = L.library()
    field_pointer = _f64p(f) if f is not None else None
    bridge.run(
        lambda: lib.uvf_quadcover(
            _f64p(p),
            len(p),
            _u32p(t),
            len(t),
            byref(options),
            field_pointer,
            _f64p(corner_uv),
            cones.ctypes.data_as(POINTER(ctypes.c_int32)),
            byref(report),
        )
    )
    return corner_uv, cones, _from_struct(QuadCoverReport, report)


def quadcover_quad_mesh(
    positions: ArrayLike,
    triangles: ArrayLike,
    *,
    density: int = 1,
    field: Optional[ArrayLike] = None,
    grid_spacing: Optional[float] = None,
    alignment: Optional[float] = None,
    cones_on_grid: bool = False,
    pair_cells: Optional[float] = None,
    untangle: bool = True,
    progress: Optional[ProgressCallback] = None,
) -> Tuple[np.ndarray, List[np.ndarray], QuadCoverReport]:
    """The integer grid lines of a :func:`quadcover` map as a polygon mesh on the surface
    (``uvf_quadcover_quad_mesh``): lines u, v ∈ ℤ / ``density`` (a whole number ≥ 1; 1: one quad
    per grid cell), joined across every seam; faces that are not quads (around cones, next to
    folded triangles, on the boundary) are split into quads and at most one triangle. Where the
    map has no cone and no fold every face is a quad; ``cones_on_grid=True`` makes most faces
    around cones quads as well. The other arguments are :func:`quadcover`'s.

    Returns:
        ``(positions, faces, report)``: ``(k, 3)`` vertex positions on the input surface, a
        list of int arrays (the corners of every face, counter-clockwise seen from outside),
        and the :class:`QuadCoverReport` of the map.
    """
    p, t = _mesh_arrays(positions, triangles)
    options, f = _quadcover_options(t, field, grid_spacing, alignment, True, cones_on_grid, pair_cells, untangle)
    bridge = _ProgressBridge(progress)
    options.progress = bridge.c_function
    report = L.UvfQuadCoverReport()
    lib = L.library()
    quad = POINTER(L.UvfQuadMesh)()
    field_pointer = _f64p(f) if f is not None else None
    bridge.run(
        lambda: lib.uvf_quadcover_quad_mesh(
            _f64p(p), len(p), _u32p(t), len(t), byref(options), field_pointer, float(density), byref(quad), byref(report)
        )
    )
    quad_positions, faces = _take_quad_mesh(lib, quad)
    return quad_positions, faces, _from_struct(QuadCoverReport, report)


def _quadcover_options(t, field, grid_spacing, alignment, round, cones_on_grid, pair_cells, untangle):
    """``UvfQuadCoverOptions`` and the checked field array (or None)."""
    options = L.UvfQuadCoverOptions()
    L.library().uvf_quadcover_options_default(byref(options))
    if pair_cells is not None:
        options.pair_cells = float(pair_cells)
    if grid_spacing is not None:
        options.grid_spacing = float(grid_spacing)
    if alignment is not None:
        options.alignment = float(alignment)
    options.round = 1 if round else 0
    options.cones_on_grid = 1 if cones_on_grid else 0
    options.untangle = 1 if untangle else 0
    f = None
    if field is not None:
        f = _as_points(field, 3, "field")
        if len(f) != len(t):
            raise InvalidArgument(f"field has {len(f)} vectors but the mesh has {len(t)} triangles")
    return options, f
