"""Shared by the accuracy benchmarks (references.py, convergence.py, equal_time.py).

Renders the bundled .blend files through the add-on and through Cycles in the
Blender 5.0 module (bpy), reads and writes the small half-float EXR
references in bench/references/, defines the image regions and the error
measures. Not a script.

Error measures (per pixel and colour channel, reference r, image x):
- RMSE = sqrt(mean((x - r)^2)), in the scene's radiance units;
- relative MSE = mean((x - r)^2 / (r^2 + eps)) with eps = 0.01 (the usual
  relMSE of the rendering literature; these scenes' diffuse radiance is
  0.05-2, so eps only tempers the darkest pixels).

Regions (from geometry: one ray through each pixel centre into the scene the
add-on exports, with the core's `Scene.intersect`):
- emitter: pixels whose reference is brighter than 10x the median (visible lights
  and emissive panels; they are part of "all" only);
- glass: the first hit is a glass object (what is seen in and through it);
- mirror: the first hit is a mirror or metal object;
- caustic: the first hit is diffuse and the segment from it to a point or spot
  light's centre crosses a glass object first (the glass's "shadow", where all
  light from that lamp arrives through the glass: the refraction caustic);
- walls: every other diffuse pixel that sees geometry (walls, floor, diffuse
  objects). A mirror's reflection caustic is not separated: it is in "walls".
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))
sys.path.insert(0, os.path.join(ROOT, "bench"))
import bpy  # noqa: E402
from exr_io import read_exr, write_exr  # noqa: E402, F401 (re-exported)

import ppm_render  # noqa: E402

SCENES_DIR = os.path.join(ROOT, "blend_scenes")
REF_DIR = os.environ.get("PPM_BENCH_REFERENCES", os.path.join(ROOT, "bench", "references"))  # override: tests
PLOTS_DIR = os.path.join(ROOT, "bench", "plots")
SCENES = ("cornell_3spheres", "bezier_vase", "cornell_dof", "showcase", "cornell_diffuse")
CYCLES_SCENES = ("cornell_diffuse",)  # no caustics: Cycles converges there too
W, H = 320, 240
EPS = 0.01
WORKDIR = tempfile.mkdtemp(prefix="ppm_accuracy_")


# ---------------------------------------------------------------- references

def save_results(results, filename):
    """Writes a full run's result rows, as JSON, to bench/plots/<filename>."""
    os.makedirs(PLOTS_DIR, exist_ok=True)
    with open(os.path.join(PLOTS_DIR, filename), "w") as f:
        json.dump(results, f, indent=1)


def reference_path(name, engine="ppm"):
    return os.path.join(REF_DIR, f"{name}_{engine}.exr")


def load_reference(name, engine="ppm"):
    path = reference_path(name, engine)
    if not os.path.exists(path):
        raise SystemExit(f"missing {path}: run bench/references.py first")
    return read_exr(path)


# ---------------------------------------------------------------- rendering in bpy

def open_scene(name, width=W, height=H):
    if not hasattr(bpy.types.Scene, "ppm"):
        ppm_render.register()  # before loading, so the file's PPM engine setting is recognised
    bpy.ops.wm.open_mainfile(filepath=os.path.join(SCENES_DIR, f"{name}.blend"))
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = width, height, 100
    scene.render.use_border = False
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_depth = "32"
    return scene


def _render(scene, tag):
    path = os.path.join(WORKDIR, f"{tag}_{time.monotonic_ns()}.exr")
    scene.render.filepath = path
    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    seconds = time.perf_counter() - start
    image, _ = read_exr(path)
    os.remove(path)
    return image, seconds


def render_ppm(name, *, passes=1_000_000, seconds=0.0, seed=0, hit_points="AUTO", photons=200_000, threads=2,
               width=W, height=H, **settings):
    """(image, wall seconds of bpy.ops.render.render) through the add-on; stops at `passes` or
    `seconds` (0 = no time limit). `settings` are other scene.ppm properties (threshold=30, ...);
    the rest are the file's (the add-on's defaults)."""
    scene = open_scene(name, width, height)
    scene.render.engine = "PPM"
    p = scene.ppm
    p.passes, p.time_limit, p.seed, p.threads = passes, seconds, seed, threads
    p.photons_per_pass = photons
    p.hit_points = hit_points
    for key, value in settings.items():
        setattr(p, key, value)
    return _render(scene, f"ppm_{name}")


def render_cycles(name, *, samples=1 << 20, seconds=0.0, seed=0, threads=2, width=W, height=H):
    """(image, wall seconds) through Cycles on the CPU: path tracing with the PPM engine's path length
    (12 bounces of every kind), no clamping, denoising, adaptive sampling or glossy filter, caustics
    on, a 1-pixel box filter (the PPM engine averages jittered samples inside each pixel). Lights are
    made visible to camera rays: the files have that off (Blender's default for lights) but the add-on
    shows lights anyway, and both engines must render the same image."""
    scene = open_scene(name, width, height)
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device, c.samples, c.seed, c.time_limit = "CPU", samples, seed, seconds
    c.use_adaptive_sampling = c.use_denoising = False
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 12
    c.pixel_filter_type, c.filter_width = "BOX", 1.0
    scene.render.threads_mode, scene.render.threads = "FIXED", threads
    for obj in scene.objects:
        if obj.type == "LIGHT":
            obj.visible_camera = True  # the add-on shows lights to the camera whatever this says
    return _render(scene, f"cycles_{name}")


