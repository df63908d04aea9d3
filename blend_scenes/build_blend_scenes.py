"""Builds the bundled .blend scenes for the PPM add-on.

    blender -b --factory-startup --python-exit-code 1 -P blend_scenes/build_blend_scenes.py [-- --out DIR]
    .venv/bin/python blend_scenes/build_blend_scenes.py [--out DIR]           # bpy module (Blender 5.0)

Saved with Blender 3.4 (Debian's `blender`), the files open in 3.4 and 5.0
alike (newer Blenders read older files, not the other way round). The scenes:
cornell_3spheres (report figure 1), bezier_vase (figure 2), cornell_dof
(figure 3), showcase (textured meshes, several light types, instances) and
cornell_diffuse (diffuse only, for the accuracy benchmarks against Cycles), hdri_glass (image-based
light from an HDRI Blender ships, packed, with glass and its caustic) and fog_caustic (a volumetric
caustic: a spot light through a glass ball into a fog box), fog_shafts (god rays in a fog-filled
room, the camera in the fog), cloud (a medium that varies in space: a Noise cloud over a stage) and
studio (an HDRI with a sun over diffuse, rough gold and glass balls: a path tracer's kind of scene).
Geometry mirrors blend_scenes/core_scenes.py where a core scene exists.
"""

import argparse
import glob
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
for site in glob.glob(os.path.join(ROOT, ".venv", "lib", "python3*", "site-packages")):
    if site not in sys.path:
        sys.path.append(site)  # numpy and the add-on's core for Debian's Blender

import bpy
import numpy as np
from mathutils import Matrix

sys.path.insert(0, os.path.join(ROOT, "addon"))
import ppm_render
from ppm_render import bezier_revolve

# ---------------------------------------------------------------- helpers

def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Scene, "ppm"):
        ppm_render.register()


def node_material(name, node_type, **inputs):
    """A material whose surface is one BSDF node with the given input values."""
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    output = nodes.new("ShaderNodeOutputMaterial")
    bsdf = nodes.new(node_type)
    bsdf.location = (-300, 0)
    for key, value in inputs.items():
        socket = bsdf.inputs.get(key)
        if socket is not None:
            socket.default_value = value
    mat.node_tree.links.new(bsdf.outputs[0], output.inputs["Surface"])
    color = inputs.get("Color", inputs.get("Base Color", (0.8, 0.8, 0.8, 1.0)))
    mat.diffuse_color = tuple(color[:3]) + (1.0,)
    return mat


def diffuse(name, rgb):
    return node_material(name, "ShaderNodeBsdfDiffuse", Color=(*rgb, 1.0))


def mesh_object(name, vertices, faces, material=None, smooth=False):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(v) for v in vertices], [], [tuple(f) for f in faces])
    mesh.update()
    if material is not None:
        mesh.materials.append(material)
    if smooth:
        mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def quad(name, corners, material):
    return mesh_object(name, corners, [(0, 1, 2, 3)], material)


def uv_sphere(name, center, radius, material, segments=64, rings=32):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=segments, ring_count=rings, radius=radius, location=center)
    obj = bpy.context.object
    obj.name = obj.data.name = name
    obj.data.polygons.foreach_set("use_smooth", [True] * len(obj.data.polygons))
    obj.data.materials.append(material)
    return obj


def look_at(eye, target, up=(0.0, 0.0, 1.0)):
    eye, target, up = (np.asarray(v, dtype=float) for v in (eye, target, up))
    back = eye - target
    back /= np.linalg.norm(back)
    right = np.cross(up, back)
    right /= np.linalg.norm(right)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = right, np.cross(back, right), back, eye
    return Matrix(m.tolist())


def camera(eye, target, lens=40.0, sensor=36.0):
    data = bpy.data.cameras.new("Camera")
    data.lens, data.sensor_width, data.sensor_fit = lens, sensor, "AUTO"
    data.clip_start = 0.01
    obj = bpy.data.objects.new("Camera", data)
    bpy.context.scene.collection.objects.link(obj)
    obj.matrix_world = look_at(eye, target)
    bpy.context.scene.camera = obj
    return obj


