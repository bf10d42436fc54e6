"""The "uvflat Unwrap" operator: unwraps the selected faces of every mesh in Edit Mode.

Steps (all objects of a multi-object Edit Mode together):

1. switch to Object Mode for a moment, so the meshes can be read and written with
   ``foreach_get``/``foreach_set`` (numpy speed instead of per-loop Python);
2. split each mesh's selected faces into islands (``islands.split_islands``: seams, the selection
   border, non-manifold and inconsistently oriented edges cut), triangulated with Blender's own
   tessellation (``mesh.loop_triangles``), so n-gons, concave ones too, are solved as triangles
   and written back per loop;
3. solve every island with the chosen uvflat method; closed islands (no boundary) and islands
   that are not topological disks with holes (genus > 0) are first cut into a disk by the
   library's cut graph along polygon edges (or, with "Cut Closed Islands" off, skipped with a
   warning, keeping their UVs); islands the library rejects (e.g. zero-area faces) are skipped
   and the warning quotes the library's message;
4. pins: pinned loops never change. With natural conformal and two or more pinned vertices on an
   island, every pin is a point constraint of the solve (``uvf_pinned_natural_conformal_map``);
   if the library finds them conflicting, the two pins farthest apart in UV constrain it and
   the others are kept where they are but do not constrain the solve (reported).
   Every other method (and natural conformal with one pin) solves without constraints and
   then moves the island by the similarity (rotation, uniform scale, translation) that best
   matches its pins. Islands with pins are not moved by the layout;
5. islands without pins are scaled so that their UV area equals their 3D area (relative sizes
   as in 3D), corrected for the image aspect ratio if asked, placed side by side without
   overlapping and fitted into the unit square; optionally Blender's ``uv.pack_islands`` then
   packs them (pinned islands stay locked);
6. back to Edit Mode; the operator reports islands, faces, seconds and the mean angle
   distortion in the status bar.
"""

from __future__ import annotations

import time
from typing import Any, Dict, List, Optional, Tuple

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty

from . import islands as isl
from ._binding import binding

#: Facts about the last run, for tests and scripts (the operator itself cannot return data).
LAST_RUN: Dict[str, Any] = {}

