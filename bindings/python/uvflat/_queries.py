"""Mesh queries and independent checks of a layout: counts and topology, boundary loops,
components, distortion metrics, the exact layout check."""

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
from ._common import ArrayLike, _as_indices, _as_points, _check, _f64p, _from_struct, _mesh_arrays, _u32p


@dataclasses.dataclass(frozen=True)
class MeshInfo:
    """Counts and topological invariants of a mesh (``UvfMeshInfo``)."""

    #: Vertices in the input arrays (including unreferenced ones).
    vertices: int
    #: Vertices used by at least one triangle.
    referenced_vertices: int
    #: Triangles.
    triangles: int
    #: Undirected edges.
    edges: int
    #: Connected components.
    components: int
    #: Boundary loops.
    boundary_loops: int
    #: Total number of vertices over all boundary loops.
    boundary_vertices: int
    #: Euler characteristic V − E + F.
    euler_characteristic: int
    #: Total genus.
    genus: int


@dataclasses.dataclass(frozen=True)
class Metrics:
    """Distortion summary of a UV map (``UvfMetrics``); distortion fields are NaN when no
    triangle is measurable. Angles are in radians."""

    #: Number of triangles measured.
    triangles: int
    #: Triangles whose UV orientation is opposite to the layout's majority orientation.
    flipped: int
    #: Triangles with (numerically) zero UV area, left out of every distortion figure.
    degenerate_uv: int
    #: Proper crossings between UV boundary edges.
    boundary_intersections: int
    #: Sander et al. 2001 L2 stretch after a global scale; 1 is optimal.
    stretch_l2: float
    #: Sander et al. 2001 L∞ stretch after the same scale.
    stretch_linf: float
    #: Area-weighted mean of σmax/σmin; 1 is conformal.
    conformal_mean: float
    #: Largest σmax/σmin.
    conformal_max: float
    #: Mean |UV corner angle − surface corner angle|, radians.
    angle_mean: float
    #: Largest corner angle error, radians.
    angle_max: float
    #: Area-weighted mean |ln(s·A_uv / A_3d)| with one global scale s; 0 is authalic.
    area_mean: float
    #: Largest |ln(s·A_uv / A_3d)|.
    area_max: float


def mesh_info(positions: ArrayLike, triangles: ArrayLike) -> MeshInfo:
    """Validates a mesh and reports its counts and topology (``uvf_mesh_info``).

    Raises :class:`InvalidMesh` (naming the bad triangle, vertex or edge) or
    :class:`InvalidArgument`.
    """
    p, t = _mesh_arrays(positions, triangles)
    info = L.UvfMeshInfo()
    _check(L.library().uvf_mesh_info(_f64p(p), len(p), _u32p(t), len(t), byref(info)))
    return _from_struct(MeshInfo, info)


def boundary_loops(positions: ArrayLike, triangles: ArrayLike) -> List[np.ndarray]:
    """Ordered boundary loops, counter-clockwise with the surface on the left
    (``uvf_boundary_loops``): one uint32 array of vertex indices per loop."""
    p, t = _mesh_arrays(positions, triangles)
    info = mesh_info(p, t)
    vertices = np.empty(info.boundary_vertices, dtype=np.uint32)
    offsets = np.empty(info.boundary_loops + 1, dtype=np.uint32)
    _check(
        L.library().uvf_boundary_loops(
            _f64p(p), len(p), _u32p(t), len(t), _u32p(vertices), len(vertices), _u32p(offsets), len(offsets)
        )
    )
    return [vertices[offsets[k] : offsets[k + 1]] for k in range(info.boundary_loops)]


def triangle_components(positions: ArrayLike, triangles: ArrayLike) -> np.ndarray:
    """Connected component id (0-based) of every triangle, a uint32 array of length m
    (``uvf_triangle_components``)."""
    p, t = _mesh_arrays(positions, triangles)
    out = np.empty(len(t), dtype=np.uint32)
    _check(L.library().uvf_triangle_components(_f64p(p), len(p), _u32p(t), len(t), _u32p(out)))
    return out


@dataclasses.dataclass(frozen=True)
class SnappedRepair:
    """What to weld and leave out so that a mesh with zero-area triangles can be solved
    (:func:`snapped_repair`)."""

    #: ``(n,)`` uint32 solve vertex of every input vertex, numbered in order of their lowest
    #: input vertex.
    vertex: np.ndarray
    #: ``(m,)`` bool, True for the triangles to solve.
    keep: np.ndarray
    #: Solve vertices.
    vertices: int
    #: Input vertices welded onto another.
    welded: int
    #: Triangles left out.
    left_out: int
    #: Solve vertices only left-out triangles use (a solve gives them no UV).
    unreferenced: int