def light(name, kind, location, energy, target=None, **props):
    data = bpy.data.lights.new(name, kind)
    data.energy = energy
    for key, value in props.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(name, data)
    bpy.context.scene.collection.objects.link(obj)
    if target is None:
        obj.location = location
    else:  # light objects emit along local -Z, like cameras look
        obj.matrix_world = look_at(location, target)
    return obj


def world(rgb, strength=1.0):
    w = bpy.data.worlds.new("World")
    if w.node_tree is None or bpy.app.version < (5, 0, 0):
        w.use_nodes = True
    background = next(n for n in w.node_tree.nodes if n.bl_idname == "ShaderNodeBackground")
    background.inputs["Color"].default_value = (*rgb, 1.0)
    background.inputs["Strength"].default_value = strength
    bpy.context.scene.world = w


def render_settings(width=640, height=480, passes=200, photons=200_000):
    scene = bpy.context.scene
    scene.render.engine = "PPM"
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.ppm.passes, scene.ppm.photons_per_pass = passes, photons
    scene.view_settings.view_transform = "Standard"


def cornell_box(size=2.0):
    """Walls as in core_scenes.cornell_box: x, y in [-1, 1], z in [0, 2], open towards -y."""
    h = size / 2.0
    white, red, blue = diffuse("white", (0.75, 0.75, 0.75)), diffuse("red", (0.75, 0.25, 0.25)), \
        diffuse("blue", (0.25, 0.25, 0.75))
    z0, z1 = 0.0, size
    quad("floor", [(-h, -h, z0), (h, -h, z0), (h, h, z0), (-h, h, z0)], white)
    quad("ceiling", [(-h, -h, z1), (-h, h, z1), (h, h, z1), (h, -h, z1)], white)
    quad("back", [(-h, h, z0), (h, h, z0), (h, h, z1), (-h, h, z1)], white)
    quad("left", [(-h, -h, z0), (-h, h, z0), (-h, h, z1), (-h, -h, z1)], red)
    quad("right", [(h, -h, z0), (h, -h, z1), (h, h, z1), (h, h, z0)], blue)
    return white


# ---------------------------------------------------------------- scenes

def cornell_3spheres():
    """Report figure 1: mirror, glass and diffuse spheres; a small sphere light in the box's centre."""
    reset()
    cornell_box()
    mirror = node_material("mirror", "ShaderNodeBsdfGlossy", Color=(0.95, 0.95, 0.95, 1.0), Roughness=0.0)
    glass = node_material("glass", "ShaderNodeBsdfGlass", Color=(1.0, 1.0, 1.0, 1.0), IOR=1.5, Roughness=0.0)
    matte = diffuse("matte", (0.8, 0.7, 0.3))
    uv_sphere("mirror_ball", (-0.45, 0.2, 0.35), 0.35, mirror)
    uv_sphere("glass_ball", (0.45, -0.25, 0.35), 0.35, glass)
    uv_sphere("matte_ball", (-0.3, 0.55, 1.45), 0.25, matte)
    light("lamp", "POINT", (0.0, 0.0, 1.3), 25.0, shadow_soft_size=0.05)
    camera((0.0, -4.4, 1.0), (0.0, 0.0, 1.0), lens=40.0)
    world((0.0, 0.0, 0.0))
    render_settings()


def revolve_object(name, profile, material, location, handle="AUTO"):
    """A Bezier revolve object (upright, profile (radius, height) in local XY)."""
    curve = bpy.data.curves.new(name, "CURVE")
    curve.dimensions, curve.fill_mode = "2D", "NONE"
    spline = curve.splines.new("BEZIER")
    spline.bezier_points.add(len(profile) - 1)
    for point, (r, h) in zip(spline.bezier_points, profile):
        point.co = (r, h, 0.0)
        point.handle_left_type = point.handle_right_type = handle
    first = spline.bezier_points[0]
    first.handle_left_type = first.handle_right_type = "FREE"
    first.handle_left, first.handle_right = (-0.1, profile[0][1], 0.0), (0.1, profile[0][1], 0.0)
    curve.materials.append(material)
    obj = bpy.data.objects.new(name, curve)
    bpy.context.scene.collection.objects.link(obj)
    obj.location = location
    obj.rotation_euler = (math.pi / 2.0, 0.0, 0.0)
    bezier_revolve.make_revolve(obj)
    return obj


