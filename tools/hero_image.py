"""The README's first picture, docs/hero.png: the stored long PPM references of two bundled scenes
(bench/references/cornell_3spheres_ppm.exr and bezier_vase_ppm.exr, 1200 passes each, made by
`bench/run.py references_blend`; bench/README.md), side by side, tone-mapped as the benchmark
plots are (Reinhard, then gamma 2.2). It renders nothing, so it takes a second:

    .venv/bin/python tools/hero_image.py
"""

import os
import sys

import numpy as np
import OpenImageIO as oiio

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
from harness.exr_io import read_exr  # noqa: E402
from harness.plots import tone  # noqa: E402

SCENES = ("cornell_3spheres", "bezier_vase")
HERO = os.path.join(ROOT, "docs", "hero.png")


def main(out=HERO):
    images = [read_exr(os.path.join(ROOT, "bench", "references", f"{s}_ppm.exr"))[0] for s in SCENES]
    pixels = (np.concatenate([tone(i) for i in images], axis=1) * 255 + 0.5).astype(np.uint8)
    output = oiio.ImageOutput.create(out)
    if output is None or not output.open(out, oiio.ImageSpec(pixels.shape[1], pixels.shape[0], 3, oiio.UINT8)):
        raise RuntimeError(f"cannot write {out}: {oiio.geterror()}")
    output.write_image(pixels)
    output.close()
    print(out)


if __name__ == "__main__":
    main(*sys.argv[1:])
