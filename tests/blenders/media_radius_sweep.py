"""The volume estimate's radius and boundary against Cycles, media_compare's scenes at 64x48: Cycles
once per scene at 4096 samples (saved as .npy, rows top-down), then PPM through the add-on's export
and the core directly, for each volume_radius_scale (SCALES) and seeds 1 and 2, at 256 passes and on
to 1024; TAG=b renders with volume_boundary on and NEW_CORE=1 (no TAG) with it off (a core that has
it); `table` prints each variant's worst block error against Cycles and the seeds' block spread.

    cd /tmp/x && PYTHONPATH=<build> .venv/bin/python tests/blenders/media_radius_sweep.py cycles
    cd /tmp/x && PYTHONPATH=<build> NEW_CORE=1 .venv/bin/python tests/blenders/media_radius_sweep.py ppm
    cd /tmp/x && PYTHONPATH=<build> TAG=b SCALES=1.0 .venv/bin/python tests/blenders/media_radius_sweep.py ppm
    cd /tmp/x && .venv/bin/python tests/blenders/media_radius_sweep.py table
(OUT: where the arrays go, /tmp/vr by default; THREADS: 2.)"""
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy
import numpy as np

import cycles_compare as cc
import media_compare as mc

OUT = os.environ.get("OUT", "/tmp/vr")
CASES = ("smoke_ball", "world_fog", "fog_cube_spot", "glowing_cloud")
SCALES = tuple(float(x) for x in os.environ.get("SCALES", "1.0 0.5 0.25").split())
TAG = os.environ.get("TAG", "")
EXTRA = {"volume_boundary": bool(TAG)} if TAG or os.environ.get("NEW_CORE") else {}
SEEDS = (1, 2)
SAMPLES = 4096


def cycles(case):
    path = f"{OUT}/cycles_{case}.npy"
    if os.path.exists(path):
        return
    scene = mc.build(case)
    cc.configure_cycles(scene, SAMPLES, mc.BOUNCES)
    mc.configure_for(case)(scene, "CYCLES")
    scene.render.threads = int(os.environ.get("THREADS", "2"))
    t = time.time()
    rgb = cc.render_to_array(scene, f"{OUT}/cycles_{case}.exr")
    np.save(path, rgb[::-1].copy())  # Blender's rows are bottom-up
    print(f"cycles {case} {time.time() - t:.0f}s", flush=True)


def ppm(case):
    scene = mc.build(case)
    from ppm_render import core, export
    from ppm_render.export.camera import Frame
    from ppm_render.properties import render_settings
    ppm_core = core.load()
    print("core", ppm_core.__file__, flush=True)
    cc.configure_ppm(scene, 1024)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    warnings = []
    frame = Frame.from_render_settings(scene.render)
    core_scene, _, _ = export.build_scene(ppm_core, depsgraph, frame, warnings.append)
    reference = np.load(f"{OUT}/cycles_{case}.npy")
    rows = []
    for scale in SCALES:
        for seed in SEEDS:
            settings = {**render_settings(scene), "hit_points": "stochastic", "seed": seed,
                        "threads": int(os.environ.get("THREADS", "2")), "volume_radius_scale": scale, **EXTRA}
            r = ppm_core.Renderer(core_scene, **settings)
            t = time.time()
            for passes in (256, 1024):
                r.run(passes=passes - r.stats()["passes"])
                image = np.asarray(r.image())[..., :3]
                np.save(f"{OUT}/ppm{TAG}_{case}_{scale}_{seed}_{passes}.npy", image)
                err = cc.worst_block_error({"CYCLES": reference, "PPM": image})
                row = dict(case=case, scale=scale, seed=seed, passes=passes, worst=err,
                           seconds=time.time() - t, blocks=cc.block_means(image).tolist())
                rows.append(row)
                print(json.dumps({k: v for k, v in row.items() if k != "blocks"}), flush=True)
    with open(f"{OUT}/rows{TAG}_{case}.json", "w") as f:
        json.dump(rows, f)


def table():
    print("| scene | variant | passes | worst seed 1 | worst seed 2 | worst of mean | spread max |")
    print("|---|---|---|---|---|---|---|")
    for case in ("smoke_ball", "world_fog", "fog_cube_spot", "glowing_cloud"):
        ref = cc.block_means(np.load(f"{OUT}/cycles_{case}.npy"))
        den = np.maximum(ref, 1e-4)
        for tag, scale in (("", 1.0), ("", 0.5), ("", 0.25), ("b", 1.0)):
            for passes in (256, 1024):
                files = [f"{OUT}/ppm{tag}_{case}_{scale}_{s}_{passes}.npy" for s in (1, 2)]
                if not all(map(os.path.exists, files)):
                    continue
                b = [cc.block_means(np.load(f)) for f in files]
                e = [abs(x - ref) / den for x in b]
                name = f"scale {scale}" + (" + boundary" if tag else "")
                mean, spread = abs((b[0] + b[1]) / 2 - ref) / den, abs(b[0] - b[1]) / den
                print(f"| {case} | {name} | {passes} | {100 * e[0].max():.1f}% | {100 * e[1].max():.1f}% | "
                      f"{100 * mean.max():.1f}% | {100 * spread.max():.1f}% |")


def main():
    mode, cases = sys.argv[1], sys.argv[2:] or CASES
    if mode == "table":
        return table()
    try:
        for case in cases:
            (cycles if mode == "cycles" else ppm)(case)
    finally:
        cc.unregister_checkout_addon()


main()
