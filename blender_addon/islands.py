"""The arrays of each UV island of a face selection, around the library's calls (islands by
``uvflat.polygon_islands``, zero-area faces by ``uvflat.snapped_repair``); numpy and the uvflat
binding only, no bpy.

Everything here works on flat arrays read from a Blender mesh with ``foreach_get``:

- ``loop_vert``, ``loop_edge``: vertex and edge of every loop (face corner);
- ``poly_start``, ``poly_total``: first loop and loop count of every polygon (Blender keeps a
  polygon's loops contiguous and in polygon order);
- ``face_selected``: polygons to unwrap (selected and not hidden);
- ``edge_seam``: edges marked as seams;
- ``tri_loops``, ``tri_poly``: Blender's own tessellation (``mesh.loop_triangles``), three loop
  indices per triangle, counter-clockwise like their polygon.

An island is a set of selected polygons connected through *inner* edges: edges that are not
seams, are shared by exactly two polygons of the mesh, both selected, and traversed in
opposite directions by them (so a flipped neighbour starts a new island). Every other edge of
a selected polygon is a cut: the selection border, seams, non-manifold and inconsistently
oriented edges.

A mesh vertex may become several island vertices: the loops around it are joined only across
inner edges, so a seam that ends inside an island slits it open, and two fans touching at a
single vertex are pulled apart. The island vertex of a loop is the connected component of its
loop in that "same UV" relation, which is exactly what Blender's own unwrap does.
"""

from __future__ import annotations

import dataclasses
from typing import Any, List, Optional, Sequence, Tuple

import numpy as np


@dataclasses.dataclass
class Island:
    """One island: a triangle mesh of its own, and where its vertices come from."""

    #: (k, 3) float64 positions of the island's vertices.
    positions: np.ndarray
    #: (m, 3) uint32 island-local vertex indices, counter-clockwise.
    triangles: np.ndarray
    #: Mesh polygons of the island.
    polys: np.ndarray
    #: Loops of the island's polygons.
    loops: np.ndarray
    #: Island-local vertex index of each of ``loops``.
    loop_vertex: np.ndarray
    #: (m, 3) mesh loop of every triangle corner (row t is ``triangles[t]``).
    triangle_loops: np.ndarray
    #: (m, 3) True where half-edge k of triangle t (corner k to k + 1) is not a polygon edge but
    #: a diagonal of the tessellation of an n-gon.
    triangle_diagonals: np.ndarray


@dataclasses.dataclass
class Split:
    """The selection split into islands."""

    islands: List[Island]
    #: Number of selected polygons.
    selected_polys: int
    #: Edges of selected polygons used by more than two polygons (cut: non-manifold).
    non_manifold_edges: int = 0
    #: Edges between two selected polygons that traverse them in the same direction (cut: the
    #: polygons' orientations disagree).
    misoriented_edges: int = 0