def bezier_vase():
    """Report figure 2: a glass vase and a gold bowl, exact Bezier revolves, casting caustics."""
    reset()
    floor = diffuse("floor", (0.7, 0.7, 0.7))
    wall = diffuse("wall", (0.6, 0.62, 0.65))
    quad("floor", [(-3, -3, 0), (3, -3, 0), (3, 3, 0), (-3, 3, 0)], floor)
    quad("wall", [(-3, 1.5, 0), (3, 1.5, 0), (3, 1.5, 3), (-3, 1.5, 3)], wall)
    glass = node_material("vase_glass", "ShaderNodeBsdfGlass", Color=(1.0, 1.0, 1.0, 1.0), IOR=1.5, Roughness=0.0)
    gold = node_material("gold", "ShaderNodeBsdfPrincipled", **{
        "Base Color": (1.0, 0.78, 0.34, 1.0), "Metallic": 1.0, "Roughness": 0.15})
    revolve_object("vase", bezier_revolve.DEFAULT_PROFILE, glass, (-0.35, 0.2, 0.0))
    revolve_object("bowl", ((0.0, 0.0), (0.3, 0.02), (0.5, 0.25), (0.55, 0.35)), gold, (0.75, -0.1, 0.0))
    light("spot", "SPOT", (-1.8, -1.6, 3.2), 600.0, target=(-0.2, 0.2, 0.6),
          spot_size=math.radians(35), spot_blend=0.2, shadow_soft_size=0.0)
    light("fill", "AREA", (1.5, -2.5, 2.5), 80.0, target=(0.0, 0.0, 0.5), shape="RECTANGLE", size=1.0, size_y=0.6)
    camera((0.0, -4.2, 1.6), (0.1, 0.2, 0.7), lens=45.0)
    world((0.02, 0.02, 0.025))
    render_settings()


def cornell_dof():
    """Report figure 3: spheres at three depths, the middle one in focus (f/1.4)."""
    reset()
    cornell_box()
    spheres = [("near_ball", (0.5, -0.7, 0.25), (0.8, 0.3, 0.2)),
               ("mid_ball", (-0.1, 0.0, 0.3), (0.3, 0.7, 0.3)),
               ("far_ball", (-0.5, 0.65, 0.35), (0.3, 0.4, 0.8))]
    for name, center, rgb in spheres:
        uv_sphere(name, center, center[2], diffuse(name, rgb))
    mirror = node_material("mirror", "ShaderNodeBsdfGlossy", Color=(0.95, 0.95, 0.95, 1.0), Roughness=0.0)
    uv_sphere("mirror_ball", (0.55, 0.5, 0.3), 0.3, mirror)
    light("lamp", "AREA", (0.0, 0.0, 1.98), 60.0, shape="SQUARE", size=0.5)
    cam = camera((0.0, -4.4, 1.0), (0.0, 0.0, 0.6), lens=50.0)
    cam.data.dof.use_dof = True
    cam.data.dof.aperture_fstop = 1.4
    cam.data.dof.focus_object = bpy.data.objects["mid_ball"]
    world((0.0, 0.0, 0.0))
    render_settings()
    bpy.context.scene.ppm.dof_mode = "LENS"


def checker_image(name, size=256, squares=8):
    """A packed sRGB checker texture (two colours), built with numpy."""
    y, x = np.mgrid[0:size, 0:size] * squares // size
    odd = ((x + y) % 2).astype(bool)
    rgba = np.ones((size, size, 4), dtype=np.float32)
    rgba[odd, :3] = (0.9, 0.85, 0.7)
    rgba[~odd, :3] = (0.15, 0.25, 0.5)
    image = bpy.data.images.new(name, size, size, alpha=False)
    image.pixels.foreach_set(rgba.ravel())
    image.file_format = "PNG"
    image.pack()
    return image


