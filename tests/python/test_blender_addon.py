"""Headless tests of the Blender add-on (blender_addon/) with the `bpy` module from PyPI.

The add-on is registered from the source tree and uses the installed `uvflat` binding with
$UVFLAT_LIBRARY (scripts/python_tests.sh sets both up). Meshes are built with bpy: a grid, a UV
sphere with seams, disk_nefertiti_small.obj imported with wm.obj_import, a honeycomb of
hexagons (n-gons), a torus. Every check reads the UVs back per loop and recomputes what it
asserts itself (islands from UV connectivity, orientation, angle distortion).

Undo: bpy in background mode keeps an undo stack, but `ed.undo` polls False unless the context
has a window and an area; test_undo overrides the context with the window manager's window and
undoes / redoes the operator for real.
"""

from __future__ import annotations

import math
import os
import sys
from pathlib import Path
from typing import Dict, List, Sequence, Tuple

import numpy as np
import pytest

from conftest import IN_CI, REPO, islands_overlap, library_file, mesh_path, missing

try:
    import bpy  # type: ignore[import-not-found]
    import bmesh  # type: ignore[import-not-found]
except ImportError:  # pragma: no cover - depends on the machine
    bpy = None

PICTURES = Path(os.environ.get("UVFLAT_PICTURES", REPO / "target" / "blender-pictures"))


@pytest.fixture(scope="module", autouse=True)
def addon():
    """The add-on, registered once from the source tree."""
    if bpy is None:
        missing(
            "bpy is not installed: the Blender add-on tests need `pip install 'bpy==4.5.*'` on "
            "Python 3.11 (scripts/python_tests.sh does it)"
        )
    os.environ.setdefault("UVFLAT_LIBRARY", str(library_file()))
    sys.path.insert(0, str(REPO))
    import blender_addon

    bpy.ops.wm.read_factory_settings(use_empty=True)
    blender_addon.register()
    yield blender_addon
    blender_addon.unregister()
    sys.path.remove(str(REPO))


@pytest.fixture(autouse=True)
def empty_scene(addon):
    if bpy.context.object is not None and bpy.context.object.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    for me in list(bpy.data.meshes):
        bpy.data.meshes.remove(me)
    bpy.context.scene.tool_settings.mesh_select_mode = (False, False, True)
    yield


# --- building and reading meshes ---------------------------------------------------------------


def get(collection, name: str, dtype, width: int = 1) -> np.ndarray:
    out = np.empty(len(collection) * width, dtype=dtype)
    collection.foreach_get(name, out)
    return out.reshape(-1, width) if width > 1 else out


def object_from(verts: Sequence, faces: Sequence, name: str = "mesh"):
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(v) for v in verts], [], [tuple(f) for f in faces])
    me.update()
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def grid(n: int = 12, name: str = "grid"):
    """An n×n quad grid over [-1, 1]², bent so that no unwrap is trivially exact."""
    xs = np.linspace(-1, 1, n + 1)
    verts = [(x, y, 0.35 * math.sin(2 * x) * math.cos(1.5 * y) + 0.2 * x * y) for y in xs for x in xs]
    faces = [(j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i) for j in range(n) for i in range(n)]
    return object_from(verts, faces, name)


def honeycomb(rows: int = 6, cols: int = 7):
    """Hexagons (6-gons) on a bumpy surface, plus a concave 8-gon at the side."""
    verts: List[Tuple[float, float, float]] = []
    index: Dict[Tuple[int, int], int] = {}

    def vertex(p: Tuple[float, float]) -> int:
        key = (round(p[0] * 1000), round(p[1] * 1000))
        if key not in index:
            index[key] = len(verts)
            verts.append((p[0], p[1], 0.15 * math.sin(p[0]) * math.sin(1.3 * p[1])))
        return index[key]

    faces = []
    for r in range(rows):
        for c in range(cols):
            cx = c * 1.5
            cy = r * math.sqrt(3) + (math.sqrt(3) / 2 if c % 2 else 0)
            faces.append([vertex((cx + math.cos(k * math.pi / 3), cy + math.sin(k * math.pi / 3))) for k in range(6)])
    # A concave 8-gon (an L shape) below the first column, sharing no edge with the hexagons.
    l_shape = [(0, -3), (2, -3), (2, -2.5), (0.5, -2.5), (0.5, -1.5), (0, -1.5)]
    faces.append([vertex(p) for p in l_shape])
    return object_from(verts, faces, "honeycomb")