def split_islands(
    uvflat: Any,
    positions: np.ndarray,
    loop_vert: np.ndarray,
    loop_edge: np.ndarray,
    poly_start: np.ndarray,
    poly_total: np.ndarray,
    face_selected: np.ndarray,
    edge_seam: np.ndarray,
    tri_loops: np.ndarray,
    tri_poly: np.ndarray,
) -> Split:
    """Splits the selected polygons into islands (the library's ``uvflat.polygon_islands``,
    see the module docstring), then gathers each island's vertices, loops and triangles."""
    n_loops = len(loop_vert)
    n_polys = len(poly_start)
    loop_vert = np.asarray(loop_vert, dtype=np.int64)
    poly_start = np.asarray(poly_start, dtype=np.int64)
    poly_total = np.asarray(poly_total, dtype=np.int64)
    if (n_polys and not np.array_equal(poly_start, np.cumsum(poly_total) - poly_total)) or int(poly_total.sum()) != n_loops:
        # Blender always stores a polygon's loops contiguously in polygon order.
        raise ValueError("polygon loops are not contiguous in polygon order")
    loop_next = np.arange(1, n_loops + 1, dtype=np.int64)
    if n_polys:
        loop_next[poly_start + poly_total - 1] = poly_start
    found = uvflat.polygon_islands(
        loop_vert,
        poly_total,
        vertex_count=len(positions),
        selected=face_selected,
        seams=np.asarray(edge_seam, dtype=bool)[np.asarray(loop_edge, dtype=np.int64)],
    )
    n_islands = found.islands
    poly_island = found.face_island.astype(np.int64)
    poly_island[found.face_island == uvflat.NOT_IN_AN_ISLAND] = -1
    corner = found.corner_vertex.astype(np.int64)

    tri_loops = np.asarray(tri_loops, dtype=np.int64).reshape(-1, 3)
    tri_island = poly_island[np.asarray(tri_poly, dtype=np.int64)]
    keep = tri_island >= 0
    tri_loops, tri_island = tri_loops[keep], tri_island[keep]
    tri_order = np.argsort(tri_island, kind="stable")
    tri_bounds = np.searchsorted(tri_island[tri_order], np.arange(n_islands + 1))

    loop_poly = np.repeat(np.arange(n_polys, dtype=np.int64), poly_total)
    island_loops = np.flatnonzero(poly_island[loop_poly] >= 0)
    loop_island = poly_island[loop_poly[island_loops]]
    loop_order = np.argsort(loop_island, kind="stable")
    island_loops, loop_island = island_loops[loop_order], loop_island[loop_order]
    loop_bounds = np.searchsorted(loop_island, np.arange(n_islands + 1))

    # Island vertices are numbered island by island: each island's are one range.
    vertex_island = np.empty(found.island_vertices, dtype=np.int64)
    vertex_island[corner[island_loops]] = loop_island
    vertex_bounds = np.searchsorted(vertex_island, np.arange(n_islands + 1))
    vertex_loop = np.empty(found.island_vertices, dtype=np.int64)
    vertex_loop[corner[island_loops]] = island_loops
    all_positions = np.ascontiguousarray(positions[loop_vert[vertex_loop]], dtype=np.float64)
    tris = tri_loops[tri_order]
    diagonals = _diagonals(tris, loop_next)

    selected_polys = np.flatnonzero(poly_island >= 0)
    poly_order = selected_polys[np.argsort(poly_island[selected_polys], kind="stable")]
    poly_bounds = np.searchsorted(poly_island[poly_order], np.arange(n_islands + 1))

    islands = []
    for i in range(n_islands):
        loops = slice(loop_bounds[i], loop_bounds[i + 1])
        tri = slice(tri_bounds[i], tri_bounds[i + 1])
        islands.append(
            Island(
                positions=all_positions[vertex_bounds[i] : vertex_bounds[i + 1]],
                triangles=(corner[tris[tri]] - vertex_bounds[i]).astype(np.uint32),
                polys=poly_order[poly_bounds[i] : poly_bounds[i + 1]],
                loops=island_loops[loops],
                loop_vertex=corner[island_loops[loops]] - vertex_bounds[i],
                triangle_loops=tris[tri],
                triangle_diagonals=diagonals[tri],
            )
        )
    return Split(
        islands=islands,
        selected_polys=len(selected_polys),
        non_manifold_edges=found.non_manifold_edges,
        misoriented_edges=found.misoriented_edges,
    )


def _diagonals(tri_loops: np.ndarray, loop_next: np.ndarray) -> np.ndarray:
    """(m, 3) flags: half-edge k of a triangle (loop a to loop b) is a polygon edge exactly when
    b follows a or a follows b in their polygon; otherwise it is a tessellation diagonal."""
    a = tri_loops
    b = np.roll(tri_loops, -1, axis=1)
    return (loop_next[a] != b) & (loop_next[b] != a)


def cut_open(island: Island, cut_triangles: np.ndarray, cut_positions: np.ndarray) -> Optional[Island]:
    """The island re-indexed over a cut mesh that has the island's triangles in the same order
    (``uvflat.cut_to_disk``). Every loop takes the cut vertex of a triangle corner it belongs
    to; None when a cut runs through the inside of a polygon (two corners of one loop then get
    different cut vertices, which one UV per loop cannot represent)."""
    cut_triangles = np.asarray(cut_triangles, dtype=np.int64)
    position = np.searchsorted(island.loops, island.triangle_loops)
    loop_vertex = np.full(len(island.loops), -1, dtype=np.int64)
    loop_vertex[position.ravel()] = cut_triangles.ravel()
    if (loop_vertex[position] != cut_triangles).any() or (loop_vertex < 0).any():
        return None
    return dataclasses.replace(
        island,
        positions=np.ascontiguousarray(cut_positions, dtype=np.float64),
        triangles=np.ascontiguousarray(cut_triangles, dtype=np.uint32),
        loop_vertex=loop_vertex,
    )


