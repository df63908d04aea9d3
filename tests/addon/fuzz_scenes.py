"""Random hostile Blender scenes for the add-on's export: objects with any transform (zero, negative,
huge and tiny scales, far away), vertices that are NaN or Inf, lights of every kind with extreme or
negative values, cameras of every type (and an Empty or a light as the camera), extreme materials
and worlds (constant, or an environment image with extreme texels and any Mapping rotation), any
ray visibility, holdouts, transparent film and stereo. Cycles renders every one of these frames, so
PPM must too.

Used by tests/addon/test_fuzz_scenes.py (a few dozen scenes in `make test`) and by
bench/run.py fuzz_addon (thousands, in every Blender version).
"""

import math

import bpy
import numpy as np

EXTREME = (0.0, 1e-30, 1e-6, 1.0, 1e6, 1e30, -1.0, float("inf"), float("nan"))
SCALES = (0.0, -1.0, 1e-9, 1e-3, 1.0, 1e3, 1e9)


def pick(rng, values):
    return values[int(rng.integers(len(values)))]


def vector(rng, spread=3.0, odd=0.1):
    """A random 3-vector; now and then an extreme one."""
    if rng.random() < odd:
        return tuple(float(pick(rng, EXTREME)) * float(rng.choice((-1.0, 1.0))) for _ in range(3))
    return tuple(float(v) for v in rng.normal(0.0, spread, 3))


def set_transform(rng, obj):
    obj.location = vector(rng)
    obj.rotation_euler = tuple(float(v) for v in rng.uniform(-math.pi, math.pi, 3))
    if rng.random() < 0.4:
        obj.scale = tuple(float(pick(rng, SCALES)) for _ in range(3))


