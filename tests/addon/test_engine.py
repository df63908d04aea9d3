"""Engine behaviour: settings reach the core, time limit, cancel, border, errors and warnings."""

import math
import time

import numpy as np
import pytest

from conftest import bpy, camera_looking_down, render_file
from ppm_render import core, engine, export, properties
from ppm_render.export import material as material_export
from ppm_render.properties import CORE_KEYS

ppm_core = core.load()


def simple_scene(width=40, height=30):
    scene = bpy.context.scene
    mesh = bpy.data.meshes.new("floor")
    mesh.from_pydata([(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], [], [(0, 1, 2, 3)])
    scene.collection.objects.link(bpy.data.objects.new("floor", mesh))
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 2.0
    scene.collection.objects.link(sun)
    lamp = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "POINT"))
    lamp.location = (0.5, 0.3, 1.0)
    scene.collection.objects.link(lamp)
    camera_looking_down(scene, 3.0, width, height)
    scene.render.engine = "PPM"
    return scene


class Spy:
    """Stands in for the ppm_core module and records the Renderer the engine makes."""

    def __init__(self):
        self.renderers, self.kwargs = [], []
        self.Scene = ppm_core.Scene

    def Renderer(self, scene, **kwargs):
        self.kwargs.append(kwargs)
        self.renderers.append(ppm_core.Renderer(scene, **kwargs))
        return self.renderers[-1]


@pytest.fixture
def spy(monkeypatch):
    s = Spy()
    monkeypatch.setattr(engine.core, "load", lambda: s)
    return s


def test_settings_reach_the_core(spy, tmp_path):
    scene = simple_scene()
    values = {"photons_per_pass": 12_345, "alpha": 0.55, "threshold": 3, "max_bounces": 5,
              "samples_per_pixel": 2, "seed": 17, "threads": 1, "adaptive_samples": 3}
    render_file(scene, tmp_path / "a.exr", passes=3, animated_seed=False, **values)
    renderer = spy.renderers[-1]
    for key, value in values.items():
        assert renderer.settings[key] == pytest.approx(value), key
    assert set(spy.kwargs[-1]) == set(CORE_KEYS) | {"dof_mode", "hit_points", "transparent_background",
                                                    "transparent_glass", "light_path_limits", "light_passes",
                                                    "component_passes"}
    assert spy.kwargs[-1]["light_path_limits"] is False
    assert renderer.settings["dof_mode"] == "off" and renderer.settings["hit_points"] == "stochastic"
    stats = renderer.stats()
    assert stats["passes"] == 3
    assert stats["photons_emitted"] == 3 * 12_345


def test_cycles_light_paths_reach_the_core(spy, tmp_path):
    """With Cycles Light Paths on, the scene's Cycles Max Bounces go to the core; a light's and the
    world's own Max Bounces go with them either way."""
    scene = simple_scene()
    cycles = scene.cycles
    cycles.max_bounces, cycles.diffuse_bounces, cycles.glossy_bounces, cycles.transmission_bounces = 7, 1, 2, 3
    cycles.volume_bounces = 4
    lamp = next(o for o in scene.objects if o.type == "LIGHT")
    lamp.data.cycles.max_bounces = 5
    scene.world = bpy.data.worlds.new("limited world")
    scene.world.cycles.max_bounces = 2
    render_file(scene, tmp_path / "a.exr", passes=1, cycles_light_paths=True)
    assert {k: spy.kwargs[-1][k] for k in ("light_path_limits", "total_bounces", "diffuse_bounces",
                                           "glossy_bounces", "transmission_bounces", "volume_bounces")} == {
        "light_path_limits": True, "total_bounces": 7, "diffuse_bounces": 1, "glossy_bounces": 2,
        "transmission_bounces": 3, "volume_bounces": 4}
    renderer = spy.renderers[-1]
    assert renderer.settings["light_path_limits"] is True and renderer.settings["diffuse_bounces"] == 1
    assert renderer.settings["volume_bounces"] == 4
    assert export.visibility.own_max_bounces(lamp.data) == 5
    assert export.visibility.own_max_bounces(scene.world) == 2
    render_file(scene, tmp_path / "b.exr", passes=1, cycles_light_paths=False)
    assert spy.kwargs[-1]["light_path_limits"] is False and "diffuse_bounces" not in spy.kwargs[-1]