def uv_sphere_with_seams():
    """A UV sphere (32 × 16) with seams on two latitude rings and one meridian: three islands
    (two caps and a band, the band cut open by the meridian)."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=1)
    obj = bpy.context.object
    me = obj.data
    co = get(me.vertices, "co", np.float64, 3)
    ev = get(me.edges, "vertices", np.int64, 2)
    z0, z1 = co[ev[:, 0], 2], co[ev[:, 1], 2]
    ring = lambda z: (np.abs(z0 - z) < 1e-4) & (np.abs(z1 - z) < 1e-4)  # noqa: E731
    zs = np.unique(np.round(co[:, 2], 5))
    upper, lower = zs[len(zs) * 2 // 3], zs[len(zs) // 3]
    x0, x1, y0, y1 = co[ev[:, 0], 0], co[ev[:, 1], 0], co[ev[:, 0], 1], co[ev[:, 1], 1]
    meridian = (np.abs(y0) < 1e-5) & (np.abs(y1) < 1e-5) & (x0 >= -1e-6) & (x1 >= -1e-6)
    seam = ring(upper) | ring(lower) | meridian
    me.edges.foreach_set("use_seam", seam)
    me.update()
    return obj


def set_uvs(obj, rng: np.random.Generator) -> np.ndarray:
    """Random UVs on every loop (so untouched loops are recognisable); returns them."""
    me = obj.data
    if not me.uv_layers:
        me.uv_layers.new(name="UVMap")
    uv = rng.random((len(me.loops), 2)).astype(np.float32)
    me.uv_layers.active.uv.foreach_set("vector", uv.ravel())
    return uv


def set_pins(obj, loops: Sequence[int]) -> None:
    me = obj.data
    pin = np.zeros(len(me.loops), dtype=bool)
    pin[list(loops)] = True
    me.uv_layers.active.pin.foreach_set("value", pin)


def edit(objects, faces_of) -> None:
    """Enters Edit Mode on `objects` (the first active) with exactly the faces
    `faces_of(obj)` (a boolean mask over polygons) selected."""
    bpy.ops.object.select_all(action="DESELECT")
    for obj in objects:
        obj.select_set(True)
        mask = np.asarray(faces_of(obj), dtype=bool)
        me = obj.data
        me.polygons.foreach_set("select", mask)
        verts = np.zeros(len(me.vertices), dtype=bool)
        loops_vert = get(me.loops, "vertex_index", np.int64)
        starts, totals = get(me.polygons, "loop_start", np.int64), get(me.polygons, "loop_total", np.int64)
        for p in np.flatnonzero(mask):
            verts[loops_vert[starts[p] : starts[p] + totals[p]]] = True
        me.vertices.foreach_set("select", verts)
        ev = get(me.edges, "vertices", np.int64, 2)
        # An edge is selected when one of its faces is (not merely both its vertices).
        sel_edges = np.zeros(len(me.edges), dtype=bool)
        loop_edge = get(me.loops, "edge_index", np.int64)
        for p in np.flatnonzero(mask):
            sel_edges[loop_edge[starts[p] : starts[p] + totals[p]]] = True
        me.edges.foreach_set("select", sel_edges)
        del ev
        me.update()
    bpy.context.view_layer.objects.active = objects[0]
    bpy.ops.object.mode_set(mode="EDIT")


def read(obj) -> Dict[str, np.ndarray]:
    """UVs and the arrays the checks need; leaves Edit Mode first."""
    if bpy.context.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")
    me = obj.data
    me.calc_loop_triangles()
    return {
        "uv": get(me.uv_layers.active.uv, "vector", np.float32, 2).astype(np.float64),
        "co": get(me.vertices, "co", np.float64, 3),
        "loop_vert": get(me.loops, "vertex_index", np.int64),
        "loop_edge": get(me.loops, "edge_index", np.int64),
        "poly_start": get(me.polygons, "loop_start", np.int64),
        "poly_total": get(me.polygons, "loop_total", np.int64),
        "tri_loops": get(me.loop_triangles, "loops", np.int64, 3),
        "tri_poly": get(me.loop_triangles, "polygon_index", np.int64),
    }


def poly_loops(data: Dict[str, np.ndarray], polys: np.ndarray) -> np.ndarray:
    s, t = data["poly_start"][polys], data["poly_total"][polys]
    return np.concatenate([np.arange(a, a + b) for a, b in zip(s, t)]) if len(polys) else np.zeros(0, np.int64)


def face_centers(obj) -> np.ndarray:
    return get(obj.data.polygons, "center", np.float64, 3)


# --- what the checks compute -------------------------------------------------------------------


def uv_islands(data: Dict[str, np.ndarray], polys: np.ndarray) -> List[np.ndarray]:
    """Islands of the UV layout itself: polygons of `polys` joined when they share a mesh edge
    whose two ends have the same UV on both sides."""
    polys = np.asarray(polys)
    parent = {int(p): int(p) for p in polys}

    def find(x: int) -> int:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    uv, lv, le = data["uv"], data["loop_vert"], data["loop_edge"]
    sides: Dict[int, List[Tuple[int, Dict[int, np.ndarray]]]] = {}
    for p in polys:
        loops = poly_loops(data, np.array([p]))
        at = {int(lv[l]): uv[l] for l in loops}
        for l in loops:
            sides.setdefault(int(le[l]), []).append((int(p), at))
    for e, faces in sides.items():
        if len(faces) != 2:
            continue
        (p, a), (q, b) = faces
        common = set(a) & set(b)
        if len(common) == 2 and all(np.allclose(a[v], b[v], atol=1e-6) for v in common):
            parent[find(p)] = find(q)
    groups: Dict[int, List[int]] = {}
    for p in polys:
        groups.setdefault(find(int(p)), []).append(int(p))
    return [np.array(g) for g in groups.values()]


def triangles_of(data: Dict[str, np.ndarray], polys: np.ndarray) -> np.ndarray:
    return data["tri_loops"][np.isin(data["tri_poly"], polys)]


def signed_areas(data: Dict[str, np.ndarray], tris: np.ndarray) -> np.ndarray:
    a, b, c = data["uv"][tris[:, 0]], data["uv"][tris[:, 1]], data["uv"][tris[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def angle_distortion(data: Dict[str, np.ndarray], polys: np.ndarray) -> float:
    """Mean over the triangles' corners of |UV angle − 3D angle| (radians)."""
    tris = triangles_of(data, polys)
    p3 = data["co"][data["loop_vert"][tris]]
    p2 = data["uv"][tris]

    def angles(p: np.ndarray) -> np.ndarray:
        out = []
        for k in range(3):
            u = p[:, (k + 1) % 3] - p[:, k]
            v = p[:, (k + 2) % 3] - p[:, k]
            cos = (u * v).sum(1) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
            out.append(np.arccos(np.clip(cos, -1, 1)))
        return np.stack(out, 1)

    return float(np.abs(angles(p2) - angles(p3)).mean())


def assert_no_flips(data: Dict[str, np.ndarray], islands: List[np.ndarray], exclude_loops: Sequence[int] = ()) -> None:
    """No triangle of an island has the orientation opposite to the island's majority.
    (Zero-area triangles are not flips: a square boundary makes one when a triangle has all
    three corners on one side; the tests that allow this say so.)"""
    for polys in islands:
        tris = triangles_of(data, polys)
        area = signed_areas(data, tris[~np.isin(tris, list(exclude_loops)).any(axis=1)])
        flipped = min((area > 0).sum(), (area < 0).sum())
        assert flipped == 0, f"island of {len(polys)} faces has {flipped} flipped triangles"


def assert_no_overlap(data: Dict[str, np.ndarray], islands: List[np.ndarray]) -> None:
    """No triangle of one island overlaps a triangle of another (exact test in conftest)."""
    pair = islands_overlap([data["uv"][triangles_of(data, polys)].astype(np.float64) for polys in islands])
    assert pair is None, f"islands {pair} overlap"


def run(**props) -> Dict:
    result = bpy.ops.uv.uvflat_unwrap(**props)
    assert result == {"FINISHED"}, result
    import blender_addon.unwrap as unwrap

    return dict(unwrap.LAST_RUN)


def blender_conformal(obj_factory, select, **unwrap_props) -> Dict[str, np.ndarray]:
    """UVs from Blender's own unwrap (CONFORMAL) on a fresh copy of the same mesh/selection."""
    obj = obj_factory()
    edit([obj], select)
    bpy.ops.uv.unwrap(method="CONFORMAL", margin=0.001, **unwrap_props)
    data = read(obj)
    return data


def compare_with_blender(obj_factory, select, expected_islands=None) -> Tuple[Dict, Dict, List[np.ndarray]]:
    """Unwraps obj_factory() with uvflat and a fresh copy with Blender's CONFORMAL; checks
    islands, flips and per-island angle distortion (ours <= Blender's + 1e-6)."""
    obj = obj_factory()
    rng = np.random.default_rng(1)
    before = set_uvs(obj, rng).astype(np.float64)
    mask = np.asarray(select(obj), dtype=bool)
    edit([obj], select)
    summary = run()
    ours = read(obj)
    selected = np.flatnonzero(mask)
    unselected_loops = poly_loops(ours, np.flatnonzero(~mask))
    np.testing.assert_array_equal(ours["uv"][unselected_loops], before[unselected_loops])
    islands = uv_islands(ours, selected)
    assert len(islands) == summary["islands"]
    if expected_islands is not None:
        assert len(islands) == expected_islands
    assert_no_flips(ours, islands)
    assert_no_overlap(ours, islands)
    for fill_holes in (False, True):
        theirs = blender_conformal(obj_factory, select, fill_holes=fill_holes)
        for polys in islands:
            a, b = angle_distortion(ours, polys), angle_distortion(theirs, polys)
            assert a <= b + 1e-6, f"island of {len(polys)} faces: uvflat {a:.6f} > Blender CONFORMAL {b:.6f} (fill_holes={fill_holes})"
    return summary, ours, islands


# --- tests -------------------------------------------------------------------------------------


def test_grid_subset_matches_or_beats_blender_conformal():
    left = lambda obj: face_centers(obj)[:, 0] < 0.3  # noqa: E731
    summary, _, _ = compare_with_blender(grid, left, expected_islands=1)
    assert summary["faces"] == int(left(grid(name="probe")).sum())
    assert summary["skipped"] == {"closed": 0, "not_disk": 0, "invalid": 0}


