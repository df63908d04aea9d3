"""The Flamenco job type for sharded stills (addon/farm/flamenco/ppm_sharded_still.js): its
compileJob run with Node and stand-ins for the Manager's API, and the commands it makes run as a
Flamenco worker would, with Debian's Blender 3.4 and only the add-on zip installed. The merged EXR
must hold every pass once and equal the merge of the shares."""

import json
import os
import subprocess
import sys

import numpy as np
from test_farm_exit_codes import blender, farm_node

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
JOB_TYPE = os.path.join(ROOT, "addon", "farm", "flamenco", "ppm_sharded_still.js")
COMPILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "flamenco_compile.js")

SMALL_SCENE = """
import bpy
bpy.ops.wm.open_mainfile(filepath=SCENE)
scene = bpy.context.scene
scene.ppm.passes, scene.ppm.photons_per_pass = 6, 10000
scene.render.resolution_percentage = 10
bpy.ops.wm.save_as_mainfile(filepath=OUT)
"""


def compiled_job(settings):
    run = subprocess.run(["node", COMPILE, JOB_TYPE, json.dumps(settings)], capture_output=True, text=True,
                         check=False)
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


def command_line(command):
    """What a Flamenco worker runs for a 'blender-render' command."""
    p = command["parameters"]
    return [p["exe"], *p["exeArgs"].split(), *p["argsBefore"], p["blendfile"], *p["args"]]


def run_task(task, env):
    for command in task["commands"]:
        assert command["type"] == "blender-render"
        line = command_line(command)
        run = subprocess.run(line, capture_output=True, text=True, timeout=300, env=env, check=False)
        assert run.returncode == 0, task["name"] + ": " + run.stdout[-2000:] + run.stderr[-2000:]


def test_the_job_renders_and_merges_every_pass_once(tmp_path):
    env = farm_node(tmp_path)
    scene = str(tmp_path / "small.blend")
    made = blender("--python-exit-code", "1", "--python-expr",
                   f"SCENE, OUT = {os.path.join(ROOT, 'blend_scenes', 'cornell_3spheres.blend')!r}, {scene!r}\n"
                   + SMALL_SCENE, env=env)
    assert made.returncode == 0, made.stderr[-2000:]
    output = str(tmp_path / "renders" / "still.exr")
    job = compiled_job({"passes": 6, "shares": 4, "render_output_path": output, "blender_cmd": "blender",
                        "blendfile": scene})
    shares = [t for t in job["tasks"] if t["name"].startswith("share-")]
    merge = next(t for t in job["tasks"] if t["name"] == "merge")
    assert len(shares) == 4 and merge["dependencies"] == [t["name"] for t in shares]
    for task in shares:
        run_task(task, env)
    run_task(merge, env)

    sys.path.insert(0, os.path.join(ROOT, "addon"))
    import OpenImageIO as oiio

    import ppm_core
    from ppm_render.farm.blender_task import load_share

    files = command_line(merge["commands"][0])[-4:]
    merged = ppm_core.merge_shares([load_share(ppm_core, f) for f in files])
    assert merged.passes == 6 and [r[0] for r in merged.ranges] == [0, 1, 3, 4]
    pixels = oiio.ImageBuf(output).get_pixels(oiio.FLOAT)
    np.testing.assert_array_equal(pixels, merged.image())  # Blender 3.4 wrote it: 32-bit float, linear
    assert pixels[..., :3].mean() > 0.0


def test_a_worker_without_the_addon_fails_the_task(tmp_path):
    env = {**os.environ, "BLENDER_USER_SCRIPTS": str(tmp_path / "scripts"),
           "BLENDER_USER_CONFIG": str(tmp_path / "config")}
    scene = os.path.join(ROOT, "blend_scenes", "cornell_3spheres.blend")
    job = compiled_job({"passes": 2, "shares": 1, "render_output_path": str(tmp_path / "x.exr"),
                        "blender_cmd": "blender", "blendfile": scene})
    run = subprocess.run(command_line(job["tasks"][0]["commands"][0]), capture_output=True, text=True, timeout=300,
                         env=env, check=False)
    assert run.returncode != 0 and "not enabled" in run.stdout + run.stderr


def test_job_settings_are_checked():
    run = subprocess.run(["node", COMPILE, JOB_TYPE, json.dumps({"passes": 4, "shares": 2, "render_output_path":
                                                                  "/tmp/out.png", "blender_cmd": "b",
                                                                  "blendfile": "/tmp/a.blend"})],
                         capture_output=True, text=True, check=False)
    assert run.returncode != 0 and "must end in .exr" in run.stderr
