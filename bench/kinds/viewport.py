"""The viewport's responsiveness, through the add-on's ViewportSession in Blender as a module (no
window, so drawing is left out: `view_draw` uploads and draws the newest image, about a millisecond):

    .venv/bin/python bench/run.py viewport [--quick]

On `scene` seen through its camera at width x height: an edit (the lamp moved) is followed by
view_update's work (session.update, called in a depsgraph handler as Blender calls view_update: a lamp
edit replaces the core scene's lights) and the thread's restart; reported are the seconds from the edit
to the first image of the new scene (a 1/4 resolution preview), to the first full-resolution image, and
session.update alone (median and 90th percentile over `edits_timed` edits). Then the images and passes
per second while refining at full resolution (each image asks Blender for a redraw; within a pass one
comes every viewport.IMAGE_INTERVAL seconds), and the process's resident memory after the edits in
`memory_marks` (each cancelling the last one's refinement after its first image, as dragging a lamp
does), as it is and after glibc's malloc_trim (what is still allocated). Last, the same scene with a
dense ball of about `heavy_triangles` triangles added: lamp edits (lights replaced), colour edits (a
material replaced) and world edits (the world replaced), which keep the BVH; moving the small ball or
the dense one (the object's mesh replaced in place and its BVH subtree refitted); a face of the small
ball or of the dense one deleted (another triangle count: the mesh read again and its subtree built
again); a cube added and deleted (its subtree built, then dropped); and, as what every edit cost before
edits in place, a viewport setting changed (the whole scene exported and its BVH built again). Then
resident memory over `object_edits` edits of the objects in the box alone (a cube added, a face of the
ball deleted, the cube deleted, in turn). Last, the box with `instances` particle instances of a small
cube: moving their host (each instance replaced in place), adding a cube, and a whole export."""

from __future__ import annotations

import os
import statistics
import sys
import time

import numpy as np

from harness import blenders

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


# What session.update must do for each edit (viewport.changed_part's parts; "scene": a whole export).
EXPECTED_PART = {"lamp": "lights", "material": "materials", "world": "world", "object": "objects",
                 "dense": "objects", "scatter": "objects", "faces": "objects", "dense_faces": "objects",
                 "cube": "objects", "delete": "objects", "setting": "scene"}


def rss_mb():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def trimmed_rss_mb():
    """Resident memory after glibc returns its free pages (malloc_trim): what is still in use, where
    rss_mb also counts what the allocator keeps for later."""
    import ctypes
    import gc

    gc.collect()
    ctypes.CDLL("libc.so.6").malloc_trim(0)
    return rss_mb()


def add_dense_ball(bpy, triangles, radius, location):
    """A UV sphere of about `triangles` triangles, made from arrays (bpy.ops' UV sphere takes minutes
    at this size, now and then)."""
    rings = max(3, int(round((triangles / 4) ** 0.5)))
    segments = 2 * rings
    theta = np.linspace(0.0, np.pi, rings + 1)[1:-1]
    phi = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    ring = np.stack([np.outer(np.sin(theta), np.cos(phi)), np.outer(np.sin(theta), np.sin(phi)),
                     np.repeat(np.cos(theta)[:, None], segments, axis=1)], axis=-1).reshape(-1, 3)
    vertices = np.concatenate([[(0.0, 0.0, 1.0)], ring, [(0.0, 0.0, -1.0)]]) * radius
    index = 1 + np.arange((rings - 1) * segments).reshape(rings - 1, segments)
    right = np.roll(index, -1, axis=1)
    top = np.stack([np.zeros(segments, int), index[0], right[0]], axis=1)
    bottom = np.stack([np.full(segments, len(vertices) - 1), right[-1], index[-1]], axis=1)
    a, b, c, d = index[:-1], right[:-1], right[1:], index[1:]
    sides = np.concatenate([np.stack([a, d, c], -1).reshape(-1, 3), np.stack([a, c, b], -1).reshape(-1, 3)])
    faces = np.concatenate([top, sides, bottom])
    mesh = bpy.data.meshes.new("dense_ball")
    mesh.from_pydata(vertices, [], faces)
    mesh.update()
    obj = bpy.data.objects.new("dense_ball", mesh)
    obj.location = location
    bpy.context.scene.collection.objects.link(obj)
    return obj