def test_two_separate_selections_are_two_islands():
    def select(obj):
        c = face_centers(obj)
        return (c[:, 0] < -0.4) | (c[:, 0] > 0.4)

    compare_with_blender(grid, select, expected_islands=2)


def test_uv_sphere_islands_follow_seams():
    everything = lambda obj: np.ones(len(obj.data.polygons), bool)  # noqa: E731
    summary, _, _ = compare_with_blender(uv_sphere_with_seams, everything, expected_islands=3)
    assert summary["skipped"]["closed"] == 0


def test_nefertiti_subset_from_obj_import():
    path = mesh_path("disk_nefertiti_small.obj")

    def nefertiti():
        bpy.ops.wm.obj_import(filepath=str(path))
        obj = bpy.context.selected_objects[0]
        obj.name = "nefertiti"
        return obj

    def select(obj):
        c = face_centers(obj)
        return c[:, 0] < np.median(c[:, 0]) + 0.1 * np.ptp(c[:, 0])

    summary, ours, islands = compare_with_blender(nefertiti, select)
    assert summary["islands"] >= 1


def test_ngons_are_written_per_loop():
    obj = honeycomb()
    before = set_uvs(obj, np.random.default_rng(2)).astype(np.float64)
    n = len(obj.data.polygons)
    edit([obj], lambda o: np.ones(n, bool))
    summary = run()
    data = read(obj)
    loops = poly_loops(data, np.arange(n))
    assert (np.abs(data["uv"][loops] - before[loops]).max(axis=1) > 0).all(), "a loop of an n-gon was not written"
    islands = uv_islands(data, np.arange(n))
    # The hexagons form one island, the concave 8-gon another.
    assert len(islands) == summary["islands"] == 2
    assert_no_flips(data, islands)
    assert_no_overlap(data, islands)
    # Loops of one vertex inside an island share one UV.
    lv = data["loop_vert"]
    for polys in islands:
        ls = poly_loops(data, polys)
        for v in np.unique(lv[ls]):
            at = data["uv"][ls[lv[ls] == v]]
            assert np.ptp(at, axis=0).max() < 1e-6


def test_pinned_uvs_stay_and_constrain_the_island():
    n = 10
    obj = grid(n)
    before = set_uvs(obj, np.random.default_rng(3)).astype(np.float64)
    data0 = read(obj)
    mask = face_centers(obj)[:, 0] < 0.5
    sel_loops = poly_loops(data0, np.flatnonzero(mask))
    lv = data0["loop_vert"]
    # Three vertices inside the selection (4 loops each); one loop of each is pinned, as when
    # a user pins a UV in the UV editor. All three constrain the natural conformal map.
    vertex = lambda x, y: round((y + 1) * n / 2) * (n + 1) + round((x + 1) * n / 2)  # noqa: E731
    a, b, c = vertex(-0.6, -0.6), vertex(0.2, 0.6), vertex(-0.2, 0.0)
    target = {a: (0.1, 0.1), b: (0.9, 0.8), c: (0.5, 0.3)}
    pinned = []
    for v, uv in target.items():
        loops = sel_loops[lv[sel_loops] == v]
        assert len(loops) == 4
        before[loops[0]] = uv
        pinned.append(loops[0])
    obj.data.uv_layers.active.uv.foreach_set("vector", before.astype(np.float32).ravel())
    set_pins(obj, pinned)
    edit([obj], lambda o: mask)
    summary = run()
    data = read(obj)
    expect = before.astype(np.float32).astype(np.float64)
    np.testing.assert_array_equal(data["uv"][pinned], expect[pinned])
    unselected = poly_loops(data, np.flatnonzero(~mask))
    np.testing.assert_array_equal(data["uv"][unselected], expect[unselected])
    assert summary["islands"] == 1
    assert summary["unenforced_pins"] == 0
    assert not any("not enforced" in w for w in summary["warnings"])
    # The other loops of every pinned vertex sit on its pin: the pins constrained the solve, and
    # the island was not moved afterwards by the layout.
    for v in (a, b, c):
        loops = sel_loops[lv[sel_loops] == v]
        np.testing.assert_allclose(data["uv"][loops], np.tile(target[v], (4, 1)), atol=1e-6)
    free = np.setdiff1d(sel_loops, pinned)
    assert (np.abs(data["uv"][free] - before[free]).max(axis=1) > 0).all()
    assert_no_flips(data, uv_islands(data, np.flatnonzero(mask)))


def test_one_pin_keeps_its_island_in_place():
    obj = grid(6)
    before = set_uvs(obj, np.random.default_rng(10)).astype(np.float64)
    data0 = read(obj)
    loops = poly_loops(data0, np.arange(len(obj.data.polygons)))
    before[loops[5]] = (3.0, 4.0)
    obj.data.uv_layers.active.uv.foreach_set("vector", before.astype(np.float32).ravel())
    set_pins(obj, [loops[5]])
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    for method in ("NATURAL_CONFORMAL", "MEAN_VALUE"):
        run(method=method)
        data = read(obj)
        lv = data["loop_vert"]
        same = loops[lv[loops] == lv[loops[5]]]
        np.testing.assert_allclose(data["uv"][same], np.tile((3.0, 4.0), (len(same), 1)), atol=1e-5)
        bpy.ops.object.mode_set(mode="EDIT")


@pytest.mark.parametrize(
    "props",
    [
        {"method": "MEAN_VALUE", "boundary": "CIRCLE"},
        {"method": "MEAN_VALUE", "boundary": "SQUARE"},
        {"method": "INTRINSIC", "lambda_": 1.0, "mu": 0.5},
        {"method": "TUTTE"},
        {"method": "FLOATER"},
        {"method": "AUTHALIC"},
        {"method": "CONFORMAL"},
        {"method": "NATURAL_CONFORMAL", "pack": True, "margin": 0.02},
        {"method": "ABF_PLUS_PLUS"},
        {"method": "CIRCLE_PATTERNS"},
        {"method": "SLIM", "iterations": 20},
        {"method": "STRETCH", "iterations": 20},
        {"method": "ARAP", "iterations": 20},
    ],
    ids=lambda p: "-".join(str(v) for v in p.values()),
)
def test_methods_and_options(props):
    def select(obj):
        c = face_centers(obj)
        return (c[:, 0] < -0.2) | (c[:, 1] > 0.5)

    obj = grid(10)
    before = set_uvs(obj, np.random.default_rng(4)).astype(np.float64)
    mask = select(obj)
    edit([obj], select)
    summary = run(**props)
    data = read(obj)
    unselected = poly_loops(data, np.flatnonzero(~mask))
    np.testing.assert_array_equal(data["uv"][unselected], before[unselected])
    islands = uv_islands(data, np.flatnonzero(mask))
    assert len(islands) == summary["islands"] == 1
    assert_no_flips(data, islands)
    loops = poly_loops(data, np.flatnonzero(mask))
    assert (data["uv"][loops] >= -1e-6).all() and (data["uv"][loops] <= 1 + 1e-6).all()