def test_an_animated_seed_differs_from_frame_to_frame():
    scene = bpy.context.scene
    scene.ppm.seed = 17
    seeds = {}
    for animated in (True, False):
        scene.ppm.animated_seed = animated
        for frame in (-3, 1, 2):
            scene.frame_current = frame
            seeds[animated, frame] = properties.core_settings(scene.ppm)["seed"]
    assert len({seeds[True, f] for f in (-3, 1, 2)}) == 3
    assert all(0 <= seeds[True, f] < 2**63 for f in (-3, 1, 2))
    assert {seeds[False, f] for f in (-3, 1, 2)} == {17}


def test_the_largest_alpha_the_panel_allows_renders():
    scene = bpy.context.scene
    scene.ppm.alpha = 1.0  # clamped by the property: the core refuses alpha >= 1
    assert scene.ppm.alpha < 1.0
    core.load().Settings(**properties.core_settings(scene.ppm))


def test_time_limit_ends_the_render(spy, tmp_path):
    scene = simple_scene(160, 120)
    start = time.monotonic()
    render_file(scene, tmp_path / "t.exr", passes=100_000, time_limit=1.0, photons_per_pass=50_000)
    assert time.monotonic() - start < 4.0
    assert 0 < spy.renderers[-1].stats()["passes"] < 100_000


def test_target_error_ends_the_render_and_the_stats_show_the_estimate(spy, monkeypatch, tmp_path):
    lines = []
    original = engine.ProgressiveDisplay.line
    monkeypatch.setattr(engine.ProgressiveDisplay, "line",
                        lambda self, passes, photons: lines.append(original(self, passes, photons)) or lines[-1])
    render_file(simple_scene(64, 48), tmp_path / "e.exr", passes=100_000, target_error=0.05,
                photons_per_pass=20_000)
    stats = spy.renderers[-1].stats()
    assert stats["target_error_reached"] and stats["error"]["bound"] <= 0.05
    assert spy.renderers[-1].settings["error_min_passes"] <= stats["passes"] < 100_000
    assert "est. error" in lines[-1] and "est. error" not in lines[0]  # unknown before two passes


def test_a_target_error_with_one_fixed_sample_per_pixel_warns_that_the_estimate_leaves_out_anti_aliasing(
        monkeypatch, tmp_path):
    warnings = []
    monkeypatch.setattr(engine.PPMRenderEngine, "warn", lambda self, message: warnings.append(message))
    scene = simple_scene()
    fixed = {"passes": 3, "photons_per_pass": 5_000, "hit_points": "FIXED"}
    render_file(scene, tmp_path / "f.exr", **fixed, samples_per_pixel=1)
    render_file(scene, tmp_path / "f.exr", **fixed, samples_per_pixel=4, target_error=0.5)
    assert not [w for w in warnings if "anti-aliasing" in w]  # no target, or samples to measure it from
    render_file(scene, tmp_path / "f.exr", **fixed, samples_per_pixel=1, target_error=0.5)
    assert len([w for w in warnings if "anti-aliasing" in w]) == 1


def test_escape_cancels_quickly_and_keeps_the_image(spy, monkeypatch, tmp_path):
    scene = simple_scene(160, 120)
    start = time.monotonic()
    # Blender's test_break() cannot be patched on the RNA class; the display's hook can.
    monkeypatch.setattr(engine.ProgressiveDisplay, "cancelled", lambda self: time.monotonic() - start > 1.0)
    image = render_file(scene, tmp_path / "c.exr", passes=100_000, photons_per_pass=50_000)
    assert time.monotonic() - start < 2.5  # cancelled within the poll interval, not at the pass count
    assert spy.renderers[-1].stats()["cancelled"]
    assert image[..., :3].mean() > 0.01  # the passes done so far are kept


def test_display_refreshes_about_once_a_second(monkeypatch, tmp_path):
    scene = simple_scene(160, 120)
    shown = []
    original = engine.ProgressiveDisplay.show
    monkeypatch.setattr(engine.ProgressiveDisplay, "show",
                        lambda self: (shown.append(time.monotonic()), original(self)))
    render_file(scene, tmp_path / "p.exr", passes=100_000, time_limit=3.2, photons_per_pass=20_000)
    gaps = np.diff(shown[:-1])  # the last call is the final image
    assert len(shown) >= 3 and (gaps >= 0.99).all() and (gaps < 2.0).all(), gaps