def add_scattered_cubes(bpy, count):
    """A plane on the floor whose hair particles instance `count` small cubes (12 triangles each); the
    plane, whose moves move them all."""
    mesh = bpy.data.meshes.new("pebble")
    mesh.from_pydata([(x, y, z) for x in (0, 0.01) for y in (0, 0.01) for z in (0, 0.01)], [],
                     [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)])
    pebble = bpy.data.objects.new("pebble", mesh)
    bpy.context.scene.collection.objects.link(pebble)
    pebble.location = (0.0, 0.0, -5.0)  # the original out of sight, under the floor
    plane = bpy.data.meshes.new("scatter")
    plane.from_pydata([(-0.3, -0.3, 0.0), (0.3, -0.3, 0.0), (0.3, 0.3, 0.0), (-0.3, 0.3, 0.0)], [], [(0, 1, 2, 3)])
    host = bpy.data.objects.new("scatter", plane)
    host.location = (0.0, 0.0, 0.05)
    bpy.context.scene.collection.objects.link(host)
    host.modifiers.new("particles", "PARTICLE_SYSTEM")
    settings = host.particle_systems[0].settings
    settings.type, settings.count, settings.render_type, settings.instance_object = "HAIR", count, "OBJECT", pebble
    return host


class Edits:
    """The session on the scene, and edits of its lamp or a material, timed."""

    def __init__(self, params, extra_triangles=0, instances=0):
        import bpy

        from ppm_render import core, viewport
        from ppm_render.viewport_camera import camera_from_projection

        bpy.ops.wm.open_mainfile(filepath=os.path.join(ROOT, "blend_scenes", params["scene"]))
        self.bpy, self.scene = bpy, bpy.context.scene
        if extra_triangles:  # a dense ball on the floor: a heavy scene that still looks like the box
            add_dense_ball(bpy, extra_triangles, 0.15, (0.45, 0.45, 0.15))
        if instances:
            add_scattered_cubes(bpy, instances)
        self.scene.ppm.viewport_photons_per_pass = self.photons = params["photons"]
        self.scene.ppm.viewport_passes = 0
        self.cubes = []  # the names of the cubes added, the newest last
        self.session = viewport.ViewportSession(core.load(), lambda: None)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        self.triangles = sum(len(p.vertices) - 2 for o in self.scene.objects if o.type == "MESH"
                             for p in o.data.polygons)
        cam = self.scene.camera
        projection = cam.calc_matrix_camera(depsgraph, x=params["width"], y=params["height"])
        self.session.export(depsgraph)
        self.session.set_view(camera_from_projection(cam.matrix_world.inverted(), projection, params["width"],
                                                     params["height"]))
        self.session.start()
        self.lamp = next(o for o in self.scene.objects if o.type == "LIGHT")
        self.matte = next(n for n in self.bpy.data.materials["matte"].node_tree.nodes if n.type.startswith("BSDF"))
        self.background = next(n for n in self.scene.world.node_tree.nodes if n.type == "BACKGROUND")
        self.step = 0

    def change(self, what):
        if what == "lamp":
            self.lamp.location.x = 0.2 * ((self.step % 5) - 2)
        elif what == "material":  # the matte ball's colour: written into its core material
            self.matte.inputs["Color"].default_value = (0.8, 0.7, 0.1 + 0.1 * (self.step % 5), 1.0)
        elif what == "world":  # the (black) world's colour: the world alone exported again
            self.background.inputs["Color"].default_value = (0.01 * (self.step % 5),) * 3 + (1.0,)
        elif what == "object":  # the matte ball moved: its mesh replaced in place
            self.scene.objects["matte_ball"].location.x = -0.3 + 0.02 * (self.step % 5)
        elif what == "dense":  # the dense ball moved: its mesh replaced in place
            self.scene.objects["dense_ball"].location.x = 0.45 - 0.02 * (self.step % 5)
        elif what == "scatter":  # the particle host moved: every instance replaced in place
            self.scene.objects["scatter"].location.x = 0.02 * (self.step % 5)
        elif what == "faces":  # a face of the matte ball deleted: its mesh read again, its subtree built again
            delete_a_face(self.bpy, self.scene.objects["matte_ball"])
        elif what == "dense_faces":  # the same for the dense ball
            delete_a_face(self.bpy, self.scene.objects["dense_ball"])
        elif what == "cube":  # a small cube added: its subtree built
            mesh = self.bpy.data.meshes.new("cube")
            mesh.from_pydata([(x, y, z) for x in (0, 0.1) for y in (0, 0.1) for z in (0, 0.1)], [],
                             [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)])
            cube = self.bpy.data.objects.new("cube", mesh)
            cube.location = (-0.4, 0.3 - 0.05 * (self.step % 8), 0.0)
            self.scene.collection.objects.link(cube)
            self.cubes.append(cube.name)
        elif what == "delete":  # the last cube added deleted: its subtree dropped
            self.bpy.data.objects.remove(self.bpy.data.objects[self.cubes.pop()])
        else:  # a viewport setting changed: the whole scene exported again (what every edit cost once)
            self.scene.ppm.viewport_photons_per_pass = self.photons + 1 + self.step % 2  # never the last value

    def edit(self, what="lamp", wait_full=True):
        """Makes the edit `what` (see EXPECTED_PART) and does what view_update (session.update, in a depsgraph
        handler as Blender calls it) and view_draw (start) do; (seconds to the first image, to the first
        full-resolution image (None without `wait_full`), of session.update)."""
        self.step += 1
        updated = []

        def handler(_scene, depsgraph):
            update_start = time.perf_counter()
            part = self.session.update(depsgraph)
            if part is not None:
                updated.append((time.perf_counter() - update_start, part))

        self.bpy.context.evaluated_depsgraph_get()
        self.bpy.app.handlers.depsgraph_update_post.append(handler)
        try:
            start = time.perf_counter()
            self.change(what)
            depsgraph = self.bpy.context.evaluated_depsgraph_get()
            if what == "setting":  # settings tag no update: view_draw sees them and calls view_update
                handler(self.scene, depsgraph)
        finally:
            self.bpy.app.handlers.depsgraph_update_post.remove(handler)
        if len(updated) != 1:
            raise RuntimeError(f"a {what} edit (step {self.step}) updated the session {len(updated)} times")
        if updated[0][1] != EXPECTED_PART[what]:  # (a handler's exceptions are only printed)
            raise RuntimeError(f"a {what} edit updated '{updated[0][1]}', not '{EXPECTED_PART[what]}'")
        self.session.start()
        generation, first, full = self.session.generation, None, None
        while full is None and (wait_full or first is None):
            image = self.session.newest()
            if image is not None and image.generation == generation:
                first = first or time.perf_counter() - start
                if image.pixel_size == 1:
                    full = time.perf_counter() - start
            if self.session.error:
                raise RuntimeError(self.session.error)
            time.sleep(0.0005)
        return first, full, updated[0][0]

    def images_per_second(self, seconds):
        """(full-resolution images, completed passes) per second while refining: an image comes after
        each pass and within one every viewport.IMAGE_INTERVAL seconds."""
        seen, start, last = 0, time.perf_counter(), self.session.newest()
        first = last
        while time.perf_counter() - start < seconds:
            image = self.session.newest()
            if image is not last and image.pixel_size == 1:
                seen, last = seen + 1, image
            time.sleep(0.0005)
        return seen / seconds, (last.passes - first.passes) / seconds


