"""The interactive render of one 3D viewport in Rendered shading.

A `ViewportSession` keeps the exported core scene and a render thread that refines the image: a
first image at a quarter and then half of the region's resolution with few photons (it appears
within a fraction of a second), then full-resolution passes until the viewport's pass count or
time limit. The core releases the GIL while it renders, so Blender's UI stays live; the thread asks
Blender to redraw after each pass, and within a full-resolution pass every IMAGE_INTERVAL seconds (the
bands of rows done so far), and `view_draw` shows the newest image.

An edit (`update`) or a new view (`set_view`) cancels the pass in progress (the core notices
within its 0.1 s poll), waits for the thread, and starts again from the new scene or view: an image
never mixes photons of two scenes. An edit of lights alone (a lamp moved, its power or colour) replaces
the core scene's lights, an edit of materials' values writes them into their core slots, and a world
edit replaces the world; these keep the scene's objects and BVH, so lighting and shading a heavy scene
stay interactive. Objects moved, reshaped (with any number of triangles), given other materials, added
or removed, and the instances of an instancer moved, are updated in place (the core scene is dynamic:
the edited objects' BVH subtrees are refitted or built again, the others kept). Any other edit exports
the scene again. Everything that reads Blender data (the export) runs on the main thread, in
view_update and view_draw; the render thread touches only the core scene, which the main thread leaves
alone while a thread runs.
"""

import threading
import time
import weakref

import bpy

from . import export
from .export import sync
from .properties import render_settings

# (pixel size, photons per pass) of the quick first images, before the full-resolution passes.
PREVIEW_LEVELS = ((4, 10_000), (2, 25_000))
# Seconds between images within a full-resolution pass: the core pauses at the next band of rows,
# the image shows the bands done, and the pass goes on (a pass of a large view takes longer).
IMAGE_INTERVAL = 0.075
# The data blocks of the objects whose shading a material edit tags.
GEOMETRY_DATA = {"Mesh", "Curve", "SurfaceCurve", "TextCurve", "MetaBall", "Curves", "PointCloud", "Volume"}
# The live sessions, for scripts that measure the viewport (tests/gui, bench): engines are not reachable.
SESSIONS = weakref.WeakSet()


class ViewportImage:
    """One image of the session: RGBA (H, W, 4) top row first, at `pixel_size` region pixels a pixel,
    to be drawn over `window` (x, y, width, height in region pixels)."""

    def __init__(self, rgba, pixel_size, passes, photons, seconds, generation, window):
        self.rgba, self.pixel_size, self.passes = rgba, pixel_size, passes
        self.photons, self.seconds, self.generation, self.window = photons, seconds, generation, window