def test_a_mesh_without_a_uv_map_unwraps_twice():
    # Regression: the add-on kept the UV map's RNA reference across the reading of its pin and
    # selection attributes, which may create them and reallocate the layer array; the second
    # unwrap of a partly selected mesh that had no UV map before then crashed Blender (a
    # segmentation fault in `uv.foreach_set`).
    def select(obj):
        c = face_centers(obj)
        return (c[:, 0] < -0.2) | (c[:, 1] > 0.5)

    obj = grid(10)
    assert len(obj.data.uv_layers) == 0
    edit([obj], select)
    for method in ("NATURAL_CONFORMAL", "CIRCLE_PATTERNS", "NATURAL_CONFORMAL"):
        run(method=method)
        data = read(obj)
        islands = uv_islands(data, np.flatnonzero(select(obj)))
        assert len(islands) == 1
        assert_no_flips(data, islands)
        bpy.ops.object.mode_set(mode="EDIT")


def test_circle_patterns_convex_boundary_makes_an_l_shaped_island_convex():
    # An L-shaped selection of a flat grid: the free circle-pattern map keeps the L (its own
    # shape, up to a similarity), so its UV area is well below that of its convex hull; with
    # Convex Boundary the island's boundary is a convex polygon, i.e. area = hull area.
    def select(obj):
        c = face_centers(obj)
        return (c[:, 0] < -0.2) | (c[:, 1] > 0.5)

    def area_over_hull(data, polys):
        uv = data["uv"][poly_loops(data, polys)].astype(np.float64)
        area = np.abs(signed_areas(data, triangles_of(data, polys))).sum()
        pts = sorted(set(map(tuple, uv)))
        cross = lambda o, a, b: (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
        hull = []
        for sweep in (pts, pts[::-1]):  # Andrew's monotone chain, lower then upper half
            half = []
            for q in sweep:
                while len(half) >= 2 and cross(half[-2], half[-1], q) <= 0:
                    half.pop()
                half.append(q)
            hull += half[:-1]
        h = np.array(hull)
        hull_area = 0.5 * abs(np.dot(h[:, 0], np.roll(h[:, 1], -1)) - np.dot(h[:, 1], np.roll(h[:, 0], -1)))
        return area / hull_area

    obj = grid(10)
    mask = select(obj)
    polys = np.flatnonzero(mask)
    edit([obj], select)
    run(method="CIRCLE_PATTERNS")
    assert area_over_hull(read(obj), polys) < 0.9
    bpy.ops.object.mode_set(mode="EDIT")
    run(method="CIRCLE_PATTERNS", convex_boundary=True)
    data = read(obj)
    assert_no_flips(data, uv_islands(data, polys))
    # float32 UVs: the hull and the island agree to about 1e-6 of its size.
    assert area_over_hull(data, polys) > 1 - 1e-4


def test_abf_plus_plus_uses_two_pins_in_its_reconstruction():
    n = 8
    obj = grid(n)
    before = set_uvs(obj, np.random.default_rng(11)).astype(np.float64)
    data0 = read(obj)
    loops = poly_loops(data0, np.arange(len(obj.data.polygons)))
    lv = data0["loop_vert"]
    a, b = 0, (n + 1) * (n + 1) - 1  # opposite grid corners
    targets = {a: (0.2, 0.3), b: (0.7, 0.9)}
    pinned = []
    for v, uv in targets.items():
        loop = loops[lv[loops] == v][0]
        before[loop] = uv
        pinned.append(loop)
    obj.data.uv_layers.active.uv.foreach_set("vector", before.astype(np.float32).ravel())
    set_pins(obj, pinned)
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    summary = run(method="ABF_PLUS_PLUS")
    data = read(obj)
    assert summary["unenforced_pins"] == 0
    for v, uv in targets.items():
        np.testing.assert_allclose(data["uv"][loops[lv[loops] == v]], np.tile(uv, (len(loops[lv[loops] == v]), 1)), atol=1e-6)
    assert_no_flips(data, uv_islands(data, np.arange(len(obj.data.polygons))))


def _unwrap_run(obj, **settings):
    """An UnwrapRun over obj's selected faces (Object Mode), as the operator starts one."""
    import blender_addon.unwrap as unwrap
    from blender_addon._binding import binding

    values = {"method": "NATURAL_CONFORMAL", "boundary": "circle", "lambda": 1.0, "mu": 0.0, "iterations": 100}
    values.update(cut_closed=True, **settings)
    bpy.ops.object.mode_set(mode="OBJECT")
    return unwrap.UnwrapRun(binding(), values, [obj], correct_aspect=False)


def test_cancel_stops_the_running_method_within_one_iteration_and_keeps_the_uvs():
    import blender_addon.unwrap as unwrap

    obj = grid(30)
    before = set_uvs(obj, np.random.default_rng(12)).astype(np.float64)
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    job = _unwrap_run(obj, method="SLIM", iterations=1000)
    calls = []
    keep_going = job._keep_going

    def press_escape_on_the_third_callback(fraction):
        calls.append(fraction)
        if len(calls) == 3:
            job.cancel.set()  # what the modal operator does on Esc
        return keep_going(fraction)

    job._keep_going = press_escape_on_the_third_callback
    with pytest.raises(unwrap.Cancelled):
        job.solve(lambda f: None)
    assert len(calls) == 3, "the library called back again after it was told to stop"
    assert job.solved == []
    np.testing.assert_array_equal(read(obj)["uv"], before.astype(np.float32).astype(np.float64))


def test_worker_thread_solve_matches_the_synchronous_one_and_can_be_cancelled():
    import threading

    import blender_addon.unwrap as unwrap

    def solve_on_a_thread(job):
        thread = threading.Thread(target=job.solve_catching)
        thread.start()
        thread.join(timeout=120)
        assert not thread.is_alive()

    obj = grid(16)
    select = lambda o: face_centers(o)[:, 0] < 0.2  # noqa: E731
    edit([obj], select)
    synchronous = _unwrap_run(obj, method="ABF_PLUS_PLUS")
    synchronous.solve(lambda f: None)
    threaded = _unwrap_run(obj, method="ABF_PLUS_PLUS")
    solve_on_a_thread(threaded)
    assert threaded.error is None
    assert len(threaded.solved) == len(synchronous.solved) == 1
    np.testing.assert_array_equal(threaded.solved[0].uv, synchronous.solved[0].uv)
    cancelled = _unwrap_run(obj, method="ABF_PLUS_PLUS")
    cancelled.cancel.set()
    solve_on_a_thread(cancelled)
    assert isinstance(cancelled.error, unwrap.Cancelled) and cancelled.solved == []


def _fake_modal_operator(job, reports):
    """The state invoke() leaves on the operator, with the window manager calls stubbed: the
    modal handler's logic then runs for real (bpy's background mode has no event loop)."""
    import threading
    from types import SimpleNamespace

    import blender_addon.unwrap as unwrap

    op = SimpleNamespace(_run=job, _thread=threading.Thread(target=job.solve_catching), _timer=None, margin=0.001)
    op.pack = False
    op.report = lambda kind, message: reports.append((kind, message))
    op._finish = lambda context, run: unwrap.UVFLAT_OT_unwrap._finish(op, context, run)
    wm = SimpleNamespace(progress_update=lambda v: None, event_timer_remove=lambda t: None, progress_end=lambda: None)
    context = SimpleNamespace(window_manager=wm, workspace=SimpleNamespace(status_text_set=lambda text: None))
    return op, context


def test_modal_handler_cancels_on_escape_and_finishes_when_the_worker_is_done():
    import threading
    from types import SimpleNamespace

    import blender_addon.unwrap as unwrap

    modal = unwrap.UVFLAT_OT_unwrap.modal
    timer, escape = SimpleNamespace(type="TIMER", value="NOTHING"), SimpleNamespace(type="ESC", value="PRESS")
    obj = grid(12)
    before = set_uvs(obj, np.random.default_rng(13)).astype(np.float32).astype(np.float64)
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))

    # Esc while the library is running: the worker stops, the mesh keeps its UVs.
    job = _unwrap_run(obj, method="SLIM", iterations=100)
    inside, keep_going = threading.Event(), job._keep_going

    def wait_for_escape(fraction):
        inside.set()
        job.cancel.wait(60)
        return keep_going(fraction)

    job._keep_going = wait_for_escape
    reports = []
    op, context = _fake_modal_operator(job, reports)
    op._thread.start()
    assert inside.wait(60)
    assert modal(op, context, timer) == {"RUNNING_MODAL"}
    assert modal(op, context, escape) == {"RUNNING_MODAL"}
    op._thread.join(60)
    assert modal(op, context, timer) == {"CANCELLED"}
    assert reports == [({"WARNING"}, "uvflat: cancelled; UVs unchanged")]
    assert bpy.context.mode == "EDIT_MESH"
    np.testing.assert_array_equal(read(obj)["uv"], before)

    # No Esc: the first timer event after the worker is done writes the UVs back.
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    job = _unwrap_run(obj, method="SLIM", iterations=5)
    reports = []
    op, context = _fake_modal_operator(job, reports)
    op._thread.start()
    op._thread.join(60)
    assert modal(op, context, timer) == {"FINISHED"}
    assert len(reports) == 1 and reports[0][0] == {"INFO"} and "1 islands" in reports[0][1]
    data = read(obj)
    assert (np.abs(data["uv"] - before).max(axis=1) > 0).all()
    assert_no_flips(data, uv_islands(data, np.arange(len(obj.data.polygons))))


