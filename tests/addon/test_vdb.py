"""The add-on's OpenVDB reader (export/vdb.py) on files Blender's own OpenVDB wrote (tests/data/smoke_*.vdb,
a smoke simulation's cache: make_smoke_vdb.py): the density grid voxel for voxel as Blender holds it,
ZIP float and Blosc half; the grids' layout through the core's lookup; files it cannot read refused
with a reason, never a crash."""

import os
import struct

import numpy as np
import pytest

import ppm_core
from ppm_render.export import vdb

DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "data")


def read(name, **keywords):
    return vdb.read(os.path.join(DATA, name), blosc=ppm_core.blosc_decompress, **keywords)


def dense(grid, shape):
    """The grid's leaves and tiles as a dense (z, y, x) array from index 0."""
    out = np.zeros(tuple(n + 8 for n in shape[::-1]), np.float32)  # (x, y, z)
    for (x, y, z), values in zip(grid.origins, grid.values):
        out[x:x + 8, y:y + 8, z:z + 8] = values[:, 0].reshape(8, 8, 8)  # z fastest
    for origins, values in zip(grid.tile_origins, grid.tile_values):
        for (x, y, z), value in zip(origins, values):
            out[x:x + 8, y:y + 8, z:z + 8] = value[0]
    return out[:shape[2], :shape[1], :shape[0]].transpose(2, 1, 0)


@pytest.mark.parametrize("name, tolerance", [("smoke_zip.vdb", 0.0), ("smoke_blosc_half.vdb", 1e-3)])
def test_a_simulations_density_reads_as_blender_holds_it(name, tolerance):
    """Every voxel of the cache's density equals the domain's density_grid at that frame (exactly from
    ZIP floats; within half's rounding, 2^-11 relative, from Blosc halves)."""
    reference = np.load(os.path.join(DATA, "smoke_density.npy"))
    grids = read(name)
    assert {"density", "temperature", "flame", "velocity"} <= set(grids)
    density = grids["density"]
    assert density.grid_class == "fog volume" and density.channels == 1
    np.testing.assert_allclose(dense(density, reference.shape), reference, rtol=tolerance, atol=1e-6)
    assert grids["velocity"].channels == 3
    # The index-to-object map: a uniform voxel size, no rotation.
    m = density.index_to_object
    assert m[0, 0] > 0 and m[0, 0] == m[1, 1] == m[2, 2] and not np.any(m[:3, :3] - np.diag(np.diag(m[:3, :3])))


def test_names_pick_the_grids_read():
    assert set(read("smoke_zip.vdb", names={"density"})) == {"density"}


def test_the_core_looks_a_grid_up_at_its_voxel_centres():
    """add_sparse_grid with the reader's bricks: the program's grid instruction at index (i, j, k)
    mapped to object space reads voxel (i, j, k) of Blender's density."""
    reference = np.load(os.path.join(DATA, "smoke_density.npy"))
    grid = read("smoke_zip.vdb", names={"density"})["density"]
    scene = ppm_core.Scene()
    index = scene.add_sparse_grid("density", grid.values, grid.origins, np.linalg.inv(grid.index_to_object))
    scene.set_object_info(0, np.eye(4), grids=[index])
    program = {"constants": [], "code": [{"op": "coord", "mode": 3, "out": [1]},  # Object
                                         {"op": "grid", "in": [1], "out": [2, 3, 4], "data": 0}],
               "outputs": [3], "registers": 5}
    k, j, i = np.nonzero(reference > 0.05)
    points = (grid.index_to_object @ np.stack([i, j, k, np.ones_like(i)]).astype(float))[:3].T
    values = scene.run_program(program, points, object=0)[:, 0, 0]
    np.testing.assert_allclose(values, reference[k, j, i], rtol=1e-5)


def header(version=224):
    return struct.pack("<qIIIB", vdb.MAGIC, version, 10, 0, 1) + b"0" * 36


@pytest.mark.parametrize("data, reason", [
    (b"not a vdb", "not an OpenVDB file"),
    (header(221), "older than"),
    (header(), "ends before"),
])
def test_files_it_cannot_read_are_refused_with_a_reason(data, reason):
    with pytest.raises(vdb.VdbError, match=reason):
        vdb.read_bytes(data)


