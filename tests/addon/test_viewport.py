"""The viewport's code path without a window (bpy as a module has none, so view_draw's drawing is
tested in tests/gui): the view read from a region's matrices, the export, the render thread's
refinement from a coarse preview to full resolution, restarts after edits, and stopping."""

import os
import threading
import time

import bmesh
import bpy
import numpy as np
import pytest

from conftest import SCENES_DIR
from ppm_render import core, viewport
from ppm_render.export.camera import Frame, camera_arguments
from ppm_render.viewport_camera import camera_from_projection, sub_window, with_camera_lens

ppm_core = core.load()


def camera(kind="PERSP"):
    bpy.ops.object.camera_add(location=(1.0, -5.0, 2.0), rotation=(1.2, 0.1, 0.3))
    cam = bpy.context.object
    cam.data.type, cam.data.lens, cam.data.ortho_scale = kind, 35.0, 4.0
    cam.data.shift_x, cam.data.shift_y = 0.13, -0.21
    cam.data.clip_start, cam.data.clip_end = 0.3, 80.0
    return cam


@pytest.mark.parametrize("kind", ["PERSP", "ORTHO"])
@pytest.mark.parametrize("size", [(640, 480), (300, 500)])
def test_a_view_read_from_its_matrices_is_the_camera_blender_projects(kind, size):
    """A camera's own projection matrix (as a viewport in camera view gets it) gives the same core
    camera as the camera's data: field of view or scale, shifts and clipping."""
    cam = camera(kind)
    width, height = size
    projection = cam.calc_matrix_camera(bpy.context.evaluated_depsgraph_get(), x=width, y=height)
    ours = camera_from_projection(cam.matrix_world.inverted(), projection, width, height)
    expected = camera_arguments(cam, Frame(width, height), print)
    for key in ("fov", "ortho_scale", "shift_x", "shift_y"):
        if key in expected:
            assert ours[key] == pytest.approx(expected[key], rel=1e-5, abs=1e-6), key
    assert ours["projection"] == expected["projection"]
    forward = -expected["matrix"][:3, 2]
    if kind == "PERSP":
        assert ours["clip_start"] == pytest.approx(0.3, rel=1e-4)
        assert ours["clip_end"] == pytest.approx(80.0, rel=1e-4)
        assert np.allclose(ours["matrix"], expected["matrix"], atol=1e-5)
    else:  # the eye moved onto the near plane: the same visible slab
        assert np.allclose(ours["matrix"][:3, 3], expected["matrix"][:3, 3] + 0.3 * forward, atol=1e-4)
        assert ours["clip_start"] == 0.0 and ours["clip_end"] == pytest.approx(79.7, rel=1e-4)


@pytest.mark.parametrize("kind", ["PERSP", "ORTHO"])
def test_a_render_region_renders_the_same_pixels_as_a_render_border(kind):
    """A window of the region, narrowed from the region's camera, is the camera F12 renders for the same
    border (export/camera.py's Frame window), so the region's pixels stay where they were."""
    cam = camera(kind)
    width, height, window = 640, 480, (100, 60, 200, 300)
    projection = cam.calc_matrix_camera(bpy.context.evaluated_depsgraph_get(), x=width, y=height)
    ours = sub_window(camera_from_projection(cam.matrix_world.inverted(), projection, width, height), *window)
    expected = camera_arguments(cam, Frame(width, height, *window), print)
    for key in ("fov", "ortho_scale", "shift_x", "shift_y"):
        if key in expected:
            assert ours[key] == pytest.approx(expected[key], rel=1e-5, abs=1e-6), key
    assert (ours["width"], ours["height"], ours["frame"]) == (200, 300, expected["frame"])
    preview = viewport.scaled_view(ours, 4)
    assert (preview["width"], preview["height"], preview["frame"]) == (50, 75, (25, 15, 160, 120))
    assert viewport.window_of(ours) == window


def test_an_orthographic_view_that_sees_behind_its_eye_starts_its_rays_behind_it():
    """Blender's orthographic user views clip from a negative distance: the eye moves back."""
    near, far = -50.0, 50.0
    projection = np.diag([0.5, 0.5, -2.0 / (far - near), 1.0])
    projection[2, 3] = -(far + near) / (far - near)
    args = camera_from_projection(np.eye(4), projection, 100, 100)
    assert args["matrix"][:3, 3] == pytest.approx([0.0, 0.0, 50.0])  # moved back along +Z (it looks down -Z)
    assert (args["clip_start"], args["clip_end"]) == (0.0, pytest.approx(100.0))