def without_degenerate(uvflat: Any, island: Island) -> Island:
    """The island without its zero-area triangles (two vertices snapped together but not
    merged, collinear corners), which the library's methods refuse, by the library's
    ``uvflat.snapped_repair``: vertices that coincide are welded into one for the solve (both
    keep their mesh vertices; their loops get the one UV), the triangles still of zero area
    are left out (slits of zero area, free boundaries of the solve, their loops still getting
    the UVs of their vertices). The island is returned unchanged when it has none, or when a
    vertex would be left in no triangle (the solve would give it no UV; the library's refusal
    then names the face)."""
    try:
        repair = uvflat.snapped_repair(island.positions, island.triangles)
    except uvflat.Error:
        return island  # (a non-finite coordinate: the solve refuses the island and names it)
    if repair.left_out == 0 or repair.unreferenced > 0 or not repair.keep.any():
        return island
    vertex = repair.vertex.astype(np.int64)
    first = np.unique(vertex, return_index=True)[1]
    return dataclasses.replace(
        island,
        positions=np.ascontiguousarray(island.positions[first]),
        triangles=np.ascontiguousarray(vertex[island.triangles[repair.keep].astype(np.int64)], dtype=np.uint32),
        loop_vertex=vertex[island.loop_vertex],
        triangle_loops=island.triangle_loops[repair.keep],
        triangle_diagonals=island.triangle_diagonals[repair.keep],
    )


def cut_edges(before: Island, after: Island, loop_edge: np.ndarray, loop_next: np.ndarray) -> np.ndarray:
    """Mesh edges that the cut from ``before`` to ``after`` (:func:`cut_open`) opened: edges
    whose two loops in the island join the same two island vertices before and different ones
    after (a UV seam the mesh does not mark)."""

    def split_edges(island: Island) -> np.ndarray:
        loops = island.loops
        following = np.searchsorted(loops, loop_next[loops])
        ends = np.sort(np.stack([island.loop_vertex, island.loop_vertex[following]], axis=1), axis=1)
        edges = loop_edge[loops]
        order = np.argsort(edges, kind="stable")
        paired = edges[order][1:] == edges[order][:-1]
        i, j = order[:-1][paired], order[1:][paired]
        return edges[i][(ends[i] != ends[j]).any(axis=1)]

    return np.setdiff1d(split_edges(after), split_edges(before))


def fill_holes(
    positions: np.ndarray, triangles: np.ndarray, loops: List[np.ndarray]
) -> Tuple[np.ndarray, np.ndarray]:
    """Blender's "Fill Holes" for free-boundary solves: every boundary loop but the longest
    (in 3D) is closed by a cone of triangles around a virtual vertex appended after the
    island's vertices, so a tube or a holed patch is solved as a disk instead of being free to
    fold onto itself. The apex sits at the loop's centroid, moved along the loop's (Newell)
    normal by half its mean radius so that no cone triangle is flat; loops that enclose no
    area (the slits of :func:`without_degenerate`) stay open. ``loops`` run with the surface
    on their left (``uvflat.boundary_loops``)."""
    p = np.asarray(positions, dtype=np.float64)
    if len(loops) < 2:
        return p, triangles
    lengths = [float(np.linalg.norm(p[np.roll(lp, -1)] - p[lp], axis=1).sum()) for lp in loops]
    outer = int(np.argmax(lengths))
    points, tris = [p], [np.asarray(triangles, dtype=np.int64)]
    apex = len(p)
    for k, lp in enumerate(loops):
        lp = np.asarray(lp, dtype=np.int64)
        ring = p[lp]
        centroid = ring.mean(axis=0)
        normal = np.cross(ring - centroid, np.roll(ring, -1, axis=0) - centroid).sum(axis=0)
        radius = float(np.linalg.norm(ring - centroid, axis=1).mean())
        if k == outer or not np.linalg.norm(normal) > 1e-6 * radius * radius:
            continue
        points.append((centroid - 0.5 * radius * normal / np.linalg.norm(normal))[None, :])
        # Boundary half-edges a -> b have the surface on their left; the cone holds b -> a.
        tris.append(np.stack([np.roll(lp, -1), lp, np.full(len(lp), apex)], axis=1))
        apex += 1
    return np.concatenate(points), np.ascontiguousarray(np.concatenate(tris), dtype=np.uint32)