def test_a_truncated_or_corrupt_file_is_refused():
    with open(os.path.join(DATA, "smoke_zip.vdb"), "rb") as f:
        data = f.read()
    with pytest.raises(vdb.VdbError):
        vdb.read_bytes(data[:len(data) // 2])
    corrupt = bytearray(data)
    corrupt[len(data) // 2:len(data) // 2 + 64] = b"\xff" * 64  # inside the leaves' ZIP data
    with pytest.raises(vdb.VdbError):
        vdb.read_bytes(bytes(corrupt))
    with pytest.raises(vdb.VdbError, match="cannot be read"):
        vdb.read(os.path.join(DATA, "no such file.vdb"))


def test_corrupt_bytes_anywhere_read_or_raise_vdb_error_only():
    """300 copies of the Blosc file with 8 random bytes overwritten each: every one reads, or raises
    VdbError (never another exception, never a crash in the core's Blosc decoder)."""
    with open(os.path.join(DATA, "smoke_blosc_half.vdb"), "rb") as f:
        data = f.read()
    rng = np.random.default_rng(7)
    for _ in range(300):
        corrupt = bytearray(data)
        for at in rng.integers(0, len(data), 8):
            corrupt[at] = int(rng.integers(0, 256))
        try:
            vdb.read_bytes(bytes(corrupt), blosc=ppm_core.blosc_decompress)
        except vdb.VdbError:
            pass


def volume_object(scene, path, material=True):
    """A Volume object of the .vdb at `path` (scaled 0.5), with a Principled Volume of density 4 (its
    Density and Temperature Attributes read density and temperature) and a blackbody."""
    import bpy

    volume = bpy.data.volumes.new("vdb")
    volume.filepath = path
    obj = bpy.data.objects.new("vdb", volume)
    obj.scale = (0.5, 0.5, 0.5)
    scene.collection.objects.link(obj)
    if material:
        mat = bpy.data.materials.new("vdb")
        if mat.node_tree is None or bpy.app.version < (5, 0, 0):
            mat.use_nodes = True
        nodes = mat.node_tree.nodes
        nodes.clear()
        out, principled = nodes.new("ShaderNodeOutputMaterial"), nodes.new("ShaderNodeVolumePrincipled")
        principled.inputs["Density"].default_value = 4.0
        principled.inputs["Blackbody Intensity"].default_value = 1.0
        mat.node_tree.links.new(principled.outputs["Volume"], out.inputs["Volume"])
        volume.materials.append(mat)
    return obj


def test_a_volume_object_exports_the_grids_its_material_reads_and_renders(tmp_path):
    """The smoke cache as a Volume object: no warning; the core holds its density and temperature grids
    (the material's attributes), not its shadow, flame or velocity; its glow shows in the render."""
    from test_forgiving_input import export_scene, floor_scene, renders

    scene = floor_scene()
    volume_object(scene, os.path.join(DATA, "smoke_zip.vdb"))
    core_scene, warnings = export_scene(scene)
    assert warnings == [], warnings
    assert core_scene.grid_count() == 2 and core_scene.grid_info(0)["max_value"] > 0.5
    lit = renders(scene, tmp_path)
    assert lit[..., 0].max() > 2.0 * np.median(lit[..., 0])  # the fire's glow above the floor


@pytest.mark.parametrize("case, reason", [("missing", "cannot be loaded"), ("corrupt", "its file"),
                                          ("no material", "no material with a Volume output")])
def test_a_volume_object_it_cannot_render_is_named_once_and_the_frame_renders(case, reason, tmp_path):
    from test_forgiving_input import export_scene, floor_scene, renders

    scene = floor_scene()
    path = os.path.join(DATA, "smoke_zip.vdb")
    if case == "missing":
        path = str(tmp_path / "gone.vdb")
    elif case == "corrupt":
        path = str(tmp_path / "corrupt.vdb")
        with open(os.path.join(DATA, "smoke_zip.vdb"), "rb") as f:
            data = bytearray(f.read())
        with open(path, "wb") as f:
            f.write(bytes(data[:len(data) // 3]))
    volume_object(scene, path, material=case != "no material")
    _, warnings = export_scene(scene)
    assert sum("object 'vdb'" in w and reason in w for w in warnings) == 1, warnings
    renders(scene, tmp_path)


def test_a_volume_objects_grid_of_any_name_is_read_by_the_attribute_that_names_it():
    """The cache's "shadow" grid (not one of Cycles' standard names) read by the Principled Volume's
    Density Attribute: the core holds it (its largest value, 1) beside the temperature."""
    from test_forgiving_input import export_scene, floor_scene

    scene = floor_scene()
    obj = volume_object(scene, os.path.join(DATA, "smoke_zip.vdb"))
    principled = next(n for n in obj.data.materials[0].node_tree.nodes if n.bl_idname == "ShaderNodeVolumePrincipled")
    principled.inputs["Density Attribute"].default_value = "shadow"
    core_scene, warnings = export_scene(scene)
    assert warnings == [], warnings
    maxima = sorted(core_scene.grid_info(i)["max_value"] for i in range(core_scene.grid_count()))
    assert len(maxima) == 2 and maxima[0] == 1.0  # shadow (1.0) and temperature (2.9)