class ViewportSession:
    """The core scene, the render thread and the newest image of one viewport."""

    def __init__(self, ppm_core, redraw):
        self.ppm_core, self.redraw = ppm_core, redraw
        self.core_scene = None  # the exported scene; only the render thread uses it while it runs
        self.settings = None  # Renderer keyword arguments of the full-resolution passes
        self.settings_key = None  # settings_key() of the scene exported
        self.limits = (0, 0.0)  # (passes, seconds); 0 = none
        self.view = None  # set_camera arguments of the full region
        self.thread = None
        self.stop_requested = threading.Event()
        self.renderer = None
        self.lock = threading.Lock()
        self.image = None  # the newest ViewportImage
        self.generation = 0  # counts restarts; an image from an older one is dropped
        self.error = None
        self.done = False
        self.exporter = None  # the last whole export's Exporter: what it made of each object (sync)
        self.materials = None  # its MaterialExporter: its core material slots
        self.world_textures = 0  # the core's texture count before the world's (export_world)
        self.object_warnings = []  # of the last whole export (objects, materials)
        self.light_warnings = []  # of the last export of the lights
        self.material_warnings = []  # of the materials updated in place since the last export
        self.world_warnings = []  # of the last export of the world
        self.last_part = None  # what the last update brought up to date
        SESSIONS.add(self)

    @property
    def warnings(self):
        return self.object_warnings + self.light_warnings + self.material_warnings + self.world_warnings

    def update(self, depsgraph):
        """Brings the core scene up to the depsgraph's updates (main thread): what changed_part says,
        or the whole scene where materials or the world cannot be updated in place. Returns the part
        updated (None: nothing that is rendered changed)."""
        part = changed_part(depsgraph, self)
        if part == "materials" and not self.update_materials(depsgraph):
            part = "scene"
        if part == "world" and not self.update_world(depsgraph):
            part = "scene"
        if part == "objects" and not self.update_objects(depsgraph):
            part = "scene"
        if part == "lights":
            self.export_lights(depsgraph)
        elif part == "scene":
            self.export(depsgraph)
        if part is not None:
            self.last_part = part  # for scripts that check what an edit did (tests/gui)
        return part

    def export(self, depsgraph):
        """(Re)exports the whole scene from the evaluated depsgraph, stopping the thread."""
        self.stop()
        self.core_scene = None  # until the export succeeds: a failed one renders nothing and shows its error
        self.object_warnings, self.light_warnings, self.material_warnings, self.world_warnings = [], [], [], []
        exporter = export.scene_exporter(self.ppm_core, depsgraph, self.object_warnings.append, lights=False,
                                         world_warn=self.world_warnings.append,
                                         exporter_class=sync.SyncingExporter)
        export.export_lights(exporter.scene, depsgraph, self.light_warnings.append)
        self.core_scene, self.exporter, self.materials = exporter.scene, exporter, exporter.materials
        self.world_textures = exporter.world_textures
        scene = depsgraph.scene
        self.settings = renderer_settings(scene)
        self.limits = (scene.ppm.viewport_passes, scene.ppm.viewport_time_limit)
        self.settings_key = settings_key(scene)

    def export_lights(self, depsgraph):
        """Replaces the core scene's lights with the depsgraph's, stopping the thread; the objects, the
        world and the BVH built from them stay."""
        self.stop()
        core_scene, self.core_scene = self.core_scene, None  # as in export: a failure renders nothing
        self.light_warnings = []
        export.export_lights(core_scene, depsgraph, self.light_warnings.append)
        self.core_scene = core_scene

    def update_materials(self, depsgraph):
        """Writes the edited materials into their core slots, stopping the thread; False (the scene
        then needs a whole export) where one cannot be updated in place."""
        self.stop()
        core_scene, self.core_scene = self.core_scene, None  # as in export: a failure renders nothing
        self.use_attributes_of(depsgraph)
        warnings, edited = [], edited_materials(depsgraph)
        self.materials.warn = warnings.append
        try:
            if not all(self.materials.update(material) for material in edited):
                return False
        finally:
            self.materials.warn = self.object_warnings.append
        # The edited materials' warnings from before are replaced by the new ones; the others stay.
        stale = tuple(f"material '{material.name}':" for material in edited)
        self.object_warnings = [w for w in self.object_warnings if not w.startswith(stale)]
        self.material_warnings = [w for w in self.material_warnings if not w.startswith(stale)] + warnings
        self.core_scene = core_scene
        return True

    def update_objects(self, depsgraph):
        """Brings the objects up to the depsgraph in place, stopping the thread: mesh objects neither
        instanced nor instancing that moved or were reshaped alone (SyncingExporter.update_placed), anything else
        (objects added or removed, instancers moved, collections changed) through a walk over every
        instance (Exporter.sync), with the lights exported again. False (the scene then needs a whole
        export) where that cannot be. A camera object is the view's business (view_draw)."""
        self.stop()
        core_scene, self.core_scene = self.core_scene, None  # as in export: a failure renders nothing
        self.use_attributes_of(depsgraph)
        updates = [update for update in depsgraph.updates
                   if not (isinstance(update.id, bpy.types.Object) and update.id.type == "CAMERA")]
        moved = [update for update in updates if isinstance(update.id, bpy.types.Object)
                 and (update.is_updated_transform or update.is_updated_geometry)]
        reshaped = {update.id.original.name for update in moved if update.is_updated_geometry}
        exporter, warnings = self.exporter, []
        try:
            if all(is_object_or_geometry(update.id) for update in updates) and all(
                    exporter.is_placed(update.id) for update in moved):
                exporter.update_placed([update.id for update in moved], reshaped, warnings.append)
            else:
                if not exporter.sync(depsgraph, reshaped, warnings.append):
                    return False
                self.light_warnings = []  # lights may have come, gone or moved with what instances them
                export.export_lights(core_scene, depsgraph, self.light_warnings.append)
        except ValueError:
            return False
        stale = tuple(f"object '{name}':" for name in exporter.touched)
        self.object_warnings = [w for w in self.object_warnings if not w.startswith(stale)] + warnings
        self.core_scene = core_scene
        return True

    def use_attributes_of(self, depsgraph):
        """View-layer attributes, for what is exported in place: read from this depsgraph's."""
        table = self.materials.attributes_table
        if table is not None:
            table.view_layer, table.scene = depsgraph.view_layer, depsgraph.scene

    def update_world(self, depsgraph):
        """Replaces the world alone, stopping the thread; False (a whole export then) where the core
        refuses. Its warnings replace the last world's."""
        self.stop()
        core_scene, self.core_scene = self.core_scene, None  # as in export: a failure renders nothing
        self.use_attributes_of(depsgraph)
        table = self.materials.attributes_table
        warnings = []
        try:
            export.export_world(core_scene, depsgraph, warnings.append, self.world_textures, table)
        except ValueError:
            return False
        self.core_scene, self.world_warnings = core_scene, warnings
        return True

    def set_view(self, view):
        """Restarts with the camera arguments `view` if they differ from the current ones."""
        if self.view is not None and same_view(self.view, view):
            return False
        self.stop()
        self.view = view
        return True

    def start(self):
        """Starts refining (a no-op while running or without a scene and view)."""
        if self.thread is not None or self.core_scene is None or self.view is None:
            return
        self.generation += 1
        self.stop_requested.clear()
        self.error, self.done = None, False
        self.thread = threading.Thread(target=self.refine, args=(self.generation,), name="PPM viewport", daemon=True)
        self.thread.start()

    def stop(self):
        """Cancels the pass in progress and waits for the thread (the core stops within 0.1 s)."""
        if self.thread is None:
            return
        self.stop_requested.set()
        renderer = self.renderer
        if renderer is not None:
            renderer.cancel()
        self.thread.join()
        self.thread = None

    def newest(self):
        with self.lock:
            return self.image

    # The render thread.

    def refine(self, generation):
        try:
            start = time.monotonic()
            for pixel_size, photons in PREVIEW_LEVELS:
                if self.level_fits(pixel_size):
                    self.render_level(generation, start, pixel_size, {"photons_per_pass": photons}, passes=1)
            self.render_level(generation, start, 1, {}, passes=None)
        except Exception as error:  # noqa: BLE001 - shown in the viewport's header by view_draw
            self.error = str(error)
            self.redraw()
        finally:
            self.renderer = None
            self.done = True

    def level_fits(self, pixel_size):
        """A preview level is worth it where its image has at least a few pixels."""
        return min(self.view["width"], self.view["height"]) >= 8 * pixel_size

    def render_level(self, generation, start, pixel_size, overrides, passes):
        """Renders passes at one pixel size (`passes`: None = up to the viewport's limits)."""
        if self.stop_requested.is_set():
            return
        self.core_scene.set_camera(**scaled_view(self.view, pixel_size))
        renderer = self.ppm_core.Renderer(self.core_scene, **{**self.settings, **overrides})
        self.renderer = renderer
        max_passes, max_seconds = self.limits
        done, shown = 0, 0.0  # passes completed, and those plus the share of the next in the image
        while not self.stop_requested.is_set():
            if passes is not None and done >= passes:
                break
            if passes is None and ((max_passes and done >= max_passes)
                                   or (max_seconds and time.monotonic() - start >= max_seconds)):
                break
            renderer.run(passes=1, callback=lambda _info: not self.stop_requested.is_set(),
                         pause_after=IMAGE_INTERVAL if pixel_size == 1 else 0.0)
            stats = renderer.stats()
            if self.stop_requested.is_set() or stats["cancelled"] or stats["passes"] + stats["pass_done"] <= shown:
                break
            done, shown = stats["passes"], stats["passes"] + stats["pass_done"]
            self.publish(ViewportImage(renderer.image(), pixel_size, done, stats["photons_emitted"],
                                       time.monotonic() - start, generation, window_of(self.view)))
        self.renderer = None
        del renderer  # the next level may change the scene's camera only once no renderer holds it

    def publish(self, image):
        with self.lock:
            if image.generation == self.generation:
                self.image = image
        if self.redraw() is False:  # nobody to show it to
            self.stop_requested.set()


