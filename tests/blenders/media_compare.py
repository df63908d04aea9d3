"""PPM against Cycles through participating media, in the running Blender.

A floor (albedo 0.5) and a diffuse ball seen from the side, in media the add-on reads from Blender
(export/volume.py) and the core renders with volume photons:
- world_fog: the World's Volume Scatter (density 0.08, anisotropy 0.3) around
  everything, under a point light of radius 0.1 m;
- fog_room: the same fog in a 12 m cube (no Surface) around the camera, the light and the floor:
  where users put fog, and where the camera and the light start their paths inside a mesh medium;
- smoke_in_fog_room: the smoke ball (below) inside the fog room: Cycles adds the fog to the smoke;
- fog_cube_spot: a 2 m cube of Volume Scatter (density 0.4, no Surface) under a spot light of radius
  0.1 m, the ball outside it: the beam and its shadow in the fog;
- ink_in_glass: a glass cube (IOR 1.33) holding red Volume Absorption, on the floor under an area light;
- smoke_ball: a Principled Volume ball (density 3, a colour, an absorption colour) under a point light;
- glowing_cloud: a Principled Volume cube with Emission Strength and a blackbody, in the dark: the
  only light, its photons light the floor and the ball and scatter in the cloud;
- noise_cloud: a cube of Principled Volume whose Density is a Noise through a ColorRamp (a cloud that
  varies in space), under a point light;
- noise_fire: a cube of Principled Volume whose Emission Strength is a Noise through a ColorRamp, in
  the dark: a glow that varies in space, the only light;
- mixed_fog: a cube whose Volume mixes scatter into absorption by a node group's Gradient, the
  absorption's Color a Checker, under a spot light;
- smoke_sim, fire_sim (FLUID: where Blender runs fluid simulations): Quick Smoke's domain as users
  make one (smoke; fire and smoke) over a small emitter, simulated at resolution 32 to frame 24: the
  domain's density, flame and temperature grids, the fire lighting the floor. The smoke's Density
  comes through an Attribute node (density, times 5), the fire's through the Principled Volume's
  own Density and Temperature Attributes;
- vdb_smoke: a Volume object loading an OpenVDB file (tests/data/smoke_zip.vdb, a smoke and fire
  cache Blender 3.4 wrote), its Principled Volume's Density and Temperature Attributes reading its
  density and temperature grids (a glow), under a point light;
- glass_ball_in_fog (GAPS): a spot light through a glass ball in a fog box.
Lights are given a size so that Cycles converges (a small light's volumetric caustic leaves Cycles
fireflies). Cycles renders with volume bounces as PPM's (unlimited there: 12 here, every kind),
unclamped. The same saved file is rendered by both engines; the mean radiance of 4x3 image blocks
must agree within TOLERANCE (CASE_TOLERANCE: where and why a case is looser).

PPM renders with the add-on's defaults, Volume Beams on since 2026-12-07 (split camera paths, half
of their scatterings drawn towards a light, and photon beams in homogeneous fog); the figures in the
comments below were measured before, with volume photons as points, unless they say otherwise. With
it on, seed 1, worst block, Blender 5.0 / 3.4: fog_cube_spot 0.98/1.02%, ink_in_glass 1.15/1.45%,
smoke_ball 0.76/3.60%, glowing_cloud 3.74/2.00%, world_fog 1.79/4.01%, fog_room 1.14/0.85%,
smoke_in_fog_room 1.37% (5.0), ink_box_in_world_fog 1.55/1.53%, noise_cloud 1.05/1.15%, mixed_fog
0.63/0.84%, noise_fire 3.54/2.30%, vdb_smoke 0.34/0.44%, smoke_sim 1.27%, fire_sim 4.05% (3.4).
Seeds 1-3 (PPM_SEED), Blender 5.0: smoke_ball 0.76, 1.11, 1.44% (without Volume Beams 0.97, 8.99,
2.33%), fog_room 1.14, 0.76, 0.67% (1.67, 0.81, 3.69%), world_fog 1.79, 0.79, 1.09%; in 3.4 the
world fog reads 4.01, 3.36, 4.27% from the same PPM images: its Cycles image (256 samples) differs
from 5.0's there.

Nothing stands on the floor: a cube of glass or of a medium whose bottom face lies in the floor's
plane is ill-defined (which of two coplanar faces a ray meets first), and the two engines resolve it
differently. Measured with the cubes standing on the floor, 256 passes against 4096 samples: the
block holding a clear glass cube 34% brighter than Cycles, an absorbing cube's lit floor 0.2-0.36 of
Cycles'; lifted by 2 cm, the same blocks agree within 0.7%.

    .venv/bin/python tests/blenders/media_compare.py                  # Blender 5.0 (bpy); likewise 4.2-5.2
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/media_compare.py
"""