def test_the_camera_view_has_the_cameras_depth_of_field_where_the_settings_ask_for_it():
    cam = camera()
    cam.data.dof.use_dof, cam.data.dof.aperture_fstop, cam.data.dof.focus_distance = True, 2.8, 3.0
    projection = cam.calc_matrix_camera(bpy.context.evaluated_depsgraph_get(), x=320, y=240)
    view = camera_from_projection(cam.matrix_world.inverted(), projection, 320, 240)
    assert with_camera_lens(view, cam, "OFF") is view
    lens = with_camera_lens(view, cam, "LENS")
    assert lens["aperture_radius"] == pytest.approx(35e-3 / (2 * 2.8)) and lens["focus_distance"] == 3.0
    assert lens["fov"] == view["fov"] and lens["shift_x"] == view["shift_x"]  # the view's own framing


class Session:
    """A ViewportSession on the Cornell box, with the redraws it asks for counted."""

    def __init__(self, width=160, height=120, open_file=True):
        if open_file:
            bpy.ops.wm.open_mainfile(filepath=os.path.join(SCENES_DIR, "cornell_3spheres.blend"))
        self.scene = bpy.context.scene
        self.scene.ppm.viewport_photons_per_pass = 5_000
        self.scene.ppm.viewport_passes = 6
        self.redraws = 0
        self.session = viewport.ViewportSession(ppm_core, self.redraw)
        self.session.export(bpy.context.evaluated_depsgraph_get())
        cam = self.scene.camera
        projection = cam.calc_matrix_camera(bpy.context.evaluated_depsgraph_get(), x=width, y=height)
        self.session.set_view(camera_from_projection(cam.matrix_world.inverted(), projection, width, height))

    def redraw(self):
        self.redraws += 1

    def images_until_done(self, timeout=60.0):
        """Each new image seen while the thread refines, until it is done."""
        seen, start = [], time.monotonic()
        while time.monotonic() - start < timeout:
            image = self.session.newest()
            if image is not None and (not seen or seen[-1] is not image):
                seen.append(image)
            if self.session.done and self.session.newest() is seen[-1]:
                return seen
            time.sleep(0.002)
        raise AssertionError("the viewport did not finish refining")


def updated_after(session, change, update=True):
    """The parts changed_part names after `change()` (None, "lights", "objects", ...), as view_update sees
    them; with `update`, session.update then brings the session up to them, as view_update does. The
    updates a depsgraph lists exist only while it reports them (here in a depsgraph_update_post
    handler)."""
    answers = []

    def handler(_scene, depsgraph):
        answers.append(session.update(depsgraph) if update else viewport.changed_part(depsgraph, session))

    bpy.context.evaluated_depsgraph_get()  # settles earlier changes
    bpy.app.handlers.depsgraph_update_post.append(handler)
    try:
        change()
        bpy.context.evaluated_depsgraph_get()
    finally:
        bpy.app.handlers.depsgraph_update_post.remove(handler)
    return {answer for answer in answers if answer is not None} or {None}


def part_changed_by(session, change):
    """The one part changed_part names after `change()`."""
    (part,) = updated_after(session, change, update=False)
    return part


def bsdf_colour(material_name, rgb):
    node = next(n for n in bpy.data.materials[material_name].node_tree.nodes if n.type.startswith("BSDF"))
    node.inputs["Color"].default_value = (*rgb, 1.0)


def edited_image_is_a_fresh_exports(s):
    """Refines the edited session `s` and asserts its image is, to the last bit, the one a session
    exporting the edited scene afresh renders; returns that image."""
    s.session.start()
    edited = s.images_until_done()[-1]
    s.session.stop()
    fresh = Session(open_file=False)
    fresh.session.start()
    expected = fresh.images_until_done()[-1]
    fresh.session.stop()
    np.testing.assert_array_equal(edited.rgba, expected.rgba)
    return edited


def test_the_viewport_refines_from_a_coarse_preview_to_full_resolution_and_stops_at_its_passes():
    s = Session()
    s.session.start()
    images = s.images_until_done()
    s.session.stop()
    assert s.session.error is None
    assert images[0].pixel_size > 1 and images[0].rgba.shape[1] < 160  # a coarse image first
    last = images[-1]
    assert last.pixel_size == 1 and last.rgba.shape == (120, 160, 4) and last.passes == 6
    assert s.redraws >= 3  # the thread asks Blender to redraw for each image
    assert np.isfinite(last.rgba).all() and last.rgba[..., :3].mean() > 0.01


