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
"""

from __future__ import annotations

import numpy as np

from .addon_route import bpy, open_scene

NAMES = ("all", "emitter", "glass", "mirror", "caustic", "walls")


def material_kind(obj):
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


def caustic_pixels(core_scene, points, diffuse, glass_ids):
    """Diffuse hit points whose segment to a point or spot light's centre crosses glass first."""
    caustic = np.zeros(len(points), dtype=bool)
    for lamp in bpy.data.objects:
        if lamp.type != "LIGHT" or lamp.data.type not in ("POINT", "SPOT") or not glass_ids:
            continue
        to_lamp = np.array(lamp.matrix_world.translation) - points[diffuse]
        dist = np.linalg.norm(to_lamp, axis=1)
        dirs = to_lamp / dist[:, None]
        shadow = core_scene.intersect(np.ascontiguousarray(points[diffuse] + 1e-4 * dirs), np.ascontiguousarray(dirs))
        blocked = (np.asarray(shadow["t"]) < dist) & np.isin(np.asarray(shadow["object"]), glass_ids)
        caustic[np.flatnonzero(diffuse)[blocked]] = True
    return caustic


def region_masks(name, reference, width, height):
    """Boolean (H, W) masks, top row first, of the regions the scene has (module docstring)."""
    core_scene, names = exported_scene(open_scene(name, width, height))
    origins, directions = core_scene.camera_rays()
    hits = core_scene.intersect(origins, directions)
    t, obj_id = np.asarray(hits["t"]), np.asarray(hits["object"])
    kinds = {i: material_kind(bpy.data.objects[n]) for i, n in names.items()}
    kind = np.array([kinds.get(int(i), "none") for i in obj_id])
    hit = np.isfinite(t)
    points = origins + np.where(hit, t, 0.0)[:, None] * directions
    diffuse = hit & (kind == "diffuse")
    caustic = caustic_pixels(core_scene, points, diffuse, [i for i, k in kinds.items() if k == "glass"])

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
    }
    return {k: m for k, m in masks.items() if m.any()}