import hashlib
import math
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy
import numpy as np

import cycles_compare

CASES = ("fog_cube_spot", "ink_in_glass", "smoke_ball", "glowing_cloud", "world_fog", "fog_room",
         "smoke_in_fog_room", "ink_box_in_world_fog", "noise_cloud", "mixed_fog",
         "noise_fire", "smoke_sim", "fire_sim", "vdb_smoke")
# Simulated smoke and fire, in Blenders that run Mantaflow: the blender binary does, Blender as a Python
# module (the bpy wheels 4.2 to 5.2) does not (its Mantaflow scripts fail, and the process aborts at
# exit once a fluid domain exists, measured in 4.2, 4.5, 5.0 and 5.2).
FLUID = ("smoke_sim", "fire_sim")
FLUID_SIMULATES = bool(bpy.app.binary_path)
FLUID_FRAME = 24
VDB_FILE = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "data", "smoke_zip.vdb")
# Run by name only. A glass ball focusing a spot into fog: Cycles' reference stays noisy at the samples
# a test can afford.
GAPS = ("glass_ball_in_fog",)
LIFT = 0.02  # media and glass stand this far above the floor: see the module's comment
BOUNCES = 12
TOLERANCE = 0.03
# A dense ball's volume photons near its lit surface: gather spheres reach out of the medium, where
# no photon is; each hit point's photons are divided by its sphere's share inside (the core's
# volume_boundary). Blender 5.0, 1024 samples against 256 passes: every block within 0.41% (13.69%
# without it, the lit edge's dim top block; the lit top 6-9% dark). At 64 passes that dim block
# (0.0007) is noise-bound (15.8%), so the ball renders 256.
# The glowing cloud's darkest lit block (the floor left of the ball, 0.0008) is Cycles' noise at 1024
# samples: it reads 0.00075 there and 0.00079 at 8192. Blender 5.0, 8192 samples against 1024 passes:
# every block within 2.7% (the floor in front of the cloud 2.8% dark, the cloud 0.9-1.1%); 1024
# samples against 256 passes: within 4.6%.
# The world fog, the camera inside it: when a pixel's volume hit points shared its first one's radius
# (tiny where that lay near the lens), Blender 5.0, 1024 samples against 64 passes: 9.9%; 256
# passes: 5.14% for seed 1, and two seeds' blocks up to 9.3% apart. Each with its own radius, no
# smaller than the volume photons' spacing: 0.97% at 256 passes (three seeds' blocks within 5.1%,
# the light's own block; the rest within 1.3%), 3.31% at 64; against 256 samples 3.23% at 64 passes.
# The fog cube and the smoke ball at this test's samples: Blender 5.0 3.59% and 0.41%, 3.4 2.72% and
# 4.03% (its dim top block, 0.0007, where 1024 Cycles samples are noise-bound); against 4096 samples,
# the mean of seeds 1 and 2: 1.7% and 0.9% (media_radius_sweep.py).
# The simulated fire's dim bottom-right block (0.023 against the image's 0.17) is noise-bound at its
# 512 passes: seeds 1-6 (Blender 3.4, PPM_SEED=N in the environment: cycles_compare.configure_ppm) 4.05,
# 4.38, 2.37, 0.86, 1.31, 1.92%, and 2.45, 3.28, 1.68, 1.86, 1.45, 0.86% before photons left the
# glow's floor of collisions (Scene::track); the image's mean within 0.35% of Cycles' for every seed.
CASE_TOLERANCE = {"glowing_cloud": 0.05, "world_fog": 0.05, "fog_room": 0.05, "fog_cube_spot": 0.05,
                  "smoke_ball": 0.05, "smoke_in_fog_room": 0.05, "ink_box_in_world_fog": 0.05, "noise_cloud": 0.04,
                  "noise_fire": 0.06, "smoke_sim": 0.04, "fire_sim": 0.05}