def delete_a_face(bpy, obj):
    import bmesh

    mesh = bmesh.new()
    mesh.from_mesh(obj.data)
    bmesh.ops.delete(mesh, geom=[next(iter(mesh.faces))], context="FACES_ONLY")
    mesh.to_mesh(obj.data)
    mesh.free()
    obj.data.update()


def measure(params):
    sys.path.insert(0, os.path.join(ROOT, "addon"))
    import bpy

    import ppm_render

    bpy.ops.wm.read_factory_settings(use_empty=True)
    ppm_render.register()
    try:
        edits = Edits(params)
        timed = [edits.edit() for _ in range(params["edits_timed"])]
        rate = edits.images_per_second(params["refine_seconds"])
        memory = {}
        for count in range(edits.step + 1, params["edits"] + 1):
            edits.edit(wait_full=False)  # the next edit cancels the refinement, as a dragged lamp does
            if count in params["memory_marks"]:
                memory[count] = (rss_mb(), trimmed_rss_mb())
        object_memory = {}
        for count in range(1, params["object_edits"] + 1):
            edits.edit(OBJECT_CYCLE[count % len(OBJECT_CYCLE)], wait_full=False)
            if count in params["memory_marks"]:
                object_memory[count] = (rss_mb(), trimmed_rss_mb())
        edits.session.stop()
        heavy = {}
        if params["heavy_triangles"]:
            edits = Edits(params, params["heavy_triangles"])
            for what in HEAVY_EDITS:
                heavy[what] = [edits.edit(what) for _ in range(params["heavy_edits_timed"])]
            heavy["triangles"] = edits.triangles
            edits.session.stop()
        scattered = {}
        if params["instances"]:
            edits = Edits(params, instances=params["instances"])
            for what in SCATTER_EDITS:
                scattered[what] = [edits.edit(what) for _ in range(params["heavy_edits_timed"])]
            edits.session.stop()
    finally:
        ppm_render.unregister()  # bpy 4.2 and 4.5 crash or hang at exit otherwise
    return {"version": bpy.app.version_string, "timed": timed, "images_per_s": rate, "rss_mb": memory,
            "object_rss_mb": object_memory, "heavy": heavy, "scattered": scattered}


