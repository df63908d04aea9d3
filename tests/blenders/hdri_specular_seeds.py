"""The distribution of PPM's ball means over many seeds at a fixed pass count, for a case of
hdri_specular_compare.py: mean (with its standard error), median, spread and range per region. Where
the sun's image in a ball covers a small part of a pixel, the renders' mean should still be Cycles'
while single renders scatter widely and their median lies below it.

    .venv/bin/python tests/blenders/hdri_specular_seeds.py --case front --passes 32 --seeds 120
"""

import argparse
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy
import numpy as np

import cycles_compare
import hdri_specular_compare as cases


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else \
        (sys.argv[1:] if os.path.basename(sys.argv[0]) == os.path.basename(__file__) else [])
    parser = argparse.ArgumentParser()
    parser.add_argument("--case", default="front", choices=cases.CASES)
    parser.add_argument("--passes", type=int, default=32)
    parser.add_argument("--seeds", type=int, default=120)
    parser.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE",
                        help="scene.ppm settings besides the case's (e.g. adaptive_samples=1)")
    args = parser.parse_args(argv)
    try:
        with tempfile.TemporaryDirectory() as workdir:
            cases.build(args.case, (96, 64))
            masks = cases.regions(bpy.context.scene, cases.balls_of(args.case))
            blend = os.path.join(workdir, "seeds.blend")
            bpy.ops.wm.save_as_mainfile(filepath=blend)
            values = {region: [] for region in masks}
            for seed in range(1, args.seeds + 1):
                bpy.ops.wm.open_mainfile(filepath=blend)
                scene = bpy.context.scene
                cases.configure_ppm(scene, args.passes, seed)
                for name, value in (item.split("=", 1) for item in args.set):
                    setattr(scene.ppm, name, type(getattr(scene.ppm, name))(value))
                image = cycles_compare.render_to_array(scene, os.path.join(workdir, "ppm.exr")).mean(axis=2)
                for region, mask in masks.items():
                    values[region].append(float(image[mask].mean()))
    finally:
        cycles_compare.unregister_checkout_addon()
    for region, v in values.items():
        v = np.array(v)
        error = v.std(ddof=1) / np.sqrt(len(v))
        print(f"hdri_specular_seeds: Blender {bpy.app.version_string} {args.case} {args.passes} passes, "
              f"{len(v)} seeds {' '.join(args.set)}, {region}: mean {v.mean():.4f} (s.e. {error:.4f}) "
              f"median {np.median(v):.4f} sd {v.std(ddof=1):.4f} min {v.min():.4f} max {v.max():.4f}", flush=True)


if __name__ == "__main__":
    main()
