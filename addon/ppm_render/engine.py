"""The PPM RenderEngine: F12 and animation renders through ppm_core.

`render()` runs once per view layer: export the evaluated depsgraph, then run
photon passes while the render window shows the image about once a second,
the progress bar and stats move, and Esc stops the core within a poll
interval (0.1 s), keeping the passes done so far. Every failure ends in
`report({'ERROR'})` so it reaches the user (and makes bpy.ops.render.render
raise in scripts); the render result is always closed.
"""

import math
import time

import bpy

from . import core, export, passes, viewport
from .export.camera import Frame
from .properties import media_settings, render_settings
from .viewport_camera import region_view

DISPLAY_INTERVAL = 1.0  # seconds between refreshes of the render window
# id(engine) -> its viewport's ViewportSession (None before its first view_update). Kept outside the
# engine: after Blender invalidates an engine, its __del__ can no longer read its attributes.
VIEWPORT_SESSIONS = {}


def render_views(scene):
    """The views to render: each active view of a stereo 3D or multi-view render, else one ("")."""
    if not scene.render.use_multiview:
        return [""]
    return [view.name for view in scene.render.views if view.use] or [""]


def stats_line(passes, total, photons, seconds, error=math.inf):
    """The render window's stats; `error` is the core's estimate (stats()['error']['bound']), shown once known."""
    minutes, secs = divmod(int(seconds), 60)
    line = f"Pass {passes}/{total} | {photons / 1e6:.1f} M photons | {minutes:02d}:{secs:02d}"
    return line + (f" | est. error {100.0 * error:.1f}%" if math.isfinite(error) else "")


class ProgressiveDisplay:
    """Runs the photon passes one run(passes=1) at a time (the core's image() is only readable
    between runs) and, between them, refreshes the render window about once a second. During a
    pass the core calls back every 0.1 s: that is where Esc is noticed and stats move."""

    def __init__(self, engine, renderer, result, settings):
        self.engine, self.renderer, self.result = engine, renderer, result
        self.total = settings.passes
        self.time_limit = settings.time_limit
        self.start = time.monotonic()
        self.last_display = None
        self.stopped = False
        self.passes = 0
        self.photons = 0
        self.shown = -1  # passes in the displayed image
        self.memory_peak = 0.0  # MiB, the most the core has held
        self.error = math.inf  # the image's estimated error (the core's stats()['error']['bound'])
        self.target_reached = False

    def cancelled(self):
        return self.engine.test_break()  # Esc in the render window

    def elapsed(self):
        return time.monotonic() - self.start

    def __call__(self, info):
        """The core's progress callback; False cancels the pass in progress."""
        if self.cancelled():
            self.stopped = True
            return False
        self.report(info["passes"], info["photons_emitted"], info["pass_done"])
        return True

    def report(self, passes, photons, pass_done=0.0):
        fraction = (passes + pass_done) / self.total
        if self.time_limit > 0:
            fraction = max(fraction, self.elapsed() / self.time_limit)
        self.engine.update_progress(min(fraction, 1.0))
        self.engine.update_stats("", self.line(passes, photons))

    def line(self, passes, photons):
        return stats_line(passes, self.total, photons, self.elapsed(), self.error)

    def run(self):
        """Passes until the pass count, the time limit, the target error or Esc, whichever comes first."""
        while self.passes < self.total and not self.stopped and not self.target_reached:
            remaining = self.time_limit - self.elapsed() if self.time_limit > 0 else 0.0
            if self.time_limit > 0 and remaining <= 0.0:
                break
            self.renderer.run(passes=1, callback=self)
            stats = self.renderer.stats()
            self.passes, self.photons = stats["passes"], stats["photons_emitted"]
            self.error, self.target_reached = stats["error"]["bound"], stats["target_error_reached"]
            self.report_memory(stats)
            now = time.monotonic()
            if self.last_display is None or now - self.last_display >= DISPLAY_INTERVAL:
                self.show()
                self.last_display = now
        if self.shown != self.passes:
            self.show()
        self.report(self.passes, self.photons)

    def report_memory(self, stats):
        """The core's memory into the render window's header ("Mem:"), as Cycles reports its own."""
        used = stats["memory_bytes"] / 2**20
        self.memory_peak = max(self.memory_peak, used)
        self.engine.update_memory_stats(memory_used=used, memory_peak=self.memory_peak)

    def show(self):
        if bpy.app.background:  # no render window: the terminal shows progress instead
            print("PPM:", self.line(self.passes, self.photons), flush=True)
        passes.write_pixels(self.result, self.renderer.image())
        self.engine.update_result(self.result)
        self.shown = self.passes


