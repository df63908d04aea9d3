"""PPM against Cycles under image-based light (an Environment Texture in the world), in the running
Blender, with two of the HDRIs Blender ships (datafiles/studiolights/world): sunrise.exr, whose sun
carries more than half of the light in 0.1% of the texels, and courtyard.exr, a soft sky.

A diffuse floor and two balls, seen from the side with the sky behind them: the floor and a diffuse
ball check the light (direct and indirect), the sky and, under the soft sky, a mirror ball check
where each direction looks in the image. Under the sunrise both balls are diffuse: a mirror ball
there reflects the sun onto the floor, a caustic that Cycles renders as fireflies (at 1024 samples
single 8x8-pixel blocks were 33% off, either way), and the glint of the sun in it came out 40%
dimmer in PPM: it covers well under 1% of its pixel, which 64 passes of 4 eye samples meet a few
times or not at all (zoomed on it, PPM and Cycles agree within 1%: hdri_specular_zoom.py; the sun
seen directly or in a flat mirror agrees within 0.1%).
Cases: each HDRI as it is, the sunrise turned by a Mapping node, the courtyard read as a mirror
ball, the sunrise hidden from the camera (World > Ray Visibility), and two node networks the add-on
bakes into an image: a procedural sky (a ColorRamp of the direction's height) and the sunrise
tinted by a MixRGB at a strength a Value node gives, and the sunrise behind a plain backdrop that only
camera rays see (Light Path's Is Camera Ray: baked twice). The same saved file is
rendered by both engines (Cycles 1024 samples, PPM 64 passes: at 512 and 32 the noise alone moved
a block by up to 3.2% from one seed to the next); the mean radiance of 4x3 image blocks must agree
within 3%.

    .venv/bin/python tests/blenders/world_compare.py                  # Blender 5.0 (bpy); likewise 4.2-5.2
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/world_compare.py
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy

import cycles_compare

CASES = ("sunrise", "courtyard", "sunrise_turned", "courtyard_mirror_ball", "sunrise_hidden_from_camera",
         "procedural_sky", "sunrise_tinted", "sunrise_backdrop")


def hdri_path(name):
    return os.path.join(bpy.utils.system_resource("DATAFILES"), "studiolights", "world", name + ".exr")


def procedural_sky(nodes, links, background):
    """A sky from the direction's height: a ColorRamp from a warm horizon to a blue zenith."""
    coordinates, split = nodes.new("ShaderNodeTexCoord"), nodes.new("ShaderNodeSeparateXYZ")
    links.new(coordinates.outputs["Generated"], split.inputs[0])
    ramp = nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = (1.0, 0.7, 0.4, 1.0)
    ramp.color_ramp.elements[1].position, ramp.color_ramp.elements[1].color = 0.6, (0.15, 0.3, 0.9, 1.0)
    links.new(split.outputs["Z"], ramp.inputs["Fac"])
    links.new(ramp.outputs["Color"], background.inputs["Color"])
    background.inputs["Strength"].default_value = 1.5


def tinted(nodes, links, background, environment):
    """The environment times a colour (MixRGB multiply) at a strength a Value node gives."""
    tint = nodes.new("ShaderNodeMixRGB")
    tint.blend_type, tint.inputs["Fac"].default_value = "MULTIPLY", 1.0
    tint.inputs["Color2"].default_value = (0.9, 0.75, 1.0, 1.0)
    links.new(environment.outputs["Color"], tint.inputs["Color1"])
    links.new(tint.outputs["Color"], background.inputs["Color"])
    value = nodes.new("ShaderNodeValue")
    value.outputs[0].default_value = 0.8
    links.new(value.outputs[0], background.inputs["Strength"])


def backdrop(nodes, links, background, environment):
    """Camera rays see a plain grey-blue; everything else the environment (Is Camera Ray mixes them)."""
    mix, path = nodes.new("ShaderNodeMixRGB"), nodes.new("ShaderNodeLightPath")
    mix.inputs["Color2"].default_value = (0.2, 0.25, 0.35, 1.0)
    links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
    links.new(environment.outputs["Color"], mix.inputs["Color1"])
    links.new(mix.outputs["Color"], background.inputs["Color"])


def set_environment(case):
    world = bpy.data.worlds.new("World")
    if world.node_tree is None or bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = next(n for n in nodes if n.bl_idname == "ShaderNodeBackground")
    if case == "procedural_sky":
        procedural_sky(nodes, links, background)
        bpy.context.scene.world = world
        return
    environment = nodes.new("ShaderNodeTexEnvironment")
    environment.image = bpy.data.images.load(hdri_path(case.split("_")[0]))
    links.new(environment.outputs["Color"], background.inputs["Color"])
    if case.endswith("tinted"):
        tinted(nodes, links, background, environment)
    if case.endswith("backdrop"):
        backdrop(nodes, links, background, environment)
    if case.endswith("mirror_ball"):
        environment.projection = "MIRROR_BALL"
    if case.endswith(("turned", "mirror_ball")):
        # A mirror ball's image squeezes the directions around +Y into its rim: turned so that the
        # camera, looking along +Y, sees the sky from the well-sampled middle of the ball instead.
        turn = (15, -10, 120) if case.endswith("turned") else (0, 0, 180)
        coordinates, mapping = nodes.new("ShaderNodeTexCoord"), nodes.new("ShaderNodeMapping")
        mapping.inputs["Rotation"].default_value = tuple(math.radians(a) for a in turn)
        links.new(coordinates.outputs["Generated"], mapping.inputs["Vector"])
        links.new(mapping.outputs["Vector"], environment.inputs["Vector"])
    if case.endswith("hidden_from_camera"):
        world.cycles_visibility.camera = False
    bpy.context.scene.world = world


def build(case):
    cycles_compare.reset()
    scene = bpy.context.scene
    cycles_compare.plane("floor", 3.0, 0.0, cycles_compare.diffuse_material("floor", (cycles_compare.ALBEDO,) * 3))
    cycles_compare.ball("matte", (-0.6, 0.0, 0.5), 0.5, cycles_compare.diffuse_material("matte", (0.7, 0.7, 0.7)))
    right = (cycles_compare.diffuse_material("matte right", (0.3, 0.5, 0.7)) if case.startswith("sunrise")
             else cycles_compare.glossy_material("mirror", (0.9, 0.9, 0.9)))
    cycles_compare.ball("right", (0.6, 0.0, 0.5), 0.5, right)
    cycles_compare.side_camera((0.0, -4.0, 1.3), 30.0)
    set_environment(case)
    cycles_compare.set_exr_output(scene)


def compare(case, workdir, samples, passes):
    build(case)
    return cycles_compare.block_comparison(case, workdir, samples, passes)


def compare_cases(cases=CASES, samples=1024, passes=64):
    def one(case, workdir):
        return compare(case, workdir, samples, passes)
    return cycles_compare.run_cases("world_compare", cases, one, cycles_compare.describe_blocks)


def main():
    cycles_compare.run_as_script("world_compare", compare_cases, cycles_compare.beyond_tolerance)


if __name__ == "__main__":
    main()
