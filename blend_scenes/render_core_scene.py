"""Render a bundled scene through ppm_core and write linear EXR plus an sRGB PNG.

    python blend_scenes/render_core_scene.py cornell_3spheres --output out/cornell.exr --seconds 20

Progress goes to stdout; Ctrl-C stops the render and keeps the image so far.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
import OpenImageIO as oiio

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402

SCENES = {
    "cornell_3spheres": core_scenes.cornell_3spheres,
    "bezier_vase": core_scenes.bezier_vase,
}


def write_images(rgba: np.ndarray, exr_path: str) -> str:
    """Writes `rgba` (H, W, 4, linear, top row first) as EXR and an sRGB PNG beside it."""
    os.makedirs(os.path.dirname(os.path.abspath(exr_path)), exist_ok=True)
    h, w = rgba.shape[:2]
    exr = oiio.ImageBuf(oiio.ImageSpec(w, h, 4, "half"))
    exr.set_pixels(oiio.ROI(), np.ascontiguousarray(rgba, dtype=np.float32))
    if not exr.write(exr_path):
        raise RuntimeError(f"could not write {exr_path}: {exr.geterror()}")
    rgb = np.clip(rgba[..., :3], 0.0, None)
    srgb = np.where(rgb <= 0.0031308, 12.92 * rgb, 1.055 * np.power(rgb, 1.0 / 2.4) - 0.055)
    png_path = os.path.splitext(exr_path)[0] + ".png"
    png = oiio.ImageBuf(oiio.ImageSpec(w, h, 3, "uint8"))
    png.set_pixels(oiio.ROI(), np.clip(srgb, 0.0, 1.0).astype(np.float32))
    if not png.write(png_path):
        raise RuntimeError(f"could not write {png_path}: {png.geterror()}")
    return png_path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", choices=sorted(SCENES))
    parser.add_argument("--output", required=True, help="EXR path; a PNG is written beside it")
    parser.add_argument("--seconds", type=float, default=0.0, help="time limit (0 = none)")
    parser.add_argument("--passes", type=int, default=0, help="pass limit (0 = none)")
    parser.add_argument("--resolution", type=int, nargs=2, default=(640, 480), metavar=("W", "H"))
    parser.add_argument("--photons-per-pass", type=int, default=200_000)
    parser.add_argument("--threads", type=int, default=0)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    if args.seconds <= 0 and args.passes <= 0:
        parser.error("give --seconds or --passes")

    scene = SCENES[args.scene](*args.resolution)
    renderer = ppm_core.Renderer(
        scene, photons_per_pass=args.photons_per_pass, threads=args.threads, seed=args.seed
    )
    last = [0.0]

    def progress(info):
        if info["seconds"] - last[0] >= 1.0:
            last[0] = info["seconds"]
            print(f"  pass {info['passes']}  {info['photons_emitted'] / 1e6:.1f} M photons  "
                  f"{info['seconds']:.0f} s", flush=True)
        return True

    start = time.time()
    try:
        renderer.run(passes=args.passes, seconds=args.seconds, callback=progress)
    except KeyboardInterrupt:
        print("interrupted: writing the image so far")
    stats = renderer.stats()
    png = write_images(renderer.image(), args.output)
    print(f"{args.scene}: {stats['passes']} passes, {stats['photons_emitted'] / 1e6:.1f} M photons, "
          f"{time.time() - start:.1f} s -> {args.output}, {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
