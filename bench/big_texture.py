"""Seconds and memory to hand one big 8-bit PNG texture (16k x 16k by default) from Blender to the
core, through the add-on's image export, in the Blender that runs this script.

    .venvs/bpy-5.2/bin/python bench/big_texture.py    # file bytes through imbuf (Blender 5.2+)
    .venv/bin/python bench/big_texture.py             # Image.pixels (bpy 5.0; likewise 4.2, 4.5)

The PNG is written once into build/bench-cache/ (about 1 GB, by a child process so that its memory
does not count). Prints the export's seconds, the process's peak RSS above what it held before
the export, and what it still holds once the export is done (the core's copy).
"""

import argparse
import os
import resource
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402

from ppm_render import core  # noqa: E402
from ppm_render.export import image as image_export  # noqa: E402

GIB = 1024.0 ** 3


def rss_bytes():
    with open("/proc/self/status") as status:
        kib = next(int(line.split()[1]) for line in status if line.startswith("VmRSS:"))
    return kib * 1024


def peak_rss_bytes():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # KiB on Linux


def write_png(path, size):
    """A size x size RGBA PNG of gradients and a xor pattern, saved by Blender."""
    image = bpy.data.images.new("big", size, size, alpha=True)
    pixels = np.empty((size, size, 4), dtype=np.float32)
    x = np.arange(size)
    for row in range(size):
        pixels[row, :, 0] = x / (size - 1)
        pixels[row, :, 1] = row / (size - 1)
        pixels[row, :, 2] = ((x ^ row) & 255) / 255.0
    pixels[..., 3] = 1.0
    image.pixels.foreach_set(pixels.reshape(-1))
    del pixels
    image.filepath_raw = path
    image.file_format = "PNG"
    image.save()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=16384)
    parser.add_argument("--write-png", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.write_png:
        write_png(args.write_png, args.size)
        return
    path = os.path.join(ROOT, "build", "bench-cache", f"texture-{args.size}.png")
    if not os.path.exists(path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        subprocess.run([sys.executable, __file__, "--size", str(args.size), "--write-png", path + ".tmp"],
                       check=True)
        os.replace(path + ".tmp", path)
    image = bpy.data.images.load(path)
    scene = core.load().Scene()
    before = rss_bytes()
    start = time.monotonic()
    index, _ = image_export.add_texture(scene, image)
    seconds = time.monotonic() - start
    peak, after = peak_rss_bytes() - before, rss_bytes() - before
    info = scene.texture_info(index)
    way = "file bytes (imbuf)" if image_export.can_read_file_bytes(image) else "Image.pixels"
    print(f"big_texture: Blender {bpy.app.version_string}, {args.size} x {args.size} PNG by {way}: "
          f"{seconds:.2f} s, peak +{peak / GIB:.2f} GiB, after +{after / GIB:.2f} GiB "
          f"(core texture {info['bytes'] / GIB:.2f} GiB, {info['storage']})")


if __name__ == "__main__":
    main()
