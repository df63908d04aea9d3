"""Image regions of a bundled .blend, from geometry: one ray through each pixel centre into the scene
the add-on exports (the core's own camera rays and `Scene.intersect`).

- emitter: pixels whose reference is brighter than 10x the median (visible lights and emissive
  panels; they are part of "all" only);
- glass: the first hit is a glass object (what is seen in and through it);
- mirror: the first hit is a mirror or metal object;
- caustic: the first hit is diffuse and the segment from it to a point or spot light's centre crosses
  a glass object first (the glass's "shadow", where all light from that lamp arrives through the
  glass: the refraction caustic);
- walls: every other diffuse pixel that sees geometry. A mirror's reflection caustic is in "walls".
- beam (scenes with media): pixels whose camera ray, up to the first surface, passes through the
  glass's shadow from a point or spot light in 4 or more of 64 points along it (where all light from
  that lamp arrives through the glass: the volumetric caustic, and the dark around it). Objects whose
  material has only a Volume (a fog box's boundary) are seen through, for every region.
"""

from __future__ import annotations

import numpy as np

from .addon_route import bpy, open_scene

NAMES = ("all", "emitter", "glass", "mirror", "caustic", "walls", "beam")
BEAM_POINTS, BEAM_MIN_POINTS = 64, 4


def material_kind(obj):
    """'glass', 'mirror' (mirror or metal), 'volume' (a Volume output alone) or 'diffuse', from the
    object's first material's nodes."""
    for slot in obj.material_slots:
        mat = slot.material
        if mat is None or mat.node_tree is None:
            continue
        outputs = [n for n in mat.node_tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"]
        if outputs and all(not o.inputs["Surface"].is_linked and o.inputs["Volume"].is_linked for o in outputs):
            return "volume"
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


def exported_scene(scene):
    """The core scene the add-on exports, its camera set, and {object id: object name}."""
    import ppm_core
    from ppm_render import export
    from ppm_render.export.camera import Frame

    depsgraph = bpy.context.evaluated_depsgraph_get()
    names = {}

    class NamingExporter(export.Exporter):
        def add_geometry(self, item):
            names[item.object_id] = item.obj.original.name
            super().add_geometry(item)

        def add_revolve(self, item):
            names[item.object_id] = item.obj.original.name
            super().add_revolve(item)

    exporter = NamingExporter(ppm_core.Scene(), lambda message: None)
    for instance in depsgraph.object_instances:
        exporter.visit(instance)
    exporter.finish_curves()
    frame = Frame.from_render_settings(scene.render)
    camera = export.camera.camera_arguments(scene.camera.evaluated_get(depsgraph), frame, lambda m: None, "OFF")
    exporter.scene.set_camera(**camera)
    return exporter.scene, names


def first_hits(core_scene, origins, directions, volume_ids):
    """t and object of each ray's first hit, seen through objects in `volume_ids` (inf, -1: none)."""
    t = np.zeros(len(origins))
    obj = np.full(len(origins), -1)
    todo = np.arange(len(origins))
    start = origins.copy()
    for _ in range(8):
        hits = core_scene.intersect(np.ascontiguousarray(start[todo]), np.ascontiguousarray(directions[todo]))
        ht, ho = np.asarray(hits["t"]), np.asarray(hits["object"])
        t[todo] += np.where(np.isfinite(ht), ht, np.inf)
        obj[todo] = np.where(np.isfinite(ht), ho, -1)
        again = np.isfinite(ht) & np.isin(ho, volume_ids)
        todo = todo[again]
        if len(todo) == 0:
            break
        start[todo] = origins[todo] + (t[todo] + 1e-4)[:, None] * directions[todo]
        t[todo] += 1e-4
    return t, obj


def glass_shadowed(core_scene, points, glass_ids, volume_ids):
    """Which points' segment to a point or spot light's centre crosses glass first."""
    shadowed = np.zeros(len(points), dtype=bool)
    for lamp in bpy.data.objects:
        if lamp.type != "LIGHT" or lamp.data.type not in ("POINT", "SPOT") or not glass_ids or not len(points):
            continue
        to_lamp = np.array(lamp.matrix_world.translation) - points
        dist = np.linalg.norm(to_lamp, axis=1)
        dirs = to_lamp / dist[:, None]
        t, obj = first_hits(core_scene, points + 1e-4 * dirs, dirs, volume_ids)
        shadowed |= (t < dist) & np.isin(obj, glass_ids)
    return shadowed


def beam_pixels(core_scene, origins, directions, t, glass_ids, volume_ids):
    """Camera rays that pass through the glass's shadow in BEAM_MIN_POINTS of BEAM_POINTS points."""
    if not volume_ids or not glass_ids:
        return np.zeros(len(origins), dtype=bool)
    end = np.where(np.isfinite(t), t, 0.0)
    count = np.zeros(len(origins), dtype=int)
    for k in range(BEAM_POINTS):
        points = origins + ((k + 0.5) / BEAM_POINTS * end)[:, None] * directions
        count += glass_shadowed(core_scene, points, glass_ids, volume_ids)
    return count >= BEAM_MIN_POINTS


def region_masks(name, reference, width, height):
    """Boolean (H, W) masks, top row first, of the regions the scene has (module docstring)."""
    core_scene, names = exported_scene(open_scene(name, width, height))
    origins, directions = core_scene.camera_rays()
    kinds = {i: material_kind(bpy.data.objects[n]) for i, n in names.items()}
    glass_ids = [i for i, k in kinds.items() if k == "glass"]
    volume_ids = [i for i, k in kinds.items() if k == "volume"]
    t, obj_id = first_hits(core_scene, origins, directions, volume_ids)
    kind = np.array([kinds.get(int(i), "none") for i in obj_id])
    hit = np.isfinite(t)
    points = origins + np.where(hit, t, 0.0)[:, None] * directions
    diffuse = hit & (kind == "diffuse")
    caustic = np.zeros(len(points), dtype=bool)
    caustic[diffuse] = glass_shadowed(core_scene, points[diffuse], glass_ids, volume_ids)
    beam = beam_pixels(core_scene, origins, directions, t, glass_ids, volume_ids) & (kind != "glass")

    def image(mask):
        return mask.reshape(height, width)[::-1]  # camera_rays: bottom row first

    lum = reference[..., :3].mean(axis=2)
    emitter = lum > 10.0 * np.median(lum[image(hit)] if hit.any() else lum)
    masks = {
        "all": np.ones((height, width), dtype=bool),
        "emitter": emitter,
        "glass": image(kind == "glass") & ~emitter,
        "mirror": image(kind == "mirror") & ~emitter,
        "caustic": image(caustic) & ~emitter,
        "walls": image(diffuse & ~caustic) & ~emitter,
        "beam": image(beam) & ~emitter,
    }
    return {k: m for k, m in masks.items() if m.any()}