METHODS = [
    ("NATURAL_CONFORMAL", "Natural Conformal", "Free-boundary natural conformal map (= LSCM, Desbrun et al. 2002); honours every pin"),
    ("ABF_PLUS_PLUS", "ABF++", "Angle Based Flattening (Sheffer et al. 2005), then least-squares reconstruction; free boundary"),
    ("INTRINSIC", "Intrinsic (λ, μ)", "λ·discrete conformal + μ·discrete authalic weights, fixed boundary (Desbrun et al. 2002)"),
    ("MEAN_VALUE", "Mean Value", "Floater's mean value coordinates, boundary fixed on a circle or square; never flips"),
    ("SLIM", "SLIM (symmetric Dirichlet)", "Isometric free-boundary map minimised by SLIM (Rabinovich et al. 2017); never flips"),
    ("STRETCH", "Minimum Stretch", "Sander et al. 2001 L2 stretch, free boundary; never flips"),
    ("ARAP", "As Rigid As Possible", "Liu et al. 2008 local/global ARAP, free boundary; never flips"),
    ("TUTTE", "Tutte", "Uniform weights, fixed convex boundary; never flips"),
    ("FLOATER", "Floater", "Floater's shape-preserving weights, fixed convex boundary; never flips"),
    ("AUTHALIC", "Authalic", "Discrete authalic (Wachspress) weights, fixed boundary"),
    ("CONFORMAL", "Conformal (fixed)", "Discrete conformal (harmonic, cotangent) weights, fixed boundary"),
]
_NONLINEAR = {"SLIM": "slim", "STRETCH": "stretch", "ARAP": "arap"}
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

    @staticmethod
    def of(obj_index: int, island: isl.Island, uv: np.ndarray, pinned: np.ndarray) -> "_Job":
        """The job of an island, with its pinned vertices and their current UVs."""
        pin_loops = island.loops[pinned[island.loops]]
        vertices, first = np.unique(island.loop_vertex[pinned[island.loops]], return_index=True)
        return _Job(obj_index, island, vertices, uv[pin_loops[first]] if len(pin_loops) else np.zeros((0, 2)))


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
    margin: FloatProperty(name="Margin", default=0.001, min=0.0, max=1.0, precision=3)  # type: ignore[valid-type]

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
        layout.prop(self, "cut_closed")
        layout.prop(self, "correct_aspect")
        layout.prop(self, "pack")
        layout.prop(self, "margin")

    # --- the run -----------------------------------------------------------------------------

    def execute(self, context: bpy.types.Context) -> set:
        try:
            uvflat = binding()
        except Exception as e:  # LibraryError, ImportError: nothing to do without the library
            self.report({"ERROR"}, f"uvflat: cannot load the library: {e}")
            return {"CANCELLED"}

        objects = [o for o in getattr(context, "objects_in_mode_unique_data", [context.edit_object]) if o.type == "MESH"]
        start = time.perf_counter()
        LAST_RUN.clear()
        wm = context.window_manager
        bpy.ops.object.mode_set(mode="OBJECT")
        wm.progress_begin(0, 100)
        try:
            summary = self._unwrap_objects(uvflat, objects, lambda f: wm.progress_update(100 * f))
        finally:
            wm.progress_end()
            bpy.ops.object.mode_set(mode="EDIT")
        if self.pack and summary["unwrapped_polys"]:
            self._pack(objects, summary)
        seconds = time.perf_counter() - start
        summary["seconds"] = seconds
        LAST_RUN.update(summary)

        message = (
            f"uvflat: {summary['islands']} islands, {summary['faces']} faces, {seconds:.3f} s, "
            f"mean angle distortion {summary['angle_mean']:.4f} rad"
        )
        warnings = summary["warnings"]
        if warnings:
            self.report({"WARNING"}, message + "; " + "; ".join(warnings))
        else:
            self.report({"INFO"}, message)
        return {"FINISHED"}

    def _unwrap_objects(self, uvflat: Any, objects: List[bpy.types.Object], progress: Any) -> Dict[str, Any]:
        """Reads, splits, solves and writes back every object; ``progress(fraction)`` is called
        after each island (Blender shows it as the cursor's progress counter)."""
        jobs: List[_Job] = []
        meshes = []
        skipped = {"closed": 0, "not_disk": 0, "invalid": 0}
        messages: List[str] = []
        unenforced_pins = 0
        for k, obj in enumerate(objects):
            me = obj.data
            if me.uv_layers.active is None:
                me.uv_layers.new(name="UVMap")
            layer = me.uv_layers.active
            n_loops, n_polys = len(me.loops), len(me.polygons)
            me.calc_loop_triangles()
            positions = _get(me.vertices, "co", np.float32, len(me.vertices), 3).astype(np.float64)
            selected = _get(me.polygons, "select", bool, n_polys) & ~_get(me.polygons, "hide", bool, n_polys)
            split = isl.split_islands(
                positions,
                _get(me.loops, "vertex_index", np.int32, n_loops),
                _get(me.loops, "edge_index", np.int32, n_loops),
                _get(me.polygons, "loop_start", np.int32, n_polys),
                _get(me.polygons, "loop_total", np.int32, n_polys),
                selected,
                _get(me.edges, "use_seam", bool, len(me.edges)),
                _get(me.loop_triangles, "loops", np.int32, len(me.loop_triangles), 3),
                _get(me.loop_triangles, "polygon_index", np.int32, len(me.loop_triangles)),
            )
            # The attribute accessors (uv, pin, vertex_selection, edge_selection), not the legacy
            # `layer.data` wrappers: in Blender 4.5, `layer.data.foreach_set("select", ...)`
            # corrupts memory.
            uv = _get(layer.uv, "vector", np.float32, n_loops, 2).astype(np.float64)
            pinned = _get(layer.pin, "value", bool, n_loops) if len(layer.pin) == n_loops else np.zeros(n_loops, bool)
            meshes.append((obj, me, layer, uv, pinned, image_aspect(obj) if self.correct_aspect else 1.0))
            jobs.extend(_Job.of(k, island, uv, pinned) for island in split.islands)

        # Solve.
        solved: List[_Job] = []
        solve_start = time.perf_counter()
        cut_islands = 0
        for index, job in enumerate(jobs):
            progress(index / len(jobs))
            problem = self._problem(uvflat, job.island)
            if problem is not None and problem[0] in ("closed", "not_disk") and self.cut_closed:
                cut = self._cut(uvflat, job.island)
                if isinstance(cut, str):
                    problem = ("invalid", cut)
                else:
                    _, _, _, uv, pinned, _ = meshes[job.obj_index]
                    job = jobs[index] = _Job.of(job.obj_index, cut, uv, pinned)
                    problem = None
                    cut_islands += 1
            if problem is not None:
                skipped[problem[0]] += 1
                if len(messages) < 3:
                    messages.append(problem[1])
                continue
            try:
                job.uv, extra = self._solve(uvflat, job)
            except uvflat.Error as e:
                skipped["invalid"] += 1
                if len(messages) < 3:
                    messages.append(f"island of {len(job.island.polys)} faces: {e.message or e}")
                continue
            unenforced_pins += extra
            solved.append(job)

        solve_seconds = time.perf_counter() - solve_start

        # Area scaling, aspect, layout (islands without pins only).
        free = [job for job in solved if len(job.pin_vertices) == 0]
        sizes = []
        for job in free:
            island = job.island
            area_3d = float(isl.triangle_areas(island.positions, island.triangles).sum())
            uv = isl.scale_to_area(job.uv, island.triangles, area_3d)
            aspect = meshes[job.obj_index][5]
            if aspect > 1:
                uv[:, 0] /= aspect
            elif aspect < 1:
                uv[:, 1] *= aspect
            uv -= uv.min(axis=0)
            job.uv = uv
            sizes.append(uv.max(axis=0))
        corners, scale = isl.shelf_layout(np.array(sizes).reshape(-1, 2), self.margin)
        for job, corner in zip(free, corners):
            job.uv = (job.uv + corner) * scale

        # Distortion, then write back (pinned loops never change).
        weighted, counted = 0.0, 0
        for job in solved:
            m = uvflat.metrics(job.island.positions, job.island.triangles, job.uv)
            if np.isfinite(m.angle_mean):
                weighted += m.angle_mean * m.triangles
                counted += m.triangles
        unwrapped_polys: List[np.ndarray] = [np.zeros(0, dtype=np.int64) for _ in objects]
        for job in solved:
            _, _, _, uv, pinned, _ = meshes[job.obj_index]
            loops = job.island.loops
            free_loops = ~pinned[loops]
            uv[loops[free_loops]] = job.uv[job.island.loop_vertex[free_loops]]
            unwrapped_polys[job.obj_index] = np.concatenate([unwrapped_polys[job.obj_index], job.island.polys])
        for k, (obj, me, layer, uv, pinned, _) in enumerate(meshes):
            layer.uv.foreach_set("vector", uv.astype(np.float32).ravel())
            # Select the UVs of unwrapped faces (as Blender's unwrap leaves them), so Pack
            # Islands and the UV editor see them.
            sel = np.zeros(len(me.loops), dtype=bool)
            starts = _get(me.polygons, "loop_start", np.int32, len(me.polygons))
            totals = _get(me.polygons, "loop_total", np.int32, len(me.polygons))
            polys = unwrapped_polys[k]
            if len(polys):
                idx = np.repeat(starts[polys], totals[polys]) + _ramp(totals[polys])
                sel[idx] = True
                for selection in (layer.vertex_selection, layer.edge_selection):
                    selection.foreach_set("value", _get(selection, "value", bool, len(me.loops)) | sel)
            me.update()

        warnings = []
        if cut_islands:
            warnings.append(f"{cut_islands} closed or higher-genus island(s) cut open along new seams (not marked)")
        if skipped["closed"]:
            warnings.append(f"{skipped['closed']} closed island(s) (no boundary) skipped: mark a seam to open them")
        if skipped["not_disk"]:
            warnings.append(f"{skipped['not_disk']} island(s) with genus > 0 skipped: add seams to cut the handles")
        if skipped["invalid"]:
            warnings.append(f"{skipped['invalid']} island(s) rejected by uvflat")
        if messages:
            warnings.append(" | ".join(messages))
        if unenforced_pins:
            warnings.append(
                f"{unenforced_pins} pinned vertices kept in place but not enforced in the solve "
                "(uvflat's natural conformal map takes exactly 2 pins)"
            )
        return {
            "islands": len(solved),
            "faces": int(sum(len(j.island.polys) for j in solved)),
            "selected_faces": int(sum(len(j.island.polys) for j in jobs)),
            "skipped": skipped,
            "cut_islands": cut_islands,
            "unenforced_pins": unenforced_pins,
            "angle_mean": weighted / counted if counted else float("nan"),
            "solve_seconds": solve_seconds,
            "warnings": warnings,
            "unwrapped_polys": int(sum(len(p) for p in unwrapped_polys)),
            "skipped_polys": [
                np.setdiff1d(np.concatenate([j.island.polys for j in jobs if j.obj_index == k] or [np.zeros(0, int)]), p)
                for k, p in enumerate(unwrapped_polys)
            ],
            "island_faces": [(j.obj_index, j.island.polys.copy()) for j in solved],
        }

    @staticmethod
    def _problem(uvflat: Any, island: isl.Island) -> Optional[Tuple[str, str]]:
        """Why an island cannot be unwrapped (kind, message), or None."""
        try:
            info = uvflat.mesh_info(island.positions, island.triangles)
        except uvflat.Error as e:
            return "invalid", f"island of {len(island.polys)} faces: {e.message or e}"
        if info.boundary_loops == 0:
            return "closed", f"closed island of {len(island.polys)} faces"
        if info.genus > 0:
            return "not_disk", f"island of {len(island.polys)} faces has genus {info.genus}"
        return None

    @staticmethod
    def _cut(uvflat: Any, island: isl.Island) -> Any:
        """The island cut into a disk (``uvflat.cut_to_disk``), or a message saying why not.
        The cost is the edge length, and a million times that on the diagonals of n-gon
        tessellations, so the seams follow polygon edges (a loop has only one UV)."""
        p, t = island.positions, island.triangles.astype(np.int64)
        length = np.linalg.norm(p[np.roll(t, -1, axis=1)] - p[t], axis=2)
        cost = length * np.where(island.triangle_diagonals, 1e6, 1.0)
        try:
            cut = uvflat.cut_to_disk(p, island.triangles, cost=cost)
        except uvflat.Error as e:
            return f"island of {len(island.polys)} faces cannot be cut: {e.message or e}"
        opened = isl.cut_open(island, cut.triangles, cut.positions)
        if opened is None:
            return f"island of {len(island.polys)} faces: the cut runs through an n-gon; mark seams by hand"
        return opened

    def _solve(self, uvflat: Any, job: _Job) -> Tuple[np.ndarray, int]:
        """UVs of the island's vertices, and how many pins were not enforced."""
        island = job.island
        pins = job.pin_vertices
        if self.method == "NATURAL_CONFORMAL":
            if len(pins) >= 2:
                i, j = isl.farthest_pair(job.pin_uv)
                if np.linalg.norm(job.pin_uv[i] - job.pin_uv[j]) > 0:
                    # Every pin is a constraint (Lagrange point constraints, Desbrun et al. 2002
                    # §4.1); pins the library finds conflicting fall back to the farthest pair.
                    try:
                        all_pins = {int(v): tuple(job.pin_uv[k]) for k, v in enumerate(pins)}
                        return uvflat.pinned_natural_conformal_map(island.positions, island.triangles, all_pins), 0
                    except uvflat.InvalidArgument:
                        pair = ((int(pins[i]), tuple(job.pin_uv[i])), (int(pins[j]), tuple(job.pin_uv[j])))
                        uv = uvflat.natural_conformal_map(island.positions, island.triangles, pins=pair)
                        return uv, len(pins) - 2
            uv = uvflat.natural_conformal_map(island.positions, island.triangles)
        elif self.method == "ABF_PLUS_PLUS":
            uv, _ = uvflat.abf(island.positions, island.triangles, variant="abf++")
        elif self.method in _NONLINEAR:
            method = _NONLINEAR[self.method]
            uv, _ = uvflat.nonlinear_map(island.positions, island.triangles, method, iterations=self.iterations)
        else:
            kwargs: Dict[str, Any] = {"weights": _FIXED_WEIGHTS[self.method], "boundary": self.boundary.lower()}
            if self.method == "INTRINSIC":
                kwargs.update(lambda_=self.lambda_, mu=self.mu)
            uv = uvflat.fixed_boundary_map(island.positions, island.triangles, **kwargs)
        if len(pins):
            # Place the island by the similarity that best matches its pins (one pin: keep the
            # size of the 3D surface and translate).
            if len(pins) == 1:
                area_3d = float(isl.triangle_areas(island.positions, island.triangles).sum())
                uv = isl.scale_to_area(uv, island.triangles, area_3d)
            a, b = isl.similarity_fit(uv[pins], job.pin_uv)
            z = a * (uv[:, 0] + 1j * uv[:, 1]) + b
            uv = np.stack([z.real, z.imag], axis=1)
        return uv, 0

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
