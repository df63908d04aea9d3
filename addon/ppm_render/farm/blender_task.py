"""A still's shares as Blender commands, for farms that run Blender and nothing else (Flamenco:
addon/farm/flamenco/ppm_sharded_still.js), and for render.py:

    blender -b scene.blend --python-exit-code 1 -P render.py -- --first-pass 0 --passes 16 --share-output s0.npz
    blender -b --python-exit-code 1 -P render.py -- --merge s0.npz s1.npz ... --output out.exr

A share renders passes first_pass .. first_pass + passes - 1 of the scene's still and saves them
(numpy .npz: ppm_core.Share.to_dict()); the merge writes the image of all of them as a 32-bit EXR
and prints its error estimate. Needs the add-on registered (scene.ppm) for a share, ppm_core only
for a merge.
"""

from __future__ import annotations

import os

import numpy as np


def save_share(path, share):
    data = share.to_dict()
    data["ranges"] = np.asarray(data["ranges"], dtype=np.uint64).reshape(-1, 2)
    if data["light_passes"] is None:
        del data["light_passes"]
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    partial = path + ".part.npz"  # renamed when complete: a merge never reads half a share
    np.savez(partial, **data)
    os.replace(partial, path)


def load_share(core_module, path):
    with np.load(path) as data:
        values = {key: data[key] for key in data.files}
    values["ranges"] = [(int(a), int(b)) for a, b in values["ranges"]]
    for key in ("width", "height", "seed", "photons_per_pass"):
        values[key] = int(values[key])
    values["alpha"] = float(values["alpha"])
    try:
        return core_module.Share.from_dict(values)
    except ValueError as error:
        raise ValueError(f"{path}: {error}") from error


def render_share_file(bpy, core_module, first_pass, passes, output, warn):
    """Renders the open scene's passes first_pass .. first_pass + passes - 1 into `output` (.npz)."""
    from .shares import render_share
    from .still_export import export_still

    still = export_still(bpy, core_module, warn)
    share, facts = render_share(still.calls, still.settings, first_pass, passes or still.passes)
    save_share(output, share)
    return share, facts


def merge_files(core_module, paths, output, bpy=None):
    """Merges the shares in `paths` into `output` (.exr); returns the merged Share. Written with
    OpenImageIO where this Python has it (error estimate in the header), else with Blender."""
    merged = core_module.merge_shares([load_share(core_module, p) for p in paths])
    try:
        from .exr import write_exr

        write_exr(output, merged, shares=len(paths))
    except ImportError:
        if bpy is None:
            raise
        write_exr_with_blender(bpy, output, merged)
    return merged


def write_exr_with_blender(bpy, path, share):
    """RGBA as a 32-bit float EXR through a Blender image (linear: EXR is saved as stored)."""
    image = bpy.data.images.new("ppm merged still", share.width, share.height, alpha=True, float_buffer=True)
    try:
        image.pixels.foreach_set(np.ascontiguousarray(share.image()[::-1]).ravel())
        settings = bpy.context.scene.render.image_settings
        settings.file_format, settings.color_depth, settings.color_mode = "OPEN_EXR", "32", "RGBA"
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        image.save_render(path, scene=bpy.context.scene)
    finally:
        bpy.data.images.remove(image)


def main(argv=None):
    """The Flamenco job type's entry (ppm_sharded_still.js), inside Blender with the add-on enabled:
        ... --python-expr "<import this module>; main()" -- share FIRST PASSES OUTPUT.npz
        ... --python-expr "<import this module>; main()" -- merge OUTPUT.exr SHARE.npz ...
    Exits non-zero with a readable message on failure (with --python-exit-code 1)."""
    import sys

    import bpy

    from .. import core

    if argv is None:
        argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    try:
        if len(argv) == 4 and argv[0] == "share":
            share, facts = render_share_file(bpy, core.load(), int(argv[1]), int(argv[2]), argv[3],
                                             lambda message: print(f"ppm share: warning: {message}", flush=True))
            print(f"ppm share: wrote {argv[3]}: passes {share.ranges} in {facts['render_seconds']:.1f} s", flush=True)
        elif len(argv) >= 3 and argv[0] == "merge":
            merged = merge_files(core.load(), argv[2:], os.path.abspath(argv[1]), bpy)
            error = merged.error_stats()
            print(f"ppm merge: wrote {argv[1]}: {merged.passes} passes, est. error {100 * error['relative']:.2f}%",
                  flush=True)
        else:
            raise ValueError("usage: -- share FIRST_PASS PASSES OUTPUT.npz | -- merge OUTPUT.exr SHARE.npz ...")
    except Exception as error:  # noqa: BLE001 - a readable message and a failing exit code
        print(f"ppm: error: {error}", file=sys.stderr, flush=True)
        sys.exit(1)