def textured_material(name, image):
    mat = node_material(name, "ShaderNodeBsdfPrincipled", Roughness=0.5)
    tree = mat.node_tree
    bsdf = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    tex = tree.nodes.new("ShaderNodeTexImage")
    tex.image = image
    tex.location = (-600, 0)
    tree.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def box_mesh(name, size, location, material):
    bpy.ops.mesh.primitive_cube_add(size=size, location=location)
    obj = bpy.context.object
    obj.name = name
    obj.data.materials.append(material)
    return obj


def showcase():
    """Textured meshes, sun + area + spot + sphere lights, an emissive panel, collection instances."""
    reset()
    checker = checker_image("checker")
    tiles = textured_material("tiles", checker)
    floor = mesh_object("floor", [(-4, -4, 0), (4, -4, 0), (4, 4, 0), (-4, 4, 0)], [(0, 1, 2, 3)], tiles)
    floor.data.uv_layers.new(name="UVMap")
    uvs = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], dtype=np.float32)
    floor.data.uv_layers.active.data.foreach_set("uv", uvs.ravel())
    box_mesh("crate", 0.8, (1.2, 0.6, 0.4), tiles)  # the cube primitive comes with UVs
    uv_sphere("ball", (-1.0, 0.3, 0.5), 0.5, node_material("ball", "ShaderNodeBsdfPrincipled", **{
        "Base Color": (0.8, 0.2, 0.1, 1.0), "Roughness": 0.4}))
    uv_sphere("glass", (0.1, -0.8, 0.4), 0.4, node_material("glass", "ShaderNodeBsdfGlass", IOR=1.45))
    glow = node_material("glow", "ShaderNodeEmission", Color=(1.0, 0.6, 0.3, 1.0), Strength=6.0)
    quad("panel", [(-2.5, 2.5, 0.2), (-1.5, 2.9, 0.2), (-1.5, 2.9, 1.4), (-2.5, 2.5, 1.4)], glow)
    # Instances: a small "tree" collection placed five times by collection-instance empties.
    trees = bpy.data.collections.new("trees")
    bpy.context.scene.collection.children.link(trees)
    bpy.ops.mesh.primitive_cone_add(radius1=0.25, depth=0.7, location=(0, 0, 0.35))
    cone = bpy.context.object
    cone.name = "tree"
    cone.data.materials.append(diffuse("leaf", (0.2, 0.55, 0.2)))
    for c in cone.users_collection:
        c.objects.unlink(cone)
    trees.objects.link(cone)
    bpy.context.view_layer.layer_collection.children["trees"].exclude = True
    for i, x in enumerate(np.linspace(-2.5, 2.5, 5)):
        empty = bpy.data.objects.new(f"tree_instance.{i}", None)
        empty.instance_type, empty.instance_collection = "COLLECTION", trees
        empty.location = (float(x), 2.0, 0.0)
        empty.scale = (1.0, 1.0, 0.8 + 0.2 * i)
        bpy.context.scene.collection.objects.link(empty)
    light("sun", "SUN", (3, -3, 5), 1.5, target=(0, 0, 0), angle=math.radians(3))
    light("area", "AREA", (2.5, -1.5, 2.5), 150.0, target=(0.5, 0.5, 0.3), shape="ELLIPSE", size=1.2, size_y=0.6)
    light("spot", "SPOT", (-2.0, -2.0, 3.0), 400.0, target=(-1.0, 0.3, 0.3),
          spot_size=math.radians(40), spot_blend=0.3, shadow_soft_size=0.0)
    light("bulb", "POINT", (0.2, 1.0, 1.6), 60.0, shadow_soft_size=0.1)
    camera((0.5, -6.0, 2.6), (0.0, 0.5, 0.5), lens=35.0)
    world((0.05, 0.07, 0.1))
    render_settings()


def box_corners(center, size, height, angle):
    """The 8 corners of an upright box (bottom 4 then top 4, counter-clockwise from above), turned by `angle`."""
    c, s = math.cos(angle), math.sin(angle)
    h = size / 2.0
    ring = [(-h, -h), (h, -h), (h, h), (-h, h)]
    xy = [(center[0] + c * x - s * y, center[1] + s * x + c * y) for x, y in ring]
    return [(x, y, 0.0) for x, y in xy] + [(x, y, height) for x, y in xy]


