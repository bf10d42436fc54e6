"""The "uvflat Unwrap" operator: unwraps the selected faces of every mesh in Edit Mode.

Steps (all objects of a multi-object Edit Mode together):

1. switch to Object Mode for a moment, so the meshes can be read and written with
   ``foreach_get``/``foreach_set`` (numpy speed instead of per-loop Python);
2. split each mesh's selected faces into islands (the library's ``uvflat.polygon_islands``: seams, the selection
   border, non-manifold and inconsistently oriented edges cut), triangulated with Blender's own
   tessellation (``mesh.loop_triangles``), so n-gons, concave ones too, are solved as triangles
   and written back per loop;
3. solve every island with the chosen uvflat method; closed islands (no boundary) and islands
   that are not topological disks with holes (genus > 0) are first cut into a disk by the
   library's cut graph along polygon edges, and the new seams are marked in the mesh (or, with
   "Cut Closed Islands" off, skipped with a warning, keeping their UVs); vertices snapped
   together but not merged are welded for the solve and other zero-area faces left out; islands
   the library still rejects are skipped and the warning quotes the library's message in the
   mesh's own vertex and face numbers; an island with holes whose free-boundary map folds is
   solved again with its holes filled ("Fill Holes");
4. pins: pinned loops never change. With natural conformal and two or more pinned vertices on an
   island, every pin is a point constraint of the solve (``uvf_pinned_natural_conformal_map``);
   if the library finds them conflicting, the two pins farthest apart in UV constrain it and
   the others are kept where they are but do not constrain the solve (reported). With ABF++
   the two pins farthest apart replace the automatic pair of its reconstruction. Every other
   method (and any method with one pin) solves without constraints and then moves the island
   by the similarity (rotation, uniform scale, translation) that best matches its pins.
   Islands with pins are not moved by the layout;
5. islands without pins are packed into the unit square by the library (``uvflat.pack_islands``:
   UV area = 3D area, so relative sizes as in 3D; corrected for the image aspect ratio if asked);
   optionally Blender's ``uv.pack_islands`` then packs them again (pinned islands stay locked);
   Every solved island is checked by the library's exact layout checker
   (``uvflat.check_layout``: flipped triangles, boundary edges that cross or touch); an island
   the chosen method folded is solved again by bijective SLIM (a scaffold around its free
   boundary keeps it one-to-one), and the island is reported as repaired;
6. back to Edit Mode; the operator reports islands, cuts and marked seams, repairs, the flip
   and overlap counts of the written layout (the exact checker over every island together),
   seconds and the mean angle error (degrees) in the status bar.

Run from the menu (``invoke``), step 3 runs on a worker thread while the operator stays modal:
the progress counter follows it and Esc cancels it (every library call gets a progress
callback, so the running method stops within one iteration) and leaves the mesh as it was.
Redo (F9), scripts and background mode run the same steps synchronously (``execute``).
"""

from __future__ import annotations

import math
import re
import threading
import time
from typing import Any, Callable, Dict, List, Optional, Tuple

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty

from . import islands as isl
from ._binding import binding

#: Element references in the library's messages (``crates/uvflat-core/src/mesh`` errors): an edge as a vertex
#: pair, a list or a pair of triangles, one triangle, one vertex.
_ELEMENT = re.compile(
    r"\bedge \((?P<edge>\d+, \d+)\)|\btriangles \[(?P<list>[\d, ]+)\]|\btriangles (?P<pair>\d+ and \d+)"
    r"|\btriangle (?P<one>\d+)|\bvertex (?P<v>\d+)"
)

#: Facts about the last run, for tests and scripts (the operator itself cannot return data).
LAST_RUN: Dict[str, Any] = {}

METHODS = [
    (
        "NATURAL_CONFORMAL",
        "Natural Conformal",
        "Free-boundary natural conformal map (= LSCM, Desbrun et al. 2002); honours every pin; "
        "islands it folds are solved again by bijective SLIM",
    ),
    ("ABF_PLUS_PLUS", "ABF++", "Angle Based Flattening (Sheffer et al. 2005), then least-squares reconstruction; free boundary"),
    (
        "CIRCLE_PATTERNS",
        "Circle Patterns",
        "Conformal map by circle patterns on the intrinsic Delaunay triangulation (Kharevych et al. 2006); free boundary",
    ),
    ("INTRINSIC", "Intrinsic (λ, μ)", "λ·discrete conformal + μ·discrete authalic weights, fixed boundary (Desbrun et al. 2002)"),
    ("MEAN_VALUE", "Mean Value", "Floater's mean value coordinates, boundary fixed on a circle or square; never flips"),
    ("SLIM", "SLIM (symmetric Dirichlet)", "Isometric free-boundary map minimised by SLIM (Rabinovich et al. 2017); never flips (unless pins beyond two pull their neighbours)"),
    ("STRETCH", "Minimum Stretch", "Sander et al. 2001 L2 stretch, free boundary; never flips (unless pins beyond two pull their neighbours)"),
    (
        "ARAP",
        "As Rigid As Possible",
        "Liu et al. 2008 local/global ARAP, free boundary; no triangle flips or shrinks below 1% of its share of the area "
        "(islands whose boundary overlaps are solved again by bijective SLIM)",
    ),
    ("TUTTE", "Tutte", "Uniform weights, fixed convex boundary; never flips"),
    ("FLOATER", "Floater", "Floater's shape-preserving weights, fixed convex boundary; never flips"),
    ("AUTHALIC", "Authalic", "Discrete authalic (Wachspress) weights, fixed boundary"),
    ("CONFORMAL", "Conformal (fixed)", "Discrete conformal (harmonic, cotangent) weights, fixed boundary"),
]
_NONLINEAR = {"SLIM": "slim", "STRETCH": "stretch", "ARAP": "arap"}
#: Methods whose holes are filled first when Fill Holes is on (the others either fix the
#: boundary and fill holes in the library, or do not fold a tube: SLIM, stretch, ARAP start
#: from a fixed-boundary map and never flip a triangle).
_FREE_BOUNDARY = {"NATURAL_CONFORMAL", "ABF_PLUS_PLUS"}
_FIXED_WEIGHTS = {
    "MEAN_VALUE": "mean_value",
    "INTRINSIC": "intrinsic",
    "TUTTE": "uniform",
    "FLOATER": "floater",
    "AUTHALIC": "authalic",
    "CONFORMAL": "conformal",
}