def test_the_header_shows_the_cores_memory(spy, monkeypatch, tmp_path):
    reported = []
    original = engine.ProgressiveDisplay.report_memory
    monkeypatch.setattr(engine.ProgressiveDisplay, "report_memory",
                        lambda self, stats: (original(self, stats), reported.append(self.memory_peak)))
    render_file(simple_scene(160, 120), tmp_path / "m.exr", passes=2, photons_per_pass=20_000)
    memory = spy.renderers[-1].stats()["memory"]
    assert len(reported) == 2
    assert reported[-1] >= sum(memory.values()) / 2**20 > 160 * 120 * 52 / 2**20  # pixels and more


class NoMemoryForFixedHitPoints:
    """A renderer whose first run finds no memory for fixed hit points, as the core's does (memory_budget.h)."""

    def stats(self):
        return {"hit_point_storage": "kept", "skipped": []}

    def run(self, **_):
        raise MemoryError("fixed hit points at 40x30 and 4 samples per pixel needs about 99.0 GB, but 1.0 GB of "
                          "memory are available; use stochastic hit points (52 bytes a pixel) or fewer samples")


def test_fixed_hit_points_without_memory_fall_back_to_stochastic_with_a_warning(spy, monkeypatch, tmp_path):
    scene = simple_scene()
    scene.ppm.hit_points = 'FIXED'
    real, warnings = spy.Renderer, []
    monkeypatch.setattr(spy, "Renderer", lambda s, **kw: NoMemoryForFixedHitPoints() if kw["hit_points"] == "fixed"
                        else real(s, **kw))
    monkeypatch.setattr(engine.PPMRenderEngine, "warn", lambda self, message: warnings.append(message))
    image = render_file(scene, tmp_path / "f.exr", passes=2, photons_per_pass=20_000)
    assert [r.settings["hit_points"] for r in spy.renderers] == ["stochastic"]
    assert spy.renderers[0].stats()["passes"] == 2 and image[..., :3].mean() > 0.01
    assert any("99.0 GB" in w and "stochastic hit points instead" in w for w in warnings), warnings


def test_streamed_fixed_hit_points_are_said_once(spy, monkeypatch, tmp_path):
    scene = simple_scene()
    scene.ppm.hit_points = 'FIXED'
    real, warnings = spy.Renderer, []
    monkeypatch.setattr(spy, "Renderer", lambda s, **kw: real(s, **kw, hit_point_storage="streamed"))
    monkeypatch.setattr(engine.PPMRenderEngine, "warn", lambda self, message: warnings.append(message))
    image = render_file(scene, tmp_path / "s.exr", passes=2, photons_per_pass=20_000)
    assert spy.renderers[0].stats()["hit_point_storage"] == "streamed" and image[..., :3].mean() > 0.01
    assert [w for w in warnings if "streamed" in w] == ["fixed hit points are streamed: an eye pass every pass"]


def test_an_unexpected_failure_is_reported_not_a_crash(monkeypatch, tmp_path):
    """An exception out of RenderEngine.render crashes Blender 5.0 (the bpy module): the engine
    reports it as an error instead, which makes the render operator raise in a script."""
    def broken(scene):
        raise RuntimeError("no views today")

    monkeypatch.setattr(engine, "render_views", broken)
    with pytest.raises(RuntimeError, match="PPM: no views today"):
        render_file(simple_scene(), tmp_path / "x.exr", passes=1)


def test_border_and_resolution_percentage(tmp_path):
    scene = simple_scene(80, 60)
    scene.render.resolution_percentage = 50
    full = render_file(scene, tmp_path / "full.exr", passes=1, samples_per_pixel=4)
    assert full.shape == (30, 40, 4)
    r = scene.render
    r.use_border, r.use_crop_to_border = True, True
    r.border_min_x, r.border_max_x, r.border_min_y, r.border_max_y = 0.25, 0.75, 0.5, 1.0
    crop = render_file(scene, tmp_path / "crop.exr", passes=1, samples_per_pixel=4)
    assert crop.shape == (15, 20, 4)
    # The top half (border y 0.5..1 from the bottom), columns 10..30: same pixels as the full frame.
    np.testing.assert_allclose(crop[..., :3], full[:15, 10:30, :3], rtol=0.02, atol=1e-4)


@pytest.mark.parametrize("width, height, percentage, border", [
    (50, 40, 58, None), (1280, 720, 70, None), (720, 64, 100, (0.35, 0.5, 0.0, 1.0)),
    (1280, 48, 100, (0.5, 0.7, 0.0, 1.0)), (1920, 32, 100, (0.25, 0.95, 0.0, 1.0)),
    (64, 720, 100, (0.0, 1.0, 0.35, 0.5)), (333, 211, 37, (0.1, 0.9, 0.45, 0.95))])