OBJECT_CYCLE = ("delete", "cube", "faces")  # edit k of the object series is OBJECT_CYCLE[k % 3]


HEAVY_EDITS = {"lamp": "lamp moved (lights replaced)", "material": "colour edited (material replaced)",
               "world": "world colour edited (world replaced)",
               "object": "matte ball moved (its mesh replaced)",
               "dense": "dense ball moved (its mesh replaced)",
               "faces": "a face of the matte ball deleted (its subtree built again)",
               "dense_faces": "a face of the dense ball deleted (its subtree built again)",
               "cube": "a cube added (its subtree built)", "delete": "that cube deleted (its subtree dropped)",
               "setting": "a viewport setting changed (all exported)"}


SCATTER_EDITS = {"scatter": "particle host moved (its instances replaced)", "cube": "a cube added (its subtree built)",
                 "setting": "a viewport setting changed (all exported)"}


def quantiles(values):
    ordered = sorted(values)
    return statistics.median(ordered), ordered[min(len(ordered) - 1, int(0.9 * len(ordered)))]


def run(experiment, results):
    params = {k: experiment[k] for k in ("scene", "width", "height", "photons", "edits_timed", "refine_seconds",
                                         "edits", "memory_marks", "heavy_triangles", "heavy_edits_timed",
                                         "instances", "object_edits")}
    m = blenders.result_of(experiment["blender"], "kinds.viewport:measure", params)
    rows = []
    for i, name in enumerate(("edit -> first image (1/4 preview)", "edit -> first full-resolution image",
                              "session.update alone (the export)")):
        median, p90 = quantiles([t[i] for t in m["timed"]])
        results.row(part="edit", measure=name, median_s=median, p90_s=p90)
        rows.append([name, f"{median:.3f}", f"{p90:.3f}"])
    results.table(["seconds", "median", "90th percentile"], rows,
                  title=f"{experiment['scene']} at {experiment['width']}x{experiment['height']}, "
                        f"{experiment['photons']:,} photons per pass, Blender {m['version']}")
    images, passes = m["images_per_s"]
    results.row(part="refine", images_per_s=images, passes_per_s=passes)
    results.table(["while refining at full resolution, per second", "images", "passes"],
                  [["", f"{images:.1f}", f"{passes:.1f}"]])
    results.row(part="memory", rss_mb=m["rss_mb"])
    results.table(["edits", "resident memory (MB)", "after malloc_trim"],
                  [[k, f"{rss:.0f}", f"{trimmed:.0f}"] for k, (rss, trimmed) in m["rss_mb"].items()])
    results.row(part="object memory", rss_mb=m["object_rss_mb"])
    results.table(["object edits (a cube added, a face deleted, the cube deleted)", "resident memory (MB)",
                   "after malloc_trim"],
                  [[k, f"{rss:.0f}", f"{trimmed:.0f}"] for k, (rss, trimmed) in m["object_rss_mb"].items()])
    if m["heavy"]:
        edits_table(results, "heavy", HEAVY_EDITS, m["heavy"],
                    f"the same with a dense ball added: {m['heavy']['triangles']:,} triangles")
    if m["scattered"]:
        edits_table(results, "scattered", SCATTER_EDITS, m["scattered"],
                    f"the Cornell box with {experiment['instances']:,} particle instances of a 12-triangle cube")


def edits_table(results, part, labels, timings, title):
    rows = []
    for what, label in labels.items():
        for i, name in enumerate(("edit -> first image", "edit -> first full-resolution image",
                                  "session.update alone")):
            median, p90 = quantiles([t[i] for t in timings[what]])
            results.row(part=part, edit=what, measure=name, median_s=median, p90_s=p90)
            rows.append([label, name, f"{median:.3f}", f"{p90:.3f}"])
    results.table(["edit", "seconds", "median", "90th percentile"], rows, title=title)