def _get(collection: Any, name: str, dtype: Any, count: int, width: int = 1) -> np.ndarray:
    out = np.empty(count * width, dtype=dtype)
    if count:
        collection.foreach_get(name, out)
    return out.reshape(-1, width) if width > 1 else out


def image_aspect(obj: bpy.types.Object) -> float:
    """Width / height of the image of the active Image Texture node of the object's active
    material (what Blender's "Correct Aspect" uses), 1 when there is none."""
    material = obj.active_material
    tree = getattr(material, "node_tree", None) if material is not None else None
    if tree is None:
        return 1.0
    nodes = [tree.nodes.active] + list(tree.nodes)
    for node in nodes:
        if node is not None and node.type == "TEX_IMAGE" and node.image is not None:
            w, h = node.image.size
            if w > 0 and h > 0:
                return float(w) / float(h)
    return 1.0


class _Job:
    """One island on its way through the solve."""

    def __init__(self, obj_index: int, island: isl.Island, pin_vertices: np.ndarray, pin_uv: np.ndarray) -> None:
        self.obj_index = obj_index
        self.island = island
        self.pin_vertices = pin_vertices  # island-local vertices with a pinned loop (unique)
        self.pin_uv = pin_uv  # their current UVs
        self.uv: Optional[np.ndarray] = None
        self.holes = True  # whether it may have more than one boundary loop (False once known)

    def with_pin_uv(self, pin_uv: np.ndarray) -> "_Job":
        """The same job with its pins at ``pin_uv`` (the island and what is known of it kept)."""
        job = _Job(self.obj_index, self.island, self.pin_vertices, pin_uv)
        job.holes = self.holes
        return job

    @staticmethod
    def of(obj_index: int, island: isl.Island, uv: np.ndarray, pinned: np.ndarray) -> "_Job":
        """The job of an island, with its pinned vertices and their current UVs."""
        pin_loops = island.loops[pinned[island.loops]]
        vertices, first = np.unique(island.loop_vertex[pinned[island.loops]], return_index=True)
        return _Job(obj_index, island, vertices, uv[pin_loops[first]] if len(pin_loops) else np.zeros((0, 2)))


class Cancelled(Exception):
    """The user pressed Esc (or a caller's ``cancelled()`` said so) during the solve."""


