"""PPM's mean over each region of a bundled scene against its Cycles reference: renders the .blend
through the add-on (bpy 5.0) for a number of passes and prints PPM / reference per region and channel
(bench/harness/regions.py names the regions). A bias shows here apart from noise.

    cd /tmp/clean && /work/main/.venv/bin/python /work/main/tools/region_means.py studio --passes 400 --seed 3
"""

import argparse
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))

import numpy as np  # noqa: E402

from harness import addon_route, exr_io, regions  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("scene")
    parser.add_argument("--passes", type=int, default=400)
    parser.add_argument("--seed", type=int, default=3)
    args = parser.parse_args()
    reference, _ = exr_io.read_exr(os.path.join(ROOT, "bench", "references", f"{args.scene}_cycles.exr"))
    height, width = reference.shape[:2]
    image = np.asarray(addon_route.render_ppm(args.scene, width, height, seed=args.seed, passes=args.passes).image)
    for name, mask in regions.region_masks(args.scene, reference, width, height).items():
        ratio = image[..., :3][mask].mean(axis=0) / reference[..., :3][mask].mean(axis=0)
        print(f"{name:8s} {int(mask.sum()):6d} pixels  PPM / Cycles {np.round(ratio, 4).tolist()}")


if __name__ == "__main__":
    main()