def test_invoke_without_a_window_runs_synchronously():
    obj = grid(6)
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    assert bpy.ops.uv.uvflat_unwrap("INVOKE_DEFAULT") == {"FINISHED"}
    import blender_addon.unwrap as unwrap

    assert unwrap.LAST_RUN["islands"] == 1


def add_wide_image(obj) -> None:
    """A material whose active node is a 200 × 100 image texture (what Correct Aspect reads)."""
    mat = bpy.data.materials.new("wide")
    mat.use_nodes = True
    node = mat.node_tree.nodes.new("ShaderNodeTexImage")
    node.image = bpy.data.images.new("wide", 200, 100)
    mat.node_tree.nodes.active = node
    obj.data.materials.append(mat)


def test_correct_aspect_uses_the_active_image():
    """With a 2:1 image, Correct Aspect squeezes u by 2: stretched back, the layout has the angle
    distortion of the plain unwrap of the same grid (the same map up to a similarity), and
    squeezed it has much more."""

    def unwrap(aspect_image: bool) -> Tuple[Dict[str, np.ndarray], np.ndarray]:
        for o in list(bpy.data.objects):
            bpy.data.objects.remove(o)
        obj = grid(6)
        if aspect_image:
            add_wide_image(obj)
        edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
        run(correct_aspect=True)
        return read(obj), np.arange(len(obj.data.polygons))

    plain, polys = unwrap(False)
    wide, _ = unwrap(True)
    assert angle_distortion(wide, polys) > 10 * angle_distortion(plain, polys)
    stretched = dict(wide, uv=wide["uv"] * np.array([2.0, 1.0]))
    assert angle_distortion(stretched, polys) == pytest.approx(angle_distortion(plain, polys), rel=1e-3)
    assert (wide["uv"] >= -1e-6).all() and (wide["uv"] <= 1 + 1e-6).all()


def covered_more_than_once(data: Dict[str, np.ndarray], polys: np.ndarray, samples: int = 150) -> float:
    """Share of the island's UV footprint (points of a samples × samples lattice over its
    bounding box inside at least one triangle) that two or more triangles cover: 0 for a
    layout that does not overlap itself."""
    tris = triangles_of(data, polys)
    uv = data["uv"]
    lo, hi = uv[tris].reshape(-1, 2).min(0), uv[tris].reshape(-1, 2).max(0)
    g = np.stack(np.meshgrid(*(np.linspace(lo[d], hi[d], samples + 2)[1:-1] for d in range(2))), -1).reshape(-1, 2)
    count = np.zeros(len(g), dtype=np.int64)
    for a, b, c in uv[tris]:
        d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        if d == 0:
            continue
        l1 = ((g[:, 0] - a[0]) * (c[1] - a[1]) - (g[:, 1] - a[1]) * (c[0] - a[0])) / d
        l2 = ((b[0] - a[0]) * (g[:, 1] - a[1]) - (b[1] - a[1]) * (g[:, 0] - a[0])) / d
        count += (l1 > 1e-9) & (l2 > 1e-9) & (l1 + l2 < 1 - 1e-9)
    return float((count > 1).sum() / max((count > 0).sum(), 1))


def tube():
    """An open cylinder (two boundary loops), all faces selected."""
    bpy.ops.mesh.primitive_cylinder_add(vertices=32, end_fill_type="NOTHING")
    obj = bpy.context.object
    bpy.ops.object.mode_set(mode="OBJECT")
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    return obj


@pytest.mark.parametrize("method", ["NATURAL_CONFORMAL", "ABF_PLUS_PLUS"])
def test_a_tube_is_unwrapped_with_its_second_hole_filled_and_does_not_fold(method):
    obj = tube()
    summary = run(method=method)
    data = read(obj)
    polys = np.arange(len(obj.data.polygons))
    assert summary["islands"] == 1 and summary["faces"] == 32
    # Solved as it is first, the tube folds; filled, it does not, so the filled map is kept.
    assert summary["filled_islands"] == 1 and summary["repaired_islands"] == 0, summary
    assert (summary["flipped"], summary["overlaps"]) == (0, 0)
    assert_no_flips(data, [polys])
    assert covered_more_than_once(data, polys) == 0.0