def test_an_edit_restarts_from_the_new_scene_and_no_image_mixes_the_two():
    s = Session()
    s.session.start()
    before = s.images_until_done()[-1]
    ball = s.scene.objects["matte_ball"]
    assert updated_after(s.session, lambda: setattr(ball.location, "x", ball.location.x + 0.3)) == {"objects"}
    s.session.start()
    after = s.images_until_done()
    s.session.stop()
    assert all(image.generation == after[-1].generation for image in after[1:])
    assert after[-1].generation > before.generation
    assert np.abs(after[-1].rgba[..., :3] - before.rgba[..., :3]).mean() > 0.002  # the ball moved


def test_a_moved_or_reshaped_mesh_object_is_replaced_in_place_and_renders_as_a_new_export_would():
    """Moving, turning and scaling a mesh object and moving its vertices keep the exported scene (the
    object's BVH subtree is refitted); the image is a fresh export's, to the last bit."""
    s = Session()
    kept = s.session.core_scene
    ball = s.scene.objects["matte_ball"]

    def reshape():
        for vertex in ball.data.vertices[:40]:
            vertex.co.z += 0.05
        ball.data.update()

    assert updated_after(s.session, lambda: setattr(ball.location, "x", ball.location.x + 0.3)) == {"objects"}
    assert updated_after(s.session, lambda: setattr(ball.rotation_euler, "z", 0.7)) == {"objects"}
    assert updated_after(s.session, lambda: setattr(ball, "scale", (1.2, 0.8, 1.0))) == {"objects"}
    assert updated_after(s.session, reshape) == {"objects"}
    assert s.session.core_scene is kept
    edited_image_is_a_fresh_exports(s)


def collection_instance(scene):
    """An empty instancing a collection of a small cube and a point lamp; the empty."""
    collection = bpy.data.collections.new("props")
    mesh = bpy.data.meshes.new("prop")
    mesh.from_pydata([(x, y, z) for x in (0, 0.1) for y in (0, 0.1) for z in (0, 0.1)], [],
                     [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)])
    collection.objects.link(bpy.data.objects.new("prop", mesh))
    lamp = bpy.data.objects.new("prop_lamp", bpy.data.lights.new("prop_lamp", "POINT"))
    lamp.data.energy, lamp.location = 5.0, (0.05, 0.05, 0.3)
    collection.objects.link(lamp)
    empty = bpy.data.objects.new("props", None)
    empty.instance_type, empty.instance_collection = "COLLECTION", collection
    empty.location = (-0.3, 0.2, 0.0)
    scene.collection.objects.link(empty)
    return empty


def test_instances_and_the_camera_moved_keep_the_scene_and_render_as_a_new_export_would():
    """Moving an empty that instances a collection (a mesh and a lamp) moves its instances in place;
    moving the camera object changes no core object (the view follows in view_draw)."""
    s = Session()
    empty = collection_instance(s.scene)
    s.session.export(bpy.context.evaluated_depsgraph_get())
    kept = s.session.core_scene
    assert updated_after(s.session, lambda: setattr(empty.location, "y", -0.2)) == {"objects"}
    assert updated_after(s.session, lambda: setattr(empty.rotation_euler, "z", 0.5)) == {"objects"}
    camera_z = s.scene.camera.location.z
    for z in (camera_z + 0.5, camera_z):  # (and back: the fresh export's view is read from the camera)
        assert updated_after(s.session, lambda value=z: setattr(s.scene.camera.location, "z", value)) == {"objects"}
    assert s.session.core_scene is kept
    edited_image_is_a_fresh_exports(s)


def drop_a_face(obj):
    mesh = bmesh.new()
    mesh.from_mesh(obj.data)
    bmesh.ops.delete(mesh, geom=[next(iter(mesh.faces))], context="FACES_ONLY")
    mesh.to_mesh(obj.data)
    mesh.free()
    obj.data.update()


