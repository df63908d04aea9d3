"""Seconds to export a mesh of about a million triangles from Blender to the core (the add-on's
Exporter: foreach_get into numpy, then Scene.add_mesh), in the Blender that runs this script.

    .venv/bin/python bench/export_speed.py               # bpy 5.0
    .venvs/bpy-5.2/bin/python bench/export_speed.py      # bpy 5.2 (likewise bpy-4.2, bpy-4.5)

Prints the median of --repeats runs. The export is a goal of seconds, not a test: on a loaded
machine it takes longer.
"""

import argparse
import os
import statistics
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))

import bpy
import numpy as np

import ppm_render
from ppm_render import core, export


def export_seconds(obj):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    start = time.monotonic()
    exporter = export.Exporter(core.load(), print)
    exporter.add_geometry(export.instance.Instance(obj.evaluated_get(depsgraph), "grid", np.eye(4), 0))
    return time.monotonic() - start, exporter.triangles


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    ppm_render.register()
    try:
        bpy.ops.mesh.primitive_grid_add(x_subdivisions=708, y_subdivisions=708, size=2.0)
        runs = [export_seconds(bpy.context.object) for _ in range(args.repeats)]
    finally:
        ppm_render.unregister()  # bpy 4.2 and 4.5 crash or hang at exit otherwise
    seconds = [s for s, _ in runs]
    print(f"export_speed: Blender {bpy.app.version_string}: {runs[0][1]:,} triangles in "
          f"{statistics.median(seconds):.2f} s (median of {len(seconds)}: "
          f"{', '.join(f'{s:.2f}' for s in seconds)})")


if __name__ == "__main__":
    main()
