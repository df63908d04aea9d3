"""The bundled volumetric caustic (fog_caustic, its spot's radius 1 m so that Cycles converges) against
Cycles in the running Blender: Cycles with two seeds (bench/harness/addon_route.render_cycles:
12 bounces of every kind, volume ones included, no clamping), PPM through the add-on for the same
scene, and the mean of each region (bench/harness/regions.py: the beam through the fog, the floor's
caustic, the glass ball, the rest) of each, with PPM's ratio to the seeds' mean and the seeds' own
spread. For Blenders the bench's references do not cover (the bench renders 5.0's:
bench/experiments/references_caustic.toml), Debian's 3.4 above all:

    blender -b --factory-startup --python-exit-code 1 -P tools/caustic_against_cycles.py -- [--samples 4096]
    .venv/bin/python tools/caustic_against_cycles.py [--samples 4096] [--seconds 60] [--radius 1.0]  # 5.0 (bpy)
"""

import argparse
import glob
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# Blender 3.4 from Debian has no numpy and no ppm_core: borrow the .venv's (same Python 3.11).
for site in glob.glob(os.path.join(ROOT, ".venv", "lib", "python%d.%d" % sys.version_info[:2], "site-packages")):
    if site not in sys.path:
        sys.path.append(site)
sys.path.insert(0, os.path.join(ROOT, "bench"))
sys.path.insert(0, os.path.join(ROOT, "tools"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402
from light_radius_sweep import REGIONS, SCENE, SIZE  # noqa: E402

from harness import addon_route, regions  # noqa: E402


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=4096, help="Cycles samples per seed")
    parser.add_argument("--seconds", type=float, default=60.0, help="PPM's time")
    parser.add_argument("--radius", type=float, default=1.0, help="the spot's radius, m")
    args = parser.parse_args(argv)
    radius = {"objects.spot.data.shadow_soft_size": args.radius}
    seeds = [addon_route.render_cycles(SCENE, *SIZE, seed=seed, passes=args.samples, **radius) for seed in (1, 2)]
    cycles = (seeds[0].image + seeds[1].image) / 2
    ppm = addon_route.render_ppm(SCENE, *SIZE, seed=7, seconds=args.seconds, **radius)
    masks = regions.region_masks(SCENE, cycles, *SIZE)
    version = ".".join(map(str, bpy.app.version))
    print(f"Blender {version}: Cycles {args.samples} samples a seed ({seeds[0].wall:.0f} s, {seeds[1].wall:.0f} s), "
          f"PPM {args.seconds:.0f} s ({ppm.wall:.0f} s with export), {SIZE[0]}x{SIZE[1]}, spot radius {args.radius} m")
    print("| region | pixels | Cycles seed 1 | Cycles seed 2 | seeds apart | PPM | PPM / Cycles |")
    print("|---|---|---|---|---|---|---|")
    for name in (r for r in REGIONS if r in masks):
        m = masks[name]
        a, b, p = seeds[0].image[m].mean(), seeds[1].image[m].mean(), ppm.image[m].mean()
        print(f"| {name} | {int(m.sum())} | {a:.4f} | {b:.4f} | {abs(a - b) / ((a + b) / 2):.2%} | {p:.4f} | "
              f"{p / ((a + b) / 2):.3f} |", flush=True)
    if not all(np.isfinite(s.image).all() for s in (*seeds, ppm)):
        raise SystemExit("an image holds NaN or Inf")


if __name__ == "__main__":
    main()
