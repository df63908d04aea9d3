"""The instructions ppm_core executes for a fixed render, counted by valgrind's callgrind: a measure
of what a change costs that, unlike timing, a loaded machine does not disturb (it misses cache and
memory effects). Build the two cores with `-DCMAKE_STRIP=/bin/true` to see function names.

    .venv/bin/python tools/instruction_counts.py BUILD_DIR [BUILD_DIR ...] [--work eye|photons]

Each BUILD_DIR holds a ppm_core module. The work: cornell_3spheres with stochastic hit points on 1
thread; `eye`: 320x240, 4 passes of 1,000 photons (the eye pass, its direct light and gather);
`photons`: 160x120, 2 passes of 100,000 photons. Prints the instructions in ppm_core and its five
costliest functions."""

import argparse
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORK = {"eye": ((320, 240), 4, 1_000), "photons": ((160, 120), 2, 100_000)}


def render(work):
    sys.path.insert(0, os.path.join(ROOT, "blend_scenes"))
    import core_scenes  # noqa: PLC0415
    import ppm_core  # noqa: PLC0415

    size, passes, photons = WORK[work]
    renderer = ppm_core.Renderer(
        core_scenes.cornell_3spheres(*size), hit_points="stochastic", photons_per_pass=photons, threads=1, seed=1
    )
    renderer.run(passes=passes)


def count(build_dir, work):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "callgrind.out")
        env = {**os.environ, "PYTHONPATH": build_dir}
        subprocess.run(
            ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", sys.executable, __file__, "--render", work],
            env=env,
            check=True,
            capture_output=True,
        )
        text = subprocess.run(["callgrind_annotate", "--threshold=100", out], capture_output=True, text=True).stdout
    total, rows = 0, []
    for line in text.splitlines():
        if "ppm_core.cpython" not in line:
            continue
        ir = int(line.split()[0].replace(",", ""))
        total += ir
        name = line.split(":", 1)[1].rsplit(" [", 1)[0] if ":" in line else "?"
        rows.append((ir, name[:90]))
    return total, rows[:5]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("builds", nargs="*")
    parser.add_argument("--work", choices=sorted(WORK), default="eye")
    parser.add_argument("--render", choices=sorted(WORK))
    args = parser.parse_args()
    if args.render:
        render(args.render)
        return
    for build in args.builds:
        total, top = count(build, args.work)
        print(f"{build} {args.work}: {total:,} instructions in ppm_core")
        for ir, name in top:
            print(f"    {ir:>14,}  {name}")


if __name__ == "__main__":
    main()