BOX_FACES = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def cornell_diffuse():
    """Diffuse only (accuracy benchmark against Cycles): the Cornell box walls, a tall and a short
    white block and a square area light under the ceiling; no specular surface, no depth of field.
    core_scenes.cornell_diffuse has the same geometry."""
    reset()
    white = cornell_box()
    mesh_object("tall_block", box_corners((-0.35, 0.3), 0.6, 1.2, math.radians(20)), BOX_FACES, white)
    mesh_object("short_block", box_corners((0.4, -0.3), 0.6, 0.6, math.radians(-18)), BOX_FACES, white)
    light("lamp", "AREA", (0.0, 0.0, 1.98), 60.0, shape="SQUARE", size=0.5)
    camera((0.0, -4.4, 1.0), (0.0, 0.0, 1.0), lens=40.0)
    world((0.0, 0.0, 0.0))
    render_settings()


def environment_world(hdri, turn_degrees=0.0):
    """A world lit by one of the HDRIs Blender ships (CC0), packed into the .blend so that the file
    renders wherever it is opened, turned about Z by a Mapping node."""
    path = os.path.join(bpy.utils.system_resource("DATAFILES"), "studiolights", "world", hdri + ".exr")
    w = bpy.data.worlds.new("World")
    if w.node_tree is None or bpy.app.version < (5, 0, 0):
        w.use_nodes = True
    nodes, links = w.node_tree.nodes, w.node_tree.links
    background = next(n for n in nodes if n.bl_idname == "ShaderNodeBackground")
    environment = nodes.new("ShaderNodeTexEnvironment")
    environment.image = bpy.data.images.load(path)
    environment.image.pack()
    coordinates, mapping = nodes.new("ShaderNodeTexCoord"), nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(turn_degrees))
    links.new(coordinates.outputs["Generated"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], environment.inputs["Vector"])
    links.new(environment.outputs["Color"], background.inputs["Color"])
    bpy.context.scene.world = w


def hdri_glass():
    """Image-based light: Blender's city.exr, whose sun stands 48 degrees high, turned so that it
    shines from behind the camera's left; a glass ball throws its caustic into its shadow on a pale
    floor, beside a glass vase (a Bezier revolve) and a matte ball."""
    reset()
    mesh_object("floor", [(-6, -6, 0), (6, -6, 0), (6, 6, 0), (-6, 6, 0)], [(0, 1, 2, 3)],
                diffuse("floor", (0.8, 0.78, 0.74)))
    glass = node_material("glass", "ShaderNodeBsdfGlass", IOR=1.5)
    uv_sphere("glass_ball", (0.0, 0.0, 0.45), 0.45, glass)
    uv_sphere("matte_ball", (-1.1, 0.9, 0.3), 0.3, diffuse("clay", (0.7, 0.35, 0.25)))
    vase = [(0.0, 0.0), (0.28, 0.0), (0.32, 0.25), (0.18, 0.55), (0.12, 0.8), (0.22, 1.0)]
    revolve_object("vase", vase, glass, (1.1, 0.8, 0.0))
    camera((0.3, -4.2, 2.2), (0.2, 0.3, 0.3), lens=40.0)
    environment_world("city", turn_degrees=150.0)
    render_settings()
    bpy.context.scene.view_settings.exposure = -2.5  # a sunlit floor is about 4


def studio():
    """A product shot under an HDRI, the kind of scene a path tracer renders well: Blender's city.exr
    (its sun 48 degrees high) turned so that the sun comes from the camera's left, a grey floor, and
    three Principled balls: diffuse clay, rough gold (roughness 0.25) and smooth glass (IOR 1.5)."""
    reset()
    quad("floor", [(-8, -8, 0), (8, -8, 0), (8, 8, 0), (-8, 8, 0)], diffuse("floor", (0.5, 0.5, 0.5)))
    principled = "ShaderNodeBsdfPrincipled"
    clay = node_material("clay", principled, **{"Base Color": (0.8, 0.45, 0.3, 1.0), "Roughness": 0.6})
    gold = node_material("gold", principled, **{"Base Color": (1.0, 0.76, 0.33, 1.0), "Metallic": 1.0,
                                                "Roughness": 0.25})
    glass = node_material("glass", principled, **{"Transmission Weight": 1.0, "Transmission": 1.0,
                                                  "Roughness": 0.0, "IOR": 1.5})
    uv_sphere("clay_ball", (-1.25, 0.4, 0.5), 0.5, clay)
    uv_sphere("gold_ball", (0.0, 0.0, 0.5), 0.5, gold)
    uv_sphere("glass_ball", (1.25, 0.4, 0.5), 0.5, glass)
    camera((0.0, -4.5, 1.6), (0.0, 0.2, 0.45), lens=45.0)
    environment_world("city", turn_degrees=250.0)
    render_settings()
    bpy.context.scene.view_settings.exposure = -2.0