# ---------------------------------------------------------------- regions

def _material_kind(obj):
    """'glass', 'mirror' (mirror or metal) or 'diffuse', from the object's first material's nodes."""
    for slot in obj.material_slots:
        mat = slot.material
        if mat is None or mat.node_tree is None:
            continue
        for node in mat.node_tree.nodes:
            if node.bl_idname in ("ShaderNodeBsdfGlass", "ShaderNodeBsdfRefraction"):
                return "glass"
            if node.bl_idname in ("ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic"):
                return "mirror"
            if node.bl_idname == "ShaderNodeBsdfPrincipled":
                weight = node.inputs.get("Transmission Weight") or node.inputs.get("Transmission")
                if weight is not None and weight.default_value > 0.5:
                    return "glass"
                if node.inputs["Metallic"].default_value >= 0.5:
                    return "mirror"
    return "diffuse"


def region_masks(name, reference, width=W, height=H):
    """Boolean (H, W) masks, top row first: all, emitter, glass, mirror, caustic, walls (module docstring)."""
    import ppm_core
    from ppm_render import export
    from ppm_render.export.camera import Frame

    scene = open_scene(name, width, height)
    depsgraph = bpy.context.evaluated_depsgraph_get()

    class NamingExporter(export.Exporter):
        names = {}

        def add_geometry(self, item):
            self.names[item.object_id] = item.obj.original.name
            super().add_geometry(item)

        def add_revolve(self, item):
            self.names[item.object_id] = item.obj.original.name
            super().add_revolve(item)

    exporter = NamingExporter(ppm_core, lambda message: None)
    for instance in depsgraph.object_instances:
        exporter.visit(instance)
    exporter.finish_curves()
    core_scene = exporter.scene
    frame = Frame.from_render_settings(scene.render)
    args = export.camera.camera_arguments(scene.camera.evaluated_get(depsgraph), frame, lambda m: None, "OFF")
    core_scene.set_camera(**args)
    origins, directions = core_scene.camera_rays()
    hits = core_scene.intersect(origins, directions)
    t, obj_id = np.asarray(hits["t"]), np.asarray(hits["object"])
    kinds = {i: _material_kind(bpy.data.objects[n]) for i, n in exporter.names.items()}
    kind = np.array([kinds.get(int(i), "none") for i in obj_id])
    hit = np.isfinite(t)
    points = origins + np.where(hit, t, 0.0)[:, None] * directions
    caustic = np.zeros(len(t), dtype=bool)
    glass_ids = [i for i, k in kinds.items() if k == "glass"]
    diffuse = hit & (kind == "diffuse")
    for lamp in bpy.data.objects:
        if lamp.type != "LIGHT" or lamp.data.type not in ("POINT", "SPOT") or not glass_ids:
            continue
        centre = np.array(lamp.matrix_world.translation)
        to_lamp = centre - points[diffuse]
        dist = np.linalg.norm(to_lamp, axis=1)
        dirs = to_lamp / dist[:, None]
        shadow = core_scene.intersect(np.ascontiguousarray(points[diffuse] + 1e-4 * dirs), np.ascontiguousarray(dirs))
        blocked = (np.asarray(shadow["t"]) < dist) & np.isin(np.asarray(shadow["object"]), glass_ids)
        caustic[np.flatnonzero(diffuse)[blocked]] = True

    def image(mask):
        return mask.reshape(height, width)[::-1]  # camera_rays: bottom row first

    lum = reference[..., :3].mean(axis=2)
    emitter = lum > 10.0 * np.median(lum[image(hit)]) if hit.any() else lum > 10.0 * np.median(lum)
    masks = {
        "all": np.ones((height, width), dtype=bool),
        "emitter": emitter,
        "glass": image(kind == "glass") & ~emitter,
        "mirror": image(kind == "mirror") & ~emitter,
        "caustic": image(caustic) & ~emitter,
        "walls": image(diffuse & ~caustic) & ~emitter,
    }
    return {k: m for k, m in masks.items() if m.any()}


# ---------------------------------------------------------------- errors

def rel_mse(image, reference, mask=None):
    d2 = (image[..., :3] - reference[..., :3]) ** 2 / (reference[..., :3] ** 2 + EPS)
    return float(d2[mask].mean() if mask is not None else d2.mean())


def rmse(image, reference, mask=None):
    d2 = (image[..., :3] - reference[..., :3]) ** 2
    return float(np.sqrt(d2[mask].mean() if mask is not None else d2.mean()))


def error_row(image, reference, meta, masks, regions):
    """The errors the scripts report for one render against one reference: RMSE, relative MSE, the
    reference's own noise, and the relative MSE of each of `regions` the scene has a mask for."""
    return {"rmse": rmse(image, reference), "rel_mse": rel_mse(image, reference),
            "ref_noise": reference_noise(meta),
            "regions": {k: rel_mse(image, reference, masks[k]) for k in regions if k in masks}}


def reference_noise(meta, key="rel_mse_noise"):
    """The reference's own estimated relative MSE (from its two independent halves), or nan."""
    return float(meta.get(key, float("nan")))


def fit_slope(xs, ys):
    """Slope of log(y) against log(x) by least squares."""
    x, y = np.log(np.asarray(xs, dtype=float)), np.log(np.asarray(ys, dtype=float))
    return float(np.polyfit(x, y, 1)[0])