def test_holes_are_filled_only_where_the_map_folds_without():
    # A grid with one inner face left out: an island with a hole whose natural conformal map
    # does not fold, so it is kept as it is, the same map as the library's on the island.
    n = 6
    obj = grid(n)
    hole = (n // 2) * n + n // 2
    edit([obj], lambda o: np.arange(len(o.data.polygons)) != hole)
    summary = run()
    assert summary["islands"] == 1 and summary["filled_islands"] == 0 and summary["repaired_islands"] == 0, summary
    assert (summary["flipped"], summary["overlaps"]) == (0, 0)


def test_without_fill_holes_the_folded_map_of_a_tube_is_repaired():
    # The conformal map of the tube itself is pressed flat, its two layers folded at the sides
    # (what Fill Holes avoids); the exact checker finds the fold and the island is solved
    # again by bijective SLIM, which leaves no point of it covered twice.
    obj = tube()
    import blender_addon.unwrap as unwrap
    import uvflat

    p = np.array([v.co[:] for v in obj.data.vertices])
    t = np.array([[f.vertices[0], f.vertices[k], f.vertices[k + 1]] for f in obj.data.polygons for k in (1, 2)])
    folded = uvflat.natural_conformal_map(p, t)
    assert unwrap.is_folded(uvflat, folded, t.astype(np.uint32))
    summary = run(method="NATURAL_CONFORMAL", fill_holes=False)
    data = read(obj)
    polys = np.arange(len(obj.data.polygons))
    assert summary["repaired_islands"] == 1 and summary["folded_islands"] == 0, summary
    assert summary["filled_islands"] == 0 and (summary["flipped"], summary["overlaps"]) == (0, 0)
    assert_no_flips(data, [polys])
    assert covered_more_than_once(data, polys) == 0.0


def test_a_folding_method_is_repaired_and_the_status_says_so():
    # Blender's own conformal unwrap and uvflat's natural conformal map both fold the
    # mannequin-like three peaks disk; the operator repairs it (the test checks UVs itself).
    path = mesh_path("disk_three_peaks.obj")
    bpy.ops.wm.obj_import(filepath=str(path))
    obj = bpy.context.selected_objects[0]
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    summary = run(method="NATURAL_CONFORMAL")
    data = read(obj)
    polys = np.arange(len(obj.data.polygons))
    assert summary["repaired_islands"] == 1 and summary["folded_islands"] == 0, summary
    assert (summary["flipped"], summary["overlaps"]) == (0, 0)
    assert_no_flips(data, [polys])
    assert covered_more_than_once(data, polys, samples=60) == 0.0


def test_nothing_selected_says_so():
    obj = grid()
    edit([obj], lambda o: np.zeros(len(o.data.polygons), bool))
    summary = run()
    assert summary["selected_faces"] == 0 and summary["islands"] == 0


def test_every_face_an_island_next_to_a_tube_in_one_run():
    # Thousands of islands are checked, scaled, laid out and measured together (one library
    # call for all instead of one per island): each face of the seamed grid must still come out
    # as its own unfolded island at the common scale, and the tube in the same run, which the
    # stacked check cannot call a disk (Euler characteristic 0), must still get its second hole
    # filled (without, it folds and is repaired: test_without_fill_holes_the_folded_map_of_a_tube_is_repaired).
    n = 8
    obj = grid(n)
    obj.data.edges.foreach_set("use_seam", np.ones(len(obj.data.edges), dtype=bool))
    bpy.ops.mesh.primitive_cylinder_add(vertices=32, end_fill_type="NOTHING", location=(4, 0, 0))
    cylinder = bpy.context.object
    bpy.ops.object.mode_set(mode="OBJECT")
    edit([obj, cylinder], lambda o: np.ones(len(o.data.polygons), bool))
    summary = run()
    assert summary["islands"] == n * n + 1 and summary["faces"] == n * n + 32, summary
    assert summary["warnings"] == []
    data, tube_data = read(obj), read(cylinder)
    faces = [np.array([p]) for p in range(n * n)]
    assert len(uv_islands(data, np.arange(n * n))) == n * n
    assert_no_flips(data, faces)
    assert_no_overlap(data, faces)
    # UV area / 3D area is one number for every island (each keeps its relative size).
    ratios = []
    for p in range(n * n):
        tris = triangles_of(data, np.array([p]))
        a, b, c = (data["co"][data["loop_vert"][tris[:, k]]] for k in range(3))
        area_3d = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()
        ratios.append(np.abs(signed_areas(data, tris)).sum() / area_3d)
    assert np.ptp(ratios) < 1e-4 * np.mean(ratios), ratios
    tube_polys = np.arange(len(cylinder.data.polygons))
    assert_no_flips(tube_data, [tube_polys])
    assert covered_more_than_once(tube_data, tube_polys) == 0.0
    # The summary's mean angle error is the mean over every triangle of both objects.
    ours = (angle_distortion(data, np.arange(n * n)) * 2 * n * n + angle_distortion(tube_data, tube_polys) * 64) / (
        2 * n * n + 64
    )
    assert summary["angle_mean"] == pytest.approx(ours, abs=1e-4)


def test_vertices_snapped_together_do_not_stop_their_island():
    # Two vertices at one point, not merged: two zero-area triangles, which the library
    # refuses; the island is solved without them and every loop gets a UV.
    obj = grid(6)
    obj.data.vertices[24].co = obj.data.vertices[25].co
    before = set_uvs(obj, np.random.default_rng(21)).astype(np.float64)
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    summary = run()
    data = read(obj)
    assert summary["islands"] == 1 and summary["faces"] == 36 and summary["warnings"] == []
    assert (data["uv"] != before).any(axis=1).all()
    snapped = np.flatnonzero(np.isin(data["loop_vert"], [24, 25]))
    assert_no_flips(data, [np.arange(36)], exclude_loops=snapped)


def test_a_snapped_vertex_that_only_a_zero_area_face_holds_is_welded_for_the_solve():
    # The grid's corner vertex moved onto its neighbour, its quad split so that the corner is
    # in the zero-area triangle only: leaving that triangle out would leave the vertex in no
    # triangle; welded to its neighbour instead, the island is solved and both get one UV.
    obj = object_from(
        [(0, 0, 0), (1, 0, 0.1), (2, 0, 0), (0, 1, 0.2), (1, 1, 0.4), (2, 1, 0), (0, 2, 0), (1, 2, 0.1), (2, 2, 0)],
        [(0, 1, 3), (1, 4, 3), (1, 2, 5, 4), (3, 4, 7, 6), (4, 5, 8, 7)],
    )
    obj.data.vertices[0].co = obj.data.vertices[1].co
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    summary = run()
    data = read(obj)
    assert summary["islands"] == 1 and summary["faces"] == 5 and summary["warnings"] == [], summary
    uv = data["uv"]
    assert np.isfinite(uv).all()
    corner = np.flatnonzero(data["loop_vert"] == 0)
    neighbour = np.flatnonzero(data["loop_vert"] == 1)
    assert np.abs(uv[corner] - uv[neighbour[0]]).max() < 1e-6
    assert_no_flips(data, [np.arange(1, 5)])


def test_a_refused_island_is_named_by_the_meshs_own_indices():
    # A triangle whose corners are collinear and whose apex is in no other face: leaving it
    # out would leave that vertex in no triangle, so the island is refused, and the message
    # names the mesh's face 1 (the island's triangle 2, after the quad's two).
    obj = object_from([(0, 0, 0), (1, 0, 0), (1, 1, 0.2), (0, 1, 0), (1, 2, 0.4)], [(0, 1, 2, 3), (2, 1, 4)])
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    summary = run()
    assert summary["skipped"]["invalid"] == 1 and summary["islands"] == 0, summary
    message = " ".join(summary["warnings"])
    assert "face 1 is degenerate" in message and "(mesh indices)" in message, message
    assert "triangle 2" not in message


def uv_discontinuous_edges(data, polys) -> np.ndarray:
    """Mesh edges between two of `polys` whose two loops do not meet in the same UVs."""
    loops = poly_loops(data, polys)
    following = np.arange(1, len(data["loop_vert"]) + 1)
    following[data["poly_start"] + data["poly_total"] - 1] = data["poly_start"]
    edges = data["loop_edge"][loops]
    order = np.argsort(edges, kind="stable")
    paired = edges[order][1:] == edges[order][:-1]
    i, j = loops[order[:-1][paired]], loops[order[1:][paired]]
    uv = data["uv"]
    apart = (np.abs(uv[i] - uv[following[j]]).max(1) > 1e-7) | (np.abs(uv[following[i]] - uv[j]).max(1) > 1e-7)
    return np.unique(data["loop_edge"][i][apart])


def test_seams_the_cut_makes_are_marked_in_the_mesh():
    sphere, torus, _ = closed_and_genus_objects()
    summary = run()
    assert summary["cut_islands"] == 2 and summary["seams_marked"] > 0, summary
    marked = 0
    for obj in (sphere, torus):
        data = read(obj)
        seams = np.flatnonzero(get(obj.data.edges, "use_seam", bool))
        polys = np.flatnonzero(np.arange(len(obj.data.polygons)) != (0 if obj is torus else -1))
        # The marked seams are exactly where the UVs are cut (neither had seams before).
        np.testing.assert_array_equal(seams, uv_discontinuous_edges(data, polys))
        marked += len(seams)
    assert marked == summary["seams_marked"]


def test_islands_split_at_non_manifold_and_misoriented_edges_say_so():
    # Three quads on one edge (non-manifold) and a fourth quad whose orientation disagrees with
    # its neighbour's: every one is its own island, and the warning says why.
    obj = object_from(
        [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (0, -1, 0), (1, -1, 0), (2, 0, 0), (2, 1, 0)],
        [(0, 1, 2, 3), (1, 0, 4, 5), (0, 1, 7, 6), (1, 2, 9, 8)],
    )
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    summary = run()
    assert summary["islands"] == 4, summary
    message = " ".join(summary["warnings"])
    assert "1 non-manifold edge(s) and 1 edge(s) between faces of opposite orientation" in message, message


def test_pins_keep_their_place_in_an_aspect_corrected_layout():
    # Pins taken from Blender's own aspect-corrected unwrap of a flat grid (which every method
    # maps exactly): the island is solved in square space and put back into the image's
    # aspect, so nothing moves.
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=4, y_subdivisions=4)
    obj = bpy.context.object
    bpy.ops.object.mode_set(mode="OBJECT")
    add_wide_image(obj)
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    bpy.ops.uv.unwrap(method="CONFORMAL", correct_aspect=True, margin=0.001)
    reference = read(obj)["uv"]
    corners = np.flatnonzero(np.isin(read(obj)["loop_vert"], [0, len(obj.data.vertices) - 1]))
    set_pins(obj, corners)
    for method in ("NATURAL_CONFORMAL", "ABF_PLUS_PLUS", "SLIM"):
        edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
        run(method=method, correct_aspect=True)
        # (SLIM stops at its relative tolerance, 1e-4 off; the island squeezed twice, as
        # before this was fixed, moved by 0.25.)
        assert np.abs(read(obj)["uv"] - reference).max() < (1e-3 if method == "SLIM" else 1e-5), method


