#!/usr/bin/env python3
"""Fill Holes in the Blender add-on, measured on Suzanne: the monkey primitive subdivided by
Catmull–Clark (`--level`, default 5: 503,808 faces), everything selected, unwrapped by *uvflat
Unwrap* (Natural Conformal) with Fill Holes on and off. Flipped triangles and overlaps by the
library's exact checker over the written UVs (welded per vertex where equal), the mean angle
error from the operator's summary, wall seconds of the operator.

Usage (the venv of scripts/python_tests.sh, which has bpy 4.5):
    UVFLAT_LIBRARY=target/release/libuvflat.so target/python-venv/bin/python benches/blender_fill_holes.py [--level N]
"""

import argparse
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def measure(level: int, fill: bool) -> str:
    import bpy
    import uvflat
    from blender_addon import unwrap

    if bpy.context.object is not None and bpy.context.object.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")
    for old in list(bpy.data.objects):
        bpy.data.objects.remove(old)
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.object
    modifier = obj.modifiers.new("subdivision", "SUBSURF")
    modifier.levels = level
    bpy.ops.object.modifier_apply(modifier="subdivision")
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    start = time.perf_counter()
    assert bpy.ops.uv.uvflat_unwrap(method="NATURAL_CONFORMAL", fill_holes=fill) == {"FINISHED"}
    seconds = time.perf_counter() - start
    summary = dict(unwrap.LAST_RUN)
    bpy.ops.object.mode_set(mode="OBJECT")
    me = obj.data
    me.calc_loop_triangles()
    uv = np.zeros(2 * len(me.loops), np.float32)
    me.uv_layers.active.uv.foreach_get("vector", uv)
    uv = uv.reshape(-1, 2).astype(np.float64)
    loop_vertex = np.zeros(len(me.loops), np.int64)
    me.loops.foreach_get("vertex_index", loop_vertex)
    tri_loops = np.zeros(3 * len(me.loop_triangles), np.int64)
    me.loop_triangles.foreach_get("loops", tri_loops)
    _, index = np.unique(np.concatenate([loop_vertex[:, None].astype(np.float64), uv], axis=1), axis=0, return_inverse=True)
    index = index.reshape(-1)
    welded = np.zeros((index.max() + 1, 2))
    welded[index] = uv
    check = uvflat.check_layout(welded, index[tri_loops].reshape(-1, 3).astype(np.uint32))
    return (f"| {len(me.polygons)} | {'on' if fill else 'off'} | {summary['islands']} | {summary.get('filled_islands', 0)} | "
            f"{summary['repaired_islands']} | {check.flipped} | {check.overlaps} | {np.degrees(summary['angle_mean']):.3f} | "
            f"{seconds:.1f} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--level", type=int, default=5)
    args = parser.parse_args()
    sys.path.insert(0, ROOT)
    import bpy
    import blender_addon

    bpy.ops.wm.read_factory_settings(use_empty=True)
    blender_addon.register()
    print("| faces | Fill Holes | islands | filled | repaired | flips | overlaps | angle° | s |")
    print("|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for fill in (True, False):
        print(measure(args.level, fill), flush=True)
    # bpy 4.5 as a module can hang in its exit handlers (a condition variable destroyed while
    # a thread waits on it); the results are printed, so leave without them.
    os._exit(0)


if __name__ == "__main__":
    main()
