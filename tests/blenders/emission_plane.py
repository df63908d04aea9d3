"""A textured emitting plane rendered by Cycles, one sample at each pixel centre, with what Cycles
saw there: world position, UV, Generated and Object coordinates, normal. A material that shows a
quantity through an Emission shader of strength 1 renders that quantity exactly (Standard view,
float EXR), so a node's output can be checked pixel by pixel against numpy.

    scene = fresh scene (bpy.ops.wm.read_factory_settings(use_empty=True))
    out = render_cycles(emission_material("uv", lambda tree, nodes: ...), size=32)

Run as a script it checks itself (Generated, Object, UV, Position rendered against the arrays):

    .venv/bin/python tests/blenders/emission_plane.py                                         # 5.0 (bpy)
    .venvs/bpy-4.2/bin/python tests/blenders/emission_plane.py                                # 4.2
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/emission_plane.py     # 3.4
"""

import glob
import math
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# Blender 3.4 from Debian may have no numpy: borrow the .venv's (same Python 3.11).
for site in glob.glob(os.path.join(ROOT, ".venv", "lib", "python%d.%d" % sys.version_info[:2], "site-packages")):
    if site not in sys.path:
        sys.path.append(site)

import bpy
import numpy as np

LOCATION = (0.3, -0.2, 0.1)
ROTATION = (0.0, 0.0, math.radians(20.0))  # Euler XYZ
SCALE = 1.5  # uniform
CAMERA_DISTANCE = 5.0  # along the plane's normal, in world units
THREADS = 2
TOLERANCE = 1e-4


def emission_material(name, build):
    """A material that emits (strength 1) the socket `build(tree, nodes)` returns; a float socket
    shows as grey, a vector as its components."""
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    emission = tree.nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1.0
    tree.links.new(build(tree, tree.nodes), emission.inputs["Color"])
    tree.links.new(emission.outputs[0], out.inputs["Surface"])
    return mat


def plane(material, extent, normals=None):
    """Two triangles spanning [-extent/2, extent/2]^2 at z = 0 in object space, UVs 0..1, placed at
    LOCATION, ROTATION, SCALE. `normals`: the four corners' smooth normals (object space), if not +z."""
    h = extent / 2
    mesh = bpy.data.meshes.new("emission_plane")
    mesh.from_pydata([(-h, -h, 0.0), (h, -h, 0.0), (h, h, 0.0), (-h, h, 0.0)], [], [(0, 1, 2), (0, 2, 3)])
    uv = mesh.uv_layers.new(name="UVMap")
    corners = [mesh.vertices[loop.vertex_index].co for loop in mesh.loops]
    uv.data.foreach_set("uv", [c / extent + 0.5 for co in corners for c in co[:2]])
    mesh.materials.append(material)
    if normals is not None:
        for polygon in mesh.polygons:
            polygon.use_smooth = True
        if bpy.app.version < (4, 1, 0):
            mesh.use_auto_smooth = True
        mesh.normals_split_custom_set_from_vertices([tuple(n / np.linalg.norm(n)) for n in np.array(normals)])
    mesh.update()
    obj = bpy.data.objects.new("emission_plane", mesh)
    obj.location, obj.rotation_euler, obj.scale = LOCATION, ROTATION, (SCALE,) * 3
    bpy.context.scene.collection.objects.link(obj)
    return obj


def top_down_camera(extent):
    """The scene camera on the plane's normal, axes along the plane's, framing its square exactly."""
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.data.type, cam.data.ortho_scale = "ORTHO", extent * SCALE
    cam.data.clip_start, cam.data.clip_end = 0.1, 10.0 * CAMERA_DISTANCE
    cam.rotation_euler = ROTATION
    cam.location = np.array(LOCATION) + np.array(cam.rotation_euler.to_matrix().col[2]) * CAMERA_DISTANCE
    bpy.context.scene.collection.objects.link(cam)
    bpy.context.scene.camera = cam
    return cam


def black_world(scene):
    world = bpy.data.worlds.new("black")
    if world.node_tree is None or bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    background = next(n for n in world.node_tree.nodes if n.bl_idname == "ShaderNodeBackground")
    background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    background.inputs["Strength"].default_value = 0.0
    world.color = (0.0, 0.0, 0.0)
    scene.world = world


def configure(scene, size, samples):
    """Cycles on the CPU, `samples` per pixel (the first on its centre, the rest near it), nothing
    after the camera ray, no colour transform; float RGBA EXR output."""
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device, c.samples, c.seed = "CPU", samples, 0
    c.use_adaptive_sampling = c.use_denoising = False
    # Cycles' narrowest filter: the first sample lands on the pixel centre (a Box filter is always 1 px
    # wide, whatever filter_width says, and its first sample is 1/2048 px off the centre).
    c.pixel_filter_type, c.filter_width = "BLACKMAN_HARRIS", 0.01
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 0
    c.volume_bounces = c.transparent_max_bounces = 0
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.film_exposure = 1.0
    render = scene.render
    render.resolution_x = render.resolution_y = size
    render.resolution_percentage = 100
    render.film_transparent, render.dither_intensity = False, 0.0
    render.threads_mode, render.threads = "FIXED", THREADS
    render.use_compositing = render.use_sequencer = False
    view = scene.view_settings
    view.view_transform, view.look, view.exposure, view.gamma = "Standard", "None", 0.0, 1.0
    view.use_curve_mapping = False
    settings = render.image_settings
    settings.file_format, settings.color_mode, settings.color_depth = "OPEN_EXR", "RGBA", "32"
    settings.exr_codec = "ZIP"  # lossless
    render.use_file_extension = False


