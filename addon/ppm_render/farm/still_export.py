"""A .blend's still exported once for the farm: the scene's builder calls (scene_record.py), its
camera at the render's size, and the render settings the add-on would use, made into a share's
(stochastic hit points, the global radius schedule). Needs bpy and this add-on registered."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass
class Still:
    calls: list      # the core scene's builder calls
    settings: dict   # ppm_core.Renderer's keyword arguments, first_pass and threads aside
    passes: int      # the scene's pass count (scene.ppm.passes)
    width: int
    height: int
    target_error: float = 0.0  # the scene's (scene.ppm.target_error): the merged image's, not a share's


def share_settings(settings, warn):
    """The add-on's render settings made into a share's: passes of a still merge only with stochastic
    hit points and the global radius schedule (engine/ppm/radius_schedule.h)."""
    # A share renders all its passes: the scene's target error is the merged image's (the farm's).
    out = {**settings, "hit_points": "stochastic", "radius_schedule": "global", "light_passes": False,
           "target_error": 0.0}
    if settings.get("hit_points") == "fixed":
        warn("fixed hit points do not split into shares: rendering with stochastic ones")
    if settings.get("photon_guiding"):
        warn("photon guiding learns from the passes before: shares render without it")
        out["photon_guiding"] = False
    if settings.get("dof_mode") == "post":
        warn("depth of field 'Post Process' blurs a finished image, not a share: rendering it as 'Lens'")
        out["dof_mode"] = "lens"
    out.pop("threads", None)
    return out


def export_still(bpy, core_module, warn):
    """The Still of bpy.context.scene, seen through its camera."""
    from .. import export
    from ..export.camera import Frame
    from ..properties import render_settings
    from .scene_record import RecordingCore

    scene = bpy.context.scene
    depsgraph = bpy.context.evaluated_depsgraph_get()
    frame = Frame.from_render_settings(scene.render)
    recorder = RecordingCore(core_module)
    export.build_scene(recorder, depsgraph, frame, warn)
    settings = render_settings(scene)
    return Still(calls=recorder.scenes[0].calls, settings=share_settings(settings, warn), passes=scene.ppm.passes,
                 width=frame.window_width, height=frame.window_height, target_error=scene.ppm.target_error)
