"""Production sizes: memory and time per pass as the image grows, and memory per mesh triangle.

    .venv/bin/python bench/run.py sizes [--quick]

Images: cornell_3spheres through ppm_core at each of `sizes`, for each of `hit_points` (fixed:
`samples_per_pixel` eye samples per pixel, kept for the render; fixed-streamed: the same, made
again band by band every pass; stochastic: one per pixel and pass, made in bands) and each of
`gathers` (the set the grid indexes: "photons", the default, or "hit_points"), `photons` photons
per pass, 2 threads, one untimed pass and then `passes` timed ones. Reported: the process's peak
resident memory grown over the render (bytes per pixel, image read back included; and per hit
point for fixed ones), the core's own figures by part (stats()["memory"]), seconds per pass and
per stage, photon paths per second (trace, index, gather).

Meshes: the raycast kind's terrain at about each of `triangles`, added to a scene and built in
each of `geometry_layouts` (Scene.geometry_layout) and with each of `mesh_attributes` ("none", or
"normals+uvs": a normal per vertex and a UV per corner, as a smooth UV-mapped mesh exports): peak
and resident memory grown per triangle (resident after glibc's malloc_trim, so that memory the
allocator keeps for later does not count), the core's scene bytes per triangle (stats()["memory"]),
seconds to add and build.

Each measurement runs in a fresh process (`python -m kinds.sizes image|mesh ...` from bench/),
so that its peak is its own."""

from __future__ import annotations

import ctypes
import json
import os
import subprocess
import sys
import time

import numpy as np

BENCH_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STAGES = ("eye_pass", "photon_trace", "index_build", "gather", "direct_light", "progressive_update")


def status_bytes(field):
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) * 1024 for line in f if line.startswith(field + ":"))


def image_child(width, height, hit_points, photons, passes, spp, gather):
    import core_scenes
    import ppm_core

    # Storage named only where streamed: a core from before hit_point_storage still runs the rest (A/B).
    mode = {"fixed-streamed": {"hit_points": "fixed", "hit_point_storage": "streamed"}}.get(
        hit_points, {"hit_points": hit_points})
    if hit_points == "fixed" and "hit_point_storage" in ppm_core.default_settings():
        mode["hit_point_storage"] = "kept"
    before = status_bytes("VmRSS")
    r = ppm_core.Renderer(core_scenes.cornell_3spheres(width, height), threads=2, photons_per_pass=photons,
                          samples_per_pixel=spp, seed=1, gather=gather, **mode)
    r.run(passes=1)
    s0 = r.stats()
    start = time.perf_counter()
    r.run(passes=passes)
    wall = time.perf_counter() - start
    s1 = r.stats()
    r.image()
    step = {k: (s1["seconds"][k] - s0["seconds"][k]) / passes for k in STAGES}
    photon_s = step["photon_trace"] + step["index_build"] + step["gather"]
    return {"width": width, "height": height, "hit_points": hit_points, "gather": gather,
            "hit_point_count": s1["hit_points"], "grown_bytes": status_bytes("VmHWM") - before,
            "memory": s1.get("memory", {}), "seconds_per_pass": wall / passes, "step": step,
            "paths_per_s": photons / photon_s if photon_s > 0 else 0.0, "first_pass": s0["seconds"]["total"]}


def mesh_attribute_arrays(vertices, tris, attributes):
    """Smooth normals per vertex and a planar UV per corner, or none."""
    if attributes == "none":
        return {}
    normals = np.zeros_like(vertices)
    n = np.cross(vertices[tris[:, 1]] - vertices[tris[:, 0]], vertices[tris[:, 2]] - vertices[tris[:, 0]])
    for k in range(3):
        np.add.at(normals, tris[:, k], n)
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-30)
    normals[np.linalg.norm(normals, axis=1) == 0] = (0.0, 0.0, 1.0)
    uvs = vertices[tris][:, :, :2].copy()  # (T, 3, 2): per corner
    return {"normals": normals, "uvs": uvs}