def material(rng, name):
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    nodes = mat.node_tree.nodes
    kind = pick(rng, ("ShaderNodeBsdfPrincipled", "ShaderNodeBsdfDiffuse", "ShaderNodeBsdfGlass",
                      "ShaderNodeEmission", "ShaderNodeBsdfGlossy", "ShaderNodeHoldout"))
    out = next(n for n in nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    node = nodes.new(kind)
    for socket in node.inputs if kind != "ShaderNodeHoldout" else ():
        if rng.random() < 0.3 and socket.type == "VALUE":
            socket.default_value = float(pick(rng, EXTREME))
        elif rng.random() < 0.3 and socket.type == "RGBA":
            socket.default_value = (*(float(pick(rng, EXTREME)) for _ in range(3)), 1.0)
    mat.node_tree.links.new(node.outputs[0], out.inputs["Surface"])
    return mat


RAY_FLAGS = ("visible_camera", "visible_diffuse", "visible_glossy", "visible_transmission", "visible_shadow")


def set_visibility(rng, obj):
    """Now and then a ray kind the object hides from, or a holdout."""
    for flag in RAY_FLAGS:
        if hasattr(obj, flag) and rng.random() < 0.15:
            setattr(obj, flag, not getattr(obj, flag))
    if rng.random() < 0.1:
        obj.is_holdout = True


def mesh_object(rng, index):
    count = int(rng.integers(3, 9))
    vertices = [vector(rng, odd=0.05) for _ in range(count)]
    faces = [tuple(int(v) for v in rng.choice(count, 3, replace=False)) for _ in range(int(rng.integers(1, 6)))]
    mesh = bpy.data.meshes.new(f"mesh{index}")
    mesh.from_pydata(vertices, [], faces)
    mesh.materials.append(material(rng, f"material{index}"))
    obj = bpy.data.objects.new(f"mesh{index}", mesh)
    set_transform(rng, obj)
    set_visibility(rng, obj)
    return obj


def light_object(rng, index):
    kind = pick(rng, ("POINT", "SPOT", "AREA", "SUN"))
    light = bpy.data.lights.new(f"light{index}", kind)
    light.energy = float(pick(rng, EXTREME)) * float(rng.choice((-1.0, 1.0)))
    light.color = tuple(float(v) for v in rng.uniform(0.0, 1.0, 3))
    if kind in ("POINT", "SPOT"):
        light.shadow_soft_size = float(pick(rng, (0.0, 1e-6, 0.25, 10.0, 1e6)))
    if kind == "SPOT":
        light.spot_size = float(rng.uniform(0.01, math.pi))
        light.spot_blend = float(rng.uniform(0.0, 1.0))
    if kind == "AREA":
        light.shape = pick(rng, ("SQUARE", "RECTANGLE", "DISK", "ELLIPSE"))
        light.size, light.size_y = float(pick(rng, SCALES[:5])) ** 2, float(pick(rng, SCALES[:5])) ** 2
    if kind == "AREA" and hasattr(light, "spread"):
        light.spread = float(pick(rng, (math.radians(1), 0.05, 1.0, math.pi)))
    if kind == "SUN":
        light.angle = float(pick(rng, (0.0, 1e-6, 0.1, 3.0, math.pi)))
    if rng.random() < 0.2:
        light.use_shadow = False
    obj = bpy.data.objects.new(f"light{index}", light)
    set_transform(rng, obj)
    set_visibility(rng, obj)
    return obj


def camera_object(rng):
    holder = pick(rng, ("CAMERA", "CAMERA", "CAMERA", "EMPTY", "LIGHT"))
    if holder == "CAMERA":
        cam = bpy.data.cameras.new("camera")
        cam.type = pick(rng, ("PERSP", "ORTHO", "PANO"))
        cam.lens = float(pick(rng, (1.0, 5.0, 35.0, 5000.0)))
        cam.ortho_scale = float(pick(rng, (1e-4, 1.0, 1e4)))
        cam.sensor_fit = pick(rng, ("AUTO", "HORIZONTAL", "VERTICAL"))
        cam.shift_x, cam.shift_y = (float(v) for v in rng.uniform(-2.0, 2.0, 2))
        cam.clip_start = float(pick(rng, (1e-6, 0.1, 10.0)))
        cam.clip_end = cam.clip_start * float(pick(rng, (1.01, 1e3, 1e9)))
        data = cam
    else:
        data = None if holder == "EMPTY" else bpy.data.lights.new("viewer", "POINT")
    obj = bpy.data.objects.new("camera", data)
    set_transform(rng, obj)
    obj.location = vector(rng, odd=0.0)  # a camera at NaN or beyond 1e30 m fails, clearly (test_forgiving_input)
    return obj


def world(rng):
    w = bpy.data.worlds.new("world")
    if w.node_tree is None or bpy.app.version < (5, 0, 0):
        w.use_nodes = True
    background = next(n for n in w.node_tree.nodes if n.bl_idname == "ShaderNodeBackground")
    background.inputs["Strength"].default_value = float(pick(rng, EXTREME))
    if rng.random() < 0.4:
        environment_texture(rng, w, background)
    if rng.random() < 0.2:
        w.cycles_visibility.camera = False
    return w


def environment_texture(rng, w, background):
    """An Environment Texture of a small float image with extreme texels, perhaps turned by any rotation."""
    nodes, links = w.node_tree.nodes, w.node_tree.links
    width, height = int(pick(rng, (1, 2, 16))), int(pick(rng, (1, 8)))
    image = bpy.data.images.new("sky", width, height, float_buffer=True)
    pixels = rng.uniform(0.0, 2.0, width * height * 4)
    pixels[rng.random(pixels.size) < 0.2] = pick(rng, EXTREME)
    image.pixels.foreach_set(pixels.astype(np.float32))
    environment = nodes.new("ShaderNodeTexEnvironment")
    environment.image = image
    environment.projection = pick(rng, ("EQUIRECTANGULAR", "MIRROR_BALL"))
    links.new(environment.outputs["Color"], background.inputs["Color"])
    if rng.random() < 0.5:
        mapping = nodes.new("ShaderNodeMapping")
        mapping.inputs["Rotation"].default_value = vector(rng, spread=3.0, odd=0.2)
        links.new(mapping.outputs["Vector"], environment.inputs["Vector"])


def build(seed):
    """A random scene in a fresh file, set to render with PPM at 16x12, 1 pass."""
    rng = np.random.default_rng(seed)
    bpy.ops.wm.read_homefile(use_empty=True, use_factory_startup=True)
    scene = bpy.context.scene
    for i in range(int(rng.integers(0, 4))):
        scene.collection.objects.link(mesh_object(rng, i))
    for i in range(int(rng.integers(0, 4))):
        scene.collection.objects.link(light_object(rng, i))
    camera = camera_object(rng)
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.world = world(rng)
    scene.render.engine = "PPM"
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 16, 12, 100
    scene.ppm.passes, scene.ppm.photons_per_pass, scene.ppm.samples_per_pixel = 1, 2000, 1
    scene.ppm.dof_mode = pick(rng, ("OFF", "POST", "LENS"))
    scene.ppm.hit_points = pick(rng, ("FIXED", "STOCHASTIC"))
    scene.render.film_transparent = rng.random() < 0.3
    scene.render.use_multiview = rng.random() < 0.1
    return scene
