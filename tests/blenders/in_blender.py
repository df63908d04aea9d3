"""Runs inside one Blender and reports, as JSON, what a user of that version would get from the zip.

    .venvs/bpy-4.5/bin/python tests/blenders/in_blender.py --zip Z --report R.json [--no-core]
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/in_blender.py -- --zip Z --report R.json

Installs the add-on zip the way a user does (an extension in 4.2+, a legacy add-on in 3.4) into the
user folders the caller chose (BLENDER_USER_RESOURCES, or BLENDER_USER_SCRIPTS/CONFIG for 3.4), then
renders every bundled .blend through it at low resolution, runs the per-light-kind, per-lens,
ray-visibility, image-based-light, alpha, stereo, light-path-limit and material Cycles agreement
(cycles_compare.py, lens_compare.py, visibility_compare.py, world_compare.py, alpha_compare.py,
stereo_compare.py, light_paths_compare.py, materials_compare.py; nodes_compare.py: texture and
utility nodes pixel by pixel) and
records every Python warning raised in the add-on's files (deprecations included). With --no-core
it only tries one render and records the error. The assertions are in test_blender_versions.py,
which runs this in each version.
"""

import argparse
import glob
import json
import os
import sys
import warnings

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)

import bpy
import numpy as np

import alpha_compare
import cycles_compare
import lens_compare
import light_paths_compare
import materials_compare
import nodes_compare
import stereo_compare
import visibility_compare
import world_compare

SCENES = sorted(glob.glob(os.path.join(ROOT, "blend_scenes", "*.blend")))
RESOLUTION_PERCENT = 12  # 640x480 -> 76x57


def record_addon_warnings(found):
    """Shows every warning (Python hides DeprecationWarning outside __main__) and keeps those raised
    in the add-on's own files."""
    warnings.simplefilter("always")
    show = warnings.showwarning

    def keep(message, category, filename, lineno, file=None, line=None):
        if "ppm_render" in filename:
            found.append(f"{filename}:{lineno}: {category.__name__}: {message}")
        show(message, category, filename, lineno, file, line)

    warnings.showwarning = keep


def install(zip_path):
    """The add-on's module name after installing and enabling the zip as a user of this version would."""
    if bpy.app.version >= (4, 2, 0):
        bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default", enable_on_install=True)
        module = "bl_ext.user_default.ppm_render"
    else:
        bpy.ops.preferences.addon_install(filepath=zip_path)
        bpy.ops.preferences.addon_enable(module="ppm_render")
        module = "ppm_render"
    if module not in bpy.context.preferences.addons.keys():
        raise RuntimeError(f"{module} is not enabled after installing {zip_path}")
    return module


def render_scene(blend, workdir):
    """Renders one bundled scene with PPM at low resolution; returns the figures the test checks."""
    bpy.ops.wm.open_mainfile(filepath=blend)
    scene = bpy.context.scene
    scene.render.resolution_percentage = RESOLUTION_PERCENT
    scene.ppm.passes, scene.ppm.photons_per_pass, scene.ppm.samples_per_pixel = 3, 30_000, 1
    image = scene.render.image_settings
    image.file_format, image.color_depth = "OPEN_EXR", "32"
    scene.render.use_file_extension = False
    scene.render.filepath = os.path.join(workdir, os.path.basename(blend) + ".exr")
    bpy.ops.render.render(write_still=True)
    rgb = cycles_compare.read_image(scene.render.filepath)[..., :3]
    finite = bool(np.isfinite(rgb).all())
    rgb = np.nan_to_num(rgb)
    return {"engine": scene.render.engine, "shape": list(rgb.shape[:2]), "finite": finite, "min": float(rgb.min()),
            "mean": float(rgb.mean()), "std": float(rgb.std()), "lit": float((rgb.mean(axis=2) > 1e-3).mean())}


def try_one_render(workdir):
    """The error a render raises, or None if it renders."""
    try:
        render_scene(SCENES[0], workdir)
    except RuntimeError as error:
        return str(error)
    return None


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser()
    parser.add_argument("--zip", required=True)
    parser.add_argument("--report", required=True)
    parser.add_argument("--workdir", required=True)
    parser.add_argument("--no-core", action="store_true", help="the zip has no core for this Python")
    parser.add_argument("--samples", type=int, default=128, help="Cycles samples of the agreement check")
    args = parser.parse_args(argv)
    found_warnings = []
    record_addon_warnings(found_warnings)
    module = install(args.zip)
    addon = sys.modules[module]
    report = {"blender": bpy.app.version_string, "python": "%d.%d" % sys.version_info[:2],
              "addon_file": addon.__file__}
    if args.no_core:
        report["render_error"] = try_one_render(args.workdir)
        report["panel_message"] = sys.modules[module + ".core"].problem()
    else:
        report["scenes"] = {os.path.basename(b): render_scene(b, args.workdir) for b in SCENES}
        report["core_file"] = sys.modules["ppm_core"].__file__
        report["cycles"] = cycles_compare.compare_kinds(cycles_compare.kinds_for_this_blender(), args.samples,
                                                        passes=24)
        report["lenses"] = lens_compare.compare_cases(args.samples, passes=24)
        report["visibility"] = visibility_compare.compare_cases()  # seconds: its own 256 samples, 32 passes
        report["worlds"] = world_compare.compare_cases()
        report["alpha"] = alpha_compare.compare_cases()
        report["stereo"] = stereo_compare.compare()
        report["light_paths"] = light_paths_compare.compare_cases()
        # The procedural materials in 3.4 and 5.0 only: their nodes are checked pixel by pixel in every
        # version (nodes_compare), and five versions of 23 renders each would add minutes to the tests.
        names = [name for name in materials_compare.material_library.MATERIALS
                 if not name.startswith("proc_") or bpy.app.version[:2] in ((3, 4), (5, 0))]
        report["materials"] = materials_compare.compare_cases(names, samples=256, passes=32)
        report["nodes"] = nodes_compare.compare_cases(package=module)
    report["addon_warnings"] = found_warnings
    with open(args.report, "w") as f:
        json.dump(report, f, indent=1)


if __name__ == "__main__":
    main()
