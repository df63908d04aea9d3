"""The fingerprint that finds Cycles' stored image of a comparison scene (cycles_references.py): the same
for the same scene built in another process and folder, different when anything Cycles reads changes,
and a stored image read back as it was written. Blender 5.0 (bpy); every version's own fingerprints are
checked by test_blender_versions.py, which finds its stored images or fails."""

import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import bpy  # noqa: E402

import cycles_compare  # noqa: E402
import cycles_references  # noqa: E402

TEXTURE = os.path.join(bpy.utils.system_resource("DATAFILES"), "studiolights", "world")
BUILD = """
import sys
sys.path.insert(0, {here!r})
import bpy, cycles_compare, cycles_references
cycles_compare.build("point")
image = bpy.data.images.load({texture!r})
cycles_compare.configure_cycles(bpy.context.scene, 64)
print("fingerprint", cycles_references.fingerprint())
"""


def hdri():
    return os.path.join(TEXTURE, sorted(f for f in os.listdir(TEXTURE) if f.endswith(".exr"))[0])


def fingerprint_in_a_new_process(folder):
    """A case built in a fresh Blender 5.0 whose image texture is a copy in `folder` (another path)."""
    os.makedirs(folder)
    texture = shutil.copy(hdri(), folder)
    run = subprocess.run([sys.executable, "-c", BUILD.format(here=HERE, texture=texture)], cwd=folder,
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr[-2000:]
    return run.stdout.split("fingerprint ")[1].split()[0]


def test_one_scene_built_in_two_processes_and_folders_has_one_fingerprint(tmp_path):
    first = fingerprint_in_a_new_process(str(tmp_path / "a"))
    assert len(first) == 64 and first == fingerprint_in_a_new_process(str(tmp_path / "elsewhere" / "b"))


@pytest.fixture
def scene():
    cycles_compare.build("point")
    material = cycles_compare.diffuse_material("painted", (0.5, 0.5, 0.5))
    cycles_compare.ball("ball", (0.0, 0.0, 0.3), 0.2, material)
    mesh = bpy.data.objects["ball"].data
    mesh.uv_layers.new(name="uv")
    mesh.color_attributes.new("paint", "FLOAT_COLOR", "POINT")
    generated = bpy.data.images.new("generated", 4, 4)
    texture = material.node_tree.nodes.new("ShaderNodeTexImage")
    texture.image = generated
    cycles_compare.configure_cycles(bpy.context.scene, 64)
    return bpy.context.scene


def set_pixel(image):
    pixels = np.zeros(len(image.pixels), dtype=np.float32)
    pixels[5] = 0.7
    image.pixels.foreach_set(pixels)


def link_texture(material):
    tree = material.node_tree
    tree.links.new(tree.nodes["Image Texture"].outputs["Color"], tree.nodes["Diffuse BSDF"].inputs["Color"])


EDITS = {
    "a light's power": lambda s: setattr(bpy.data.lights[0], "energy", bpy.data.lights[0].energy * 1.01),
    "a vertex": lambda s: setattr(bpy.data.objects["ball"].data.vertices[3].co, "x", 0.01),
    "a uv": lambda s: setattr(bpy.data.objects["ball"].data.uv_layers["uv"].data[7].uv, "x", 0.3),
    "a colour attribute": lambda s: setattr(
        bpy.data.objects["ball"].data.color_attributes["paint"].data[2], "color", (1.0, 0.0, 0.0, 1.0)),
    "a node's input": lambda s: setattr(
        bpy.data.materials["painted"].node_tree.nodes["Diffuse BSDF"].inputs["Roughness"], "default_value", 0.3),
    "a link": lambda s: link_texture(bpy.data.materials["painted"]),
    "an image's pixel": lambda s: set_pixel(bpy.data.images["generated"]),
    "the samples": lambda s: setattr(s.cycles, "samples", 65),
    "an object hidden from renders": lambda s: setattr(bpy.data.objects["ball"], "hide_render", True),
    "an object moved": lambda s: setattr(bpy.data.objects["ball"].location, "z", 0.31),
    "the exposure": lambda s: setattr(s.view_settings, "exposure", 0.5),
}


@pytest.mark.parametrize("edit", EDITS)
def test_any_change_cycles_reads_changes_the_fingerprint(scene, edit):
    before = cycles_references.fingerprint()
    assert cycles_references.fingerprint() == before
    EDITS[edit](scene)
    assert cycles_references.fingerprint() != before


def test_an_image_file_is_known_by_its_contents(scene, tmp_path):
    path = str(tmp_path / "texture.exr")
    shutil.copy(hdri(), path)
    bpy.data.images.load(path)
    before = cycles_references.fingerprint()
    other = [f for f in sorted(os.listdir(TEXTURE)) if f.endswith(".exr")][1]
    shutil.copy(os.path.join(TEXTURE, other), path)
    assert cycles_references.fingerprint() != before


def test_the_stored_image_of_a_case_is_what_cycles_renders_for_it(tmp_path):
    """cycles_compare's point light as in_blender.py renders it (128 samples): its stored image is found and
    is this Cycles' image (a machine with other vector instructions may differ by rounding)."""
    cycles_compare.build("point")
    blend = str(tmp_path / "point.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    bpy.ops.wm.open_mainfile(filepath=blend)
    scene = bpy.context.scene
    cycles_compare.configure_cycles(scene, 128)
    scene.render.filepath = str(tmp_path / "point_CYCLES.exr")  # as render_to_array names it
    stored, _ = cycles_references.lookup("point_CYCLES")
    assert stored is not None
    bpy.ops.render.render(write_still=True)
    live = cycles_compare.read_image(scene.render.filepath)
    blocks = [cycles_compare.block_means(image[..., :3]) for image in (stored, live)]
    np.testing.assert_allclose(blocks[0], blocks[1], rtol=2e-3)
    assert np.mean(np.isclose(stored, live, rtol=2.0 ** -10, atol=1e-6)) > 0.99


def test_a_stored_image_is_found_for_its_scene_alone(scene, tmp_path, monkeypatch):
    monkeypatch.setattr(cycles_references, "STORE", str(tmp_path))
    monkeypatch.setattr(cycles_references, "RECORD", True)
    rgba = np.random.default_rng(1).uniform(0.0, 4.0, (48, 64, 4)).astype(np.float32)
    assert cycles_references.lookup("case")[0] is None
    cycles_references.store("case", cycles_references.fingerprint(), rgba)
    found, _ = cycles_references.lookup("case")
    np.testing.assert_allclose(found, rgba, rtol=2.0 ** -11)
    scene.cycles.samples += 1
    assert cycles_references.lookup("case")[0] is None


def test_a_mesh_is_known_by_its_faces_not_their_order():
    """Blender 3.4 builds one UV sphere with its faces and corners in another order in each process."""
    def fingerprint_of(faces):
        cycles_compare.reset()
        mesh = bpy.data.meshes.new("quad_pair")
        mesh.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0, 0), (2, 1, 0)], [], faces)
        bpy.context.scene.collection.objects.link(bpy.data.objects.new("quads", mesh))
        return cycles_references.fingerprint()

    first = fingerprint_of([(0, 1, 2, 3), (1, 4, 5, 2)])
    assert fingerprint_of([(4, 5, 2, 1), (2, 3, 0, 1)]) == first  # other order, other first corners
    assert fingerprint_of([(0, 3, 2, 1), (1, 4, 5, 2)]) != first  # a face turned over
