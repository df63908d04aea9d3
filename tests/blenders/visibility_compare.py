"""PPM against Cycles for ray visibility (Object > Visibility > Ray Visibility) and lights' shadows,
in the running Blender.

Each case starts from cycles_compare's floor under a point light, seen from above, and changes one
thing: a small sphere light in view (Blender lights hide from the camera by default), the same with
`visible_camera`, a mirror floor reflecting a sphere light (with and without `visible_glossy`), and
a diffuse square between light and floor hidden from the camera, from shadow rays, or under a light
that casts no shadow. The same saved file is rendered by both engines; the mean radiance of 4x3
image blocks must agree within 3% (absolute below 1e-4).

    .venv/bin/python tests/blenders/visibility_compare.py                 # Blender 5.0 (bpy); likewise 4.2-5.2
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/visibility_compare.py
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy

import cycles_compare


# Seen from the camera at (0.1, -0.2, 1.5) through its 30 mm lens (a pixel spans 0.01875 of the
# distance), a point at height z lies at the centre of image block (row 1, column 1), 8 pixels left of
# the image centre, at x = 0.1 - 8 * 0.01875 * (1.5 - z): for the mirror image of a light at z, at
# x = 0.1 - 8 * 0.01875 * (1.5 + z).
def block_centre_x(z):
    return 0.1 - 8 * 0.01875 * abs(1.5 - z)


Y = -0.2
CASES = ("light_in_view", "light_in_view_camera_visible", "mirror_sees_light", "mirror_light_not_glossy",
         "occluder_not_camera", "occluder_no_shadow", "light_casts_no_shadow")


def build(case):
    cycles_compare.build("point")  # floor, camera, point light at (0.3, 0.2, 2.2), black world
    if case.startswith("light_in_view"):
        light = cycles_compare.add_light("POINT", 5.0, (block_centre_x(0.7), Y, 0.7), shadow_soft_size=0.05)
        light.visible_camera = case.endswith("camera_visible")
    elif case.startswith("mirror"):
        bpy.data.objects.remove(bpy.data.objects["POINT"])
        bpy.data.objects["floor"].data.materials[0] = cycles_compare.glossy_material("mirror", (0.8, 0.8, 0.8))
        light = cycles_compare.add_light("POINT", 100.0, (block_centre_x(-2.2), Y, 2.2), shadow_soft_size=0.3)
        light.visible_glossy = case != "mirror_light_not_glossy"
    else:
        # A dim sky, so that the square's shadow is not lit by second bounces alone: there PPM is
        # about 10% low at 20k photons a pass (its gather radius averages the light under a small
        # occluder with the dimmer light around it; measured the same without any visibility flag).
        cycles_compare.set_world(0.1)
        square = cycles_compare.plane("square", 0.3, 1.0, cycles_compare.diffuse_material("square", (0.5,) * 3))
        square.location = (block_centre_x(1.0), Y, 0.0)
        square.visible_camera = case != "occluder_not_camera" and case != "light_casts_no_shadow"
        square.visible_shadow = case != "occluder_no_shadow"
        if case == "light_casts_no_shadow":
            light = bpy.data.lights["POINT"]
            if bpy.app.version < (4, 0, 0):
                light.cycles.cast_shadow = False
            else:
                light.use_shadow = False


def compare(case, workdir, samples, passes):
    build(case)
    return cycles_compare.block_comparison(case, workdir, samples, passes)


def compare_cases(cases=CASES, samples=256, passes=32):
    def one(case, workdir):
        return compare(case, workdir, samples, passes)
    return cycles_compare.run_cases("visibility_compare", cases, one, cycles_compare.describe_blocks)


def main():
    cycles_compare.run_as_script("visibility_compare", compare_cases, cycles_compare.beyond_tolerance)


if __name__ == "__main__":
    main()
