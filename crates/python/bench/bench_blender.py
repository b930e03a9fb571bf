"""Times the Blender extension's operator on ~10⁵ vertices (the issue's bar: ≤ 3 s end to end).

    python crates/python/bench/bench_blender.py [--segments 129] [--repeat 3]

A cube with each face a k×k quad grid (6k² + 2 vertices: k = 129 gives 99 848), jittered, with
its 12 edges infinitely sharp (--creases) or not; the whole `bpy.ops.object.subdiv_interpolate()`
call is timed (reading the mesh, the library, writing the cage and its modifier), then Blender's
evaluation of the cage (limit surface, level 1) and the deviation of its first n vertices from
the data. Needs `bpy` (pip install bpy, CPython 3.11) and the package installed.
"""

import argparse
import sys
import time
from pathlib import Path

import bpy  # first: bmesh is importable once bpy is
import bmesh
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "blender"))
import subdiv_interpolate  # noqa: E402


def cube(k: int, creases: bool):
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=2.0)
    bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=k - 1, use_grid_fill=True)
    mesh = bpy.data.meshes.new("bench")
    bm.to_mesh(mesh)
    bm.free()
    n = len(mesh.vertices)
    co = np.empty(3 * n, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    p = co.reshape(n, 3).astype(np.float64)
    if creases:
        edges = np.empty(2 * len(mesh.edges), dtype=np.int32)
        mesh.edges.foreach_get("vertices", edges)
        on_edge = (np.abs(np.abs(p) - 1) < 1e-6).sum(1) >= 2
        edges = edges.reshape(-1, 2)
        sharp = on_edge[edges[:, 0]] & on_edge[edges[:, 1]]
        mesh.attributes.new("crease_edge", "FLOAT", "EDGE").data.foreach_set("value", sharp.astype(np.float32))
    p += (0.2 / k) * np.random.default_rng(1).standard_normal(p.shape)
    mesh.vertices.foreach_set("co", p.astype(np.float32).ravel())
    obj = bpy.data.objects.new("bench", mesh)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    return obj, p


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--segments", type=int, default=129)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--creases", action="store_true")
    parser.add_argument("--method", default="CHENG")
    args = parser.parse_args()
    subdiv_interpolate.register()
    for run in range(args.repeat):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        obj, data = cube(args.segments, args.creases)
        n = len(data)
        start = time.perf_counter()
        assert bpy.ops.object.subdiv_interpolate(method=args.method) == {"FINISHED"}
        seconds = time.perf_counter() - start
        cage = bpy.context.view_layer.objects.active
        start = time.perf_counter()
        evaluated = cage.evaluated_get(bpy.context.evaluated_depsgraph_get())
        mesh = evaluated.to_mesh()
        co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
        mesh.vertices.foreach_get("co", co)
        evaluation = time.perf_counter() - start
        d = np.linalg.norm(data.max(0) - data.min(0))
        deviation = np.linalg.norm(co.reshape(-1, 3)[:n] - data, axis=1).max() / d
        print(
            f"{n} vertices, {len(obj.data.polygons)} faces, creases {args.creases}, {args.method}: "
            f"operator {seconds:.2f} s; Blender's evaluation (quality {cage.modifiers[0].quality}) "
            f"{evaluation:.2f} s; max deviation {deviation:.2e}·d",
            flush=True,
        )
    subdiv_interpolate.unregister()


if __name__ == "__main__":
    main()
