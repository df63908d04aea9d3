"""Renders a .blend file with the PPM engine, from a shell.

    blender -b --python-exit-code 1 -P render.py -- scene.blend --output out.exr [--passes N]
            [--time-limit S] [--target-error E] [--resolution W H] [--photons N] [--seed N]
    python render.py scene.blend --output out.exr [...]        # with the bpy module (pip install bpy)

`blender -b scene.blend -P render.py -- --output out.exr` works too, but Blender then reads the file
before this script registers the engine and reports "Engine 'PPM' not available" first (harmless):
given after `--`, the file is read once the engine is registered.

A still in shares, rendered anywhere and merged (addon/ppm_render/farm/blender_task.py):
    blender -b scene.blend --python-exit-code 1 -P render.py -- --first-pass 0 --passes 16 --share-output s0.npz
    blender -b --python-exit-code 1 -P render.py -- --merge s0.npz s1.npz --output out.exr

Registers the add-on from this checkout unless an installed PPM add-on is
already active, renders the scene camera with write_still, prints progress
and exits non-zero with a readable message on failure. The output format
follows the extension: .exr (32-bit float, linear) or .png (8-bit, view transform).
"""

import argparse
import glob
import importlib
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def make_core_importable():
    """Blender 3.4 from Debian has no numpy and no ppm_core: borrow this checkout's .venv (same Python 3.11)."""
    for site in glob.glob(os.path.join(HERE, ".venv", "lib", "python%d.%d" % sys.version_info[:2], "site-packages")):
        if site not in sys.path:
            sys.path.append(site)  # appended: Blender's own modules keep priority


def parse_arguments(argv, need_blend):
    parser = argparse.ArgumentParser(prog="render.py", description="Render a .blend file with the PPM engine.")
    parser.add_argument("blend", nargs="?", help=".blend file to render (inside Blender: the file Blender "
                                                 "opened, if not given)")
    parser.add_argument("--output", help="output image (.exr or .png)")
    parser.add_argument("--passes", type=int, help="photon passes (default: the scene's setting)")
    parser.add_argument("--time-limit", type=float, help="seconds (default: the scene's setting)")
    parser.add_argument("--resolution", type=int, nargs=2, metavar=("W", "H"), help="image size in pixels")
    parser.add_argument("--photons", type=int, help="photons per pass")
    parser.add_argument("--seed", type=int, help="random seed")
    parser.add_argument("--samples", type=int, help="eye samples per pixel")
    parser.add_argument("--target-error", type=float,
                        help="stop once the estimated mean error is at most this share of the image's mean "
                             "brightness (e.g. 0.02), or at the passes or time limit")
    parser.add_argument("--first-pass", type=int, default=0,
                        help="with --share-output: the first of the still's passes this share renders")
    parser.add_argument("--share-output", help="render a share of the still's passes into this .npz file")
    parser.add_argument("--merge", nargs="+", metavar="SHARE", help="merge these .npz shares into --output (.exr)")
    args = parser.parse_args(argv)
    if not args.share_output and not args.output:
        parser.error("give --output (or --share-output)")
    if args.merge and (args.share_output or not args.output.lower().endswith(".exr")):
        parser.error("--merge writes an --output .exr")
    if need_blend and not args.merge and not args.blend:
        parser.error("give the .blend file to render")
    if args.merge and args.blend:
        parser.error("--merge takes no .blend file")
    return args


def ensure_addon(bpy):
    """The checkout's add-on, registered here, or None when an installed PPM add-on is active."""
    if hasattr(bpy.types.Scene, "ppm"):
        return None
    sys.path.insert(0, os.path.join(HERE, "addon"))
    import ppm_render

    ppm_render.register()
    return ppm_render


def configure_settings(scene, args):
    """The scene's PPM settings and size, with the command line's."""
    scene.render.engine = "PPM"
    settings = scene.ppm
    for name, value in (("passes", args.passes), ("time_limit", args.time_limit),
                        ("photons_per_pass", args.photons), ("seed", args.seed), ("samples_per_pixel", args.samples),
                        ("target_error", args.target_error)):
        if value is not None:
            setattr(settings, name, value)
    if args.resolution:
        scene.render.resolution_x, scene.render.resolution_y = args.resolution
        scene.render.resolution_percentage = 100


