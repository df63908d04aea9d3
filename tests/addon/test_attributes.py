"""Mesh attributes in node programs: a Color Attribute or Attribute node reads the mesh's values at
the shading point (per vertex, per corner or per face; byte or float colours, vectors, floats, a
UV map by name), the exporter carrying the one attribute a material reads. A plane whose attribute
runs linearly across it, rendered by PPM through an Emission shader, shows that ramp (which any
interpolation, Cycles' too, gives exactly). Object and instancer attributes: an instancer's property
comes before the object's (their agreement with Cycles: nodes_compare.py's object_attribute_*)."""

import bpy
import numpy as np
import pytest

from conftest import render_file
from ppm_render.export import mesh as mesh_export

SIZE = 16


def plane_with(attribute_type, domain, name="paint"):
    """A 2 x 2 plane (4 x 4 quads) with attribute `name` = (x, y, 0.25) mapped to [0, 1], as `domain`."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=4, y_subdivisions=4, size=2.0)
    obj = bpy.context.object
    mesh = obj.data
    layer = mesh.attributes.new(name, attribute_type, domain)
    if domain == "POINT":
        points = np.array([v.co[:2] for v in mesh.vertices])
    elif domain == "CORNER":
        points = np.array([mesh.vertices[loop.vertex_index].co[:2] for loop in mesh.loops])
    else:
        points = np.array([p.center[:2] for p in mesh.polygons])
    rgb = np.column_stack([(points + 1.0) / 2.0, np.full(len(points), 0.25)])
    if attribute_type in ("FLOAT_COLOR", "BYTE_COLOR"):
        layer.data.foreach_set("color", np.column_stack([rgb, np.ones(len(points))]).ravel())
    elif attribute_type == "FLOAT_VECTOR":
        layer.data.foreach_set("vector", rgb.ravel())
    else:
        layer.data.foreach_set("value", rgb[:, 0])
    return obj


def emission_of(obj, build):
    mat = bpy.data.materials.new("painted")
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    emission = tree.nodes.new("ShaderNodeEmission")
    tree.links.new(build(tree), emission.inputs["Color"])
    tree.links.new(emission.outputs[0], out.inputs["Surface"])
    obj.data.materials.append(mat)


def view_from_above(scene):
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.data.type, cam.data.ortho_scale = "ORTHO", 2.0
    cam.location = (0.0, 0.0, 3.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.render.resolution_x = scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    if scene.world is not None:
        scene.world = None


def expected(channel_values):
    """The attribute at the pixel centres (a linear ramp: any interpolation gives it exactly)."""
    centres = (np.arange(SIZE) + 0.5) / SIZE
    x, y = np.meshgrid(centres, centres[::-1])
    return channel_values(x, y)


@pytest.mark.parametrize("attribute_type, domain", [("FLOAT_COLOR", "POINT"), ("BYTE_COLOR", "CORNER"),
                                                    ("FLOAT_VECTOR", "POINT")])
def test_a_color_attribute_colours_the_surface_as_cycles_reads_it(tmp_path, attribute_type, domain):
    obj = plane_with(attribute_type, domain)

    def attribute(tree):
        node = tree.nodes.new("ShaderNodeAttribute")
        node.attribute_name = "paint"
        return node.outputs["Color"]

    emission_of(obj, attribute)
    scene = bpy.context.scene
    view_from_above(scene)
    image = render_file(scene, tmp_path / "ppm.exr", passes=8, photons_per_pass=1000)
    # Each pixel averages its jittered samples: compare means along the direction a channel is constant.
    tolerance = 0.01 if attribute_type == "BYTE_COLOR" else 0.005  # bytes round the colours
    np.testing.assert_allclose(image[..., 0].mean(axis=0), expected(lambda x, y: x)[0], atol=tolerance)
    np.testing.assert_allclose(image[..., 1].mean(axis=1), expected(lambda x, y: y)[:, 0], atol=tolerance)
    np.testing.assert_allclose(image[..., 2].mean(), 0.25, atol=tolerance)


def test_face_and_float_attributes_and_a_uv_map_by_name_are_read_per_corner():
    obj = plane_with("FLOAT", "FACE", "heat")
    depsgraph = bpy.context.evaluated_depsgraph_get()
    data = mesh_export.MeshData.from_object(obj.evaluated_get(depsgraph), attribute="heat")
    assert data.colors.shape == (len(data.triangles), 3, 4)
    # One value per face, on all three corners of each of its triangles; a float fills R, G and B.
    assert np.allclose(data.colors[:, 0], data.colors[:, 1]) and np.allclose(data.colors[..., 0], data.colors[..., 2])
    assert set(np.round(np.unique(data.colors[..., 0]), 3)) == {0.125, 0.375, 0.625, 0.875}
    uv = mesh_export.MeshData.from_object(obj.evaluated_get(depsgraph), attribute=obj.data.uv_layers[0].name)
    np.testing.assert_allclose(uv.colors[..., :2], uv.uvs, atol=1e-6)
    missing = mesh_export.MeshData.from_object(obj.evaluated_get(depsgraph), attribute="nothing")
    assert missing.colors is None and missing.attribute_missing


def test_an_instancer_attribute_is_read_from_the_instancer_first_then_from_the_object(tmp_path):
    """One plane instanced twice by collection instances: the left instancer has the property, so its
    copy shows it; the right one has not, so its copy shows the plane's own (Blender's lookup order)."""
    bpy.ops.mesh.primitive_plane_add(size=1.0)
    plane = bpy.context.object
    plane["tint"] = (0.0, 0.0, 1.0)
    collection = bpy.data.collections.new("instanced")
    collection.objects.link(plane)
    bpy.context.scene.collection.objects.unlink(plane)

    def attribute(tree):
        node = tree.nodes.new("ShaderNodeAttribute")
        node.attribute_type, node.attribute_name = "INSTANCER", "tint"
        return node.outputs["Color"]

    emission_of(plane, attribute)
    for name, x, tint in (("left", -0.5, (1.0, 0.0, 0.0)), ("right", 0.5, None)):
        empty = bpy.data.objects.new(name, None)
        empty.instance_type, empty.instance_collection, empty.location = "COLLECTION", collection, (x, 0.0, 0.0)
        if tint is not None:
            empty["tint"] = tint
        bpy.context.scene.collection.objects.link(empty)
    scene = bpy.context.scene
    view_from_above(scene)
    image = render_file(scene, tmp_path / "ppm.exr", passes=2, photons_per_pass=1000)
    middle = SIZE // 2
    np.testing.assert_allclose(image[middle, SIZE // 4, :3], (1.0, 0.0, 0.0), atol=1e-3)
    np.testing.assert_allclose(image[middle, 3 * SIZE // 4, :3], (0.0, 0.0, 1.0), atol=1e-3)
    np.testing.assert_allclose(image[1, 1, :3], 0.0, atol=1e-3)  # no plane there