def stacked_triangles(triangle_lists: Sequence[np.ndarray], vertex_counts: Sequence[int]) -> Tuple[np.ndarray, np.ndarray]:
    """The triangles of several islands as one (n, 3) array indexing their vertices stacked in
    the same order, and the island of each triangle: one numpy pass over a mesh's islands
    instead of one per island (a mesh may have thousands)."""
    offsets = np.concatenate([[0], np.cumsum(np.asarray(vertex_counts, dtype=np.int64))[:-1]])
    owner = np.repeat(np.arange(len(triangle_lists)), [len(t) for t in triangle_lists])
    tris = np.concatenate(triangle_lists).astype(np.int64).reshape(-1, 3) + offsets[owner][:, None]
    return tris, owner


def triangle_areas(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Unsigned areas of triangles of 2D or 3D points."""
    p = np.asarray(points, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64)
    e1 = p[t[:, 1]] - p[t[:, 0]]
    e2 = p[t[:, 2]] - p[t[:, 0]]
    if p.shape[1] == 2:
        return 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    return 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)


def farthest_pair(points: np.ndarray) -> Tuple[int, int]:
    """Indices of the two points farthest apart: exact up to 2000 points, otherwise the usual
    double sweep (farthest from the first, then farthest from that one)."""
    p = np.asarray(points, dtype=np.float64)
    if len(p) <= 2000:
        d = ((p[:, None, :] - p[None, :, :]) ** 2).sum(axis=2)
        i, j = np.unravel_index(int(np.argmax(d)), d.shape)
        return int(i), int(j)
    i = int(np.argmax(((p - p[0]) ** 2).sum(axis=1)))
    j = int(np.argmax(((p - p[i]) ** 2).sum(axis=1)))
    return i, j


def similarity_fit(source: np.ndarray, target: np.ndarray) -> Tuple[complex, complex]:
    """The similarity z -> a·z + b (rotation, uniform scale, translation; complex numbers)
    that maps 2D ``source`` points onto ``target`` in the least-squares sense."""
    s = source[:, 0] + 1j * source[:, 1]
    t = target[:, 0] + 1j * target[:, 1]
    if len(s) == 1:
        return 1.0 + 0j, complex(t[0] - s[0])
    sc, tc = s - s.mean(), t - t.mean()
    denom = float(np.vdot(sc, sc).real)
    a = complex(np.vdot(sc, tc) / denom) if denom > 0 else 1.0 + 0j
    return a, complex(t.mean() - a * s.mean())


def area_scale(area_3d: np.ndarray, area_uv: np.ndarray) -> np.ndarray:
    """The uniform UV scales that make UV areas ``area_uv`` equal to ``area_3d`` (as Blender
    does before packing, islands keep their relative sizes); 1 where either area is not
    positive (or the UV area not finite)."""
    area_3d, area_uv = np.asarray(area_3d, dtype=np.float64), np.asarray(area_uv, dtype=np.float64)
    valid = (area_uv > 0) & np.isfinite(area_uv) & (area_3d > 0)
    factor = np.ones(area_uv.shape)
    factor[valid] = np.sqrt(area_3d[valid] / area_uv[valid])
    return factor


def scale_to_area(uv: np.ndarray, triangles: np.ndarray, area_3d: float) -> np.ndarray:
    """``uv`` scaled uniformly so that its area equals ``area_3d`` (:func:`area_scale`)."""
    return uv * float(area_scale(np.array([area_3d]), np.array([triangle_areas(uv, triangles).sum()]))[0])


def angle_distortion(positions: np.ndarray, uv: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Per triangle, the mean |UV corner angle − 3D corner angle| in radians."""

    def corner_angles(p: np.ndarray) -> np.ndarray:
        t = np.asarray(triangles, dtype=np.int64)
        out = []
        for k in range(3):
            a, b, c = p[t[:, k]], p[t[:, (k + 1) % 3]], p[t[:, (k + 2) % 3]]
            u, v = b - a, c - a
            nu = np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1)
            cos = np.einsum("ij,ij->i", u, v) / np.where(nu > 0, nu, 1)
            out.append(np.arccos(np.clip(cos, -1, 1)))
        return np.stack(out, axis=1)

    return np.abs(corner_angles(np.asarray(uv, float)) - corner_angles(np.asarray(positions, float))).mean(axis=1)