def configure(bpy, scene, args):
    configure_settings(scene, args)
    output = os.path.abspath(args.output)
    os.makedirs(os.path.dirname(output), exist_ok=True)
    image = scene.render.image_settings
    if output.lower().endswith(".exr"):
        image.file_format, image.color_depth, image.color_mode = "OPEN_EXR", "32", "RGBA"
    elif output.lower().endswith(".png"):
        image.file_format, image.color_mode = "PNG", "RGBA"
    else:
        raise ValueError(f"output '{args.output}': use a .exr or .png file name")
    scene.render.filepath = output
    scene.render.use_file_extension = False
    return output


def render(argv, in_blender):
    import bpy

    args = parse_arguments(argv, need_blend=not in_blender)
    if args.merge:
        return merge(bpy, args)
    if args.blend is None and not bpy.data.filepath:
        raise ValueError("no .blend file was loaded (missing or unreadable file?): "
                         "blender -b --python-exit-code 1 -P render.py -- scene.blend --output out.exr")
    if args.blend is not None and not os.path.isfile(args.blend):
        raise ValueError(f"'{args.blend}' does not exist")
    make_core_importable()
    # Registered before the file is read, so that Blender finds the scene's engine (reading it first
    # reports "Engine 'PPM' not available", an ERROR a user takes for a failure).
    addon = ensure_addon(bpy)
    if args.blend is not None:
        bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.blend))
    try:
        scene = bpy.context.scene
        if args.share_output:
            return render_share(bpy, scene, args)
        output = configure(bpy, scene, args)
        print(f"render.py: {bpy.data.filepath} -> {output} (Blender {bpy.app.version_string})", flush=True)
        bpy.ops.render.render(write_still=True)  # the engine's report({'ERROR'}) raises RuntimeError here
    finally:
        if addon is not None:  # bpy 4.2 crashes and 4.5 hangs at exit while a script's classes are registered
            addon.unregister()
    if not os.path.isfile(output):
        raise RuntimeError(f"Blender wrote no image to {output}")
    print(f"render.py: wrote {output}", flush=True)


def active_addon():
    """The PPM add-on's package that is registered: an installed one (bl_ext.*.ppm_render in Blender
    4.2+, ppm_render before) or this checkout's."""
    name = next((n for n in sys.modules if n.split(".")[-1] == "ppm_render"), "ppm_render")
    return importlib.import_module(name)


def render_share(bpy, scene, args):
    """Passes --first-pass .. of the still into --share-output (a share: farm/blender_task.py)."""
    package = active_addon()
    blender_task = importlib.import_module(package.__name__ + ".farm.blender_task")
    configure_settings(scene, args)
    share, facts = blender_task.render_share_file(bpy, package.core.load(), args.first_pass, args.passes,
                                                  args.share_output,
                                                  lambda message: print(f"render.py: warning: {message}", flush=True))
    print(f"render.py: wrote {args.share_output}: passes {share.ranges} in {facts['render_seconds']:.1f} s",
          flush=True)


def merge(bpy, args):
    make_core_importable()
    sys.path.insert(0, os.path.join(HERE, "addon"))
    from ppm_render import core
    from ppm_render.farm.blender_task import merge_files

    merged = merge_files(core.load(), args.merge, os.path.abspath(args.output), bpy)
    error = merged.error_stats()
    print(f"render.py: wrote {args.output}: {merged.passes} passes from {len(args.merge)} shares, est. error "
          f"{100 * error['relative']:.2f}% (bound {100 * error['bound']:.2f}% at 95%)", flush=True)


def main():
    # Inside Blender, sys.argv is Blender's command line; as a script it starts with render.py.
    in_blender = os.path.basename(sys.argv[0]) != os.path.basename(__file__)
    if in_blender:
        argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    else:
        argv = sys.argv[1:]
    try:
        render(argv, in_blender)
    except SystemExit:
        raise
    except Exception as error:  # noqa: BLE001 - a readable message and a failing exit code
        print(f"render.py: error: {error}", file=sys.stderr, flush=True)
        sys.exit(1)


if __name__ == "__main__":
    main()
