"""bpy (Blender 5.0 as a module) with the add-on registered from this checkout."""

import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy  # noqa: E402  (installed by make setup; a missing bpy must fail, not skip)

import ppm_render  # noqa: E402

SCENES_DIR = os.path.join(ROOT, "blend_scenes")


@pytest.fixture(autouse=True, scope="session")
def unregister_at_exit():
    """The bpy modules 4.2 and 4.5 crash or hang at exit while a script-registered class is still registered."""
    yield
    if hasattr(bpy.types.Scene, "ppm"):
        ppm_render.unregister()


@pytest.fixture(autouse=True)
def registered():
    """A factory-fresh Blender with the add-on registered for every test."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Scene, "ppm"):
        ppm_render.register()
    yield


def read_exr(path):
    """(H, W, 4) float32, top row first, via OpenImageIO (the house's image I/O outside Blender)."""
    import OpenImageIO as oiio

    buf = oiio.ImageBuf(path)
    assert not buf.has_error, buf.geterror()
    return buf.get_pixels(oiio.FLOAT)


def render_file(scene, path, **ppm):
    """Renders the scene with PPM to an EXR and returns its pixels."""
    scene.render.engine = "PPM"
    for key, value in ppm.items():
        setattr(scene.ppm, key, value)
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.use_file_extension = False
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    return read_exr(str(path))


def camera_looking_down(scene, height, width, pixels_high):
    """The scene's camera: at (0, 0, height), looking down -Z (a new camera's direction), rendering
    width x pixels_high pixels at 100%."""
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    cam.location = (0.0, 0.0, height)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = width, pixels_high, 100
    return cam


def node_material(name="m"):
    """A material with an empty node tree but its output: (material, tree, output node)."""
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    return mat, tree, out


def add(tree, kind, **inputs):
    """A node of `kind` in `tree` with these input values."""
    node = tree.nodes.new(kind)
    for key, value in inputs.items():
        node.inputs[key].default_value = value
    return node


def shader_material(name, kind, **inputs):
    """A material of one shader node of `kind` with these input values, into the output."""
    mat, tree, out = node_material(name)
    tree.links.new(add(tree, kind, **inputs).outputs[0], out.inputs["Surface"])
    return mat