def renderer_settings(scene):
    """The Renderer's settings for the viewport's full-resolution passes: the render's, but with the
    viewport's photons per pass, new eye samples every pass (one per pixel in the core: anti-aliasing
    converges as it refines), and the camera view's depth of field sampled on the lens (a post blur
    needs the finished image)."""
    settings = scene.ppm
    return {**render_settings(scene), "photons_per_pass": settings.viewport_photons_per_pass,
            "hit_points": "stochastic", "dof_mode": "off" if settings.dof_mode == "OFF" else "lens"}


def redraw_of(engine):
    """engine.tag_redraw for the render thread, holding no reference that would keep the engine (and so
    its session and thread) alive after Blender frees it, and quiet once Blender has invalidated it."""
    engine_ref = weakref.ref(engine)

    def redraw():
        """False once the engine is gone (the thread then stops)."""
        engine = engine_ref()
        if engine is None:
            return False
        try:
            engine.tag_redraw()
        except ReferenceError:  # freed by Blender
            return False
        return True

    return redraw


def changed_part(depsgraph, session):
    """What of the rendered scene the depsgraph's updates change: None (a selection, say), "lights"
    (light objects and light data alone: moved, or their power, colour or size), "materials" (the
    values of materials: the objects using them are listed too, with only their shading tagged),
    "world" (a world and its node tree alone), "objects" (objects moved, reshaped, added or removed, with
    their data, lights' data and the collections and scene their relations tag) or "scene" (anything
    else, the add-on's settings, or a session without a scene)."""
    if session.core_scene is None or session.settings_key != settings_key(depsgraph.scene):
        return "scene"
    updates = [update for update in depsgraph.updates
               if update.is_updated_geometry or update.is_updated_transform or update.is_updated_shading
               or update.id.bl_rna.identifier not in ("Scene", "ViewLayer")]
    if not updates:
        return None
    changed = [update.id for update in updates]
    # A light's or a material's own node tree is listed with it (Blender 5.x lists a light's too).
    trees = {id.original.node_tree.as_pointer() for id in changed
             if isinstance(id, (bpy.types.Light, bpy.types.Material)) and getattr(id.original, "node_tree", None)}
    if all(is_light(id) or id.original.as_pointer() in trees for id in changed):
        return "lights"
    world_trees = {id.original.node_tree.as_pointer() for id in changed
                   if isinstance(id, bpy.types.World) and getattr(id.original, "node_tree", None)}
    if any(isinstance(id, bpy.types.World) for id in changed) and all(
            isinstance(id, bpy.types.World) or id.original.as_pointer() in world_trees for id in changed):
        return "world"
    # Objects moved, reshaped, added or removed, and collections changed (relations tag the Scene too).
    if all(is_object_or_geometry(id) or isinstance(id, (bpy.types.Light, bpy.types.Collection, bpy.types.Scene))
           or id.original.as_pointer() in trees for id in changed) and any(
            update.is_updated_transform or update.is_updated_geometry for update in updates):
        return "objects"
    if any(isinstance(id, bpy.types.Material) for id in changed) and all(
            isinstance(update.id, bpy.types.Material) or update.id.original.as_pointer() in trees
            or (is_object_or_geometry(update.id) and not is_light(update.id)
                and not (update.is_updated_geometry or update.is_updated_transform))
            for update in updates):
        return "materials"
    return "scene"


