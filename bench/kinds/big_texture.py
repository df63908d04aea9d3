"""Seconds and memory to hand one big 8-bit PNG texture (`size` x `size`, 16k x 16k by default) from
Blender to the core, through the add-on's image export, in each Blender of `blenders`, each in a
child process of its own Python (harness.blenders): Blender 5.2 and later read the file's bytes
through imbuf, 5.0 and older go through Image.pixels.

The PNG is written once into build/bench-cache/ (about 1 GB at 16k, by a child process of its own so
that its memory counts nowhere). Reports the export's seconds, the process's peak RSS above what it
held before the export, and what it still holds once the export is done (the core's copy)."""

from __future__ import annotations

import os
import resource
import sys
import time

import numpy as np

from harness import blenders

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# bpy and the add-on are imported only inside the functions that run in a child (harness.blenders):
# each child is another Blender version.
CACHE = os.path.join(ROOT, "build", "bench-cache")
GIB = 1024.0 ** 3


def rss_bytes():
    with open("/proc/self/status") as status:
        kib = next(int(line.split()[1]) for line in status if line.startswith("VmRSS:"))
    return kib * 1024


def peak_rss_bytes():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # KiB on Linux


def write_png(params):
    """In a child: a size x size RGBA PNG of gradients and a xor pattern, saved by Blender."""
    import bpy

    size = params["size"]
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
    image.filepath_raw = params["path"]
    image.file_format = "PNG"
    image.save()
    return {}


def measure(params):
    """In a child: the PNG loaded, then exported to a core scene; seconds and memory of the export."""
    sys.path.insert(0, os.path.join(ROOT, "addon"))
    import bpy

    from ppm_render import core
    from ppm_render.export import image as image_export

    image = bpy.data.images.load(params["path"])
    scene = core.load().Scene()
    before = rss_bytes()
    start = time.monotonic()
    index, _ = image_export.add_texture(scene, image)
    seconds = time.monotonic() - start
    peak, after = peak_rss_bytes() - before, rss_bytes() - before
    info = scene.texture_info(index)
    way = "file bytes (imbuf)" if image_export.can_read_file_bytes(image) else "Image.pixels"
    return {"version": bpy.app.version_string, "way": way, "seconds": seconds, "peak": peak, "after": after,
            "core_bytes": info["bytes"], "storage": info["storage"]}


def cached_png(size, blender):
    path = os.path.join(CACHE, f"texture-{size}.png")
    if not os.path.exists(path):
        os.makedirs(CACHE, exist_ok=True)
        blenders.result_of(blender, "kinds.big_texture:write_png", {"size": size, "path": path + ".tmp"})
        os.replace(path + ".tmp", path)
    return path


def run(experiment, results):
    size = experiment["size"]
    path = cached_png(size, experiment["blenders"][0])
    rows = []
    for blender in experiment["blenders"]:
        m = blenders.result_of(blender, "kinds.big_texture:measure", {"path": path})
        results.row(blender=m["version"], size=size, **{k: v for k, v in m.items() if k != "version"})
        rows.append([m["version"], m["way"], f"{m['seconds']:.2f}", f"+{m['peak'] / GIB:.2f} GiB",
                     f"+{m['after'] / GIB:.2f} GiB", f"{m['core_bytes'] / GIB:.2f} GiB, {m['storage']}"])
    results.table(["Blender", "way in", "seconds", "peak", "after", "core texture"], rows,
                  title=f"A {size} x {size} PNG through the add-on's image export")
