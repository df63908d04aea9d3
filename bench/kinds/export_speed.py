"""Seconds to export a mesh of about a million triangles (a grid of `subdivisions` x `subdivisions`,
708 by default: 1,002,528 triangles) from Blender to the core, through the add-on's Exporter
(foreach_get into numpy, then Scene.add_mesh), in each Blender of `blenders`: each version runs in a
child process of its own Python (harness.blenders). Reports the median of `repeats` exports per
version. The export is a goal of seconds, not a test: on a loaded machine it takes longer."""

from __future__ import annotations

import os
import statistics
import sys
import time

import numpy as np

from harness import blenders

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# bpy and the add-on are imported only inside the functions that run in a child (harness.blenders):
# each child is another Blender version.


def export_seconds(obj):
    import bpy

    from ppm_render import core, export

    depsgraph = bpy.context.evaluated_depsgraph_get()
    start = time.monotonic()
    exporter = export.Exporter(core.load().Scene(), print)
    exporter.add_geometry(export.instance.Instance(obj.evaluated_get(depsgraph), "grid", np.eye(4), 0))
    return time.monotonic() - start, exporter.triangles


def measure(params):
    """In the child: the grid built and exported `repeats` times; seconds of each, and the triangles."""
    sys.path.insert(0, os.path.join(ROOT, "addon"))
    import bpy

    import ppm_render

    bpy.ops.wm.read_factory_settings(use_empty=True)
    ppm_render.register()
    try:
        n = params["subdivisions"]
        bpy.ops.mesh.primitive_grid_add(x_subdivisions=n, y_subdivisions=n, size=2.0)
        runs = [export_seconds(bpy.context.object) for _ in range(params["repeats"])]
    finally:
        ppm_render.unregister()  # bpy 4.2 and 4.5 crash or hang at exit otherwise
    return {"version": bpy.app.version_string, "triangles": runs[0][1], "seconds": [s for s, _ in runs]}


def run(experiment, results):
    params = {"subdivisions": experiment["subdivisions"], "repeats": experiment["repeats"]}
    rows = []
    for blender in experiment["blenders"]:
        m = blenders.result_of(blender, "kinds.export_speed:measure", params)
        median = statistics.median(m["seconds"])
        results.row(blender=m["version"], triangles=m["triangles"], median_seconds=median, seconds=m["seconds"])
        rows.append([m["version"], f"{m['triangles']:,}", f"{median:.2f}",
                     ", ".join(f"{s:.2f}" for s in m["seconds"])])
    results.table(["Blender", "triangles", f"seconds (median of {experiment['repeats']})", "runs"], rows,
                  title=f"Export of a {experiment['subdivisions']}x{experiment['subdivisions']} grid")