def test_objects_reshaped_added_given_materials_and_removed_are_updated_in_place():
    """A face dropped (another triangle count), a cube added, another material in a slot, an object
    deleted and a collection hidden from the render keep the exported scene; the image is a fresh
    export's, to the last bit."""
    s = Session()
    kept = s.session.core_scene
    ball = s.scene.objects["matte_ball"]
    assert updated_after(s.session, lambda: drop_a_face(ball)) == {"objects"}
    add_cube = lambda: bpy.ops.mesh.primitive_cube_add(size=0.3, location=(0.0, 0.0, 0.5))  # noqa: E731
    assert updated_after(s.session, add_cube) == {"objects"}
    cube = bpy.context.object
    assert updated_after(s.session, lambda: drop_a_face(cube)) == {"objects"}
    assert updated_after(s.session, lambda: cube.data.materials.append(bpy.data.materials["red"])) == {"objects"}
    assert updated_after(s.session, lambda: setattr(ball.material_slots[0], "material", bpy.data.materials["blue"])
                         ) == {"objects"}
    assert updated_after(s.session, lambda: bpy.data.objects.remove(s.scene.objects["mirror_ball"])) == {"objects"}
    hidden = bpy.data.collections.new("hidden")
    s.scene.collection.children.link(hidden)
    hidden.objects.link(s.scene.objects["glass_ball"])
    s.scene.collection.objects.unlink(s.scene.objects["glass_ball"])
    s.session.update(bpy.context.evaluated_depsgraph_get())
    assert updated_after(s.session, lambda: setattr(hidden, "hide_render", True)) == {"objects"}
    assert s.session.core_scene is kept
    edited_image_is_a_fresh_exports(s)


def test_instances_added_and_removed_are_updated_in_place_lights_among_them():
    """A collection instance (a cube and a point lamp) added, a linked duplicate of a ball, then the
    instancer deleted: the exported scene is kept, and renders as a fresh export."""
    s = Session()
    kept = s.session.core_scene
    lights = kept.light_count
    assert updated_after(s.session, lambda: collection_instance(s.scene)) == {"objects"}
    assert kept.light_count == lights + 1  # the instanced lamp

    def duplicate():
        copy = s.scene.objects["matte_ball"].copy()
        copy.location.x -= 0.35
        s.scene.collection.objects.link(copy)

    assert updated_after(s.session, duplicate) == {"objects"}
    edited_image_is_a_fresh_exports(s)
    assert updated_after(s.session, lambda: bpy.data.objects.remove(s.scene.objects["props"])) == {"objects"}
    assert s.session.core_scene is kept and kept.light_count == lights
    edited_image_is_a_fresh_exports(s)


def test_warnings_about_objects_follow_them_when_they_are_edited_in_place():
    """An object added with a corner that is not finite gets its warning; mending it or deleting it
    takes the warning away, and warnings about other objects stay."""
    s = Session()
    s.scene.objects["floor"].data.vertices[0].co.x = float("nan")
    s.session.export(bpy.context.evaluated_depsgraph_get())
    floor = [w for w in s.session.warnings if "object 'floor'" in w]
    assert len(floor) == 1

    def add_spoiled():
        mesh = bpy.data.meshes.new("spoiled")
        mesh.from_pydata([(0, 0, 0.2), (0.2, 0, 0.2), (0, 0.2, 0.2), (float("inf"), 0, 0.2)], [],
                         [(0, 1, 2), (0, 1, 3)])
        s.scene.collection.objects.link(bpy.data.objects.new("spoiled", mesh))

    about = lambda: [w for w in s.session.warnings if "object 'spoiled'" in w]  # noqa: E731
    assert updated_after(s.session, add_spoiled) == {"objects"}
    assert len(about()) == 1 and "1 of its 2 triangles" in about()[0]
    spoiled = s.scene.objects["spoiled"]

    def mend():
        spoiled.data.vertices[3].co.x = 0.2
        spoiled.data.update()

    assert updated_after(s.session, mend) == {"objects"}
    assert about() == []
    assert updated_after(s.session, lambda: setattr(spoiled.data.vertices[3].co, "x", float("nan"))
                         or spoiled.data.update()) == {"objects"}
    assert len(about()) == 1
    assert updated_after(s.session, lambda: bpy.data.objects.remove(spoiled)) == {"objects"}
    assert about() == [] and [w for w in s.session.warnings if "object 'floor'" in w] == floor


