"""PPM with *Cycles Light Paths* on against Cycles with the same Light Paths > Max Bounces, in the
running Blender: the limits a user sets to match a Cycles render truncate PPM's light the same way.

A closed bright room (albedo 0.8, where every further diffuse bounce still adds a lot) lit by a small
sphere light, seen from inside, with a glass ball or a mirror ball in some cases. Cases: a limit on
diffuse bounces, on the total, on transmission (the glass ball then shows only its reflections), on
glossy bounces (no mirror), on volume bounces (a white fog in the room: 0, Blender's default, leaves
single scattering; measured in Blender 5.0 at 48 passes: within 1.2%, where the fog's mean is 1.5
times as bright at 2), and a light's own Max Bounces with the scene's limits off. The same saved
file is rendered by both engines (Cycles 512 samples, PPM 48 passes, 192 for the mirror); the mean
radiance of 4x3 image blocks must agree within 3%.

    .venv/bin/python tests/blenders/light_paths_compare.py       # Blender 5.0 (bpy); likewise 4.2-5.2
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/light_paths_compare.py
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy

import cycles_compare
import media_compare

# Cycles' Light Paths per case: (total, diffuse, glossy, transmission, volume), and the light's own Max
# Bounces. The fog cases fill the room's middle with a white scattering fog: Volume bounces 0 (Blender's
# default) leaves single scattering, 2 lets the light scatter up to three times.
CASES = {
    "diffuse_1": ((12, 1, 4, 12, 0), 1024),
    "total_2": ((2, 12, 12, 12, 0), 1024),
    "glass_transmission_1": ((12, 2, 4, 1, 0), 1024),
    "mirror_glossy_0": ((12, 2, 0, 12, 0), 1024),
    "light_max_bounces_1": (None, 1),  # the scene's limits off in PPM, unlimited in Cycles
    "fog_volume_0": ((12, 4, 4, 12, 0), 1024),
    "fog_volume_2": ((12, 4, 4, 12, 2), 1024),
}
UNLIMITED = (64, 64, 64, 64, 64)
# The mirror ball with no glossy bounce shows only the lamp's reflection: a few very bright pixels
# whose 4x3 block is noise-bound at 48 passes (-4.8% to +4.8% over seeds 1-3, with or without
# adaptive eye samples); at 192 passes within 1%.
PASSES = {"mirror_glossy_0": 192}


def build(case):
    cycles_compare.reset()
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, 1.25))
    room = bpy.context.object
    room.scale = (4.0, 4.0, 2.5)
    room.data.materials.append(cycles_compare.diffuse_material("room", (0.8, 0.8, 0.8)))
    if case.startswith("glass"):
        cycles_compare.ball("glass", (0.3, 0.6, 0.45), 0.45, cycles_compare.glass_material("glass", 1.5))
    if case.startswith("mirror"):
        cycles_compare.ball("mirror", (0.3, 0.6, 0.45), 0.45, cycles_compare.glossy_material("mirror", (0.9, 0.9, 0.9)))
    if case.startswith("fog"):
        cycles_compare.cube("fog", (0.0, 0.6, 1.0), 1.6, media_compare.volume_material(
            "fog", "ShaderNodeVolumeScatter", Density=1.5, Color=(1.0, 1.0, 1.0, 1.0)))
    lamp = cycles_compare.add_light("AREA", 150.0, (-0.8, 0.4, 2.4), shape="DISK", size=0.6)
    lamp.data.cycles.max_bounces = CASES[case][1]
    cycles_compare.side_camera((0.0, -1.9, 1.2), 20.0)
    cycles_compare.set_exr_output(scene)


def compare(case, workdir, samples, passes):
    build(case)
    passes = PASSES.get(case, passes)
    limits = CASES[case][0]

    def set_limits(scene, engine):
        c = scene.cycles
        c.max_bounces, c.diffuse_bounces, c.glossy_bounces, c.transmission_bounces, c.volume_bounces = \
            limits or UNLIMITED
        if engine == "PPM":
            scene.ppm.cycles_light_paths = limits is not None

    return cycles_compare.block_comparison(case, workdir, samples, passes, configure=set_limits)


def compare_cases(cases=tuple(CASES), samples=512, passes=48):
    def one(case, workdir):
        return compare(case, workdir, samples, passes)
    return cycles_compare.run_cases("light_paths_compare", cases, one, cycles_compare.describe_blocks)


def main():
    cycles_compare.run_as_script("light_paths_compare", compare_cases, cycles_compare.beyond_tolerance)


if __name__ == "__main__":
    main()
