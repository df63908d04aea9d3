"""Cycles' light passes, when the view layer enables them: Emit and Env, what camera rays see at no
bounce (the core's Renderer.light_passes); Diffuse, Glossy, Transmission and Volume Direct and
Indirect, the light by component (Renderer.component_passes), which add up to the image."""

import numpy as np
from test_media import volume_world

from conftest import bpy, camera_looking_down, render_file, shader_material
from ppm_render import passes

GLOW, SKY = (1.0, 0.5, 0.25), (0.05, 0.1, 0.2)


def record_passes(monkeypatch):
    """{pass name: (pixels, whether the result declared it)} of every pass the engine writes."""
    written = {}
    monkeypatch.setattr(passes, "write_pass", lambda result, name, pixels: written.setdefault(
        name, (np.array(pixels), result.layers[0].passes.get(name) is not None)))
    return written


def diffuse_floor(rgb):
    """A 20 m diffuse floor of colour `rgb` at z = 0; the scene."""
    scene = bpy.context.scene
    mesh = bpy.data.meshes.new("floor")
    mesh.from_pydata([(-10, -10, 0), (10, -10, 0), (10, 10, 0), (-10, 10, 0)], [], [(0, 1, 2, 3)])
    floor = bpy.data.objects.new("floor", mesh)
    floor.data.materials.append(shader_material("paint", "ShaderNodeBsdfDiffuse", Color=(*rgb, 1.0)))
    scene.collection.objects.link(floor)
    return scene


def surface_light(get):
    """(Dir + Ind) * Col summed over the Diffuse, Glossy and Transmission passes: their light again."""
    return sum((get[k + "Dir"] + get[k + "Ind"]) * get[k + "Col"] for k in ("Diff", "Gloss", "Trans"))


def panel_and_sky():
    """An emissive panel (strength 2) fills the left half of the view of a camera looking down; the
    world's colour is everywhere else."""
    scene = bpy.context.scene
    mesh = bpy.data.meshes.new("panel")
    mesh.from_pydata([(-10, -10, 0), (0, -10, 0), (0, 10, 0), (-10, 10, 0)], [], [(0, 1, 2, 3)])
    panel = bpy.data.objects.new("panel", mesh)
    panel.data.materials.append(shader_material("glow", "ShaderNodeEmission", Color=(*GLOW, 1.0), Strength=2.0))
    scene.collection.objects.link(panel)
    scene.world = bpy.data.worlds.new("sky")
    scene.world.color = SKY
    if scene.world.node_tree is not None:  # Blender 5.0 makes worlds with a Background node
        scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (*SKY, 1.0)
    camera_looking_down(scene, 4.0, 40, 30)
    return scene


def test_emit_and_env_are_written_when_the_view_layer_asks(monkeypatch, tmp_path):
    written = record_passes(monkeypatch)
    scene = panel_and_sky()
    layer = bpy.context.view_layer
    layer.use_pass_emit = layer.use_pass_environment = True
    image = render_file(scene, tmp_path / "l.exr", passes=2, photons_per_pass=1000)
    (emit, emit_registered), (env, env_registered) = written["Emit"], written["Env"]
    assert emit_registered and env_registered and emit.shape == env.shape == (30, 40, 3)
    np.testing.assert_allclose(emit[:, 3:17], np.broadcast_to(np.multiply(GLOW, 2.0), (30, 14, 3)), rtol=1e-4)
    np.testing.assert_allclose(env[:, 23:37], np.broadcast_to(SKY, (30, 14, 3)), rtol=1e-4)
    assert not env[:, 3:17].any() and not emit[:, 23:37].any()
    np.testing.assert_allclose((emit + env)[::-1], image[..., :3], atol=1e-4)  # nothing else lit here
    layer.use_pass_emit = layer.use_pass_environment = False
    written.clear()
    render_file(scene, tmp_path / "m.exr", passes=1, photons_per_pass=1000)
    assert "Emit" not in written and "Env" not in written


def test_diffuse_glossy_and_transmission_passes_are_cycles_light_over_colour(monkeypatch, tmp_path):
    """A diffuse floor under a sun: Diffuse Direct is the light (Cycles divides it by Diffuse Color),
    DiffCol the floor's colour, and (Dir + Ind) * Col with Emit and Env give the image back."""
    written = record_passes(monkeypatch)
    scene = diffuse_floor((0.5, 0.25, 0.125))
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 3.0
    scene.collection.objects.link(sun)
    scene.world = bpy.data.worlds.new("black")
    scene.world.color = (0.0, 0.0, 0.0)
    if scene.world.node_tree is not None:
        scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    camera_looking_down(scene, 4.0, 40, 30)
    layer = bpy.context.view_layer
    names = [name for name, _ in passes.COMPONENT_PASSES]
    for _, toggle in passes.COMPONENT_PASSES:
        setattr(layer, toggle, True)
    scene.ppm.caustic_pass = True
    try:
        image = render_file(scene, tmp_path / "c.exr", passes=2, photons_per_pass=1000)
    finally:
        for _, toggle in passes.COMPONENT_PASSES:
            setattr(layer, toggle, False)
        scene.ppm.caustic_pass = False
    assert all(written[name][1] for name in names + ["Caustic"])
    get = {name: written[name][0] for name in names + ["Caustic"]}
    np.testing.assert_allclose(get["DiffCol"], np.broadcast_to((0.5, 0.25, 0.125), (30, 40, 3)), rtol=1e-5)
    # A sun of strength 3 straight down: irradiance 3, radiance 3 / pi per unit of colour.
    np.testing.assert_allclose(get["DiffDir"], 3.0 / np.pi, rtol=1e-4)
    assert not get["Caustic"].any() and not get["GlossDir"].any() and not get["TransCol"].any()
    np.testing.assert_allclose(surface_light(get)[::-1], image[..., :3], rtol=1e-4, atol=1e-6)


def test_volume_passes_hold_the_fogs_light_and_the_passes_add_up(monkeypatch, tmp_path):
    """The floor under a point light in the World's fog, the camera in it: Volume Direct and Indirect
    (Cycles' toggles, view_layer.cycles) hold the fog's light, radiance without a Color pass, and with
    the floor's passes give the image back."""
    written = record_passes(monkeypatch)
    scene = diffuse_floor((0.5, 0.5, 0.5))
    lamp = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "POINT"))
    lamp.data.energy, lamp.location = 300.0, (1.0, 0.0, 3.0)
    scene.collection.objects.link(lamp)
    volume_world("fog", "ShaderNodeVolumeScatter", strength=0.0, Density=0.2)
    camera_looking_down(scene, 4.0, 40, 30)
    layer = bpy.context.view_layer
    toggles = [toggle for _, toggle in passes.COMPONENT_PASSES]
    for toggle in toggles:
        setattr(layer, toggle, True)
    for _, toggle in passes.VOLUME_PASSES:
        setattr(layer.cycles, toggle, True)
    image = render_file(scene, tmp_path / "v.exr", passes=4, photons_per_pass=5000)
    get = {name: pixels for name, (pixels, registered) in written.items() if registered}
    assert {"VolumeDir", "VolumeInd"} <= set(get), sorted(written)
    assert get["VolumeDir"].mean() > 0.01 and get["VolumeInd"].mean() > 0.0
    rebuilt = surface_light(get) + get["VolumeDir"] + get["VolumeInd"]
    np.testing.assert_allclose(rebuilt[::-1], image[..., :3], rtol=1e-4, atol=1e-5)