def test_a_lamp_edit_replaces_the_lights_alone_and_renders_as_a_new_export_would():
    """Moving a lamp and changing its power keep the exported objects (and their BVH); the image is the
    one a session exporting the edited scene afresh renders, to the last bit."""
    s = Session()
    s.session.start()
    s.images_until_done()
    kept = s.session.core_scene
    lamp = s.scene.objects["lamp"]
    assert updated_after(s.session, lambda: setattr(lamp.location, "x", lamp.location.x + 0.6)) == {"lights"}
    assert updated_after(s.session, lambda: setattr(lamp.data, "energy", 2.0 * lamp.data.energy)) == {"lights"}
    assert s.session.core_scene is kept
    edited_image_is_a_fresh_exports(s)


def test_a_material_edit_writes_its_values_in_place_and_renders_as_a_new_export_would():
    """A colour and an emission edited in the node tree keep the exported objects (and their BVH); the
    image is the one of a session exporting the edited scene afresh, to the last bit."""
    s = Session()
    s.session.start()
    before = s.images_until_done()[-1]
    kept = s.session.core_scene
    assert updated_after(s.session, lambda: bsdf_colour("matte", (0.1, 0.1, 0.9))) == {"materials"}

    def glow():
        tree = bpy.data.materials["white"].node_tree
        emission = tree.nodes.new("ShaderNodeEmission")
        emission.inputs["Strength"].default_value = 0.5
        add = tree.nodes.new("ShaderNodeAddShader")
        output = next(n for n in tree.nodes if n.type == "OUTPUT_MATERIAL")
        bsdf = output.inputs["Surface"].links[0].from_node
        tree.links.new(bsdf.outputs[0], add.inputs[0])
        tree.links.new(emission.outputs[0], add.inputs[1])
        tree.links.new(add.outputs[0], output.inputs["Surface"])

    assert updated_after(s.session, glow) == {"materials"}  # the walls glow: lights from their triangles
    assert s.session.core_scene is kept
    edited = edited_image_is_a_fresh_exports(s)
    assert edited.rgba[..., :3].mean() > 1.2 * before.rgba[..., :3].mean()  # glowing walls


def test_a_material_edited_in_place_keeps_only_its_new_warnings():
    """A warning about a material goes when an edit in place removes its cause, and comes back with
    it; warnings about other materials stay."""
    s = Session()
    tree = bpy.data.materials["matte"].node_tree
    toon = tree.nodes.new("ShaderNodeBsdfToon")  # rendered as diffuse, with a warning
    output = next(n for n in tree.nodes if n.type == "OUTPUT_MATERIAL")
    bsdf = output.inputs["Surface"].links[0].from_node
    tree.links.new(toon.outputs[0], output.inputs["Surface"])
    s.session.export(bpy.context.evaluated_depsgraph_get())
    about = lambda name: [w for w in s.session.warnings if f"material '{name}'" in w]  # noqa: E731
    assert len(about("matte")) == 1
    others = [w for w in s.session.warnings if "material 'matte'" not in w]
    assert updated_after(s.session, lambda: tree.links.new(bsdf.outputs[0], output.inputs["Surface"])) == {"materials"}
    assert about("matte") == [] and [w for w in s.session.warnings if w not in others] == []
    assert updated_after(s.session, lambda: tree.links.new(toon.outputs[0], output.inputs["Surface"])) == {"materials"}
    assert len(about("matte")) == 1
    assert updated_after(s.session, lambda: bsdf_colour("white", (0.9, 0.9, 0.8))) == {"materials"}
    assert len(about("matte")) == 1  # another material's edit leaves it


def hdri_world(scene):
    """The scene's world made an environment image (one of Blender's studio-light HDRIs); its Background node."""
    world = scene.world or bpy.data.worlds.new("world")
    scene.world = world
    if world.node_tree is None or bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    tree = world.node_tree
    background = next(n for n in tree.nodes if n.type == "BACKGROUND")
    folder = bpy.utils.system_resource("DATAFILES", path=os.path.join("studiolights", "world"))
    environment = tree.nodes.new("ShaderNodeTexEnvironment")
    environment.image = bpy.data.images.load(os.path.join(folder, sorted(f for f in os.listdir(folder)
                                                                          if f.endswith(".exr"))[0]))
    tree.links.new(environment.outputs["Color"], background.inputs["Color"])
    return background