def test_the_active_shape_key_is_unwrapped():
    # Edit Mode shows and edits the active shape key; Blender's unwrap reads it, so does ours.
    obj = grid(6)
    obj.shape_key_add(name="Basis")
    bent = obj.shape_key_add(name="Bent")
    for d in bent.data:
        d.co.z = 2 * math.sin(3 * d.co.x)
    obj.active_shape_key_index = 1

    def elongation() -> float:
        uv = read(obj)["uv"]
        s = np.linalg.svd(uv - uv.mean(0), compute_uv=False)
        return float(s[0] / s[1])

    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    run()
    ours = elongation()
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    bpy.ops.uv.unwrap(method="CONFORMAL", margin=0.001)
    assert ours == pytest.approx(elongation(), rel=1e-3) and ours > 2


def test_intrinsic_weights_that_all_vanish_are_refused():
    obj = grid(4)
    before = set_uvs(obj, np.random.default_rng(22))
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    with pytest.raises(RuntimeError, match="cannot both be 0"):
        bpy.ops.uv.uvflat_unwrap(method="INTRINSIC", lambda_=0.0, mu=0.0)
    np.testing.assert_array_equal(read(obj)["uv"], before)


def closed_and_genus_objects():
    """A whole UV sphere (closed, genus 0) and a torus with quads, minus one face (genus 1 with a
    boundary), with random UVs, both in Edit Mode with those faces selected."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, location=(-3, 0, 0))
    sphere = bpy.context.object
    bpy.ops.mesh.primitive_torus_add(major_segments=24, minor_segments=12, location=(3, 0, 0))
    torus = bpy.context.object
    bpy.ops.object.mode_set(mode="OBJECT")
    before = {sphere.name: set_uvs(sphere, np.random.default_rng(5)), torus.name: set_uvs(torus, np.random.default_rng(6))}
    edit([sphere, torus], lambda o: np.arange(len(o.data.polygons)) != (0 if o is torus else -1))
    return sphere, torus, before


def test_closed_and_genus_islands_are_skipped_untouched_when_not_cut():
    sphere, torus, before = closed_and_genus_objects()
    summary = run(cut_closed=False)
    assert summary["skipped"]["closed"] == 1 and summary["skipped"]["not_disk"] == 1
    assert summary["islands"] == 0 and summary["cut_islands"] == 0
    assert any("closed" in w for w in summary["warnings"]) and any("genus" in w for w in summary["warnings"])
    bpy.ops.object.mode_set(mode="OBJECT")
    np.testing.assert_array_equal(read(sphere)["uv"], before[sphere.name])
    np.testing.assert_array_equal(read(torus)["uv"], before[torus.name])


@pytest.mark.parametrize("method", ["NATURAL_CONFORMAL", "MEAN_VALUE", "ABF_PLUS_PLUS"])
def test_closed_and_genus_islands_are_cut_open(method):
    sphere, torus, _ = closed_and_genus_objects()
    summary = run(method=method)
    assert summary["cut_islands"] == 2 and summary["islands"] == 2, summary
    assert sum(summary["skipped"].values()) == 0
    for obj in (sphere, torus):
        data = read(obj)
        selected = np.arange(len(obj.data.polygons)) != (0 if obj is torus else -1)
        polys = np.flatnonzero(selected)
        loops = poly_loops(data, polys)
        assert np.isfinite(data["uv"][loops]).all()
        # One UV island per object: the cut opens the surface into one disk (the seams are new
        # UV discontinuities, not new islands), with no flipped triangle and real area.
        islands = uv_islands(data, polys)
        assert len(islands) == 1, f"{obj.name}: {len(islands)} UV islands"
        assert_no_flips(data, islands)
        assert np.abs(signed_areas(data, triangles_of(data, polys))).min() > 0
        # The cut follows polygon edges: every quad keeps four distinct UV corners, and every
        # mesh vertex not on the cut keeps one UV (a cut needs at least one seam).
        uv = data["uv"][loops]
        assert len(np.unique(np.round(uv, 9), axis=0)) > len(np.unique(data["loop_vert"][loops]))


def test_multi_object_edit_mode():
    a = grid(8, "a")
    b = honeycomb()
    b.location = (10, 0, 0)
    ua = set_uvs(a, np.random.default_rng(7)).astype(np.float64)
    ub = set_uvs(b, np.random.default_rng(8)).astype(np.float64)
    ma = face_centers(a)[:, 1] < 0.2
    edit([a, b], lambda o: ma if o is a else np.ones(len(o.data.polygons), bool))
    assert len(bpy.context.objects_in_mode_unique_data) == 2
    summary = run()
    assert summary["islands"] == 3  # one grid island, the hexagons, the 8-gon
    da, db = read(a), read(b)
    np.testing.assert_array_equal(da["uv"][poly_loops(da, np.flatnonzero(~ma))], ua[poly_loops(da, np.flatnonzero(~ma))])
    changed_a = poly_loops(da, np.flatnonzero(ma))
    assert (np.abs(da["uv"][changed_a] - ua[changed_a]).max(axis=1) > 0).all()
    assert (np.abs(db["uv"] - ub).max(axis=1) > 0).all()
    # The islands of both objects share one layout: no island overlaps another across objects.
    parts = [(da, np.flatnonzero(ma))] + [(db, p) for p in uv_islands(db, np.arange(len(b.data.polygons)))]
    pair = islands_overlap([data["uv"][triangles_of(data, polys)].astype(np.float64) for data, polys in parts])
    assert pair is None, f"islands {pair} overlap"


def test_an_object_without_faces_next_to_a_grid_is_passed_over():
    """Multi-object Edit Mode with an edges-only object: the grid is unwrapped, the wire object
    has no islands and stops nothing."""
    obj = grid(4)
    wire = bpy.data.meshes.new("wire")
    wire.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0)], [(0, 1), (1, 2)], [])
    wire.update()
    wire_obj = bpy.data.objects.new("wire", wire)
    bpy.context.scene.collection.objects.link(wire_obj)
    edit([obj, wire_obj], lambda o: np.ones(len(o.data.polygons), bool))
    summary = run()
    assert summary["islands"] == 1 and summary["faces"] == 16, summary
    data = read(obj)
    assert_no_flips(data, uv_islands(data, np.arange(len(obj.data.polygons))))


def test_undo():
    """Ctrl Z after the operator restores the UVs, and redo brings the unwrap back. bpy's
    background mode has an undo stack but `ed.undo` polls False without a window and area in the
    context; the test gives it the window manager's window and an area of its screen."""
    import blender_addon.unwrap as unwrap

    assert {"REGISTER", "UNDO"} <= set(unwrap.UVFLAT_OT_unwrap.bl_options)
    obj = grid(8)
    before = set_uvs(obj, np.random.default_rng(9))
    mask = face_centers(obj)[:, 0] < 0.0
    edit([obj], lambda o: mask)
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window, screen=window.screen, area=window.screen.areas[0]):
        bpy.ops.ed.undo_push(message="before uvflat")
        run()
        assert bpy.ops.ed.undo.poll()
        after = read(obj)["uv"]
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.ed.undo_push(message="read")
        assert not np.array_equal(after, before)
        bpy.ops.ed.undo()  # back over the "read" step
        bpy.ops.ed.undo()  # back over the unwrap
        np.testing.assert_array_equal(read(obj)["uv"], before)
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.ed.redo()
        np.testing.assert_array_equal(read(obj)["uv"], after)


