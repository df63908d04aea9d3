"""The add-on fuzz, the long version: random hostile Blender scenes (tests/addon/fuzz_scenes.py)
rendered through the add-on with bpy, `scenes` seeds from `first` on, in each Blender of `blenders`.
The seeds go in batches of `batch`, each batch a separate process of that version's Python
(harness.blenders) in a clean folder, so that a crash is caught and its seeds reported instead of
ending the run. tests/addon/test_fuzz_scenes.py runs the first seeds (0..59) in `make test`.
The experiment fails when any scene failed to render or a batch crashed."""

from __future__ import annotations

import os
import sys
import tempfile
import time

from harness import blenders

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# bpy and the add-on are imported only inside the functions that run in a child (harness.blenders):
# each child is another Blender version.
BATCH_TIMEOUT = 3600  # seconds: a batch that hangs is a failure of the run, not a finding


def render_batch(params):
    """In a child: renders the seeds first..last-1; the seeds that raised, with the first line of each error."""
    sys.path[:0] = [os.path.join(ROOT, "addon"), os.path.join(ROOT, "tests", "addon")]
    import bpy

    import fuzz_scenes
    import ppm_render

    ppm_render.register()
    failed = []
    for seed in range(params["first"], params["last"]):
        fuzz_scenes.build(seed)
        try:
            bpy.ops.render.render()
        except RuntimeError as error:
            failed.append([seed, str(error).strip().splitlines()[0]])
    ppm_render.unregister()  # bpy 4.2 and 4.5 crash or hang at exit otherwise
    return {"version": bpy.app.version_string, "failed": failed}


def run_batch(blender, first, last, workdir):
    """The failures of one batch as lines, and the Blender version (None if the batch crashed)."""
    result, process = blenders.call(blender, "kinds.fuzz_addon:render_batch", {"first": first, "last": last},
                                    cwd=workdir, timeout=BATCH_TIMEOUT)
    if result is None:
        return None, [f"CRASHED (exit {process.returncode}) in seeds {first}..{last - 1}: {process.stderr[-500:]}"]
    return result["version"], [f"FAILED seed {seed}: {message}" for seed, message in result["failed"]]


def fuzz(blender, first, scenes, batch):
    start, version, failures = time.monotonic(), None, []
    with tempfile.TemporaryDirectory() as workdir:
        for begin in range(first, first + scenes, batch):
            batch_version, lines = run_batch(blender, begin, min(begin + batch, first + scenes), workdir)
            version = version or batch_version
            failures += lines
    return version or blender, time.monotonic() - start, failures


def run(experiment, results):
    first, scenes, batch = experiment["first"], experiment["scenes"], experiment["batch"]
    rows, all_failures = [], []
    for blender in experiment["blenders"]:
        version, seconds, failures = fuzz(blender, first, scenes, batch)
        results.row(blender=version, scenes=scenes, first=first, seconds=seconds, failures=failures)
        rows.append([version, str(scenes), f"{first}..{first + scenes - 1}", f"{seconds:.0f}", str(len(failures))])
        all_failures += [f"{version}: {line}" for line in failures]
    results.table(["Blender", "scenes", "seeds", "seconds", "failed"], rows, title="Add-on fuzz")
    if all_failures:
        results.note("\n".join(["Failures:", "```", *all_failures, "```"]))
    return not all_failures