def test_a_world_edit_replaces_the_world_alone_and_leaves_no_texture_behind():
    """Edits of an HDRI world's strength keep the exported objects, lights and BVH and the count of
    textures (each edit's image replaces the last); the image is a fresh export's, to the last bit."""
    s = Session()
    background = hdri_world(s.scene)
    s.session.export(bpy.context.evaluated_depsgraph_get())
    kept = s.session.core_scene
    textures = kept.texture_count
    for strength in (0.3, 0.6, 0.45, 0.5):
        change = lambda value=strength: setattr(background.inputs["Strength"], "default_value", value)  # noqa: E731
        assert updated_after(s.session, change) == {"world"}
    assert s.session.core_scene is kept and kept.texture_count == textures
    edited_image_is_a_fresh_exports(s)


def test_within_a_full_resolution_pass_the_viewport_shows_the_bands_done(monkeypatch):
    """A view of more pixels than a band of rows gets images between a pass's bands too (here after
    every band), and ends on the image of whole passes."""
    monkeypatch.setattr(viewport, "IMAGE_INTERVAL", 1e-9)
    s = Session(width=400, height=300)  # 120,000 pixels: two bands of rows
    s.scene.ppm.viewport_passes = 3
    s.session.export(bpy.context.evaluated_depsgraph_get())
    published, publish = [], s.session.publish
    s.session.publish = lambda image: (published.append(image), publish(image))  # every image, none missed
    s.session.start()
    s.images_until_done()
    s.session.stop()
    full = [image for image in published if image.pixel_size == 1]
    assert [image.passes for image in full] == [0, 1, 1, 2, 2, 3]
    assert np.abs(full[1].rgba - full[2].rgba).max() > 0.0  # half a pass later: new pixels


def test_a_session_whose_engine_is_gone_stops_after_its_image():
    """redraw() returns False once Blender has freed the engine: nobody would see more passes."""
    s = Session()
    s.session.redraw = lambda: False
    s.session.start()
    images = s.images_until_done(timeout=20.0)
    s.session.stop()
    assert len(images) == 1 and images[0].pixel_size > 1


def test_stopping_mid_pass_returns_within_the_cores_poll_interval():
    s = Session(width=320, height=240)
    s.scene.ppm.viewport_photons_per_pass = 2_000_000  # passes of seconds each
    s.scene.ppm.viewport_passes = 0
    s.session.export(bpy.context.evaluated_depsgraph_get())
    s.session.start()
    time.sleep(1.0)
    start = time.monotonic()
    s.session.stop()
    assert time.monotonic() - start < 0.5
    assert s.session.thread is None and not any(t.name == "PPM viewport" for t in threading.enumerate())


def test_a_selection_alone_needs_no_export_but_a_setting_or_a_material_does():
    s = Session()

    def select_all():
        for obj in s.scene.objects:
            obj.select_set(True)

    def more_photons():
        s.scene.ppm.viewport_photons_per_pass += 1000

    def redder():
        bpy.data.materials["blue"].diffuse_color = (1.0, 0.0, 0.0, 1.0)

    assert part_changed_by(s.session, select_all) is None
    assert part_changed_by(s.session, redder) == "materials"
    # A setting of the add-on's own tags no update (Python-defined properties do not): view_draw, which
    # every change in a panel triggers, compares the settings instead.
    assert viewport.settings_key(s.scene) == s.session.settings_key
    more_photons()
    assert viewport.settings_key(s.scene) != s.session.settings_key


def test_an_export_that_fails_renders_nothing_and_keeps_its_error():
    s = Session()
    session = viewport.ViewportSession(ppm_core, s.redraw)
    session.view = s.session.view

    class Broken:
        scene, view_layer = s.scene, s.scene.view_layers[0]

        @property
        def object_instances(self):
            raise RuntimeError("broken depsgraph")

    with pytest.raises(RuntimeError):
        session.export(Broken())
    session.start()
    assert session.thread is None and session.core_scene is None


def test_a_volume_object_moved_in_the_viewport_renders_as_a_new_export_would():
    """A Volume object (tests/data/smoke_zip.vdb, test_vdb.py's material) moved: the image is a fresh
    export's, to the last bit."""
    from test_vdb import DATA, volume_object

    s = Session(open_file=True)
    smoke = volume_object(s.scene, os.path.join(DATA, "smoke_zip.vdb"))
    smoke.location = (0.0, 0.3, 0.2)
    s.session.export(bpy.context.evaluated_depsgraph_get())
    assert updated_after(s.session, lambda: setattr(smoke.location, "x", 0.4)) != {None}
    assert s.session.core_scene.grid_count() == 2  # its density and temperature
    edited_image_is_a_fresh_exports(s)
