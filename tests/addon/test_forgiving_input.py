"""Where Cycles renders a frame, PPM renders it too: what cannot be rendered is left out or clamped,
with one warning naming the object (tests/cli checks the exit codes of failed frames)."""

import math

import numpy as np
import pytest

from conftest import bpy, camera_looking_down, render_file
from ppm_render import core, export
from ppm_render.export.camera import Frame

ppm_core = core.load()


def floor_scene():
    """A lit floor seen from above, 32x24 pixels."""
    scene = bpy.context.scene
    add_mesh("floor", [(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], [(0, 1, 2, 3)])
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 2.0
    scene.collection.objects.link(sun)
    camera_looking_down(scene, 3.0, 32, 24)
    scene.render.engine = "PPM"
    return scene


def add_mesh(name, vertices, faces):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def cube(name, location=(0.0, 0.0, 0.5)):
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=location)
    bpy.context.object.name = name
    return bpy.context.object


def add_light(name, kind, **props):
    light = bpy.data.lights.new(name, kind)
    for key, value in props.items():
        setattr(light, key, value)
    obj = bpy.data.objects.new(name, light)
    obj.location = (0.0, 0.0, 2.0)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def principled_material(name):
    """A new node material and its Principled BSDF."""
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    return mat, next(n for n in mat.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")


def export_scene(scene):
    """(core scene, warnings) as the engine exports it."""
    warnings = []
    depsgraph = bpy.context.evaluated_depsgraph_get()
    core_scene, _, _ = export.build_scene(ppm_core, depsgraph, Frame.from_render_settings(scene.render),
                                          warnings.append)
    return core_scene, warnings


def renders(scene, tmp_path):
    """The frame renders: finite, non-negative, lit pixels."""
    rgb = render_file(scene, tmp_path / "frame.exr", passes=2, photons_per_pass=5000, samples_per_pixel=1)[..., :3]
    assert np.isfinite(rgb).all() and (rgb >= 0).all() and rgb.mean() > 0.01
    return rgb


def hits_at(core_scene, xy, z=3.0):
    """Distance down to the first surface above the floor point `xy` (inf if none)."""
    core_scene.set_camera(np.eye(4), 4, 4)
    return float(core_scene.intersect(np.array([[*xy, z]]), np.array([[0.0, 0.0, -1.0]]))["t"][0])


def test_an_object_scaled_to_zero_is_not_rendered_and_needs_no_warning(tmp_path):
    scene = floor_scene()
    cube("hidden").scale = (0.0, 0.0, 0.0)
    core_scene, warnings = export_scene(scene)
    assert warnings == []
    assert hits_at(core_scene, (0.0, 0.0)) == pytest.approx(3.0)  # the floor, nothing above it
    renders(scene, tmp_path)


def test_an_object_scaled_to_zero_on_one_axis_renders_flat(tmp_path):
    scene = floor_scene()
    cube("flat").scale = (1.0, 1.0, 0.0)  # as in Cycles: the top and bottom faces remain, at z = 0.5
    core_scene, warnings = export_scene(scene)
    assert warnings == []
    assert hits_at(core_scene, (0.1, 0.2)) == pytest.approx(2.5)
    renders(scene, tmp_path)


def test_triangles_with_a_non_finite_corner_are_left_out_with_one_warning(tmp_path):
    scene = floor_scene()
    add_mesh("spiky", [(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1), (float("nan"), 0, 1)], [(0, 1, 2), (0, 3, 4)])
    core_scene, warnings = export_scene(scene)
    assert len(warnings) == 1 and "object 'spiky'" in warnings[0] and "1 of its 2 triangles" in warnings[0]
    assert hits_at(core_scene, (0.7, 0.2)) == pytest.approx(2.0)  # the finite triangle stays
    renders(scene, tmp_path)


def test_an_object_beyond_the_supported_range_is_left_out_with_one_warning(tmp_path):
    scene = floor_scene()
    cube("far").location = (1e36, 0.0, 0.0)  # the core takes coordinates up to 1e30 m
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and warnings[0].startswith("object 'far': not rendered: position 0 has a component")
    renders(scene, tmp_path)


def test_one_warning_for_all_instances_of_an_object(tmp_path):
    scene = floor_scene()
    add_mesh("spiky", [(0, 0, 1), (1, 0, 1), (float("nan"), 1, 1)], [(0, 1, 2)])
    group = bpy.data.collections.new("group")
    group.objects.link(bpy.data.objects["spiky"])
    scene.collection.objects.unlink(bpy.data.objects["spiky"])
    for x in (-2.0, 2.0):
        instance = bpy.data.objects.new(f"instance{x}", None)
        instance.instance_type, instance.instance_collection = "COLLECTION", group
        instance.location = (x, 0.0, 0.0)
        scene.collection.objects.link(instance)
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and "object 'spiky'" in warnings[0] and "(in 2 instances)" in warnings[0], warnings
    renders(scene, tmp_path)


def test_a_negative_light_is_left_out_with_a_warning(tmp_path):
    scene = floor_scene()
    add_light("minus", "POINT", energy=-100.0)
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and "light 'minus'" in warnings[0] and "negative" in warnings[0]
    renders(scene, tmp_path)


def test_an_area_light_of_size_zero_is_left_out_with_a_warning(tmp_path):
    scene = floor_scene()
    add_light("flat", "AREA", energy=100.0, size=0.0)
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and "light 'flat'" in warnings[0] and "area is zero" in warnings[0]
    renders(scene, tmp_path)


def test_a_sun_of_blenders_largest_angle_renders(tmp_path):
    scene = floor_scene()
    bpy.data.objects["sun"].data.angle = math.pi
    _, warnings = export_scene(scene)
    assert warnings == []
    renders(scene, tmp_path)


def look_through(scene, data):
    """Makes an object of `data` (None: an Empty) 3 m above the floor the scene camera."""
    viewer = bpy.data.objects.new("viewer", data)
    viewer.location = (0.0, 0.0, 3.0)
    scene.collection.objects.link(viewer)
    scene.camera = viewer


@pytest.mark.parametrize("kind", ["EMPTY", "LIGHT"])
def test_any_object_can_be_the_camera(kind, tmp_path):
    scene = floor_scene()
    look_through(scene, None if kind == "EMPTY" else bpy.data.lights.new("lamp", "POINT"))
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and "'viewer'" in warnings[0] and "50 mm" in warnings[0]
    renders(scene, tmp_path)


def test_a_texture_with_bad_texels_is_still_used(tmp_path):
    scene = floor_scene()
    image = bpy.data.images.new("stains", 4, 4, float_buffer=True)
    pixels = np.full(4 * 4 * 4, 0.6, dtype=np.float32)
    pixels[3::4] = 1.0  # opaque: the colours reach the core as they are (not premultiplied by alpha)
    pixels[0], pixels[5] = np.nan, -1.0  # texel 0 red, texel 1 green
    image.pixels.foreach_set(pixels)
    mat, bsdf = principled_material("stained")
    texture = mat.node_tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    mat.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    bpy.data.objects["floor"].data.materials.append(mat)
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and "image 'stains'" in warnings[0], warnings
    assert "1 texel has values that are not a number" in warnings[0] and "(down to -1)" in warnings[0]
    renders(scene, tmp_path)


@pytest.mark.parametrize("points, cyclic, expected", [
    ([(0.5, 0.0)], True, "fewer than 2 points"),
    ([(0.0, 0.0), (0.0, 1.0)], False, "lies on the revolve axis"),
])
def test_a_revolve_profile_without_a_surface_is_skipped_with_a_warning(points, cyclic, expected, tmp_path):
    scene = floor_scene()
    curve = bpy.data.curves.new("profile", "CURVE")
    spline = curve.splines.new("BEZIER")
    spline.bezier_points.add(len(points) - 1)
    for point, (x, y) in zip(spline.bezier_points, points):
        point.co = point.handle_left = point.handle_right = (x, y, 0.0)
    spline.use_cyclic_u = cyclic
    obj = bpy.data.objects.new("vase", curve)
    obj.ppm.revolve = True
    scene.collection.objects.link(obj)
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and "'vase'" in warnings[0] and expected in warnings[0], warnings
    renders(scene, tmp_path)


def test_a_world_the_core_cannot_take_renders_black_with_a_warning(tmp_path):
    scene = floor_scene()
    world = bpy.data.worlds.new("glare")
    if world.node_tree is None or bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    background = next(n for n in world.node_tree.nodes if n.bl_idname == "ShaderNodeBackground")
    background.inputs["Strength"].default_value = -2.0
    scene.world = world
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and "world 'glare'" in warnings[0] and "black" in warnings[0]
    renders(scene, tmp_path)


def test_a_camera_scaled_to_zero_still_looks_where_it_pointed(tmp_path):
    scene = floor_scene()
    scene.camera.scale = (0.0, 0.0, 0.0)
    renders(scene, tmp_path)
    scene.camera.scale = (1.0, 1.0, 0.0)  # the view axis flattened: rebuilt from the other two
    renders(scene, tmp_path)


@pytest.mark.parametrize("where", [float("nan"), 1e35])
def test_a_camera_nowhere_fails_the_frame_with_a_clear_message(where):
    scene = floor_scene()
    scene.camera.location = (where, 0.0, 3.0)
    with pytest.raises(RuntimeError, match="PPM: camera 'cam' is at .* not a point the core can render from"):
        bpy.ops.render.render()


def test_material_values_outside_the_cores_range_are_clamped_with_one_warning(tmp_path):
    scene = floor_scene()
    mat, bsdf = principled_material("wild")
    bsdf.inputs["Base Color"].default_value = (2.0, 0.5, float("nan"), 1.0)
    bsdf.inputs["Roughness"].default_value = 7.0  # Cycles clamps roughness: no warning for it
    bpy.data.objects["floor"].data.materials.append(mat)
    _, warnings = export_scene(scene)
    assert warnings == ["material 'wild': outside what can be rendered, clamped: diffuse color (2, 0.5, nan) -> "
                        "(1, 0.5, 0)"], warnings
    renders(scene, tmp_path)


def test_stereo_through_an_empty_renders_both_views(tmp_path):
    """Blender crashes when asked for an Empty's per-view matrix: each view then looks through the
    Empty as it is."""
    scene = floor_scene()
    look_through(scene, None)
    scene.render.use_multiview, scene.render.views_format = True, "STEREO_3D"
    scene.render.image_settings.views_format = "INDIVIDUAL"
    scene.ppm.passes, scene.ppm.photons_per_pass = 1, 2000
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.filepath = str(tmp_path / "stereo.exr")
    scene.render.use_file_extension = False
    bpy.ops.render.render(write_still=True)
    assert (tmp_path / "stereo_L.exr").exists() and (tmp_path / "stereo_R.exr").exists()


def test_a_light_node_driven_by_another_node_uses_its_own_value_with_a_warning():
    scene = floor_scene()
    lamp = add_light("lamp", "POINT", energy=100.0)
    if bpy.app.version < (5, 1, 0):
        lamp.data.use_nodes = True
    tree = lamp.data.node_tree
    emission = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 2.0
    checker = tree.nodes.new("ShaderNodeTexChecker")  # a Blackbody is read: test_light_blackbody.py
    tree.links.new(checker.outputs["Color"], emission.inputs["Color"])
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and "light 'lamp'" in warnings[0] and "'Color'" in warnings[0]



def test_a_light_above_the_cores_power_is_clamped_not_left_out(tmp_path):
    """Raising a light's power never darkens the scene: above the core's 1e20 it is clamped, as emission is."""
    scene = floor_scene()
    bpy.data.objects["sun"].data.energy = 0.0
    lamp = add_light("lamp", "POINT", energy=1e19)
    below = renders(scene, tmp_path).mean()
    lamp.data.energy = 1e25
    core_scene, warnings = export_scene(scene)
    assert warnings == ["light 'lamp': its power 1e+25 is above the supported 1e+20; clamped to it"], warnings
    assert renders(scene, tmp_path).mean() > 5.0 * below


def unrendered_objects(scene):
    """A hair Curves object, a point cloud (Geometry Nodes' Mesh to Points) and a Volume object."""
    hair = bpy.data.objects.new("hair", bpy.data.hair_curves.new("hair"))
    volume = bpy.data.objects.new("smoke", bpy.data.volumes.new("smoke"))
    points = cube("points")
    modifier = points.modifiers.new("to points", "NODES")
    tree = bpy.data.node_groups.new("to points", "GeometryNodeTree")
    if hasattr(tree, "interface"):
        tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:
        tree.inputs.new("NodeSocketGeometry", "Geometry")
        tree.outputs.new("NodeSocketGeometry", "Geometry")
    group_in, group_out = tree.nodes.new("NodeGroupInput"), tree.nodes.new("NodeGroupOutput")
    to_points = tree.nodes.new("GeometryNodeMeshToPoints")
    tree.links.new(group_in.outputs[0], to_points.inputs["Mesh"])
    tree.links.new(to_points.outputs["Points"], group_out.inputs[0])
    modifier.node_group = tree
    for obj in (hair, volume):
        scene.collection.objects.link(obj)


def test_hair_curves_point_clouds_and_volume_objects_are_left_out_with_a_warning_each(tmp_path):
    scene = floor_scene()
    unrendered_objects(scene)
    _, warnings = export_scene(scene)
    for name, what in (("hair", "hair curves"), ("points", "point clouds"), ("smoke", "it has no .vdb file")):
        assert sum(f"object '{name}': {what}" in w and "not rendered yet" in w for w in warnings) == 1, warnings
    renders(scene, tmp_path)  # refused the whole frame before ("Object does not have geometry data")


def test_a_volume_on_an_open_mesh_is_named_once_and_renders(tmp_path):
    """A volume-only material on a single quad: paths entering it never leave the medium, as in Cycles;
    the object is named. (tests/addon/test_media.py checks closed media.)"""
    scene = floor_scene()
    lid = add_mesh("lid", [(-6, -6, 1), (6, -6, 1), (6, 6, 1), (-6, 6, 1)], [(0, 1, 2, 3)])
    mat = bpy.data.materials.new("fog")
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    fog = tree.nodes.new("ShaderNodeVolumeScatter")
    fog.inputs["Density"].default_value = 0.1
    tree.links.new(fog.outputs[0], output.inputs["Volume"])
    lid.data.materials.append(mat)
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and "object 'lid'" in warnings[0] and "not closed" in warnings[0], warnings
    renders(scene, tmp_path)


def test_a_missing_image_reads_magenta_as_in_cycles(tmp_path):
    scene = floor_scene()
    mat, bsdf = principled_material("painted")
    image = bpy.data.images.new("gone", 4, 4)
    image.source, image.filepath = "FILE", str(tmp_path / "gone.png")
    texture = mat.node_tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    mat.node_tree.links.new(texture.outputs["Color"], bsdf.inputs["Base Color"])
    bpy.data.objects["floor"].data.materials.append(mat)
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and "image 'gone'" in warnings[0] and "magenta" in warnings[0], warnings
    red, green, blue = renders(scene, tmp_path).reshape(-1, 3).mean(axis=0)
    assert green < 0.2 * red and blue == pytest.approx(red, rel=0.05)  # grey before (the sheen is white)


def test_settings_not_rendered_yet_are_each_named_once(tmp_path):
    scene = floor_scene()
    floor = bpy.data.objects["floor"]
    floor.is_shadow_catcher = True
    floor.modifiers.new("fur", "PARTICLE_SYSTEM").particle_system.settings.type = "HAIR"
    layer = bpy.context.view_layer
    layer.aovs.add().name = "dirt"
    layer.use_pass_cryptomatte_object = True
    if hasattr(floor, "light_linking"):  # Blender 4.0+
        bpy.data.objects["sun"].light_linking.receiver_collection = bpy.data.collections.new("lit")
    if hasattr(layer, "lightgroups"):  # Blender 3.5+
        layer.lightgroups.add(name="key")
    _, warnings = export_scene(scene)
    expected = ["object 'floor': shadow catcher", "object 'floor': hair of particle system", "shader AOVs (dirt)",
                "Cryptomatte (object)"]
    expected += ["light 'sun': light linking"] if hasattr(floor, "light_linking") else []
    expected += ["light groups (key)"] if hasattr(layer, "lightgroups") else []
    for part in expected:
        assert sum(part in w for w in warnings) == 1, (part, warnings)
    assert len(warnings) == len(expected), warnings
    renders(scene, tmp_path)


def test_a_displacement_output_is_named_once(tmp_path):
    scene = floor_scene()
    mat, bsdf = principled_material("bumpy")
    output = next(n for n in mat.node_tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    displacement = mat.node_tree.nodes.new("ShaderNodeDisplacement")
    mat.node_tree.links.new(displacement.outputs[0], output.inputs["Displacement"])
    bpy.data.objects["floor"].data.materials.append(mat)
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and "material 'bumpy'" in warnings[0] and "Displacement output" in warnings[0], warnings