# An absorbing box in World fog: the World's fog goes on inside the box, as Cycles adds the World's
# volume to every mesh's (its volume stack starts with it). Against 256 samples at 256 passes: 2.8% in
# Blender 5.0 and 3.4; with the box's medium alone inside it, 11.0% (the fog's glow in the box missing).
# Passes where 64 leave a block noise-bound: the glowing cloud's floor, lit by the cloud's photons
# alone (5.3% at 64); the smoke ball's dim top (15.8% at 64).
# The fog the camera is in, its block holding the point light (the glow about it, each pass one light
# sample a hit point): fog_room at 64 passes 4.2% (3.4, against 1024 samples), 128 passes 1.2-1.9%,
# 256 passes 1.5%.
# The Noise cloud, Blender 5.0 against 1024 samples: worst block 2.99% at 64 passes, 2.66% at 128, 2.44%
# at 256 (2.91% at 128 once ratio tracking took the bound as its majorant; 3.4: 2.72%); against 4096
# samples (two seeds within 0.46%), 512 passes: the cloud's blocks 1.1-1.9% dark (gather spheres
# averaged sigma_s over a ball), 0.93% once each divides by the ball's mean density. The mixed fog:
# 2.47%, 1.65%, 1.40% at 64, 128, 256 passes for one seed; Blender 5.0, seeds 1-3 at 128 passes 3.7%,
# 1.8%, 3.7% (its dim blocks, 0.03, noise-bound), at 512 passes 2.3%, 1.5%, 1.5%: it renders 512.
# Simulated smoke and fire (Blender 3.4, against 1024 samples; 4096 differ from them by at most 0.5% in
# a block): the smoke's worst block 7.4% at 256 passes, 4.4% at 512, 1.8% at 1024 (its thin top over
# the black sky; the gather's mean-density share halved these: before it, 15% at 256 and 3.8% at 1024
# in another framing); the fire 0.97% at 512 (4.6% at 256 in another framing). With the final core
# (another random sequence: a number drawn per tentative collision) 2.10% and 1.93%.
# The .vdb smoke and fire (256 passes against 1024 samples): 3.4, 4.2, 4.5 0.06%, 5.0 0.44%, 5.2
# 0.61%. Cycles 5.0 reads a
# volume's attributes one voxel at a time, picked by the trilinear weights, so its blackbody's T^4
# averages voxels' and glows brighter than T^4 of the interpolated T: the glow alone read 9% dark
# until the add-on asked the core's grids to do the same from 5.0 on (3.4, 4.2, 4.5 interpolate). A
# Volume object's density follows its scale in Cycles (here 0.3: 3.3 times the density and glow).
CASE_PASSES = {"glowing_cloud": 256, "smoke_ball": 256, "world_fog": 128, "fog_room": 128, "smoke_in_fog_room": 256,
               "ink_box_in_world_fog": 256, "noise_cloud": 128, "mixed_fog": 512, "noise_fire": 256,
               "smoke_sim": 1024, "fire_sim": 512, "vdb_smoke": 256}
# Cycles samples where fewer keep the blocks: the world fog (Cycles' three seeds at 1024 agreed within
# 0.4%; 1024 samples take 27 s of the case's 32 s, 256 take 7).
CASE_SAMPLES = {"world_fog": 256, "fog_room": 256, "smoke_in_fog_room": 256, "ink_box_in_world_fog": 256}
# Cycles samples where 1024 leave a block noise-bound, whatever the test asks (Cycles' image is stored,
# tests/blenders/cycles_references/, so only its first run pays): the Noise fire's dim floor (0.0018)
# at 1024 samples read 5.5% from PPM at 256 passes; two seeds of 4096 samples differ by up to 2% there,
# and PPM at 512 passes is within 2.5% of their mean in every block.
# Against 4096 samples, Blender 5.0: worst block 4.2% at 128 passes, 4.95% at 256 (that dim block, noise
# on both sides); the rest within 1.5%.
REFERENCE_SAMPLES = {"noise_fire": 4096}