def fog_box(name, corner_min, corner_max, density, anisotropy):
    """A box of Volume Scatter with nothing on its Surface: fog inside it, an invisible boundary."""
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    output, fog = nodes.new("ShaderNodeOutputMaterial"), nodes.new("ShaderNodeVolumeScatter")
    fog.inputs["Density"].default_value = density
    fog.inputs["Anisotropy"].default_value = anisotropy
    mat.node_tree.links.new(fog.outputs[0], output.inputs["Volume"])
    (x0, y0, z0), (x1, y1, z1) = corner_min, corner_max
    corners = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
               (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    return mesh_object(name, corners, BOX_FACES, mat)


def fog_caustic():
    """A volumetric caustic: a stage in fog, a spot light shining down through a glass ball on a
    plinth, towards the camera; the ball focuses it into a bright cone in the fog and a spot on the
    floor, inside the ball's shadow in the spot's shaft."""
    reset()
    stage = diffuse("stage", (0.6, 0.6, 0.6))
    quad("floor", [(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], stage)
    quad("back", [(-5, 4, 0), (5, 4, 0), (5, 4, 4), (-5, 4, 4)], stage)
    glass = node_material("glass", "ShaderNodeBsdfGlass", IOR=1.5, Roughness=0.0)
    uv_sphere("glass_ball", BALL, 0.5, glass)
    mesh_object("plinth", box_corners((BALL[0], BALL[1]), 0.25, BALL[2] - 0.505, 0.0), BOX_FACES,
                diffuse("plinth", (0.3, 0.3, 0.32)))
    light("spot", "SPOT", (-3.86, 0.6, 5.56), 12000.0, target=BALL, spot_size=math.radians(7), spot_blend=0.15,
          shadow_soft_size=0.02)
    light("fill", "AREA", (2.5, -2.8, 3.0), 8.0, target=BALL, size=1.0)
    camera((0.3, -3.0, 1.0), (0.2, 0.6, 0.6), lens=35.0)
    # The fog fills a box around the stage, the camera and the spot outside it (fog_shafts has them
    # inside); its bottom 5 cm below the floor, not in its plane.
    fog_box("fog", (-4.5, -2.5, -0.05), (4.5, 4.1, 4.5), 0.25, 0.4)
    world((0.0, 0.0, 0.0))
    render_settings()


BALL = (0.0, 0.6, 0.96)  # the glass ball's centre; its plinth stops 5 mm below it


def fog_shafts():
    """God rays: a room filled with thin fog (a box of Volume Scatter around everything, the camera
    and the lights inside it), a spot light slanting down past a diffuse ball and a rough metal one,
    their shadows cut out of its shaft, and a dim fill light; no glass, so that Cycles converges (the
    equal-time bench's media scene)."""
    reset()
    stage = diffuse("stage", (0.55, 0.55, 0.55))
    quad("floor", [(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], stage)
    quad("back", [(-5, 4, 0), (5, 4, 0), (5, 4, 4), (-5, 4, 4)], stage)
    uv_sphere("ball", (-0.7, 1.2, 0.6), 0.6, diffuse("ball", (0.7, 0.3, 0.2)))
    metal = node_material("metal", "ShaderNodeBsdfGlossy", Roughness=0.3, Color=(0.9, 0.75, 0.5, 1.0))
    uv_sphere("metal_ball", (0.9, 0.8, 0.5), 0.5, metal)
    light("spot", "SPOT", (-3.0, 2.5, 4.6), 3500.0, target=(0.2, 0.6, 0.0), spot_size=math.radians(35),
          spot_blend=0.2, shadow_soft_size=0.05)
    light("fill", "AREA", (2.5, -2.5, 3.0), 30.0, target=(0.0, 1.0, 0.5), size=1.0)
    camera((0.2, -3.2, 1.3), (0.0, 1.0, 0.9), lens=30.0)
    fog_box("fog", (-6, -6, -0.05), (6, 6, 6), 0.12, 0.3)  # its bottom below the floor, not in its plane
    world((0.0, 0.0, 0.0))
    render_settings()


def cloud_material():
    """Principled Volume (a warm white) whose Density is a Noise texture (its default coordinates,
    Generated; scale 4, detail 3) through a ColorRamp (clear below 0.45, full above 0.65) times 6:
    a cloud with clear gaps, as users make one."""
    mat = bpy.data.materials.new("cloud")
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    output, volume = nodes.new("ShaderNodeOutputMaterial"), nodes.new("ShaderNodeVolumePrincipled")
    volume.inputs["Color"].default_value = (0.95, 0.9, 0.85, 1.0)
    noise, ramp, times = nodes.new("ShaderNodeTexNoise"), nodes.new("ShaderNodeValToRGB"), nodes.new("ShaderNodeMath")
    noise.inputs["Scale"].default_value, noise.inputs["Detail"].default_value = 4.0, 3.0
    ramp.color_ramp.elements[0].position, ramp.color_ramp.elements[1].position = 0.45, 0.65
    times.operation, times.inputs[1].default_value = "MULTIPLY", 6.0
    links.new(noise.outputs["Fac"], ramp.inputs["Fac"])
    links.new(ramp.outputs["Color"], times.inputs[0])
    links.new(times.outputs["Value"], volume.inputs["Density"])
    links.new(volume.outputs[0], output.inputs["Volume"])
    return mat


def cloud():
    """A cloud that varies in space (a Noise through a ColorRamp as its density) in a flattened ball
    over a stage, a diffuse ball in its shadow, lit by a spot light from above and a dim fill; no glass,
    so that Cycles converges (the equal-time bench's medium that varies)."""
    reset()
    stage = diffuse("stage", (0.55, 0.55, 0.55))
    quad("floor", [(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], stage)
    quad("back", [(-5, 4, 0), (5, 4, 0), (5, 4, 4), (-5, 4, 4)], stage)
    uv_sphere("ball", (0.6, 1.0, 0.45), 0.45, diffuse("ball", (0.3, 0.45, 0.7)))
    puff = uv_sphere("cloud", (0.0, 1.0, 1.9), 1.0, cloud_material(), segments=32, rings=16)
    puff.scale = (1.5, 1.0, 0.7)
    light("spot", "SPOT", (2.5, 0.5, 5.0), 1500.0, target=(0.0, 1.0, 0.6), spot_size=math.radians(45),
          spot_blend=0.3, shadow_soft_size=0.1)
    light("fill", "AREA", (-2.5, -2.5, 2.5), 40.0, target=(0.0, 1.0, 1.2), size=1.5)
    camera((0.0, -3.6, 1.5), (0.0, 1.0, 1.3), lens=30.0)
    world((0.03, 0.035, 0.045))
    render_settings(passes=100)  # each pass about 1.2 s at 640x480 on 2 cores: shadow rays track the cloud


SCENES = {"cornell_3spheres": cornell_3spheres, "bezier_vase": bezier_vase,
          "cornell_dof": cornell_dof, "showcase": showcase, "cornell_diffuse": cornell_diffuse,
          "hdri_glass": hdri_glass, "fog_caustic": fog_caustic, "fog_shafts": fog_shafts, "cloud": cloud,
          "studio": studio}


def save(path):
    bpy.context.preferences.filepaths.save_version = 0  # no .blend1 backups next to the bundled files
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=False)
    print(f"build_blend_scenes: wrote {path}", flush=True)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else \
        (sys.argv[1:] if os.path.basename(sys.argv[0]) == os.path.basename(__file__) else [])
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default=HERE)
    parser.add_argument("--only", nargs="*", default=list(SCENES))
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    for name in args.only:
        SCENES[name]()
        save(os.path.join(args.out, f"{name}.blend"))


if __name__ == "__main__":
    main()
