#!/usr/bin/env python3
"""uvflat vs Blender 4.5 (PyPI `bpy`), same run, same meshes, same machine.

For every mesh it times, one after the other in this process:
  - Blender `bpy.ops.uv.unwrap(method='ANGLE_BASED')` (Blender's ABF++ + LSCM reconstruction),
  - Blender `bpy.ops.uv.unwrap(method='MINIMUM_STRETCH')` (Blender's SLIM, default iterations),
  - uvflat ABF++ (`uvflat.abf`, Python ctypes binding, default options),
  - uvflat SLIM (`uvflat.nonlinear_map(..., "slim")`, default options),
and prints one Markdown table: median wall seconds of REPEATS runs, mean |3D angle − uv angle|
(degrees), Sander L2 stretch, flipped triangles. The metrics are computed by the one numpy
function `distortion` below for every method, from per-corner uvs (Blender writes per-loop
uvs; uvflat's per-vertex uvs are expanded to corners), so both are measured the same way.

Blender's time is the whole operator call on a mesh already in Edit Mode with everything
selected (its ABF, LSCM and island packing; margin 0); uvflat's is the whole binding call
(mesh validation, angle optimisation, reconstruction). The mesh is a single disk chart in both.

Usage (a venv with `bpy==4.5.*` and numpy; Blender's wheels need CPython 3.11):
  cargo build --release
  python benches/blender_abf.py [--repeats N] [mesh.obj ...]
  (default meshes: the disk test meshes with at least 16k faces; UVFLAT_LIBRARY may point at the
  library, default target/release/libuvflat.so)
"""
import argparse
import os
import statistics
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "tests", "data"))
import meshes  # noqa: E402  (tests/data/meshes.py)

MESH_DIR = str(meshes.unpacked_dir())
DEFAULT_MESHES = [
    "disk_lion_head.obj",
    "disk_camelhead.obj",
    "disk_cowhead.obj",
    "disk_face_bff.obj",
    "disk_mountain.obj",
    "disk_face_libigl.obj",
    "disk_bimba_cut.obj",
]

sys.path.insert(0, os.path.join(ROOT, "bindings", "python"))
os.environ.setdefault("UVFLAT_LIBRARY", os.path.join(ROOT, "target", "release", "libuvflat.so"))
import uvflat  # noqa: E402

import bpy  # noqa: E402


def read_obj(path):
    """Vertices (n, 3) and triangles (m, 3) of an OBJ (faces fan-triangulated)."""
    verts, tris = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                idx = [int(tok.split("/")[0]) - 1 for tok in line.split()[1:]]
                for k in range(1, len(idx) - 1):
                    tris.append([idx[0], idx[k], idx[k + 1]])
    return np.asarray(verts, dtype=np.float64), np.asarray(tris, dtype=np.int64)


def corner_angles(p0, p1, p2):
    """Corner angles (m, 3) of triangles with vertices p0, p1, p2 (rows; 2D or 3D)."""

    def angle(a, b, c):
        u, v = b - a, c - a
        if u.shape[1] == 2:
            cross = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
        else:
            cross = np.linalg.norm(np.cross(u, v), axis=1)
        return np.arctan2(cross, np.einsum("ij,ij->i", u, v))

    return np.stack([angle(p0, p1, p2), angle(p1, p2, p0), angle(p2, p0, p1)], axis=1)


def distortion(V, F, corner_uv):
    """Mean angle error (degrees), L2 stretch and flips of a per-corner uv layout.

    corner_uv: (m, 3, 2), uv of corner k of triangle t. A triangle is flipped when its signed
    uv area has the sign opposite to the total (a mirrored layout is not a map of flips).
    L2 stretch (Sander et al. 2001) after scaling the uv area to the 3D area:
    sqrt(Σ A3d (σ1² + σ2²)/2 / Σ A3d)."""
    P = [V[F[:, k]] for k in range(3)]
    Q = [corner_uv[:, k, :] for k in range(3)]
    a3 = corner_angles(*P)
    a2 = corner_angles(*Q)
    e1, e2 = Q[1] - Q[0], Q[2] - Q[0]
    signed = 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    flipped = int(np.sum(signed * np.sign(signed.sum()) < 0))
    area3 = 0.5 * np.linalg.norm(np.cross(P[1] - P[0], P[2] - P[0]), axis=1)
    # Jacobian of the map uv -> surface: with s1, s2 the 3D edges and d1, d2 the uv edges,
    # |J|_F^2 = (σ1² + σ2²) = Σ over the 3D frame of the gradient norms.
    s1, s2 = P[1] - P[0], P[2] - P[0]
    area2 = np.abs(signed)
    scale = np.sqrt(area3.sum() / area2.sum())
    d1, d2 = e1 * scale, e2 * scale
    a2s = area2 * scale * scale
    ok = a2s > 0
    # f_u = (s1 d2_v − s2 d1_v) / (2A_uv), f_v = (s2 d1_u − s1 d2_u) / (2A_uv).
    fu = (s1 * d2[:, 1:2] - s2 * d1[:, 1:2])[ok] / (2 * a2s[ok])[:, None]
    fv = (s2 * d1[:, 0:1] - s1 * d2[:, 0:1])[ok] / (2 * a2s[ok])[:, None]
    sq = (np.einsum("ij,ij->i", fu, fu) + np.einsum("ij,ij->i", fv, fv)) / 2
    stretch = float(np.sqrt(np.sum(area3[ok] * sq) / np.sum(area3[ok])))
    angle = float(np.degrees(np.mean(np.abs(a2 - a3))))
    return angle, stretch, flipped


