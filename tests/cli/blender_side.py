"""What the scripts Blender 3.4 runs here share (passes_compare.py, denoising_compare.py,
light_passes_compare.py, component_passes_compare.py): this checkout's .venv packages (numpy,
OpenImageIO, ppm_core; the same Python 3.11) and its add-on on the path, a factory-fresh scene
with the add-on registered, the scene pieces and render settings the comparisons build from, and
reading one pass of a multilayer EXR."""

import glob
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
for site in glob.glob(os.path.join(ROOT, ".venv", "lib", "python3*", "site-packages")):
    if site not in sys.path:
        sys.path.append(site)  # appended: Blender's own modules keep priority
sys.path.insert(0, os.path.join(ROOT, "addon"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402
import OpenImageIO as oiio  # noqa: E402

import ppm_render  # noqa: E402


def fresh_scene():
    """Blender's factory settings, no objects, the add-on registered: the scene."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Scene, "ppm"):
        ppm_render.register()
    return bpy.context.scene


def node_material(name, kind, **inputs):
    """A material of one shader node `kind` (e.g. "ShaderNodeBsdfDiffuse") with these input values."""
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    shader, output = nodes.new(kind), nodes.new("ShaderNodeOutputMaterial")
    for key, value in inputs.items():
        shader.inputs[key].default_value = value
    material.node_tree.links.new(shader.outputs[0], output.inputs["Surface"])
    return material


def add_quad(scene, name, corners, material=None):
    """A one-face mesh object through 4 corners, linked to the scene."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(corners, [], [(0, 1, 2, 3)])
    obj = bpy.data.objects.new(name, mesh)
    if material is not None:
        obj.data.materials.append(material)
    scene.collection.objects.link(obj)
    return obj


def multilayer_output(scene, width, height):
    """Renders at width x height into one multilayer EXR (every pass), at the exact file path."""
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    r.use_file_extension = False


def plain_cycles(scene, samples):
    """Cycles as a reference: no denoising or adaptive sampling, and the pixel's square as its filter,
    as PPM's jittered eye samples."""
    c = scene.cycles
    c.samples, c.use_denoising, c.use_adaptive_sampling = samples, False, False
    c.pixel_filter_type, c.filter_width = "BOX", 1.0


def neighbourhood(image):
    """(9, H, W): each pixel's 3 x 3 neighbourhood (edges repeated), itself included."""
    padded = np.pad(image, 1, mode="edge")
    return np.stack([padded[1 + dy:padded.shape[0] - 1 + dy, 1 + dx:padded.shape[1] - 1 + dx]
                     for dy in (-1, 0, 1) for dx in (-1, 0, 1)])


def read_pass(path, prefix, channels):
    """(H, W, len(channels)) float32 of the pass named `prefix` (e.g. "Denoising Albedo", "RGB")."""
    buf = oiio.ImageBuf(str(path))
    names = buf.spec().channelnames
    index = [next(i for i, n in enumerate(names) if n.endswith(f"{prefix}.{c}")) for c in channels]
    return buf.get_pixels(oiio.FLOAT)[..., index]