def snapped_repair(positions: ArrayLike, triangles: ArrayLike) -> SnappedRepair:
    """The welds and left-out triangles that make a mesh with zero-area triangles (vertices
    snapped together but not merged, collinear corners) solvable (``uvf_snapped_repair``): in
    every degenerate triangle, the ends of an edge shorter than 1e-6 of its longest are welded;
    triangles still degenerate after welding are left out. Solve the kept triangles over
    ``positions[first input vertex of each solve vertex]``; every input vertex takes its solve
    vertex's UV. Raises :class:`InvalidMesh` for indices out of range or non-finite
    coordinates of used vertices."""
    p = _as_points(positions, 3, "positions")
    t = _as_indices(triangles, "triangles", InvalidMesh)
    vertex = np.empty(len(p), dtype=np.uint32)
    keep = np.empty(len(t), dtype=np.uint8)
    info = L.UvfSnappedRepairInfo()
    _check(
        L.library().uvf_snapped_repair(
            _f64p(p), len(p), _u32p(t), len(t), _u32p(vertex), keep.ctypes.data_as(POINTER(ctypes.c_uint8)), byref(info)
        )
    )
    return SnappedRepair(
        vertex=vertex,
        keep=keep.astype(bool),
        vertices=int(info.vertices),
        welded=int(info.welded),
        left_out=int(info.left_out),
        unreferenced=int(info.unreferenced),
    )


#: ``PolygonIslands.face_island`` of a face that is not selected, and
#: ``PolygonIslands.corner_vertex`` of its corners (``UVF_NOT_IN_AN_ISLAND``).
NOT_IN_AN_ISLAND = 0xFFFFFFFF


@dataclasses.dataclass(frozen=True)
class PolygonIslands:
    """The UV islands of a polygon mesh (:func:`polygon_islands`)."""

    #: Island of every face (uint32), :data:`NOT_IN_AN_ISLAND` where not selected; islands are
    #: numbered in order of their lowest face.
    face_island: np.ndarray
    #: Island vertex (one UV) of every corner (uint32), :data:`NOT_IN_AN_ISLAND` for corners of
    #: faces not selected; numbered island by island, so each island's are one contiguous range.
    corner_vertex: np.ndarray
    #: Number of islands.
    islands: int
    #: Number of island vertices, all islands together.
    island_vertices: int
    #: Edges of selected faces used by more than two corners (cut as non-manifold).
    non_manifold_edges: int
    #: Edges between two selected faces that traverse it the same way (cut: orientations disagree).
    misoriented_edges: int


def polygon_islands(
    corner_vertices: ArrayLike,
    face_sizes: Optional[ArrayLike] = None,
    vertex_count: Optional[int] = None,
    selected: Optional[ArrayLike] = None,
    seams: Optional[ArrayLike] = None,
) -> PolygonIslands:
    """Splits the selected faces of a polygon mesh into UV islands, as an interactive unwrap
    does with seams and a face selection (``uvf_polygon_islands``).

    Args:
        corner_vertices: vertex of every face corner, face after face (counter-clockwise), as
            Blender's ``loop.vertex_index``.
        face_sizes: corners of every face; ``None`` when every face is a triangle.
        vertex_count: number of vertices (default: the largest index + 1).
        selected: one flag per face, true for the faces to lay out; ``None`` for all.
        seams: one flag per corner, true when the edge from that corner to the next one of its
            face is a seam (Blender: ``edge.use_seam[loop.edge_index]``); ``None`` for none.

    Faces are in one island when joined through edges used by exactly two corners of the mesh,
    both in selected faces and in opposite directions, that are not seams; corners of one vertex
    share an island vertex only across such edges (a seam ending inside an island slits it).
    Raises :class:`InvalidArgument` for mis-sized arrays, indices past ``vertex_count``, faces
    of fewer than three corners.
    """
    corners = _as_indices(corner_vertices, "corner_vertices", InvalidArgument, None, "corner {row} references vertex {value}, which {reason}")
    if face_sizes is None:
        sizes = None
        face_count = len(corners) // 3
    else:
        sizes = _as_indices(face_sizes, "face_sizes", InvalidArgument, None, "face {row} has {value} corners, which {reason}")
        face_count = len(sizes)
    if vertex_count is None:
        vertex_count = int(corners.max()) + 1 if len(corners) else 0
    select = _flags(selected, face_count, "selected")
    seam = _flags(seams, len(corners), "seams")
    face_island = np.empty(face_count, dtype=np.uint32)
    corner_vertex = np.empty(len(corners), dtype=np.uint32)
    info = L.UvfPolygonIslandsInfo()
    _check(
        L.library().uvf_polygon_islands(
            _u32p(corners),
            len(corners),
            int(vertex_count),
            None if sizes is None else _u32p(sizes),
            face_count,
            None if select is None else select.ctypes.data_as(POINTER(ctypes.c_uint8)),
            None if seam is None else seam.ctypes.data_as(POINTER(ctypes.c_uint8)),
            _u32p(face_island),
            _u32p(corner_vertex),
            byref(info),
        )
    )
    return PolygonIslands(
        face_island=face_island,
        corner_vertex=corner_vertex,
        islands=int(info.islands),
        island_vertices=int(info.island_vertices),
        non_manifold_edges=int(info.non_manifold_edges),
        misoriented_edges=int(info.misoriented_edges),
    )