def volume_material(name, node_type, surface=None, **inputs):
    """A material whose Volume is one node of `node_type` (inputs by name); its Surface `surface`
    (a node type and its inputs), or nothing."""
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    node = nodes.new(node_type)
    for socket, value in inputs.items():
        node.inputs[socket].default_value = value
    links.new(node.outputs[0], out.inputs["Volume"])
    if surface is not None:
        kind, values = surface
        shader = nodes.new(kind)
        for socket, value in values.items():
            shader.inputs[socket].default_value = value
        links.new(shader.outputs[0], out.inputs["Surface"])
    return mat


def fog_volume_scatter():
    return volume_material("fog", "ShaderNodeVolumeScatter", Density=0.08, Anisotropy=0.3)


def smoke_material():
    return volume_material("smoke", "ShaderNodeVolumePrincipled", Density=3.0, Color=(0.8, 0.6, 0.3, 1.0),
                           **{"Absorption Color": (0.2, 0.3, 0.6, 1.0)})


def noise_through_ramp(mat, socket, scale, low, high, times):
    """Drives the Principled Volume's input `socket` of `mat` as users drive one with a Noise: a Noise
    texture (its default coordinates, Generated; scale `scale`, detail 2) through a ColorRamp (0 below
    `low`, 1 above `high`) times `times`."""
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    noise = nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = scale
    noise.inputs["Detail"].default_value = 2.0
    ramp = nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].position, ramp.color_ramp.elements[1].position = low, high
    product = nodes.new("ShaderNodeMath")
    product.operation = "MULTIPLY"
    product.inputs[1].default_value = times
    links.new(noise.outputs["Fac"], ramp.inputs["Fac"])
    links.new(ramp.outputs["Color"], product.inputs[0])
    volume = next(n for n in nodes if n.bl_idname == "ShaderNodeVolumePrincipled")
    links.new(product.outputs["Value"], volume.inputs[socket])
    return mat


def noise_cloud_material():
    """A cloud as users build one: Principled Volume whose Density is a Noise (scale 3) through a
    ColorRamp (clear below 0.45, dense above 0.6) times 4."""
    mat = volume_material("cloud", "ShaderNodeVolumePrincipled", Color=(0.9, 0.85, 0.8, 1.0))
    return noise_through_ramp(mat, "Density", 3.0, 0.45, 0.6, 4.0)


def mixed_fog_material():
    """Fog as users mix it: a Mix Shader whose factor comes out of a node group (a Gradient texture of
    the Generated coordinates through a Map Range) blends Volume Scatter (density 0.8) into Volume
    Absorption whose Color a Checker texture drives (density 1.5)."""
    mat = bpy.data.materials.new("mixed fog")
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    group = bpy.data.node_groups.new("fog mask", "ShaderNodeTree")
    if bpy.app.version >= (4, 0, 0):
        group.interface.new_socket("Mask", in_out="OUTPUT", socket_type="NodeSocketFloat")
    else:
        group.outputs.new("NodeSocketFloat", "Mask")
    gradient = group.nodes.new("ShaderNodeTexGradient")
    remap = group.nodes.new("ShaderNodeMapRange")
    remap.inputs["From Min"].default_value, remap.inputs["From Max"].default_value = 0.2, 0.8
    group_out = group.nodes.new("NodeGroupOutput")
    group.links.new(gradient.outputs["Fac"], remap.inputs["Value"])
    group.links.new(remap.outputs["Result"], group_out.inputs[0])
    mask = nodes.new("ShaderNodeGroup")
    mask.node_tree = group
    scatter = nodes.new("ShaderNodeVolumeScatter")
    scatter.inputs["Density"].default_value = 0.8
    scatter.inputs["Anisotropy"].default_value = 0.2
    absorb = nodes.new("ShaderNodeVolumeAbsorption")
    absorb.inputs["Density"].default_value = 1.5
    checker = nodes.new("ShaderNodeTexChecker")
    checker.inputs["Scale"].default_value = 3.0
    checker.inputs["Color1"].default_value = (0.9, 0.3, 0.2, 1.0)
    checker.inputs["Color2"].default_value = (0.2, 0.5, 0.9, 1.0)
    mix = nodes.new("ShaderNodeMixShader")
    links.new(checker.outputs["Color"], absorb.inputs["Color"])
    links.new(absorb.outputs[0], mix.inputs[1])
    links.new(scatter.outputs[0], mix.inputs[2])
    links.new(mask.outputs[0], mix.inputs["Fac"])
    links.new(mix.outputs[0], out.inputs["Volume"])
    return mat