def mesh_child(triangles, layout, attributes):
    import ppm_core
    from kinds.raycast import terrain

    n = max(2, int((triangles * 0.72 / 2) ** 0.5))  # the terrain's grid; the leaves are the rest
    vertices, tris = terrain(n, max(1, triangles - 2 * n * n), np.random.default_rng(7))
    vertices = vertices.astype(float)
    extra = mesh_attribute_arrays(vertices, tris, attributes)
    before = status_bytes("VmRSS")
    start = time.perf_counter()
    scene = ppm_core.Scene()
    scene.geometry_layout = layout
    scene.add_material("ground", base_color=(0.7, 0.7, 0.7))
    scene.add_mesh("terrain", vertices, tris, **extra)
    added = time.perf_counter() - start
    scene.set_camera(np.eye(4), 64, 48)
    scene.build()
    built = time.perf_counter() - start - added
    del vertices, tris, extra
    peak = status_bytes("VmHWM") - before
    ctypes.CDLL("libc.so.6").malloc_trim(0)  # what is still in use, not what the allocator keeps for later
    core = ppm_core.Renderer(scene, photons_per_pass=1).stats()["memory"].get("scene", 0)
    return {"triangles": triangles, "layout": layout, "attributes": attributes, "grid": n, "grown_bytes": peak,
            "resident_bytes": status_bytes("VmRSS") - before,
            "core_scene_bytes": core, "add_seconds": added, "build_seconds": built}


def child(args):
    if args[0] == "image":
        w, h, mode, photons, passes, spp, gather = args[1:]
        row = image_child(int(w), int(h), mode, int(photons), int(passes), int(spp), gather)
    else:
        row = mesh_child(int(args[1]), args[2], args[3])
    print(json.dumps(row), flush=True)


def fresh(*args):
    out = subprocess.run([sys.executable, "-m", "kinds.sizes", *map(str, args)], cwd=BENCH_DIR,
                         stdout=subprocess.PIPE, text=True, check=True)
    return json.loads(out.stdout.splitlines()[-1])


def share(memory, parts, scale):
    """The core's bytes in `parts` over `scale`; n/a for a core from before stats()["memory"] (A/B)."""
    return f"{sum(memory[p] for p in parts) / scale:.0f}" if memory else "n/a"


def images_part(experiment, results):
    rows = []
    gathers = experiment.get("gathers", ["photons"])
    for width, height in experiment["sizes"]:
        for mode, gather in ((m, g) for m in experiment["hit_points"] for g in gathers):
            r = fresh("image", width, height, mode, experiment["photons"], experiment["passes"],
                      experiment["samples_per_pixel"], gather)
            results.row(part="images", **r)
            pixels = width * height
            mem = r["memory"]
            rows.append([f"{width}x{height}", mode + ("" if gathers == ["photons"] else f", {gather} indexed"),
                         f"{r['grown_bytes'] / 2**20:.0f}",
                         f"{r['grown_bytes'] / pixels:.0f}",
                         f"{r['grown_bytes'] / r['hit_point_count']:.0f}" if mode != "stochastic" else "",
                         share(mem, ("pixels",), pixels),
                         share(mem, ("hit_points",), 2**20), share(mem, ("photons", "index"), 2**20),
                         f"{r['seconds_per_pass']:.2f}", f"{r['step']['eye_pass']:.2f}",
                         f"{r['step']['gather']:.2f}", f"{r['step']['direct_light']:.2f}",
                         f"{r['paths_per_s'] / 1e6:.2f} M"])
    results.table(["image", "hit points", "peak grown MB", "peak B/pixel", "peak B/hit point", "core pixels B/pixel",
                   "core hit points MB", "core photons + index MB", "s/pass", "eye s", "gather s", "direct s",
                   "photon paths/s"], rows)


def meshes_part(experiment, results):
    if not experiment["triangles"]:
        return
    rows = []
    layouts = experiment.get("geometry_layouts", ["auto"])
    attributes = experiment.get("mesh_attributes", ["none"])
    for triangles, layout, extra in ((t, g, a) for t in experiment["triangles"] for g in layouts for a in attributes):
        r = fresh("mesh", triangles, layout, extra)
        results.row(part="meshes", **r)
        rows.append([f"{triangles:,}", layout, extra, f"{r['grown_bytes'] / triangles:.0f}",
                     f"{r['resident_bytes'] / triangles:.0f}", f"{r['core_scene_bytes'] / triangles:.0f}",
                     f"{r['add_seconds']:.2f}", f"{r['build_seconds']:.2f}"])
    results.table(["triangles", "layout", "attributes", "peak grown B/triangle",
                   "resident B/triangle after the build (trimmed)", "core scene B/triangle", "add s", "build s"], rows)


def run(experiment, results):
    results.note(f"cornell_3spheres, {experiment['photons']} photons per pass, 2 threads, "
                 f"{experiment['passes']} timed passes; fixed hit points at {experiment['samples_per_pixel']} "
                 "samples per pixel")
    images_part(experiment, results)
    meshes_part(experiment, results)


if __name__ == "__main__":
    sys.path.insert(0, os.path.join(os.path.dirname(BENCH_DIR), "blend_scenes"))
    child(sys.argv[1:])