def read_exr(path):
    """(H, W, 4) float32 of a float image read by Blender (linear), row 0 at the top."""
    image = bpy.data.images.load(path, check_existing=False)
    try:
        width, height = image.size
        pixels = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
    finally:
        bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4)[::-1]


def smooth_normals(u, v, normals):
    """The corner normals interpolated over the plane's two triangles (0, 1, 2) and (0, 2, 3) at (u, v)
    in 0..1, normalised, as Cycles interpolates a smooth mesh's normals."""
    n = np.array(normals, dtype=np.float64)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    lower = (v <= u)[..., None]  # triangle (0, 1, 2): corners (0, 0), (1, 0), (1, 1)
    first = (1 - u)[..., None] * n[0] + (u - v)[..., None] * n[1] + v[..., None] * n[2]
    second = (1 - v)[..., None] * n[0] + u[..., None] * n[2] + (v - u)[..., None] * n[3]
    out = np.where(lower, first, second)
    return out / np.linalg.norm(out, axis=-1, keepdims=True)


def coordinates(obj, size, extent, normals=None):
    """What Cycles sees at each pixel centre (row 0 at the top): object and world positions, UV,
    Generated, world normal, and the world matrix."""
    centres = (np.arange(size) + 0.5) / size  # 0..1 across the plane, left to right / bottom to top
    u, v = np.meshgrid(centres, centres[::-1])
    local = np.stack([(u - 0.5) * extent, (v - 0.5) * extent, np.zeros_like(u)], axis=-1)
    matrix = np.array(obj.matrix_world, dtype=np.float64)
    world = local @ matrix[:3, :3].T + matrix[:3, 3]
    mesh = obj.data
    loc, half = np.array(mesh.texspace_location), np.array(mesh.texspace_size)
    local_normal = np.broadcast_to([0.0, 0.0, 1.0], local.shape) if normals is None else \
        smooth_normals(u, v, normals)
    normal = local_normal @ np.linalg.inv(matrix[:3, :3])  # (M^-T n) per row
    return {"P": world, "uv": np.stack([u, v], axis=-1), "generated": (local - (loc - half)) / (2 * half),
            "object": local, "N": normal / np.linalg.norm(normal, axis=-1, keepdims=True), "matrix": matrix}


def render_cycles(material, size=32, extent=2.0, samples=1, normals=None, prepare=None):
    """Renders the plane of `material` in the current scene (a fresh one); its rgb and coordinates.
    `normals`: the plane's corner normals (plane()); `prepare(plane)`: called before the render."""
    scene = bpy.context.scene
    obj = plane(material, extent, normals)
    top_down_camera(extent)
    black_world(scene)
    configure(scene, size, samples)
    if prepare is not None:
        prepare(obj)
    bpy.context.view_layer.update()
    with tempfile.TemporaryDirectory(prefix="emission_plane_") as folder:
        scene.render.filepath = os.path.join(folder, "render.exr")
        bpy.ops.render.render(write_still=True)
        rgba = read_exr(scene.render.filepath)
    return {"rgb": rgba[..., :3].astype(np.float64), **coordinates(obj, size, extent, normals)}


def texture_coordinate(output):
    return lambda tree, nodes: nodes.new("ShaderNodeTexCoord").outputs[output]


def position(tree, nodes):
    return nodes.new("ShaderNodeNewGeometry").outputs["Position"]


CHECKS = {  # name -> (the socket to show, the returned array it must equal)
    "generated": (texture_coordinate("Generated"), lambda out: out["generated"]),
    "object": (texture_coordinate("Object"), lambda out: out["object"]),
    "uv": (texture_coordinate("UV"), lambda out: np.concatenate([out["uv"], 0 * out["uv"][..., :1]], axis=-1)),
    "position": (position, lambda out: out["P"]),
    "smooth_normal": (texture_coordinate("Normal"), lambda out: out["N"] @ out["matrix"][:3, :3]
                      / np.linalg.norm(out["N"] @ out["matrix"][:3, :3], axis=-1, keepdims=True)),
}
CORNER_NORMALS = ((1.0, 0.2, 0.3), (-0.3, 1.0, 0.2), (0.2, -0.4, 1.0), (-1.0, -0.5, 0.4))  # all three axes lead


def self_check(size=32):
    """Renders each of CHECKS on a fresh scene; prints and returns the max abs difference of each."""
    worst = {}
    for name, (build, expected) in CHECKS.items():
        bpy.ops.wm.read_factory_settings(use_empty=True)
        out = render_cycles(emission_material(name, build), size=size,
                            normals=CORNER_NORMALS if name == "smooth_normal" else None)
        worst[name] = float(np.abs(out["rgb"] - expected(out)).max())
        print(f"emission_plane: Blender {bpy.app.version_string} {name}: max abs difference {worst[name]:.3g}"
              f" (values {expected(out).min():.3f}..{expected(out).max():.3f})", flush=True)
    return worst


if __name__ == "__main__":
    bad = {name: d for name, d in self_check().items() if not d <= TOLERANCE}
    if bad:
        print(f"emission_plane: beyond {TOLERANCE}: {bad}", flush=True)
        sys.exit(1)