class PPMRenderEngine(bpy.types.RenderEngine):
    bl_idname = "PPM"
    bl_label = "PPM"
    bl_use_preview = False
    bl_use_shading_nodes_custom = False  # keep Principled BSDF and the standard node menus
    bl_use_postprocess = True

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)  # the plain __init__(self) form crashes Blender 5.0
        stale = VIEWPORT_SESSIONS.pop(id(self), None)  # of a freed engine whose __del__ never ran
        if stale is not None:
            stale.stop()
        VIEWPORT_SESSIONS[id(self)] = None  # the viewport's ViewportSession, once it has one
        self.drawn = None  # the viewport_draw.DrawnImage on screen

    def __del__(self):
        # Blender may have invalidated this instance already (its attributes then raise ReferenceError),
        # so the session is found by the instance's id.
        session = VIEWPORT_SESSIONS.pop(id(self), None)
        if session is not None:
            session.stop()  # no render thread may outlive the engine it redraws
        parent = getattr(super(), "__del__", None)
        if parent is not None:
            parent()

    def render(self, depsgraph):
        # An exception out of render() crashes Blender 5.0 (bpy, measured): every failure is reported.
        try:
            self.render_frame(depsgraph)
        except Exception as error:  # noqa: BLE001
            self.fail(error)

    def render_frame(self, depsgraph):
        scene = depsgraph.scene
        frame = Frame.from_render_settings(scene.render)
        try:
            ppm_core = core.load()
            self.update_stats("", "Exporting scene")
            ppm_scene, camera_args, pass_indices = export.build_scene(ppm_core, depsgraph, frame, self.warn,
                                                                      self.test_break)
        except export.Cancelled:
            self.update_stats("", "Cancelled while exporting the scene")
            return
        except Exception as error:  # noqa: BLE001 - every failure must reach the user
            self.fail(error)
            return
        camera_object = scene.camera.evaluated_get(depsgraph)
        for view in render_views(scene):
            if self.test_break():
                return
            if view:  # one eye of stereo 3D, or one camera of a multi-view render
                self.active_view_set(view)
            if view and camera_object.type == "CAMERA":  # (Blender crashes asked for an Empty's views)
                per_view = (self.camera_model_matrix(camera_object), self.camera_shift_x(camera_object))
                camera_args = export.camera.camera_arguments(camera_object, frame, lambda _: None,
                                                             scene.ppm.dof_mode, view=per_view)
                ppm_scene.set_camera(**camera_args)
            if not self.render_view(ppm_core, (ppm_scene, camera_args, pass_indices), depsgraph, frame, view):
                return

    def render_view(self, ppm_core, exported, depsgraph, frame, view):
        """Renders one view of `exported` (build_scene's) into its result; False after a failure."""
        ppm_scene = exported[0]
        scene = depsgraph.scene
        layer = depsgraph.view_layer
        components = passes.component_passes_wanted(layer, scene.ppm)
        settings = {**render_settings(scene), "light_passes": layer.use_pass_emit or layer.use_pass_environment,
                    "component_passes": bool(components)}
        if ppm_scene.has_media:
            settings = media_settings(settings, self.warn)
        try:
            renderer = ppm_core.Renderer(ppm_scene, **settings)
        except Exception as error:  # noqa: BLE001 - every failure must reach the user
            self.fail(error)
            return False
        # The result covers the render border only: coordinates are relative to the border.
        result = self.begin_result(0, 0, frame.window_width, frame.window_height, layer=depsgraph.view_layer.name,
                                   view=view)
        try:
            passes.write_data_passes(depsgraph.view_layer, result, *exported)
            self.warn_if_streamed(renderer)
            self.warn_if_estimate_partial(settings)
            try:
                line = self.run(renderer, result, scene.ppm)
            except MemoryError as error:  # the core found no memory for them before making them
                if settings["hit_points"] != "fixed":
                    raise
                # Where Cycles renders the frame, so do we: stochastic hit points need 52 bytes a pixel.
                self.warn(f"{error}; rendering with stochastic hit points instead")
                renderer = ppm_core.Renderer(ppm_scene, **{**settings, "hit_points": "stochastic"})
                line = self.run(renderer, result, scene.ppm)
            passes.write_render_passes(self, renderer, result, scene.ppm, (settings["light_passes"], components),
                                       exported[1], line)
            return True
        except Exception as error:  # noqa: BLE001
            self.fail(error)
            return False
        finally:
            self.end_result(result)
            del renderer  # the scene's camera may change for the next view only once no renderer holds it

    def warn_if_streamed(self, renderer):
        """Fixed hit points too large to keep are made again every pass (slower passes): said once."""
        stats = renderer.stats()
        if stats["hit_point_storage"] == "streamed":
            why = [line for line in stats["skipped"] if "streamed instead" in line]
            self.warn(why[0] if why else "fixed hit points are streamed: an eye pass every pass")

    def warn_if_estimate_partial(self, settings):
        """Fixed hit points keep their eye samples: at one sample per pixel the error estimate cannot
        measure their anti-aliasing error, and halting on it may stop early (README, "The error estimate")."""
        if settings["target_error"] > 0.0 and settings["hit_points"] == "fixed" and settings["samples_per_pixel"] == 1:
            self.warn("with fixed hit points at 1 sample per pixel the error estimate leaves out anti-aliasing "
                      "and may stop early; use 2 or more samples, or stochastic hit points (Auto)")

    def run(self, renderer, result, settings):
        """The passes, shown as they go; returns the final stats line."""
        display = ProgressiveDisplay(self, renderer, result, settings)
        display.run()
        line = display.line(display.passes, display.photons)
        if display.stopped:
            line += " | cancelled"
        elif display.target_reached:
            line += " | target error reached"
        self.update_stats("", line)
        return line

    def view_update(self, context, depsgraph):
        """The viewport's scene changed (or is shown for the first time): export what changed."""
        session = VIEWPORT_SESSIONS.get(id(self))
        try:
            if session is None:
                session = VIEWPORT_SESSIONS[id(self)] = viewport.ViewportSession(core.load(), viewport.redraw_of(self))
            if session.update(depsgraph) is None:
                return
        except Exception as error:  # noqa: BLE001 - shown in the viewport's header
            if session is not None:
                session.error = str(error)
            self.update_stats("", f"PPM: {error}")
        self.tag_redraw()

    def view_draw(self, context, depsgraph):
        """Draws the newest image; a new view (navigation, a resized region) restarts the refinement."""
        session = VIEWPORT_SESSIONS.get(id(self))
        if session is None:
            return
        try:
            if session.settings_key != viewport.settings_key(depsgraph.scene):  # they tag no depsgraph update
                self.view_update(context, depsgraph)
            session.set_view(region_view(context, depsgraph))
            session.start()
            image = session.newest()
            if image is not None and (self.drawn is None or self.drawn.image is not image):
                from .viewport_draw import DrawnImage  # gpu exists only where Blender has a window
                self.drawn = DrawnImage(image)
            if self.drawn is not None:
                self.drawn.draw(self, depsgraph.scene)
            self.update_stats("", viewport.status_line(session))
        except Exception as error:  # noqa: BLE001 - shown in the viewport's header, as view_update's
            session.error = str(error)
            self.update_stats("", f"PPM: {error}")

    def update_render_passes(self, scene=None, renderlayer=None):
        """Declares the passes this engine writes, so the compositor and the result list them."""
        passes.declare(self, scene, renderlayer)

    def warn(self, message):
        self.report({'WARNING'}, f"PPM: {message}")

    def fail(self, error):
        """One error report (it makes bpy.ops.render.render raise in scripts); with a UI, also the red
        message in the render window. error_set adds its text to the report too, so it is used only
        where there is a window to show it in."""
        message = f"PPM: {error}"
        if not bpy.app.background and hasattr(self, "error_set"):
            self.error_set(message)
        self.report({'ERROR'}, message)


def register():
    bpy.utils.register_class(PPMRenderEngine)


def unregister():
    bpy.utils.unregister_class(PPMRenderEngine)