def test_every_pixel_of_blenders_result_is_rendered(tmp_path, width, height, percentage, border):
    """Sizes where Blender's integer percentage and float32 border edges round otherwise than double
    precision does: the frame is rendered, opaque to its last row and column."""
    scene = simple_scene(width, height)
    scene.render.resolution_percentage = percentage
    scene.render.use_crop_to_border = True
    if border:
        scene.render.use_border = True
        (scene.render.border_min_x, scene.render.border_max_x,
         scene.render.border_min_y, scene.render.border_max_y) = border
    pixels = render_file(scene, tmp_path / "x.exr", passes=1, photons_per_pass=1000)
    frame = engine.Frame.from_render_settings(scene.render)
    assert pixels.shape[:2] == (frame.window_height, frame.window_width)  # Blender's result, as the export sized it
    assert np.all(pixels[..., 3] == 1.0)


def test_core_messages_keep_their_numbers_with_bpy_loaded():
    """Numbers written into the core's messages vanished in bpy while the core's static C++ runtime
    exported its symbols (they bound to the runtime Blender had loaded)."""
    scene = ppm_core.Scene()
    with pytest.raises(ValueError) as error:
        scene.add_light("point", name="bright", power=1e21)
    assert str(error.value) == "light 'bright': power 1e+21 is above the supported 1e+20"
    with pytest.raises(ValueError) as error:
        scene.add_bezier_revolve("r", points=np.array([[0.5, 0.0], [np.nan, 1.0]]),
                                 material=scene.add_material("m", "diffuse"))
    assert "point 1 has a non-finite radius (nan)" in str(error.value)


def test_core_errors_reach_the_user_once(monkeypatch):
    simple_scene()

    def broken(*args, **kwargs):
        raise ValueError("mesh 'floor': something precise")

    monkeypatch.setattr(engine.export, "build_scene", broken)
    with pytest.raises(RuntimeError, match="PPM: mesh 'floor': something precise") as error:
        bpy.ops.render.render()
    assert str(error.value).count("PPM:") == 1, str(error.value)  # once, not once per channel


def test_unsupported_node_warns_once_naming_material_and_node():
    mat = bpy.data.materials.new("odd")
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    tree = mat.node_tree
    toon = tree.nodes.new("ShaderNodeBsdfToon")
    out = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    tree.links.new(toon.outputs[0], out.inputs["Surface"])
    warnings = []
    exporter = material_export.MaterialExporter(ppm_core.Scene(), warnings.append)
    first = exporter.index(mat)
    assert exporter.index(mat) == first
    assert len(warnings) == 1 and "odd" in warnings[0] and toon.name in warnings[0]


def test_instances_are_exported_with_their_own_matrices():
    scene = simple_scene()
    coll = bpy.data.collections.new("things")
    scene.collection.children.link(coll)
    mesh = bpy.data.meshes.new("tri")
    mesh.from_pydata([(0, 0, 0), (0.2, 0, 0), (0, 0.2, 0)], [], [(0, 1, 2)])
    coll.objects.link(bpy.data.objects.new("tri", mesh))
    bpy.context.view_layer.layer_collection.children["things"].exclude = True
    for i in range(3):
        empty = bpy.data.objects.new(f"inst{i}", None)
        empty.instance_type, empty.instance_collection = "COLLECTION", coll
        empty.location = (i, 0.0, 1.0)
        scene.collection.objects.link(empty)
    exporter = export.Exporter(ppm_core.Scene(), print)
    for instance in bpy.context.evaluated_depsgraph_get().object_instances:
        exporter.visit(instance)
    assert exporter.triangles == 2 + 3  # the floor quad + three instanced triangles
    exporter.scene.set_camera(np.eye(4), 4, 4)
    origins = np.array([[i + 0.05, 0.05, 2.0] for i in range(3)])
    hits = exporter.scene.intersect(origins, np.tile([0.0, 0.0, -1.0], (3, 1)))
    np.testing.assert_allclose(hits["t"], 1.0, atol=1e-6)


