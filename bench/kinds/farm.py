"""What a sharded still costs beyond its passes on dask.distributed (addon/ppm_render/farm), the
figures docs/FARM.md extrapolates from:

    .venv/bin/python bench/run.py farm [--quick]

- scenes: each bundled .blend exported as the farm exports it (bpy; "+grid": with a grid of
  1,002,528 triangles added): seconds, the builder calls' pickled bytes (what goes to the workers
  once), the seconds a worker takes to replay them, and a share's bytes per pixel pickled (what
  comes back);
- round trip: `tasks` shares of 1 pass of a small scene on a LocalCluster of `workers` worker
  processes, one at a time: the client's seconds per share beyond the worker's own (submit,
  scheduling, transfer of the result, unpickling), and the merge's seconds per share at `merge_size`.
"""

from __future__ import annotations

import os
import pickle
import statistics
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))


def exported(name, width, height):
    import bpy

    import ppm_render
    from ppm_render import core
    from ppm_render.farm.still_export import export_still

    if not hasattr(bpy.types.Scene, "ppm"):
        ppm_render.register()
    base, _, extra = name.partition("+")
    bpy.ops.wm.open_mainfile(filepath=os.path.join(ROOT, "blend_scenes", f"{base}.blend"))
    if extra == "grid":  # a mesh of about a million triangles: the scene's bytes per triangle
        bpy.ops.mesh.primitive_grid_add(x_subdivisions=708, y_subdivisions=708, size=0.5, location=(0, 0, 0.01))
    render = bpy.context.scene.render
    render.resolution_x, render.resolution_y, render.resolution_percentage = width, height, 100
    start = time.perf_counter()
    still = export_still(bpy, core.load(), lambda message: None)
    return still, time.perf_counter() - start


def scene_row(name, experiment):
    from ppm_render.farm.shares import render_share

    still, seconds = exported(name, *experiment["size"])
    data = pickle.dumps(still.calls, protocol=5)
    start = time.perf_counter()
    share, facts = render_share(pickle.loads(data), {**still.settings, "photons_per_pass": 10_000}, 0, 1)
    return {"part": "scene", "scene": name, "export_seconds": seconds, "calls": len(still.calls),
            "scene_bytes": len(data), "replay_seconds": facts["replay_seconds"],
            "share_bytes_per_pixel": len(pickle.dumps(share, protocol=5)) / (share.width * share.height),
            "seconds": time.perf_counter() - start}


def round_trip_rows(experiment):
    from dask.distributed import Client, LocalCluster

    import ppm_core
    from ppm_render.farm.merge import submit_shares

    still, _ = exported("cornell_diffuse", 64, 48)
    still.settings["photons_per_pass"] = 1000
    with LocalCluster(n_workers=experiment["workers"], threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        submit_shares(client, still, 1, 1, threads=1)[0].result()  # warm: the scene on a worker
        overheads = []
        for k in range(experiment["tasks"]):
            start = time.perf_counter()
            share, facts = submit_shares(client, still, 1, 1, threads=1, first_pass=k)[0].result()
            overheads.append(time.perf_counter() - start - facts["replay_seconds"] - facts["render_seconds"])
    rows = [{"part": "round_trip", "workers": experiment["workers"], "tasks": experiment["tasks"],
             "overhead_median": statistics.median(overheads), "overhead_p90": float(np.quantile(overheads, 0.9))}]
    width, height = experiment["merge_size"]
    rng = np.random.default_rng(1)
    parts = []
    for k in range(2):
        data = {"width": width, "height": height, "seed": 0, "photons_per_pass": 1, "alpha": 0.7,
                "ranges": [(k, 1)], "image": rng.random((height, width, 4), dtype=np.float32),
                "moments": rng.random((height, width, 4), dtype=np.float32), "light_passes": None}
        parts.append(ppm_core.Share.from_dict(data))
    start = time.perf_counter()
    ppm_core.merge_shares(parts)
    rows.append({"part": "merge", "width": width, "height": height,
                 "merge_seconds": time.perf_counter() - start,
                 "bytes_per_share": len(pickle.dumps(parts[0], protocol=5))})
    return rows


def run(experiment, results):
    rows = [scene_row(name, experiment) for name in experiment["scenes"]]
    rows += round_trip_rows(experiment)
    for row in rows:
        results.row(**row)
    width, height = experiment["size"]
    results.table(["scene", "export s", "builder calls", "scene bytes", "replay s", "share bytes / pixel"],
                  [[r["scene"], f"{r['export_seconds']:.3f}", r["calls"], f"{r['scene_bytes']:,}",
                    f"{r['replay_seconds']:.3f}", f"{r['share_bytes_per_pixel']:.1f}"]
                   for r in rows if r["part"] == "scene"],
                  title=f"The scene exported once and replayed on a worker ({width}x{height})")
    trip = next(r for r in rows if r["part"] == "round_trip")
    merge = next(r for r in rows if r["part"] == "merge")
    results.table(["what", "figure"],
                  [[f"client seconds a share beyond the worker's, median of {trip['tasks']} "
                    f"({trip['workers']} local workers)", f"{trip['overhead_median']:.4f}"],
                   ["same, 90th percentile", f"{trip['overhead_p90']:.4f}"],
                   [f"merging one share into another at {merge['width']}x{merge['height']}, seconds",
                    f"{merge['merge_seconds']:.3f}"],
                   [f"a share's pickled bytes at {merge['width']}x{merge['height']}", f"{merge['bytes_per_share']:,}"]],
                  title="A share's overhead")
    return True