def test_picture_of_an_unwrapped_model():
    """Renders disk_nefertiti_small.obj with a checker texture on the uvflat UVs (Cycles, CPU)
    and writes the UV layout as SVG: target/blender-pictures/ (or $UVFLAT_PICTURES)."""
    path = mesh_path("disk_nefertiti_small.obj")
    bpy.ops.wm.obj_import(filepath=str(path))
    obj = bpy.context.selected_objects[0]
    edit([obj], lambda o: np.ones(len(o.data.polygons), bool))
    summary = run()
    assert summary["islands"] == 1
    PICTURES.mkdir(parents=True, exist_ok=True)
    svg = PICTURES / "nefertiti_uv_layout.svg"
    bpy.ops.uv.export_layout(filepath=str(svg), mode="SVG", size=(1024, 1024), export_all=False)
    assert svg.exists() and svg.stat().st_size > 1000
    bpy.ops.object.mode_set(mode="OBJECT")

    mat = bpy.data.materials.new("checker")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    checker = nodes.new("ShaderNodeTexChecker")
    checker.inputs["Scale"].default_value = 24.0
    checker.inputs["Color1"].default_value = (0.9, 0.85, 0.75, 1)
    checker.inputs["Color2"].default_value = (0.15, 0.25, 0.45, 1)
    coords = nodes.new("ShaderNodeTexCoord")
    links.new(coords.outputs["UV"], checker.inputs["Vector"])
    links.new(checker.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
    obj.data.materials.append(mat)
    bpy.ops.object.shade_smooth()

    scene = bpy.context.scene
    lo, hi = np.array(obj.bound_box).min(0), np.array(obj.bound_box).max(0)
    center, size = (lo + hi) / 2, float(np.max(hi - lo))
    cam_data = bpy.data.cameras.new("camera")
    cam = bpy.data.objects.new("camera", cam_data)
    scene.collection.objects.link(cam)
    # The model faces +Y after import (OBJ Y-up -> Blender Z-up); look at it from the front.
    cam.location = (center[0] + 0.3 * size, center[1] - 1.8 * size, center[2] + 0.3 * size)
    direction = center - np.array(cam.location)
    import mathutils

    cam.rotation_euler = mathutils.Vector(direction).to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam
    light_data = bpy.data.lights.new("sun", "SUN")
    light_data.energy = 4.0
    light = bpy.data.objects.new("sun", light_data)
    light.rotation_euler = (0.8, 0.2, -0.5)
    scene.collection.objects.link(light)
    world = bpy.data.worlds.new("world")
    world.color = (0.6, 0.6, 0.6)
    scene.world = world
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 16
    scene.render.resolution_x = scene.render.resolution_y = 512
    png = PICTURES / "nefertiti_checker.png"
    scene.render.filepath = str(png)
    bpy.ops.render.render(write_still=True)
    assert png.exists() and png.stat().st_size > 10000


def test_extension_zip_installs_and_unwraps(tmp_path):
    """scripts/build_blender_extension.sh makes a zip that Blender installs as an extension and
    that runs with its bundled binding and library (no $UVFLAT_LIBRARY, no installed binding
    on the path: a clean Python with only bpy's own modules, in a throwaway user directory)."""
    import subprocess

    zip_path = tmp_path / "uvflat.zip"
    env = dict(os.environ)
    build = subprocess.run([str(REPO / "scripts" / "build_blender_extension.sh"), str(zip_path)], capture_output=True, text=True, env=env)
    assert build.returncode == 0, build.stderr
    script = tmp_path / "install.py"
    script.write_text(
        "import sys, bpy\n"
        "sys.modules.pop('uvflat', None)\n"
        "import builtins\n"
        "real_import = builtins.__import__\n"
        "def guarded(name, *a, **k):\n"
        "    if name == 'uvflat' and not (a and a[0] and a[0].get('__package__', '').startswith('bl_ext')):\n"
        "        raise ImportError('the installed binding must not be used')\n"
        "    return real_import(name, *a, **k)\n"
        "builtins.__import__ = guarded\n"
        "bpy.ops.wm.read_factory_settings(use_empty=True)\n"
        f"assert bpy.ops.extensions.package_install_files(filepath={str(zip_path)!r}, repo='user_default', enable_on_install=True) == {{'FINISHED'}}\n"
        "bpy.ops.mesh.primitive_grid_add(x_subdivisions=8, y_subdivisions=8)\n"
        "bpy.ops.object.mode_set(mode='EDIT'); bpy.ops.mesh.select_all(action='SELECT')\n"
        "assert bpy.ops.uv.uvflat_unwrap() == {'FINISHED'}\n"
        "print('ISLANDS', sys.modules['bl_ext.user_default.uvflat.unwrap'].LAST_RUN['islands'])\n"
        "print('LIBRARY', sys.modules['bl_ext.user_default.uvflat.vendor.uvflat'].library_path())\n"
    )
    env.pop("UVFLAT_LIBRARY", None)
    env["BLENDER_USER_RESOURCES"] = str(tmp_path / "blender")
    run_ = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=300)
    assert "ISLANDS 1" in run_.stdout, run_.stdout + run_.stderr
    assert f"LIBRARY {tmp_path / 'blender'}" in run_.stdout, run_.stdout
