"""Runs inside one Blender and reports, as JSON, what a user of that version would get from the zip.

    .venvs/bpy-4.5/bin/python tests/blenders/in_blender.py --zip Z --report R.json [--no-core]
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/in_blender.py -- --zip Z --report R.json

Installs the add-on zip the way a user does (an extension in 4.2+, a legacy add-on in 3.4) into the
user folders the caller chose (BLENDER_USER_RESOURCES, or BLENDER_USER_SCRIPTS/CONFIG for 3.4), then
renders every bundled .blend through it at low resolution, runs the per-light-kind, per-lens,
ray-visibility, image-based-light, alpha, stereo, light-path-limit, media and material Cycles agreement
(cycles_compare.py, lens_compare.py, visibility_compare.py, world_compare.py, alpha_compare.py,
stereo_compare.py, light_paths_compare.py, media_compare.py, materials_compare.py; nodes_compare.py:
texture and utility nodes pixel by pixel) and
records every Python warning raised in the add-on's files (deprecations included). Cycles' image of a
case comes from tests/blenders/cycles_references when one is stored for exactly its scene, and is
rendered and stored otherwise (cycles_references.py; the report lists what was rendered). With --no-core
it only tries one render and records the error. The assertions are in test_blender_versions.py,
which runs this in each version.
"""

import argparse
import glob
import json
import os
import sys
import time
import warnings

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)

import bpy
import numpy as np

import alpha_compare
import cycles_compare
import cycles_references
import lens_compare
import light_paths_compare
import materials_compare
import media_compare
import nodes_compare
import stereo_compare
import visibility_compare
import world_compare

SCENES = sorted(glob.glob(os.path.join(ROOT, "blend_scenes", "*.blend")))
RESOLUTION_PERCENT = 12  # 640x480 -> 76x57

# With --subset (the Blenders between and after the two the tests check in full, 3.4 and 5.0): the
# cases that go through each version-dependent path (Principled's sockets, node groups, textures,
# baked worlds, light path limits) at a third of the time. Every node case runs in every version.
SUBSET_WORLDS = ("sunrise_backdrop", "procedural_sky")
SUBSET_LIGHT_PATHS = ("diffuse_1", "light_max_bounces_1", "fog_volume_0")
SUBSET_MEDIA = ("fog_cube_spot", "ink_in_glass", "noise_cloud", "vdb_smoke")
SUBSET_MATERIALS = ["glass_clear", "mix_diffuse_glossy", "node_group", "principled_default", "principled_middle",
                    "principled_gold", "principled_glass", "principled_coat", "principled_alpha",
                    "metallic_physical_gold", "glossy_anisotropic", "normal_mapped", "proc_wood", "proc_cells"]


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
    parser.add_argument("--subset", action="store_true",
                        help="the slow comparisons (worlds, light paths, materials) for a few cases only")
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
        seconds = report["seconds"] = {}  # per part, to see where the tests' time goes

        def timed(part, run):
            start = time.monotonic()
            report[part] = run()
            seconds[part] = round(time.monotonic() - start, 1)

        cycles_references.RECORD = True
        timed("scenes", lambda: {os.path.basename(b): render_scene(b, args.workdir) for b in SCENES})
        report["core_file"] = sys.modules["ppm_core"].__file__  # loaded by the first render
        timed("cycles", lambda: cycles_compare.compare_kinds(cycles_compare.kinds_for_this_blender(), args.samples,
                                                             passes=24))
        timed("lenses", lambda: lens_compare.compare_cases(args.samples, passes=24))
        timed("visibility", visibility_compare.compare_cases)  # its own 256 samples, 32 passes
        timed("worlds", lambda: world_compare.compare_cases(SUBSET_WORLDS if args.subset else world_compare.CASES))
        timed("alpha", alpha_compare.compare_cases)
        timed("stereo", stereo_compare.compare)
        timed("light_paths", lambda: light_paths_compare.compare_cases(
            SUBSET_LIGHT_PATHS if args.subset else tuple(light_paths_compare.CASES)))
        timed("media", lambda: media_compare.compare_cases(SUBSET_MEDIA if args.subset else media_compare.CASES))
        report["fluid_simulates"] = media_compare.FLUID_SIMULATES  # (its smoke and fire cases then ran)
        names = SUBSET_MATERIALS if args.subset else list(materials_compare.material_library.MATERIALS)
        timed("materials", lambda: materials_compare.compare_cases(names, samples=256, passes=32))
        timed("nodes", lambda: nodes_compare.compare_cases(package=module))
        print("in_blender: seconds per part:", seconds, flush=True)
        report["cycles_references"] = {"found": len(cycles_references.found), "rendered": cycles_references.rendered}
    report["addon_warnings"] = found_warnings
    with open(args.report, "w") as f:
        json.dump(report, f, indent=1)


if __name__ == "__main__":
    main()