def _flags(values: Optional[ArrayLike], count: int, what: str) -> Optional[np.ndarray]:
    """Optional per-element flags as a contiguous uint8 array of ``count`` entries."""
    if values is None:
        return None
    array = np.ascontiguousarray(np.asarray(values).reshape(-1) != 0, dtype=np.uint8)
    if len(array) != count:
        raise InvalidArgument(f"{what} needs {count} flags, not {len(array)}")
    return array


def metrics(
    positions: ArrayLike,
    triangles: ArrayLike,
    uv: ArrayLike,
    uv_triangles: Optional[ArrayLike] = None,
) -> Metrics:
    """Distortion of a UV map (``uvf_metrics``; course notes ch. 4, Sander et al. 2001).

    Args:
        positions: ``(n, 3)`` vertex positions.
        triangles: ``(m, 3)`` vertex indices.
        uv: ``(k, 2)`` UV coordinates; NaN rows that no triangle uses are fine.
        uv_triangles: ``(m, 3)`` indices into ``uv`` per triangle (per-corner UVs), or
            ``None`` when ``uv`` has one row per vertex (then ``k`` must equal ``n``).

    The mesh need not be manifold. Raises :class:`InvalidArgument` for mis-sized arrays,
    out-of-range indices, non-finite coordinates or no triangles.
    """
    p = _as_points(positions, 3, "positions")
    t = _as_indices(triangles, "triangles", InvalidArgument)
    q = _as_points(uv, 2, "uv")
    if uv_triangles is None:
        ut = None
    else:
        ut = _as_indices(
            uv_triangles, "uv_triangles", InvalidArgument, 3, "uv triangle {row} references uv {value}, which {reason}"
        )
        if len(ut) != len(t):
            raise InvalidArgument(f"uv_triangles has {len(ut)} rows but triangles has {len(t)}")
    out = L.UvfMetrics()
    _check(
        L.library().uvf_metrics(
            _f64p(p), len(p), _u32p(t), len(t), _f64p(q), len(q), None if ut is None else _u32p(ut), byref(out)
        )
    )
    return _from_struct(Metrics, out)


@dataclasses.dataclass(frozen=True)
class LayoutCheck:
    """What :func:`check_layout` found (``UvfLayoutCheck``)."""

    #: Triangles not strictly counter-clockwise, or with a non-finite corner.
    flipped: int
    #: Crossing, touching or overlapping boundary-edge pairs, plus islands inside another.
    overlaps: int
    #: Islands (triangles connected through shared UV vertices).
    islands: int


def check_layout(uv: ArrayLike, uv_triangles: ArrayLike) -> LayoutCheck:
    """Exact, method-independent check of any UV layout (``uvf_check_layout``): ``uv`` is
    ``(k, 2)``, ``uv_triangles`` ``(m, 3)`` indices into it. A layout with no flipped triangle
    and no overlap covers no point twice."""
    q = np.ascontiguousarray(uv, dtype=np.float64).reshape(-1, 2)
    t = np.ascontiguousarray(uv_triangles, dtype=np.uint32).reshape(-1, 3)
    out = L.UvfLayoutCheck()
    _check(L.library().uvf_check_layout(_f64p(q), len(q), _u32p(t), len(t), byref(out)))
    return LayoutCheck(out.flipped, out.overlaps, out.islands)
