"""The bundled volumetric caustic (fog_caustic) as its spot's radius shrinks: PPM through the add-on at
each radius, for the same time each, and the mean of each region of the image (bench/harness/regions.py:
the beam through the fog, the floor's caustic, the glass ball, the rest), beside Cycles' reference at
1 m (bench/references/fog_caustic_cycles.exr, made by `bench/run.py references_caustic`). Cycles
cannot converge the light the ball focuses from a small lamp; this shows PPM's image at the radius
Cycles checks and how it goes on to the bundled 2 cm.

    .venv/bin/python tools/light_radius_sweep.py [--seconds 60] [--radii 1.0 0.5 0.25 0.1 0.05 0.02]
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "bench"))
from harness import addon_route, references, regions  # noqa: E402

SCENE, SIZE, REGIONS = "fog_caustic", (160, 120), ("all", "beam", "caustic", "glass", "walls")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--radii", type=float, nargs="+", default=[1.0, 0.5, 0.25, 0.1, 0.05, 0.02])
    args = parser.parse_args()
    reference, _ = references.load_reference(SCENE, "cycles")
    masks = regions.region_masks(SCENE, reference, *SIZE)
    names = [r for r in REGIONS if r in masks]
    print("| spot radius (m) | engine | " + " | ".join(f"mean {r}" for r in names) + " |")
    print("|---|---|" + "---|" * len(names))
    print("| 1.0 | Cycles reference | " + " | ".join(f"{reference[masks[r]].mean():.4f}" for r in names) + " |")
    for radius in args.radii:
        image = addon_route.render_ppm(SCENE, *SIZE, seed=7, seconds=args.seconds,
                                       **{"objects.spot.data.shadow_soft_size": radius}).image
        print(f"| {radius} | PPM {args.seconds:.0f} s | " + " | ".join(f"{image[masks[r]].mean():.4f}" for r in names)
              + " |", flush=True)


if __name__ == "__main__":
    main()