def noise_fire_material():
    """A glow as users make one: Principled Volume (density 0.5) whose Emission Strength is a Noise
    (scale 2.5) through a ColorRamp (dark below 0.4, 4 above 0.65), an orange Emission Color."""
    mat = volume_material("fire", "ShaderNodeVolumePrincipled", Density=0.5,
                          **{"Emission Color": (1.0, 0.45, 0.15, 1.0)})
    return noise_through_ramp(mat, "Emission Strength", 2.5, 0.4, 0.65, 4.0)


def world_fog():
    world = bpy.data.worlds.new("World")
    if world.node_tree is None or bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    nodes = world.node_tree.nodes
    next(n for n in nodes if n.bl_idname == "ShaderNodeBackground").inputs["Strength"].default_value = 0.0
    fog = nodes.new("ShaderNodeVolumeScatter")
    fog.inputs["Density"].default_value = 0.08
    fog.inputs["Anisotropy"].default_value = 0.3
    output = next(n for n in nodes if n.bl_idname == "ShaderNodeOutputWorld")
    world.node_tree.links.new(fog.outputs[0], output.inputs["Volume"])
    bpy.context.scene.world = world


def simulated_smoke(style):
    """Quick Smoke (`style` SMOKE, or BOTH: fire and smoke) over a 0.4 m emitter that does not render,
    simulated at resolution 32 into an empty cache of its own and shown at FLUID_FRAME. A bake into an
    empty cache gives the same grids every time (measured: their digest); one into a cache holding a
    bake before does not. The fingerprint of cycles_references.py does not read the grids, so the
    domain's name carries their digest: where a machine simulates otherwise, Cycles renders again."""
    emitter = cycles_compare.cube("emitter", (0.4, 0.4, 0.3 + LIFT), 0.4, None)
    bpy.ops.object.select_all(action="DESELECT")
    bpy.context.view_layer.objects.active = emitter
    emitter.select_set(True)
    bpy.ops.object.quick_smoke(style=style)
    emitter.hide_render = True
    domain = next(o for o in bpy.context.scene.objects if o is not emitter and o.modifiers.get("Fluid"))
    settings = domain.modifiers["Fluid"].domain_settings
    settings.resolution_max = 32
    settings.cache_type = "ALL"
    settings.cache_directory = os.path.join(tempfile.gettempdir(), f"ppm_media_compare_{style.lower()}")
    shutil.rmtree(settings.cache_directory, ignore_errors=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, FLUID_FRAME
    settings.cache_frame_start, settings.cache_frame_end = 1, FLUID_FRAME
    with bpy.context.temp_override(object=domain, active_object=domain):
        bpy.ops.fluid.bake_all()
    scene.frame_set(FLUID_FRAME)
    evaluated = domain.evaluated_get(bpy.context.evaluated_depsgraph_get()).modifiers["Fluid"].domain_settings
    grids = b"".join(memoryview(np.array(getattr(evaluated, f"{name}_grid"), dtype=np.float32)).tobytes()
                     for name in ("density", "flame", "temperature"))
    domain.name = f"domain {hashlib.sha256(grids).hexdigest()[:16]}"
    return domain


def density_through_attribute_node(mat):
    """The Principled Volume's Density from an Attribute node "density" times its Density (5), its own
    Density Attribute cleared: what older smoke materials do."""
    tree = mat.node_tree
    principled = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeVolumePrincipled")
    attribute = tree.nodes.new("ShaderNodeAttribute")
    attribute.attribute_name = "density"
    times = tree.nodes.new("ShaderNodeMath")
    times.operation = "MULTIPLY"
    times.inputs[1].default_value = principled.inputs["Density"].default_value
    tree.links.new(attribute.outputs["Fac"], times.inputs[0])
    tree.links.new(times.outputs["Value"], principled.inputs["Density"])
    principled.inputs["Density Attribute"].default_value = ""


def volume_object(name, path, location, scale, material):
    """A Volume object loading the OpenVDB file at `path`, placed and scaled, of `material`."""
    volume = bpy.data.volumes.new(name)
    volume.filepath = path
    obj = bpy.data.objects.new(name, volume)
    obj.location, obj.scale = location, (scale,) * 3
    bpy.context.scene.collection.objects.link(obj)
    volume.materials.append(material)
    return obj


def build(case):
    cycles_compare.reset()
    scene = bpy.context.scene
    cycles_compare.plane("floor", 4.0, 0.0, cycles_compare.diffuse_material("floor", (cycles_compare.ALBEDO,) * 3))
    cycles_compare.ball("matte", (-0.9, 0.6, 0.5), 0.5, cycles_compare.diffuse_material("matte", (0.7, 0.7, 0.7)))
    cycles_compare.side_camera((0.0, -5.0, 1.4), 30.0)
    cycles_compare.set_world(0.0)
    if case in ("world_fog", "fog_room", "smoke_in_fog_room", "ink_box_in_world_fog"):
        if case in ("world_fog", "ink_box_in_world_fog"):
            world_fog()
        else:
            cycles_compare.cube("room", (0.0, 0.0, 2.0), 12.0, fog_volume_scatter())
        if case == "ink_box_in_world_fog":  # the World's fog goes on inside it
            ink = volume_material("ink", "ShaderNodeVolumeAbsorption", Color=(0.2, 0.5, 0.9, 1.0), Density=0.4)
            cycles_compare.cube("ink", (0.5, 0.4, 1.0 + LIFT), 2.0, ink)
        if case == "smoke_in_fog_room":
            cycles_compare.ball("smoke", (0.5, 0.4, 0.8), 0.8, smoke_material())
        cycles_compare.add_light("POINT", 300.0, (0.5, 0.0, 2.5), shadow_soft_size=0.1)
    elif case == "fog_cube_spot":
        cycles_compare.set_world(0.05)  # a faint sky, so that no block is black and noise-bound
        fog = volume_material("fog", "ShaderNodeVolumeScatter", Density=0.4, Anisotropy=0.2)
        cycles_compare.cube("fog", (0.6, 0.6, 1.0 + LIFT), 2.0, fog)
        cycles_compare.add_light("SPOT", 500.0, (0.6, 0.6, 3.5), shadow_soft_size=0.1, spot_size=math.radians(35),
                                 spot_blend=0.2)
    elif case == "glass_ball_in_fog":
        fog = volume_material("fog", "ShaderNodeVolumeScatter", Density=0.3, Anisotropy=0.3)
        cycles_compare.cube("fog", (0.3, 0.6, 1.2 + LIFT), 2.4, fog)
        cycles_compare.ball("lens", (0.3, 0.6, 1.4), 0.4, cycles_compare.glass_material("lens", 1.5))
        cycles_compare.add_light("SPOT", 800.0, (0.3, 0.6, 3.3), shadow_soft_size=0.25, spot_size=math.radians(20),
                                 spot_blend=0.1)
    elif case == "ink_in_glass":
        ink = volume_material("ink", "ShaderNodeVolumeAbsorption", ("ShaderNodeBsdfGlass", {"IOR": 1.33,
                                                                                              "Roughness": 0.0}),
                              Color=(0.9, 0.15, 0.1, 1.0), Density=1.5)
        cycles_compare.cube("ink", (0.5, 0.4, 0.5 + LIFT), 1.0, ink)
        cycles_compare.add_light("AREA", 300.0, (0.0, 0.0, 3.0), size=2.0)
    elif case == "smoke_ball":
        cycles_compare.ball("smoke", (0.5, 0.4, 0.8), 0.8, smoke_material())
        cycles_compare.add_light("POINT", 300.0, (1.5, -1.0, 3.0), shadow_soft_size=0.1)
    elif case == "noise_cloud":
        cycles_compare.cube("cloud", (0.4, 0.5, 1.0 + LIFT), 1.6, noise_cloud_material())
        cycles_compare.add_light("POINT", 400.0, (1.5, -1.0, 3.2), shadow_soft_size=0.1)
    elif case == "mixed_fog":
        cycles_compare.set_world(0.05)
        cycles_compare.cube("fog", (0.4, 0.5, 1.0 + LIFT), 1.8, mixed_fog_material())
        cycles_compare.add_light("SPOT", 600.0, (0.4, 0.3, 3.5), shadow_soft_size=0.1, spot_size=math.radians(45),
                                 spot_blend=0.2)
    elif case == "noise_fire":  # its glow the only light
        cycles_compare.cube("fire", (0.5, 0.4, 0.8), 1.4, noise_fire_material())
    elif case in FLUID:
        domain = simulated_smoke("SMOKE" if case == "smoke_sim" else "BOTH")
        if case == "smoke_sim":
            density_through_attribute_node(domain.active_material)
        cycles_compare.add_light("POINT", 400.0, (1.5, -1.0, 3.2), shadow_soft_size=0.1)
        bpy.context.scene.camera.location = (0.2, -3.0, 1.4)  # nearer: the smoke across most blocks
    elif case == "vdb_smoke":
        volume_object("smoke", VDB_FILE, (0.0, 0.0, LIFT), 0.3, volume_material(
            "vdb smoke", "ShaderNodeVolumePrincipled", Density=6.0, Color=(0.6, 0.6, 0.6, 1.0),
            **{"Blackbody Intensity": 1.0, "Temperature": 1000.0}))
        cycles_compare.add_light("POINT", 400.0, (1.5, -1.0, 3.2), shadow_soft_size=0.1)
    elif case == "glowing_cloud":
        cloud = volume_material("cloud", "ShaderNodeVolumePrincipled", Density=1.0,
                                **{"Emission Strength": 0.5, "Emission Color": (1.0, 0.4, 0.1, 1.0),
                                   "Blackbody Intensity": 0.5, "Temperature": 1800.0})
        cycles_compare.cube("cloud", (0.5, 0.4, 0.8), 1.4, cloud)
    cycles_compare.set_exr_output(scene)
    return scene


# Cases that take a quarter of their passes, each of four times the photons and eye samples (the
# same in all): a pass has a fixed cost, large over the simulated domains (Blender 3.4, smoke_sim:
# 256 passes of 20,000 photons and 4 samples a pixel took 5.2 s, 64 passes of 80,000 and 16 took
# 2.7 s; the Noise fire 20.4 and 19.1 s). Not the smoke ball (its dim top block 3.4% -> 13.1%: its
# radii shrink by passes there) nor the ink box in world fog (2.95% -> 4.42%, near its 5%).
BIGGER_PASSES = {"glowing_cloud": 4, "mixed_fog": 4, "noise_fire": 4, "smoke_sim": 4, "fire_sim": 4, "vdb_smoke": 4}


def configure_for(case):
    """configure() for `case`: Cycles' volume bounces, and PPM's pass size (BIGGER_PASSES)."""
    scale = BIGGER_PASSES.get(case, 1)

    def configure(scene, engine):
        if engine == "CYCLES":
            scene.cycles.volume_bounces = BOUNCES
            scene.cycles.transparent_max_bounces = BOUNCES
        elif scale > 1:
            scene.ppm.passes //= scale
            scene.ppm.photons_per_pass *= scale
            scene.ppm.samples_per_pixel *= scale
    return configure


def compare(case, workdir, samples, passes):
    build(case)
    samples = REFERENCE_SAMPLES.get(case, min(samples, CASE_SAMPLES.get(case, samples)))
    row = cycles_compare.block_comparison(case, workdir, samples, max(passes, CASE_PASSES.get(case, 0)),
                                          bounces=BOUNCES, configure=configure_for(case))
    return {**row, "tolerance": CASE_TOLERANCE.get(case, TOLERANCE)}


def beyond_tolerance(row):
    return row["max_block_error"] > row["tolerance"]


# Cases whose Cycles changed: a smoke ball inside a fog room, where Blender 4.5 and 5.0 add the two
# media (1.5-1.7% from PPM's sum), reads 22-23% brighter inside the smoke in 3.4 and 4.2 (whose sum
# rule is not known here: docs/LIMITATIONS.md).
FROM_BLENDER = {"smoke_in_fog_room": (4, 5, 0)}


def cases_for_this_blender(cases):
    return tuple(c for c in cases if bpy.app.version >= FROM_BLENDER.get(c, (0, 0, 0))
                 and (FLUID_SIMULATES or c not in FLUID))


def compare_cases(cases=CASES, samples=1024, passes=64):
    def one(case, workdir):
        return compare(case, workdir, samples, passes)
    return cycles_compare.run_cases("media_compare", cases_for_this_blender(cases), one,
                                    cycles_compare.describe_blocks)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    cases = tuple(a for a in argv if a in CASES + GAPS) or CASES
    cycles_compare.run_as_script("media_compare", lambda: compare_cases(cases), beyond_tolerance)


if __name__ == "__main__":
    main()
