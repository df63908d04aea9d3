"""Object Index and Material Index passes (passes.py): each pixel's camera ray reports the Pass
Index of the object and of the material it meets, as Cycles' IndexOB and IndexMA do; the agreement
with Cycles' own passes is tests/cli/passes_compare.py's (Blender 3.4)."""

import bpy
import numpy as np

from conftest import camera_looking_down, render_file
from ppm_render import core, export, passes
from ppm_render.export.camera import Frame

ppm_core = core.load()


def indexed_scene():
    """A floor (object 3, material 2), a cube in front of it (object 7, material 5) and a second cube
    without a material (object 4), seen from above: each fills part of the 40 x 30 frame, and the
    frame's corners see nothing."""
    scene = bpy.context.scene
    mesh = bpy.data.meshes.new("floor")
    mesh.from_pydata([(-1.8, -1, 0), (1.8, -1, 0), (1.8, 1, 0), (-1.8, 1, 0)], [], [(0, 1, 2, 3)])
    floor = bpy.data.objects.new("floor", mesh)
    scene.collection.objects.link(floor)
    floor.pass_index = 3
    floor.data.materials.append(bpy.data.materials.new("floor"))
    floor.data.materials[0].pass_index = 2
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(-1.0, 0.0, 0.5))
    bpy.context.object.pass_index = 7
    bpy.context.object.data.materials.append(bpy.data.materials.new("cube"))
    bpy.context.object.data.materials[0].pass_index = 5
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(1.0, 0.0, 0.5))
    bpy.context.object.pass_index = 4
    camera_looking_down(scene, 6.0, 40, 30)
    lamp = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "POINT"))
    lamp.location = (0.0, 0.0, 3.0)
    scene.collection.objects.link(lamp)
    return scene


def pixel_of(scene, x, y):
    """The (row from the bottom, column) where the floor's point (x, y) lands."""
    cam = scene.camera
    half = 6.0 * np.tan(cam.data.angle / 2)  # the frame's half width at the floor's distance
    return int(15 + (y / half) * 20), int(20 + (x / half) * 20)


def test_each_pixel_reports_the_pass_index_of_the_object_and_material_it_sees():
    scene = indexed_scene()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    core_scene, camera_args, indices = export.build_scene(ppm_core, depsgraph, Frame.from_render_settings(
        scene.render), print)
    objects, materials = passes.index_passes(passes.camera_hits(core_scene), camera_args, indices)
    assert objects.shape == materials.shape == (30, 40)
    for (x, y), obj, mat in [((-1.0, 0.0), 7, 5), ((1.0, 0.0), 4, 0), ((0.0, 0.8), 3, 2)]:
        row, col = pixel_of(scene, x, y)
        assert (objects[row, col], materials[row, col]) == (obj, mat), (x, y)
    assert objects[0, 0] == materials[0, 0] == 0  # beyond the floor: nothing
    assert set(np.unique(objects)) == {0, 3, 4, 7} and set(np.unique(materials)) == {0, 2, 5}


def test_the_engine_writes_the_index_passes_the_view_layer_enables(monkeypatch, tmp_path):
    scene = indexed_scene()
    layer = bpy.context.view_layer
    layer.use_pass_object_index = True
    written = {}
    monkeypatch.setattr(passes, "write_pass", lambda result, name, pixels: written.setdefault(name, pixels))
    render_file(scene, tmp_path / "i.exr", passes=1, photons_per_pass=2000)
    assert set(written) == {"IndexOB", "IndexMA"}
    row, col = pixel_of(scene, -1.0, 0.0)
    assert written["IndexOB"][row, col] == 7
    layer.use_pass_object_index = False
    written.clear()
    render_file(scene, tmp_path / "j.exr", passes=1, photons_per_pass=2000)
    assert written == {}


def test_the_engine_writes_the_error_passes_when_asked(monkeypatch, tmp_path):
    scene = indexed_scene()
    written = {}
    monkeypatch.setattr(passes, "write_pass", lambda result, name, pixels: written.setdefault(
        name, (pixels, result.layers[0].passes.get(name) is not None)))
    render_file(scene, tmp_path / "e.exr", passes=4, photons_per_pass=2000, error_passes=True)
    assert set(written) == set(passes.ERROR_PASSES)
    for name, (pixels, registered) in written.items():
        assert registered and pixels.shape == (30, 40) and np.all(np.isfinite(pixels)), name
    error, bias, noise = (written[name][0] for name in ("Error", "Bias", "Noise"))
    row, col = pixel_of(scene, 0.0, 0.8)  # the lit floor
    assert noise[row, col] >= 0.0 and error[row, col] > 0.0
    scene.ppm.error_passes = False
    written.clear()
    render_file(scene, tmp_path / "f.exr", passes=1, photons_per_pass=2000)
    assert written == {}
