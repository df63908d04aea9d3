"""The Bezier revolve object: created by its operator, exported exactly (not its Screw preview),
and rendering like a finely tessellated mesh of the same surface."""

import math

import numpy as np
import pytest

from conftest import bpy, render_file
from ppm_render import core, export
from ppm_render.export import bezier

ppm_core = core.load()


def revolve_scene():
    bpy.ops.curve.ppm_bezier_revolve_add()
    vase = bpy.context.object
    vase.data.materials.append(_diffuse("clay", (0.7, 0.6, 0.5)))
    vase.location = (0.1, 0.0, 0.0)
    vase.rotation_euler = (math.pi / 2, 0.0, math.radians(20))
    scene = bpy.context.scene
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy, sun.rotation_euler = 3.0, (math.radians(40), 0, math.radians(30))
    scene.collection.objects.link(sun)
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    cam.location, cam.rotation_euler = (0.0, -4.5, 1.6), (math.radians(80), 0, 0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 96, 72, 100
    return scene, vase


def _diffuse(name, rgb):
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    bsdf = next(n for n in mat.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    bsdf.inputs["Base Color"].default_value = (*rgb, 1.0)
    return mat


def cubic_chain(points, samples_per_segment):
    """Points on a chain of cubic Beziers (3k+1 control points), (N, 2)."""
    t = np.linspace(0.0, 1.0, samples_per_segment, endpoint=False)[:, None]
    out = []
    for i in range(0, len(points) - 1, 3):
        p0, p1, p2, p3 = points[i:i + 4]
        out.append((1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * p1 + 3 * (1 - t) * t**2 * p2 + t**3 * p3)
    out.append(points[-1][None])
    return np.concatenate(out)


def tessellated_copy(vase, around=256, per_segment=64):
    """A mesh of the same surface: profile (radius, height) in local XY swept about local Y."""
    profile = cubic_chain(bezier.spline_profile(vase.data.splines[0]), per_segment)
    phi = np.linspace(0.0, 2.0 * math.pi, around, endpoint=False)
    r, h = profile[:, 0:1], profile[:, 1:2]
    verts = np.stack([r * np.cos(phi), np.broadcast_to(h, r.shape[:1] + phi.shape), r * np.sin(phi)], axis=-1)
    n, m = len(profile), around
    i, j = np.meshgrid(np.arange(n - 1), np.arange(m), indexing="ij")
    a, b = i * m + j, i * m + (j + 1) % m
    quads = np.stack([a, b, b + m, a + m], axis=-1).reshape(-1, 4)
    mesh = bpy.data.meshes.new("tessellated")
    mesh.from_pydata(verts.reshape(-1, 3).tolist(), [], quads.tolist())
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    mesh.materials.append(vase.data.materials[0])
    obj = bpy.data.objects.new("tessellated", mesh)
    obj.matrix_world = vase.matrix_world
    bpy.context.scene.collection.objects.link(obj)
    return obj


def test_operator_creates_a_flagged_curve_with_a_preview():
    _scene, vase = revolve_scene()
    assert vase.type == "CURVE" and vase.ppm.revolve
    assert vase.data.dimensions == "2D"
    assert any(m.type == "SCREW" and m.axis == "Y" for m in vase.modifiers)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    preview = [i for i in depsgraph.object_instances if i.is_instance and i.object.type == "MESH"]
    assert preview, "the Screw preview should be listed as a MESH instance of the curve"


def test_export_sends_the_control_points_not_the_preview():
    _scene, vase = revolve_scene()
    warnings = []
    exporter = export.Exporter(ppm_core.Scene(), warnings.append)
    for instance in bpy.context.evaluated_depsgraph_get().object_instances:
        exporter.visit(instance)
    exporter.finish_curves()
    assert exporter.triangles == 0, "the Screw preview mesh was exported too"
    assert not warnings
    # A ray straight down the axis from above hits the vase's bottom (the exact surface) at its origin.
    exporter.scene.set_camera(np.eye(4), 4, 4)
    top = np.array(vase.matrix_world.translation) + np.array([0.0, 0.0, 5.0])
    hit = exporter.scene.intersect(top[None], np.array([[0.0, 0.0, -1.0]]))
    assert hit["t"][0] == pytest.approx(5.0, abs=1e-6)


def test_revolve_renders_like_a_fine_tessellation(tmp_path):
    scene, vase = revolve_scene()
    settings = {"passes": 8, "photons_per_pass": 50_000, "samples_per_pixel": 4, "seed": 3}
    exact = render_file(scene, tmp_path / "exact.exr", **settings)
    mesh = tessellated_copy(vase)
    vase.hide_render = True
    tessellated = render_file(scene, tmp_path / "mesh.exr", **settings)
    assert mesh.hide_render is False
    a, b = exact[..., :3].mean(axis=2), tessellated[..., :3].mean(axis=2)
    assert np.isfinite(a).all() and a.mean() > 0.05
    # Silhouettes and shading agree: block means within 3%, and few pixels differ noticeably.
    blocks_a = a.reshape(6, 12, 8, 12).mean(axis=(1, 3))
    blocks_b = b.reshape(6, 12, 8, 12).mean(axis=(1, 3))
    assert np.abs(blocks_a - blocks_b).max() <= 0.03 * blocks_b.max()
    assert (np.abs(a - b) > 0.1 * b.max()).mean() < 0.02


def test_edit_mode_changes_reach_the_export_and_the_preview():
    _scene, vase = revolve_scene()
    bpy.ops.object.mode_set(mode="EDIT")
    vase.data.splines[0].bezier_points[2].co.x = 0.9  # widen the belly while in Edit Mode
    depsgraph = bpy.context.evaluated_depsgraph_get()
    depsgraph.update()
    exported = bezier.spline_profile(vase.evaluated_get(depsgraph).data.splines[0])
    assert exported[6] == pytest.approx((0.9, 0.7), abs=1e-6)  # p2 is control point 3*2 of the chain
    radii = []
    for instance in depsgraph.object_instances:
        if instance.is_instance and instance.object.type == "MESH":
            mesh = instance.object.data
            co = np.empty(len(mesh.vertices) * 3)
            mesh.vertices.foreach_get("co", co)
            radii.append(np.hypot(co[0::3], co[2::3]).max())
    assert radii and radii[0] == pytest.approx(0.9, abs=0.01)
    bpy.ops.object.mode_set(mode="OBJECT")