def blender_object(V, F):
    """A fresh Blender mesh object of the triangles, active, in Edit Mode, all selected."""
    if bpy.context.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for me in list(bpy.data.meshes):
        bpy.data.meshes.remove(me)
    me = bpy.data.meshes.new("bench")
    me.from_pydata(V.tolist(), [], F.tolist())
    me.update()
    obj = bpy.data.objects.new("bench", me)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    return obj


def blender_unwrap(V, F, method):
    """Seconds of one bpy.ops.uv.unwrap call and the per-corner uvs (m, 3, 2)."""
    obj = blender_object(V, F)
    start = time.perf_counter()
    result = bpy.ops.uv.unwrap(method=method, margin=0.0)
    seconds = time.perf_counter() - start
    assert result == {"FINISHED"}, result
    bpy.ops.object.mode_set(mode="OBJECT")
    me = obj.data
    loop_uv = np.zeros(2 * len(me.loops), dtype=np.float32)
    me.uv_layers.active.uv.foreach_get("vector", loop_uv)
    loop_vert = np.zeros(len(me.loops), dtype=np.int64)
    me.loops.foreach_get("vertex_index", loop_vert)
    loop_start = np.zeros(len(me.polygons), dtype=np.int64)
    me.polygons.foreach_get("loop_start", loop_start)
    loops = loop_start[:, None] + np.arange(3)[None, :]
    # from_pydata keeps the face order and each face's vertex order.
    assert np.array_equal(loop_vert[loops], F), "Blender reordered the triangles"
    return seconds, loop_uv.reshape(-1, 2).astype(np.float64)[loops]


def uvflat_run(V, F, method):
    start = time.perf_counter()
    if method == "abf++":
        uv, report = uvflat.abf(V, F)
        info = f"{report.iterations} it., ‖∇L‖ {report.gradient_norm:.1e}"
    else:
        uv, report = uvflat.nonlinear_map(V, F, "slim")
        info = f"{report.iterations} it."
    seconds = time.perf_counter() - start
    return seconds, uv[F], info


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("meshes", nargs="*", default=DEFAULT_MESHES)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print(f"Blender {bpy.app.version_string}, uvflat {uvflat.version()}; load: {os.getloadavg()}")
    print()
    print("| mesh | faces | method | median s | angle error (°) | L2 stretch | flipped | notes |")
    print("|---|---:|---|---:|---:|---:|---:|---|")
    for name in args.meshes:
        V, F = read_obj(os.path.join(MESH_DIR, name))
        rows = []
        runs = [
            ("Blender ANGLE_BASED", lambda: blender_unwrap(V, F, "ANGLE_BASED") + ("",)),
            ("uvflat ABF++", lambda: uvflat_run(V, F, "abf++")),
            ("Blender MINIMUM_STRETCH", lambda: blender_unwrap(V, F, "MINIMUM_STRETCH") + ("",)),
            ("uvflat SLIM", lambda: uvflat_run(V, F, "slim")),
        ]
        for label, run in runs:
            times = []
            for _ in range(args.repeats):
                seconds, corner_uv, info = run()
                times.append(seconds)
            angle, stretch, flipped = distortion(V, F, corner_uv)
            rows.append((label, statistics.median(times), angle, stretch, flipped, info))
        for label, seconds, angle, stretch, flipped, info in rows:
            print(f"| {name} | {len(F)} | {label} | {seconds:.3f} | {angle:.3f} | {stretch:.4f} | {flipped} | {info} |")
        base = {r[0]: r[1] for r in rows}
        print(
            f"| {name} | | speed-up | ABF++ {base['Blender ANGLE_BASED'] / base['uvflat ABF++']:.2f}× |"
            f" | | | SLIM {base['Blender MINIMUM_STRETCH'] / base['uvflat SLIM']:.2f}× |",
            flush=True,
        )


if __name__ == "__main__":
    main()
