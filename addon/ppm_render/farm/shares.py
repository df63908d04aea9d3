"""What a worker runs: one share of a still's passes, from the exported scene's builder calls
(scene_record.py). It imports ppm_core and nothing of Blender or of this add-on: the farm sends
this module's functions by value (cloudpickle), so a worker needs only ppm_core, numpy and dask.
"""

from __future__ import annotations

import time


def plan(total_passes, shares):
    """`shares` (first, count) ranges covering passes 0 .. total_passes - 1, as even as they go."""
    if total_passes < 1 or shares < 1:
        raise ValueError("the passes and the shares must be at least 1")
    shares = min(shares, total_passes)
    bounds = [total_passes * k // shares for k in range(shares + 1)]
    return [(bounds[k], bounds[k + 1] - bounds[k]) for k in range(shares)]


def render_share(calls, settings, first_pass, passes, threads=0, until=0.0):
    """(ppm_core.Share of passes first_pass .. first_pass + passes - 1, facts): the scene replayed
    from `calls`, rendered with `settings` (radius_schedule 'global'). With `until` (a time.time()),
    the share stops there, at least one pass done, with the passes it has: they merge as well as a
    whole share's. `facts` has the worker's seconds (replay, render) and whether bpy was loaded."""
    import sys

    import ppm_core

    start = time.perf_counter()
    scene = ppm_core.Scene()
    for call in calls:  # scene_record.replay, here so that the worker needs nothing but ppm_core
        if call[0] == "=":
            setattr(scene, call[1], call[2])
        else:
            getattr(scene, call[0])(*call[1], **call[2])
    replayed = time.perf_counter()
    renderer = ppm_core.Renderer(scene, **{**settings, "first_pass": first_pass, "threads": threads})
    renderer.run(passes=passes, seconds=max(1e-3, until - time.time()) if until > 0.0 else 0.0)
    share = renderer.share()
    facts = {"replay_seconds": replayed - start, "render_seconds": time.perf_counter() - replayed,
             "bpy_loaded": "bpy" in sys.modules}
    return share, facts
