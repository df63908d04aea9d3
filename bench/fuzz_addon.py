"""The add-on fuzz, the long version: random hostile Blender scenes (tests/addon/fuzz_scenes.py)
rendered through the add-on with bpy, in batches, each batch a separate process so that a crash is
caught and its seeds reported instead of ending the run. tests/addon/test_fuzz_scenes.py runs the
first seeds in `make test`.

    .venv/bin/python bench/fuzz_addon.py [--scenes 1000] [--first 1000] [--batch 100]
    .venvs/bpy-5.2/bin/python bench/fuzz_addon.py ...      # another Blender
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

BATCH = """
import sys
sys.path[:0] = [{addon!r}, {tests!r}]
import bpy, ppm_render, fuzz_scenes
ppm_render.register()
failed = []
for seed in range({first}, {last}):
    fuzz_scenes.build(seed)
    try:
        bpy.ops.render.render()
    except RuntimeError as error:
        failed.append((seed, str(error).strip().splitlines()[0]))
for seed, message in failed:
    print(f"FAILED seed {{seed}}: {{message}}", flush=True)
ppm_render.unregister()  # bpy 4.2 and 4.5 crash or hang at exit otherwise
"""


def run_batch(first, last, workdir):
    script = BATCH.format(addon=os.path.join(ROOT, "addon"), tests=os.path.join(ROOT, "tests", "addon"),
                          first=first, last=last)
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=workdir, timeout=3600)
    failures = [line for line in run.stdout.splitlines() if line.startswith("FAILED seed")]
    if run.returncode != 0:
        failures.append(f"CRASHED (exit {run.returncode}) in seeds {first}..{last - 1}: {run.stderr[-500:]}")
    return failures


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=int, default=1000)
    parser.add_argument("--first", type=int, default=1000, help="first seed (the tests use 0..59)")
    parser.add_argument("--batch", type=int, default=100)
    args = parser.parse_args()
    start, failures = time.monotonic(), []
    with tempfile.TemporaryDirectory() as workdir:
        for first in range(args.first, args.first + args.scenes, args.batch):
            failures += run_batch(first, min(first + args.batch, args.first + args.scenes), workdir)
    print(f"fuzz_addon: {args.scenes} scenes (seeds {args.first}..{args.first + args.scenes - 1}) in "
          f"{time.monotonic() - start:.0f} s, {len(failures)} failed")
    for line in failures:
        print("  " + line)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