def is_object_or_geometry(id):
    """An object, or the data of a geometry object (a mesh, curve, ...)."""
    return isinstance(id, bpy.types.Object) or id.bl_rna.identifier in GEOMETRY_DATA


def edited_materials(depsgraph):
    """The materials among the depsgraph's updates."""
    return [update.id for update in depsgraph.updates if isinstance(update.id, bpy.types.Material)]


def is_light(id):
    """A light object, or a light's data."""
    return isinstance(id, bpy.types.Light) or (isinstance(id, bpy.types.Object) and id.type == "LIGHT")


def settings_key(scene):
    """What of the scene's settings the viewport's render depends on: its Renderer settings and limits."""
    settings = scene.ppm
    return tuple(sorted(renderer_settings(scene).items())), settings.viewport_passes, settings.viewport_time_limit


def status_line(session):
    """The viewport header's text: the error, or passes, photons and time, and the warnings' count."""
    warnings = session.warnings
    if session.error:
        return f"PPM: {session.error}"
    image = session.newest()
    if image is None:
        return "PPM: starting"
    line = f"Pass {image.passes} | {image.photons / 1e6:.1f} M photons | {image.seconds:.1f} s"
    if image.pixel_size > 1:
        line = f"Preview 1/{image.pixel_size} | " + line
    elif session.done:
        line += " | done"
    if warnings:
        line += f" | {len(warnings)} warning{'s' if len(warnings) > 1 else ''}: {warnings[0]}"
    return line


def scaled_view(view, pixel_size):
    """`view` rendered at 1 / pixel_size of its resolution (the same field of view)."""
    if pixel_size == 1:
        return view
    width, height = max(1, view["width"] // pixel_size), max(1, view["height"] // pixel_size)
    x, y, frame_width, frame_height = view["frame"]
    frame = (x // pixel_size, y // pixel_size, max(1, frame_width // pixel_size), max(1, frame_height // pixel_size))
    return {**view, "width": width, "height": height, "frame": frame}


def window_of(view):
    """(x, y, width, height) in region pixels where the image of `view` (full resolution) is drawn."""
    return view["frame"][0], view["frame"][1], view["width"], view["height"]


def same_view(a, b):
    """Whether two set_camera argument sets describe the same view (matrices compared by value)."""
    if a.keys() != b.keys():
        return False
    for key, value in a.items():
        other = b[key]
        if hasattr(value, "shape"):
            if value.shape != other.shape or not (value == other).all():
                return False
        elif value != other:
            return False
    return True