def test_a_million_triangles_export_whole():
    """Every triangle of a 708x708 grid reaches the core (its speed: bench/run.py export_speed)."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=708, y_subdivisions=708, size=2.0)
    obj = bpy.context.object
    depsgraph = bpy.context.evaluated_depsgraph_get()
    exporter = export.Exporter(ppm_core.Scene(), print)
    exporter.add_geometry(export.instance.Instance(obj.evaluated_get(depsgraph), "grid", np.eye(4), 0))
    assert exporter.triangles == 2 * 708 * 708
    exporter.scene.set_camera(np.eye(4), 4, 4)
    hits = exporter.scene.intersect(np.array([[0.3, -0.7, 1.0]]), np.array([[0.0, 0.0, -1.0]]))
    np.testing.assert_allclose(hits["t"], 1.0, atol=1e-6)


def test_stats_line_format():
    assert engine.stats_line(12, 200, 3.1e6, 12.4) == "Pass 12/200 | 3.1 M photons | 00:12"
    assert engine.stats_line(12, 200, 3.1e6, 12.4, 0.0314) == "Pass 12/200 | 3.1 M photons | 00:12 | est. error 3.1%"


def test_camera_matches_cycles_fov_rules():
    from ppm_render.export.camera import Frame, camera_arguments

    cam = bpy.data.objects.new("c", bpy.data.cameras.new("c"))
    cam.data.lens, cam.data.sensor_width, cam.data.sensor_height = 50.0, 36.0, 24.0
    cam.data.sensor_fit = "VERTICAL"
    cam.data.shift_y = 0.1
    args = camera_arguments(cam, Frame(300, 200), print)
    # Vertical fit: 24 mm across 200 px; the core gets the same pixels fitted horizontally.
    assert 2 * math.tan(args["fov"] / 2) == pytest.approx(24.0 / 50.0 * 300 / 200)
    assert args["shift_y"] * (24.0 / 50.0 * 300 / 200) == pytest.approx(0.1 * 24.0 / 50.0)
    cam.data.dof.use_dof, cam.data.dof.aperture_fstop = True, 2.0
    assert camera_arguments(cam, Frame(300, 200), print, "LENS")["aperture_radius"] == pytest.approx(0.0125)
    assert camera_arguments(cam, Frame(300, 200), print, "OFF")["aperture_radius"] == 0.0


def test_standard_panels_open_to_the_engine_and_close_on_unregister():
    import ppm_render
    from ppm_render import ui

    names = ("RENDER_PT_format", "RENDER_PT_output", "DATA_PT_lens", "DATA_PT_camera_dof", "MATERIAL_PT_preview")
    panels = [getattr(bpy.types, n) for n in names]
    assert all("PPM" in p.COMPAT_ENGINES for p in panels)
    assert engine.PPMRenderEngine.bl_use_shading_nodes_custom is False
    opened = [p for p in ui._standard_panels() if "PPM" in p.COMPAT_ENGINES]
    assert len(opened) >= 20
    ppm_render.unregister()
    try:
        assert not any("PPM" in p.COMPAT_ENGINES for p in ui._standard_panels())
        assert not hasattr(bpy.types.Scene, "ppm")
    finally:
        ppm_render.register()


class RecordingLayout:
    """Stands in for a panel's layout: records (owner, property) of every prop() drawn."""

    def __init__(self, drawn=None):
        self.drawn = [] if drawn is None else drawn
        self.use_property_split = False

    def column(self, **_):
        return RecordingLayout(self.drawn)

    def row(self, **_):
        return RecordingLayout(self.drawn)

    def prop(self, owner, name, **_):
        assert hasattr(owner, name), name
        self.drawn.append((owner, name))


def test_the_passes_panel_offers_every_pass_the_engine_writes():
    from types import SimpleNamespace

    from ppm_render import ui

    panel = ui.VIEWLAYER_PT_ppm_passes
    assert panel.bl_parent_id == "VIEWLAYER_PT_layer_passes" and panel.bl_parent_id in dir(bpy.types)
    layout = RecordingLayout()
    context = SimpleNamespace(view_layer=bpy.context.view_layer, scene=bpy.context.scene)
    panel.draw(SimpleNamespace(layout=layout), context)
    layer_flags = {name for owner, name in layout.drawn if owner == context.view_layer}
    light = {f"use_pass_{kind}_{part}" for kind in ("diffuse", "glossy", "transmission")
             for part in ("direct", "indirect", "color")}
    assert layer_flags == {"use_pass_z", "use_pass_normal", "use_pass_object_index", "use_pass_material_index",
                           "use_pass_emit", "use_pass_environment"} | light
    assert {name for owner, name in layout.drawn if owner == context.scene.ppm} == {"denoising_data",
                                                                                    "error_passes", "caustic_pass"}