class UnwrapRun:
    """One unwrap of the selected faces of ``objects`` (in Object Mode), in three steps:
    ``__init__`` reads the meshes and splits the islands (main thread), :meth:`solve` solves
    them (numpy and the library only, so it may run on a worker thread), :meth:`write_back`
    lays them out and writes the UVs (main thread)."""

    def __init__(self, uvflat: Any, settings: Dict[str, Any], objects: List[bpy.types.Object], correct_aspect: bool):
        self.uvflat = uvflat
        self.settings = settings
        self.objects = objects
        self.start = time.perf_counter()
        self.cancel = threading.Event()
        self.fraction = 0.0
        self.error: Optional[BaseException] = None
        self.meshes: List[Tuple[Any, ...]] = []
        self.has_degenerate: List[bool] = []  # per mesh: any zero-area triangle at all
        # Per mesh: each loop's vertex, edge, polygon and next loop (error messages in the
        # mesh's own indices, the seams of cut islands).
        self.loop_vertex: List[np.ndarray] = []
        self.loop_edge: List[np.ndarray] = []
        self.loop_poly: List[np.ndarray] = []
        self.loop_next: List[np.ndarray] = []
        self.new_seams: List[List[np.ndarray]] = []
        self.non_manifold_edges = 0
        self.misoriented_edges = 0
        self.jobs: List[_Job] = []
        for k, obj in enumerate(objects):
            self._read(k, obj, correct_aspect)
        self.solved: List[_Job] = []
        self.skipped = {"closed": 0, "not_disk": 0, "invalid": 0}
        self.messages: List[str] = []
        self.unenforced_pins = 0
        self.cut_islands = 0
        self.filled_islands = 0
        self.repaired_islands = 0
        self.folded_islands = 0
        self.solve_seconds = 0.0

    def _read(self, k: int, obj: bpy.types.Object, correct_aspect: bool) -> None:
        """Reads one mesh and queues its islands."""
        me = obj.data
        if me.uv_layers.active is None:
            me.uv_layers.new(name="UVMap")
        # The layer is looked up by name at every use (`_uv_layer`), never kept: reading its
        # pin or selection attributes may create them, which reallocates the mesh's layer array
        # and leaves an earlier `MeshUVLoopLayer` reference dangling (Blender 4.5 crashed in
        # `layer.uv.foreach_set` on the second unwrap of a mesh that had no UV map before).
        layer_name = me.uv_layers.active.name
        n_loops, n_polys = len(me.loops), len(me.polygons)
        me.calc_loop_triangles()
        # The shape the user edits: the active shape key's (Edit Mode shows and edits that one,
        # and Blender's own unwrap reads it), the mesh's vertices without shape keys.
        key = obj.active_shape_key
        source = key.data if key is not None and len(key.data) == len(me.vertices) else me.vertices
        positions = _get(source, "co", np.float32, len(me.vertices), 3).astype(np.float64)
        selected = _get(me.polygons, "select", bool, n_polys) & ~_get(me.polygons, "hide", bool, n_polys)
        loop_vertex = _get(me.loops, "vertex_index", np.int32, n_loops)
        loop_edge = _get(me.loops, "edge_index", np.int32, n_loops)
        poly_start = _get(me.polygons, "loop_start", np.int32, n_polys)
        poly_total = _get(me.polygons, "loop_total", np.int32, n_polys)
        tri_loops = _get(me.loop_triangles, "loops", np.int32, len(me.loop_triangles), 3)
        # Checked once for the whole mesh, so that islands are only searched when it has any.
        corners = loop_vertex[tri_loops].reshape(-1, 3)
        self.has_degenerate.append(bool(len(corners)) and self._has_zero_area(positions, corners))
        split = isl.split_islands(
            self.uvflat,
            positions,
            loop_vertex,
            loop_edge,
            poly_start,
            poly_total,
            selected,
            _get(me.edges, "use_seam", bool, len(me.edges)),
            tri_loops,
            _get(me.loop_triangles, "polygon_index", np.int32, len(me.loop_triangles)),
        )
        # The attribute accessors (uv, pin, vertex_selection, edge_selection), not the legacy
        # `layer.data` wrappers: in Blender 4.5, `layer.data.foreach_set("select", ...)`
        # corrupts memory.
        uv = _get(_uv_layer(me, layer_name).uv, "vector", np.float32, n_loops, 2).astype(np.float64)
        pin = _uv_layer(me, layer_name).pin
        pinned = _get(pin, "value", bool, n_loops) if len(pin) == n_loops else np.zeros(n_loops, bool)
        self.meshes.append((obj, me, layer_name, uv, pinned, image_aspect(obj) if correct_aspect else 1.0))
        self.loop_vertex.append(loop_vertex.astype(np.int64))
        self.loop_edge.append(loop_edge.astype(np.int64))
        self.loop_poly.append(np.repeat(np.arange(n_polys, dtype=np.int64), poly_total))
        following = np.arange(1, n_loops + 1, dtype=np.int64)
        if n_polys:
            following[poly_start.astype(np.int64) + poly_total - 1] = poly_start
        self.loop_next.append(following)
        self.new_seams.append([])
        self.jobs.extend(_Job.of(k, island, uv, pinned) for island in split.islands)
        self.non_manifold_edges += split.non_manifold_edges
        self.misoriented_edges += split.misoriented_edges

    def _has_zero_area(self, positions: np.ndarray, corners: np.ndarray) -> bool:
        """Whether the mesh has zero-area triangles (True also when the library cannot tell, a
        non-finite coordinate: the islands are then checked one by one)."""
        try:
            return self.uvflat.snapped_repair(positions, corners).left_out > 0
        except self.uvflat.Error:
            return True

    # --- solve (any thread) ------------------------------------------------------------------

    def solve_catching(self) -> None:
        """:meth:`solve` for a worker thread: the exception, if any, is kept in ``error``."""
        try:
            self.solve(lambda f: None)
        except BaseException as e:  # noqa: B902 - handed to the main thread
            self.error = e

    def solve(self, progress: Callable[[float], None]) -> None:
        """Solves every island; ``progress(fraction)`` after each one. Raises
        :class:`Cancelled` as soon as ``self.cancel`` is set (the library's own progress
        callback stops the running method within one iteration)."""
        solve_start = time.perf_counter()
        disks = self._known_disks()
        for index, job in enumerate(self.jobs):
            self._report(index / len(self.jobs), progress)
            try:
                self._solve_job(index, job, bool(disks[index]), lambda f: self._keep_going((index + f) / len(self.jobs)))
            except self.uvflat.Cancelled:
                raise Cancelled() from None
        self.solve_seconds = time.perf_counter() - solve_start

    def _report(self, fraction: float, progress: Callable[[float], None]) -> None:
        if self.cancel.is_set():
            raise Cancelled()
        self.fraction = fraction
        progress(fraction)

    def _keep_going(self, fraction: float) -> bool:
        """The library's progress callback: records the fraction, False once cancelled."""
        self.fraction = fraction
        return not self.cancel.is_set()

    def _known_disks(self) -> np.ndarray:
        """Per job, whether its island is known to be a valid disk with one boundary loop,
        found for all islands at once (one library call instead of one per island: a mesh may
        have thousands). The islands of meshes without degenerate triangles are stacked into one
        mesh; if the library accepts it, every island is valid, and an island whose Euler
        characteristic V − E + F is 1 is a disk with one boundary loop (χ = 2 − 2g − b, and an
        island is edge-connected). False where not known: those islands are checked one by one."""
        known = np.zeros(len(self.jobs), dtype=bool)
        todo = [k for k, job in enumerate(self.jobs) if not self.has_degenerate[job.obj_index]]
        if not todo:
            return known
        islands = [self.jobs[k].island for k in todo]
        counts = [len(island.positions) for island in islands]
        tris, owner = isl.stacked_triangles([island.triangles for island in islands], counts)
        try:
            self.uvflat.mesh_info(np.concatenate([island.positions for island in islands]), tris.astype(np.uint32))
        except self.uvflat.Error:
            return known
        edges = np.sort(np.stack([tris, np.roll(tris, -1, axis=1)], axis=2).reshape(-1, 2), axis=1)
        _, first = np.unique(edges[:, 0] * int(sum(counts)) + edges[:, 1], return_index=True)
        edge_count = np.bincount(owner[first // 3], minlength=len(islands))
        chi = np.asarray(counts) - edge_count + np.bincount(owner, minlength=len(islands))
        known[np.asarray(todo)] = chi == 1
        return known

    def _solve_job(self, index: int, job: _Job, known_disk: bool, progress: Callable[[float], bool]) -> None:
        uvflat = self.uvflat
        if self.has_degenerate[job.obj_index]:
            job = self.jobs[index] = _Job(job.obj_index, isl.without_degenerate(self.uvflat, job.island), job.pin_vertices, job.pin_uv)
        problem, loops = (None, 1) if known_disk else self._problem(job)
        job.holes = loops > 1
        if problem is not None and problem[0] in ("closed", "not_disk") and self.settings["cut_closed"]:
            cut = self._cut(job)
            if isinstance(cut, str):
                problem = ("invalid", cut)
            else:
                k = job.obj_index
                self.new_seams[k].append(isl.cut_edges(job.island, cut, self.loop_edge[k], self.loop_next[k]))
                _, _, _, uv, pinned, _ = self.meshes[k]
                job = self.jobs[index] = _Job.of(k, cut, uv, pinned)
                job.holes = False  # a cut graph opens the surface into one disk
                problem = None
                self.cut_islands += 1
        if problem is not None:
            self._skip(problem[0], problem[1])
            return
        try:
            job.uv, extra = self._solve(job, progress)
            job.uv = self._repaired(job, progress)
        except uvflat.Cancelled:
            raise
        except uvflat.Error as e:
            self._skip("invalid", f"island of {len(job.island.polys)} faces: {self._in_mesh_terms(job, e)}")
            return
        self.unenforced_pins += extra
        self.solved.append(job)

    def _repaired(self, job: _Job, progress: Callable[[float], bool]) -> np.ndarray:
        """The island's UVs, solved again by bijective SLIM when the method folded them (pins
        then place the island by a similarity, as for the other free-boundary methods)."""
        if not np.isfinite(job.uv).all() or is_folded(self.uvflat, job.uv, job.island.triangles):
            p, t = job.island.positions, job.island.triangles
            try:
                uv, _ = self.uvflat.nonlinear_map(p, t, "slim", bijective=True, progress=progress)
            except self.uvflat.Cancelled:
                raise
            except self.uvflat.Error:
                self.folded_islands += 1
                return job.uv
            if len(job.pin_vertices):
                uv = _fit_to_pins(uv, job)
            self.repaired_islands += 1
            if is_folded(self.uvflat, uv, t):
                self.folded_islands += 1
            return uv
        return job.uv

    def _skip(self, kind: str, message: str) -> None:
        self.skipped[kind] += 1
        if len(self.messages) < 3:
            self.messages.append(message)

    def _in_mesh_terms(self, job: _Job, error: Any) -> str:
        """The library's message about an island with its island-local vertex and triangle
        indices replaced by the mesh's own vertex and face indices (what the artist can find);
        vertices and triangles beyond the island's (the cones of Fill Holes) are named so."""
        k, island = job.obj_index, job.island
        vertex = np.full(len(island.positions), -1, dtype=np.int64)
        vertex[island.loop_vertex] = self.loop_vertex[k][island.loops]
        face = self.loop_poly[k][island.triangle_loops[:, 0]]

        def name(kind: str, index: int) -> str:
            table = vertex if kind == "vertex" else face
            if 0 <= index < len(table) and table[index] >= 0:
                return f"{'vertex' if kind == 'vertex' else 'face'} {int(table[index])}"
            return "a vertex filling a hole" if kind == "vertex" else "a triangle filling a hole"

        def translated(m: "re.Match[str]") -> str:
            edge, listed, pair, one, vertex_index = m.group("edge"), m.group("list"), m.group("pair"), m.group("one"), m.group("v")
            if edge:
                a, b = (int(i) for i in edge.split(","))
                return f"the edge between {name('vertex', a)} and {name('vertex', b)}"
            if listed:
                return ", ".join(name("face", int(i)) for i in listed.split(","))
            if pair:
                a, b = (int(i) for i in pair.split(" and "))
                return f"{name('face', a)} and {name('face', b)}"
            if one:
                return name("face", int(one))
            return name("vertex", int(vertex_index))

        # One pass, so that no index is translated twice.
        text = _ELEMENT.sub(translated, str(getattr(error, "message", None) or error))
        return text + " (mesh indices)"

    def _problem(self, job: _Job) -> Tuple[Optional[Tuple[str, str]], int]:
        """Why an island cannot be unwrapped (kind, message), or None; and its number of
        boundary loops."""
        uvflat, island = self.uvflat, job.island
        try:
            info = uvflat.mesh_info(island.positions, island.triangles)
        except uvflat.Error as e:
            return ("invalid", f"island of {len(island.polys)} faces: {self._in_mesh_terms(job, e)}"), 0
        if info.boundary_loops == 0:
            return ("closed", f"closed island of {len(island.polys)} faces"), 0
        if info.genus > 0:
            return ("not_disk", f"island of {len(island.polys)} faces has genus {info.genus}"), info.boundary_loops
        return None, info.boundary_loops

    def _cut(self, job: _Job) -> Any:
        """The island cut into a disk (``uvflat.cut_to_disk``), or a message saying why not.
        The cost is the edge length, and a million times that on the diagonals of n-gon
        tessellations, so the seams follow polygon edges (a loop has only one UV)."""
        island = job.island
        p, t = island.positions, island.triangles.astype(np.int64)
        length = np.linalg.norm(p[np.roll(t, -1, axis=1)] - p[t], axis=2)
        cost = length * np.where(island.triangle_diagonals, 1e6, 1.0)
        try:
            cut = self.uvflat.cut_to_disk(p, island.triangles, cost=cost)
        except self.uvflat.Error as e:
            return f"island of {len(island.polys)} faces cannot be cut: {self._in_mesh_terms(job, e)}"
        opened = isl.cut_open(island, cut.triangles, cut.positions)
        if opened is None:
            return f"island of {len(island.polys)} faces: the cut runs through an n-gon; mark seams by hand"
        return opened

    def _solve(self, job: _Job, progress: Callable[[float], bool]) -> Tuple[np.ndarray, int]:
        """UVs of the island's vertices, and how many pins were not enforced. The solve works
        in square UV space: pinned UVs are taken out of the image's aspect ratio first and the
        result is put back into it (as the free islands' layout does)."""
        aspect = self.meshes[job.obj_index][5]
        uv, unenforced = self._solve_square(job.with_pin_uv(to_square(job.pin_uv, aspect)), progress)
        return (from_square(uv, aspect) if len(job.pin_vertices) else uv), unenforced

    def _solve_square(self, job: _Job, progress: Callable[[float], bool]) -> Tuple[np.ndarray, int]:
        """The island solved as it is; for the free-boundary methods with Fill Holes on, an
        island with holes whose map folds is solved again with its holes filled (virtual cones,
        Blender's Fill Holes: a tube's free-boundary conformal map is pressed flat, its two
        layers folded at the sides), and the filled solve is kept when it does not fold. A map
        that does not fold is kept as it is: the cones change the map of every holed island they
        are added to, needed or not."""
        uvflat, method = self.uvflat, self.settings["method"]
        p, t = job.island.positions, job.island.triangles
        uv, unenforced = self._solve_method(job, p, t, progress)
        fill = method in _FREE_BOUNDARY and self.settings.get("fill_holes", True) and job.holes
        if fill and (not np.isfinite(uv).all() or is_folded(uvflat, uv, t)):
            fp, ft = isl.fill_holes(p, t, uvflat.boundary_loops(p, t))
            if len(fp) > len(p):
                filled, filled_unenforced = self._solve_method(job, fp, ft, progress)
                filled = filled[: len(p)]
                if np.isfinite(filled).all() and not is_folded(uvflat, filled, t):
                    self.filled_islands += 1
                    return filled, filled_unenforced
        return uv[: len(p)], unenforced

    def _solve_method(
        self, job: _Job, p: np.ndarray, t: np.ndarray, progress: Callable[[float], bool]
    ) -> Tuple[np.ndarray, int]:
        uvflat, method = self.uvflat, self.settings["method"]
        pins, pin_uv = job.pin_vertices, job.pin_uv
        pair = _farthest_pin_pair(pins, pin_uv)
        if method == "NATURAL_CONFORMAL":
            if pair is not None:
                # Every pin is a constraint (Lagrange point constraints, Desbrun et al. 2002
                # §4.1); pins the library finds conflicting fall back to the farthest pair.
                try:
                    all_pins = {int(v): tuple(pin_uv[k]) for k, v in enumerate(pins)}
                    return uvflat.pinned_natural_conformal_map(p, t, all_pins, progress=progress), 0
                except uvflat.InvalidArgument:
                    return uvflat.natural_conformal_map(p, t, pins=pair, progress=progress), len(pins) - 2
            uv = uvflat.natural_conformal_map(p, t, progress=progress)
        elif method == "ABF_PLUS_PLUS":
            # The two pins farthest apart replace the automatic pair of the reconstruction;
            # further pins keep their UVs but do not constrain it.
            uv, _ = uvflat.abf(p, t, variant="abf++", pins=pair, progress=progress)
            if pair is not None:
                return uv, len(pins) - 2
        elif method == "CIRCLE_PATTERNS":
            # As for ABF++: the two pins farthest apart place the map, further pins keep their
            # UVs without constraining it.
            convex = self.settings.get("convex_boundary", False)
            uv, _ = uvflat.circle_pattern_map(p, t, pins=pair, convex_boundary=convex, progress=progress)
            if pair is not None:
                return uv, len(pins) - 2
        elif method in _NONLINEAR:
            uv, _ = uvflat.nonlinear_map(
                p, t, _NONLINEAR[method], iterations=self.settings["iterations"], progress=progress
            )
        else:
            kwargs: Dict[str, Any] = {"weights": _FIXED_WEIGHTS[method], "boundary": self.settings["boundary"]}
            if method == "INTRINSIC":
                kwargs.update(lambda_=self.settings["lambda"], mu=self.settings["mu"])
            uv = uvflat.fixed_boundary_map(p, t, progress=progress, **kwargs)
        if len(pins):
            # A similarity fits two pins exactly; further ones keep their UVs unenforced.
            uv[: len(job.island.positions)] = _fit_to_pins(uv[: len(job.island.positions)], job)
            return uv, max(len(pins) - 2, 0)
        return uv, 0

    # --- write back (main thread) --------------------------------------------------------------

    def write_back(self, margin: float) -> Dict[str, Any]:
        """Scales, lays out and writes the solved islands (pinned loops never change); returns
        the summary the operator reports."""
        self._layout(margin)
        unwrapped_polys = self._write_uvs()
        return self._summary(unwrapped_polys)

    def _layout(self, margin: float) -> None:
        """Islands without pins, packed into [0, 1]² by the library (``uvflat.pack_islands``:
        one texel density, UV area = 3D area; rotation allowed unless an image's aspect ratio
        squeezes them, where a rotation would shear them in the image), all islands in one call."""
        free = [job for job in self.solved if len(job.pin_vertices) == 0]
        # (An island the repair could not unfold may be degenerate or not finite: left as it is;
        # measured on the stacked islands, one numpy pass for thousands of islands.)
        counts, tris, owner, uv, vertex_owner = _stacked(free)
        finite = np.bincount(vertex_owner, weights=~np.isfinite(uv).all(axis=1), minlength=len(free)) == 0
        area = np.bincount(owner, weights=np.nan_to_num(isl.triangle_areas(uv, tris)), minlength=len(free))
        if not (finite & (area > 0)).all():
            free = [job for job, ok in zip(free, finite & (area > 0)) if ok]
            counts, tris, owner, uv, vertex_owner = _stacked(free)
        if not free:
            return
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        positions = np.concatenate([job.island.positions for job in free])
        # from_square per island: an image wider than high squeezes u, a taller one v; the
        # surface areas shrink alike, so every island keeps the density of the square image.
        aspect = np.array([self.meshes[job.obj_index][5] for job in free])
        squeeze = np.where(aspect > 1, aspect, np.where(aspect < 1, 1.0 / aspect, 1.0))
        uv[:, 0] /= np.where(aspect > 1, aspect, 1.0)[vertex_owner]
        uv[:, 1] *= np.where(aspect < 1, aspect, 1.0)[vertex_owner]
        areas = isl.triangle_areas(positions, tris) / squeeze[owner]
        packed = self.uvflat.pack_islands(uv, tris, surface_areas=areas, margin=margin, rotate=bool((aspect == 1).all()))
        for job, part in zip(free, np.split(packed.uv, starts[1:])):
            job.uv = part

    def _write_uvs(self) -> List[np.ndarray]:
        """Writes every solved island's UVs into its mesh and selects them; returns the
        unwrapped polygons per object."""
        unwrapped_polys: List[np.ndarray] = [np.zeros(0, dtype=np.int64) for _ in self.objects]
        for job in self.solved:
            _, _, _, uv, pinned, _ = self.meshes[job.obj_index]
            loops = job.island.loops
            free_loops = ~pinned[loops]
            uv[loops[free_loops]] = job.uv[job.island.loop_vertex[free_loops]]
            unwrapped_polys[job.obj_index] = np.concatenate([unwrapped_polys[job.obj_index], job.island.polys])
        for k, (obj, me, layer_name, uv, pinned, _) in enumerate(self.meshes):
            _uv_layer(me, layer_name).uv.foreach_set("vector", uv.astype(np.float32).ravel())
            # Select the UVs of unwrapped faces (as Blender's unwrap leaves them), so Pack
            # Islands and the UV editor see them.
            sel = np.zeros(len(me.loops), dtype=bool)
            starts = _get(me.polygons, "loop_start", np.int32, len(me.polygons))
            totals = _get(me.polygons, "loop_total", np.int32, len(me.polygons))
            polys = unwrapped_polys[k]
            if len(polys):
                idx = np.repeat(starts[polys], totals[polys]) + _ramp(totals[polys])
                sel[idx] = True
                for kind in ("vertex_selection", "edge_selection"):
                    selection = getattr(_uv_layer(me, layer_name), kind)
                    selection.foreach_set("value", _get(selection, "value", bool, len(me.loops)) | sel)
            seams = np.concatenate(self.new_seams[k] or [np.zeros(0, dtype=np.int64)])
            if len(seams):
                # The cuts the library made, marked so that the artist sees (and may move) them.
                use_seam = _get(me.edges, "use_seam", bool, len(me.edges))
                use_seam[seams] = True
                me.edges.foreach_set("use_seam", use_seam)
            me.update()
        return unwrapped_polys

    def _verified(self) -> Tuple[int, int]:
        """Flipped triangles and overlaps of the written layout, all solved islands of all
        objects together in their final UVs, by the library's exact checker (an island mirrored
        as a whole counts: its texture would be mirrored)."""
        if not self.solved:
            return 0, 0
        counts = [len(job.uv) for job in self.solved]
        tris, _ = isl.stacked_triangles([job.island.triangles for job in self.solved], counts)
        check = self.uvflat.check_layout(np.concatenate([job.uv for job in self.solved]), tris.astype(np.uint32))
        return int(check.flipped), int(check.overlaps)

    def _mean_angle_distortion(self) -> float:
        """The library's mean angle error over every solved island's triangles, measured in
        one call on the islands stacked (one call per island took 0.2 s on thousands)."""
        if not self.solved:
            return float("nan")
        tris, _ = isl.stacked_triangles([job.island.triangles for job in self.solved], [len(job.uv) for job in self.solved])
        m = self.uvflat.metrics(
            np.concatenate([job.island.positions for job in self.solved]),
            tris.astype(np.uint32),
            np.concatenate([job.uv for job in self.solved]),
        )
        return float(m.angle_mean)

    def _warnings(self) -> List[str]:
        warnings = []
        if self.non_manifold_edges or self.misoriented_edges:
            warnings.append(
                f"islands split at {self.non_manifold_edges} non-manifold edge(s) and {self.misoriented_edges} edge(s) "
                "between faces of opposite orientation (Mesh > Clean Up, or Recalculate Normals, to join them)"
            )
        if self.folded_islands:
            warnings.append(f"{self.folded_islands} island(s) still fold after the bijective repair (degenerate faces?)")
        if self.cut_islands:
            warnings.append(f"{self.cut_islands} closed or higher-genus island(s) cut open along new seams (marked)")
        if self.skipped["closed"]:
            warnings.append(f"{self.skipped['closed']} closed island(s) (no boundary) skipped: mark a seam to open them")
        if self.skipped["not_disk"]:
            warnings.append(f"{self.skipped['not_disk']} island(s) with genus > 0 skipped: add seams to cut the handles")
        if self.skipped["invalid"]:
            warnings.append(f"{self.skipped['invalid']} island(s) rejected by uvflat")
        if self.messages:
            warnings.append(" | ".join(self.messages))
        if self.unenforced_pins:
            warnings.append(
                f"{self.unenforced_pins} pinned vertices kept in place but not enforced in the solve "
                "(conflicting pins, or more than two with a method other than Natural Conformal: the two farthest "
                "apart place the island)"
            )
        return warnings

    def _summary(self, unwrapped_polys: List[np.ndarray]) -> Dict[str, Any]:
        jobs, solved = self.jobs, self.solved
        flipped, overlaps = self._verified()
        return {
            "flipped": flipped,
            "overlaps": overlaps,
            "filled_islands": self.filled_islands,
            "seams_marked": int(sum(len(np.unique(np.concatenate(s))) for s in self.new_seams if s)),
            "islands": len(solved),
            "faces": int(sum(len(j.island.polys) for j in solved)),
            "selected_faces": int(sum(len(j.island.polys) for j in jobs)),
            "skipped": dict(self.skipped),
            "cut_islands": self.cut_islands,
            "repaired_islands": self.repaired_islands,
            "folded_islands": self.folded_islands,
            "unenforced_pins": self.unenforced_pins,
            "angle_mean": self._mean_angle_distortion(),
            "solve_seconds": self.solve_seconds,
            "warnings": self._warnings(),
            "unwrapped_polys": int(sum(len(p) for p in unwrapped_polys)),
            "skipped_polys": [
                np.setdiff1d(np.concatenate([j.island.polys for j in jobs if j.obj_index == k] or [np.zeros(0, int)]), p)
                for k, p in enumerate(unwrapped_polys)
            ],
            "island_faces": [(j.obj_index, j.island.polys.copy()) for j in solved],
        }


def _stacked(jobs: List[_Job]) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The jobs' islands stacked: UV count per job, triangles over the stacked UVs and the job
    of each, the stacked UVs and the job of each UV."""
    counts = np.array([len(job.uv) for job in jobs], dtype=np.int64)
    if not jobs:
        return counts, np.zeros((0, 3), np.int64), np.zeros(0, np.int64), np.zeros((0, 2)), np.zeros(0, np.int64)
    tris, owner = isl.stacked_triangles([job.island.triangles for job in jobs], counts)
    return counts, tris, owner, np.concatenate([job.uv for job in jobs]), np.repeat(np.arange(len(jobs)), counts)


def is_folded(uvflat: Any, uv: np.ndarray, triangles: np.ndarray) -> bool:
    """Whether the library's exact checker finds a flipped triangle or an overlap in an
    island's layout (a layout mirrored as a whole is not folded)."""
    q = uv[triangles]
    signed = (q[:, 1, 0] - q[:, 0, 0]) * (q[:, 2, 1] - q[:, 0, 1]) - (q[:, 1, 1] - q[:, 0, 1]) * (q[:, 2, 0] - q[:, 0, 0])
    oriented = uv if signed.sum() >= 0 else uv * np.array([-1.0, 1.0])
    check = uvflat.check_layout(oriented, triangles)
    return check.flipped > 0 or check.overlaps > 0


def to_square(uv: np.ndarray, aspect: float) -> np.ndarray:
    """UVs of an image of width/height ``aspect`` in square space (undoes :func:`from_square`)."""
    uv = np.array(uv, dtype=np.float64).reshape(-1, 2)
    if aspect > 1:
        uv[:, 0] *= aspect
    elif aspect < 1:
        uv[:, 1] /= aspect
    return uv


def from_square(uv: np.ndarray, aspect: float) -> np.ndarray:
    """Square-space UVs squeezed into an image of width/height ``aspect`` (Correct Aspect)."""
    uv = np.array(uv, dtype=np.float64).reshape(-1, 2)
    if aspect > 1:
        uv[:, 0] /= aspect
    elif aspect < 1:
        uv[:, 1] *= aspect
    return uv


def _uv_layer(me: Any, name: str) -> Any:
    """The mesh's UV map `name`, looked up afresh (see `UnwrapRun._read`)."""
    return me.uv_layers[name]


def _farthest_pin_pair(pins: np.ndarray, pin_uv: np.ndarray) -> Optional[Tuple[Tuple[int, Tuple[float, float]], ...]]:
    """The two pins farthest apart in UV as ``((v, (u, v)), (v, (u, v)))``, or None when there
    are fewer than two distinct pinned positions."""
    if len(pins) < 2:
        return None
    i, j = isl.farthest_pair(pin_uv)
    if not np.linalg.norm(pin_uv[i] - pin_uv[j]) > 0:
        return None
    return (int(pins[i]), tuple(map(float, pin_uv[i]))), (int(pins[j]), tuple(map(float, pin_uv[j])))


def _fit_to_pins(uv: np.ndarray, job: _Job) -> np.ndarray:
    """The island moved by the similarity that best matches its pins (one pin: the size of
    the 3D surface, translated onto the pin)."""
    island, pins = job.island, job.pin_vertices
    if len(pins) == 1:
        area_3d = float(isl.triangle_areas(island.positions, island.triangles).sum())
        uv = isl.scale_to_area(uv, island.triangles, area_3d)
    a, b = isl.similarity_fit(uv[pins], job.pin_uv)
    z = a * (uv[:, 0] + 1j * uv[:, 1]) + b
    return np.stack([z.real, z.imag], axis=1)


class UVFLAT_OT_unwrap(bpy.types.Operator):
    """Unwrap the selected faces with uvflat (islands split at seams and the selection border;
    pinned UVs kept)"""

    bl_idname = "uv.uvflat_unwrap"
    bl_label = "uvflat Unwrap"
    bl_options = {"REGISTER", "UNDO"}

    method: EnumProperty(name="Method", items=METHODS, default="NATURAL_CONFORMAL")  # type: ignore[valid-type]
    boundary: EnumProperty(  # type: ignore[valid-type]
        name="Boundary",
        items=[("CIRCLE", "Circle", "Outer boundary on a circle"), ("SQUARE", "Square", "Outer boundary on a square")],
        default="CIRCLE",
    )
    lambda_: FloatProperty(name="λ (conformal)", default=1.0, min=0.0, soft_max=1.0)  # type: ignore[valid-type]
    mu: FloatProperty(name="μ (authalic)", default=0.0, min=0.0, soft_max=1.0)  # type: ignore[valid-type]
    iterations: IntProperty(  # type: ignore[valid-type]
        name="Iterations", default=100, min=1, soft_max=1000, description="Iteration limit of SLIM, stretch and ARAP"
    )
    convex_boundary: BoolProperty(  # type: ignore[valid-type]
        name="Convex Boundary",
        default=False,
        description="Circle Patterns: keep each island's UV boundary convex, so the island cannot overlap "
        "itself (more distortion where its boundary is concave)",
    )
    fill_holes: BoolProperty(  # type: ignore[valid-type]
        name="Fill Holes",
        default=True,
        description="Natural Conformal and ABF++: an island with holes whose map folds is unwrapped again with every "
        "hole but its longest boundary virtually filled (as Blender's Fill Holes), so tubes do not fold onto themselves",
    )
    cut_closed: BoolProperty(  # type: ignore[valid-type]
        name="Cut Closed Islands",
        default=True,
        description="Cut closed and higher-genus islands into a disk with uvflat's cut graph (seams along polygon "
        "edges, steered to short edges); off: skip them with a warning",
    )
    correct_aspect: BoolProperty(  # type: ignore[valid-type]
        name="Correct Aspect", default=True, description="Take the active image's aspect ratio into account"
    )
    pack: BoolProperty(  # type: ignore[valid-type]
        name="Pack Islands", default=False, description="Pack the islands with Blender's Pack Islands afterwards"
    )
    margin: FloatProperty(name="Margin", default=0.001, min=0.0, max=0.49, precision=3)  # type: ignore[valid-type]

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        obj = context.active_object
        return obj is not None and obj.type == "MESH" and context.mode == "EDIT_MESH"

    def draw(self, context: bpy.types.Context) -> None:
        layout = self.layout
        layout.prop(self, "method")
        if self.method in _FIXED_WEIGHTS:
            layout.prop(self, "boundary")
        if self.method == "INTRINSIC":
            layout.prop(self, "lambda_")
            layout.prop(self, "mu")
        if self.method in _NONLINEAR:
            layout.prop(self, "iterations")
        if self.method == "CIRCLE_PATTERNS":
            layout.prop(self, "convex_boundary")
        if self.method in _FREE_BOUNDARY:
            layout.prop(self, "fill_holes")
        layout.prop(self, "cut_closed")
        layout.prop(self, "correct_aspect")
        layout.prop(self, "pack")
        layout.prop(self, "margin")

    # --- the run -----------------------------------------------------------------------------

    def execute(self, context: bpy.types.Context) -> set:
        """Unwraps synchronously (redo panel, scripts, background mode)."""
        run = self._start(context)
        if run is None:
            return {"CANCELLED"}
        wm = context.window_manager
        wm.progress_begin(0, 100)
        try:
            run.solve(lambda f: wm.progress_update(100 * f))
        finally:
            wm.progress_end()
        return self._finish(context, run)

    def invoke(self, context: bpy.types.Context, event: Any) -> set:
        """Interactive: the islands are solved on a worker thread (the library releases the GIL)
        while this operator stays modal, so Esc cancels — within one iteration of the running
        method, since every library call gets a progress callback — and the mesh is left as it
        was. Without a window (background mode) it is ``execute``."""
        if context.window is None or bpy.app.background:
            return self.execute(context)
        run = self._start(context)
        if run is None:
            return {"CANCELLED"}
        self._run = run
        self._thread = threading.Thread(target=run.solve_catching, name="uvflat-unwrap", daemon=True)
        wm = context.window_manager
        wm.progress_begin(0, 100)
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        context.workspace.status_text_set("uvflat: unwrapping… (Esc cancels)")
        self._thread.start()
        return {"RUNNING_MODAL"}

    def modal(self, context: bpy.types.Context, event: Any) -> set:
        run = self._run
        if event.type == "ESC" and event.value == "PRESS":
            run.cancel.set()
        if event.type != "TIMER" or self._thread.is_alive():
            if event.type == "TIMER":
                context.window_manager.progress_update(100 * run.fraction)
            return {"RUNNING_MODAL"}  # the mesh is being read by the solve: nothing else may edit it
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        if run.error is not None:
            bpy.ops.object.mode_set(mode="EDIT")
            if isinstance(run.error, Cancelled):
                self.report({"WARNING"}, "uvflat: cancelled; UVs unchanged")
            else:
                self.report({"ERROR"}, f"uvflat: {run.error}")
            return {"CANCELLED"}
        return self._finish(context, run)

    def _start(self, context: bpy.types.Context) -> Optional["UnwrapRun"]:
        """Loads the library, switches to Object Mode and reads the selected islands."""
        try:
            uvflat = binding()
        except Exception as e:  # LibraryError, ImportError: nothing to do without the library
            self.report({"ERROR"}, f"uvflat: cannot load the library: {e}")
            return None
        problem = self._invalid_setting()
        if problem is not None:
            self.report({"ERROR"}, f"uvflat: {problem}")
            return None
        objects = [o for o in getattr(context, "objects_in_mode_unique_data", [context.edit_object]) if o.type == "MESH"]
        LAST_RUN.clear()
        bpy.ops.object.mode_set(mode="OBJECT")
        return UnwrapRun(uvflat, self.settings(), objects, self.correct_aspect)

    def _invalid_setting(self) -> Optional[str]:
        """What is wrong with the settings a script can set beyond the panel's limits, or None."""
        if self.method == "INTRINSIC" and not self.lambda_ + self.mu > 0:
            return "λ and μ cannot both be 0 (the Intrinsic weights would all vanish)"
        if not 0 <= self.margin < 0.5:
            return f"margin must be at least 0 and below 0.5 (got {self.margin})"
        return None

    def _finish(self, context: bpy.types.Context, run: "UnwrapRun") -> set:
        """Lays out and writes back the solved islands, goes back to Edit Mode, packs, reports."""
        try:
            summary = run.write_back(self.margin)
        finally:
            bpy.ops.object.mode_set(mode="EDIT")
        if self.pack and summary["unwrapped_polys"]:
            self._pack(run.objects, summary)
        seconds = time.perf_counter() - run.start
        summary["seconds"] = seconds
        LAST_RUN.update(summary)

        if summary["selected_faces"] == 0:
            self.report({"WARNING"}, "uvflat: no faces selected; nothing unwrapped")
            return {"FINISHED"}
        message = (
            f"uvflat: {summary['islands']} islands ({summary['cut_islands']} cut open, {summary['seams_marked']} seam "
            f"edges marked; {summary['repaired_islands']} repaired by bijective SLIM), {summary['faces']} faces, "
            f"flips {summary['flipped']}, overlaps {summary['overlaps']}, {seconds:.3f} s, "
            f"mean angle error {math.degrees(summary['angle_mean']):.2f}°"
        )
        warnings = summary["warnings"]
        if warnings:
            self.report({"WARNING"}, message + "; " + "; ".join(warnings))
        else:
            self.report({"INFO"}, message)
        return {"FINISHED"}

    def settings(self) -> Dict[str, Any]:
        """The operator's solve options as plain values (the worker thread must not touch the
        operator's RNA properties)."""
        return {
            "method": self.method,
            "boundary": self.boundary.lower(),
            "lambda": self.lambda_,
            "mu": self.mu,
            "iterations": self.iterations,
            "cut_closed": self.cut_closed,
            "convex_boundary": self.convex_boundary,
            "fill_holes": self.fill_holes,
        }

    def _pack(self, objects: List[bpy.types.Object], summary: Dict[str, Any]) -> None:
        """Blender's Pack Islands over the unwrapped islands only: faces that were skipped are
        deselected for the call and selected again afterwards."""
        import bmesh

        skipped = summary["skipped_polys"]
        edit = []
        for obj, polys in zip(objects, skipped):
            bm = bmesh.from_edit_mesh(obj.data)
            bm.faces.ensure_lookup_table()
            for p in polys:
                bm.faces[int(p)].select = False
            edit.append((obj, bm, polys))
        try:
            bpy.ops.uv.pack_islands(margin=self.margin, pin=True, pin_method="LOCKED")
        finally:
            for obj, bm, polys in edit:
                for p in polys:
                    bm.faces[int(p)].select = True
                bmesh.update_edit_mesh(obj.data, loop_triangles=False, destructive=False)


def _ramp(totals: np.ndarray) -> np.ndarray:
    """0, 1, .., t0-1, 0, 1, .., t1-1, ... for the given run lengths."""
    totals = np.asarray(totals, dtype=np.int64)
    if len(totals) == 0:
        return np.zeros(0, dtype=np.int64)
    starts = np.cumsum(totals) - totals
    return np.arange(int(totals.sum()), dtype=np.int64) - np.repeat(starts, totals)


def menu_func(self: Any, context: bpy.types.Context) -> None:
    self.layout.separator()
    self.layout.operator(UVFLAT_OT_unwrap.bl_idname, text="uvflat Unwrap")


classes = (UVFLAT_OT_unwrap,)
