"""The commands render managers run (`blender -b file.blend -f N`, `-a`, Flamenco's `--render-frame A..B`)
with the add-on installed in a user folder, as on a farm node: every frame of a range renders, a frame
that Cycles renders renders (bad objects are left out with a warning), and a frame that cannot be
rendered makes Blender exit non-zero, so the job stops there."""

import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "blend_scenes", "cornell_3spheres.blend")

INSTALL = """
import bpy
bpy.ops.preferences.addon_install(filepath=ZIP)
bpy.ops.preferences.addon_enable(module="ppm_render")
bpy.ops.wm.save_userpref()
"""

# Objects and lights Cycles renders (or renders as nothing) and the core cannot take as they are.
HOSTILE = """
import bpy
bpy.ops.wm.open_mainfile(filepath=SCENE)
scene = bpy.context.scene
scene.ppm.passes, scene.ppm.photons_per_pass = 2, 10000
scene.render.resolution_percentage = 10
flat = bpy.data.objects.new("flat", bpy.data.lights.new("flat", "AREA"))
flat.data.size = 0.0
minus = bpy.data.objects.new("minus", bpy.data.lights.new("minus", "POINT"))
minus.data.energy = -50.0
mesh = bpy.data.meshes.new("spiky")
mesh.from_pydata([(0, 0, 1), (1, 0, 1), (float("nan"), 1, 1)], [], [(0, 1, 2)])
hidden = bpy.data.objects.new("hidden", mesh)
hidden.scale = (0.0, 0.0, 0.0)
spiky = bpy.data.objects.new("spiky", mesh)
for obj in (flat, minus, hidden, spiky):
    scene.collection.objects.link(obj)
if NO_CAMERA:
    scene.camera = None
bpy.ops.wm.save_as_mainfile(filepath=OUT)
"""


def blender(*args, env):
    return subprocess.run(["blender", "-b", *args], capture_output=True, text=True, timeout=300, env=env, check=False)


def farm_node(tmp_path, *build_args):
    """A user folder with the zip (built with `build_args`) installed and enabled, as its environment."""
    build = subprocess.run([sys.executable, os.path.join(ROOT, "addon", "build_addon.py"), "--out",
                            str(tmp_path / "zip"), *build_args], capture_output=True, text=True, check=True)
    zip_path = build.stdout.split("wrote ")[1].split(" ")[0]
    env = {**os.environ, "BLENDER_USER_SCRIPTS": str(tmp_path / "scripts"),
           "BLENDER_USER_CONFIG": str(tmp_path / "config")}
    run = blender("--python-exit-code", "1", "--python-expr", f"ZIP = {zip_path!r}\n" + INSTALL, env=env)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    return env


def scene_file(tmp_path, env, no_camera=False):
    path = str(tmp_path / ("nocamera.blend" if no_camera else "hostile.blend"))
    script = f"SCENE, OUT, NO_CAMERA = {SCENE!r}, {path!r}, {no_camera}\n" + HOSTILE
    run = blender("--python-exit-code", "1", "--python-expr", script, env=env)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    return path


def test_a_frame_cycles_renders_renders_with_warnings(tmp_path):
    env = farm_node(tmp_path)
    blend = scene_file(tmp_path, env)
    run = blender(blend, "-o", str(tmp_path / "frame_####"), "-F", "PNG", "-f", "1", env=env)
    output = run.stdout + run.stderr
    assert run.returncode == 0, output[-3000:]
    assert (tmp_path / "frame_0001.png").stat().st_size > 0
    for name in ("light 'flat'", "light 'minus'", "object 'spiky'"):
        assert name in output, output[-3000:]
    assert "'hidden'" not in output  # scaled to zero: nothing to render, as in Cycles


@pytest.mark.parametrize("frames", [["-E", "PPM", "-s", "1", "-e", "3", "-a"], ["--render-frame", "1..3"]],
                         ids=["animation", "flamenco-chunk"])
def test_every_frame_of_a_range_renders_on_a_node_with_only_the_zip(frames, tmp_path):
    """What farms run on a node with only the zip installed: an animation with the engine named (-E,
    -s, -e, -a), and Flamenco's Simple Blender Render task (--render-output, --render-format and a chunk
    of frames, --render-frame A..B): every frame written, exit 0, each frame its own noise (seed)."""
    env = farm_node(tmp_path)
    blend = scene_file(tmp_path, env)
    run = blender(blend, "--render-output", str(tmp_path / "anim_####"), "--render-format", "PNG", *frames, env=env)
    assert run.returncode == 0, (run.stdout + run.stderr)[-3000:]
    frames_written = [(tmp_path / f"anim_{n:04d}.png").read_bytes() for n in (1, 2, 3)]
    assert all(len(f) > 0 for f in frames_written) and len(set(frames_written)) == 3


@pytest.mark.parametrize("frames", [["-f", "1"], ["-s", "1", "-e", "2", "-a"]])
def test_a_frame_that_cannot_render_stops_the_job(frames, tmp_path):
    """A node whose zip has no core for its Python (3.11 here): every frame fails, loudly."""
    env = farm_node(tmp_path, "--pythons", "3.13")
    run = blender(SCENE, "-o", str(tmp_path / "frame_####"), "-F", "PNG", *frames, env=env)
    output = run.stdout + run.stderr
    assert run.returncode != 0, output[-3000:]
    assert "no compiled core for Blender 3.4" in output, output[-3000:]
    assert not (tmp_path / "frame_0002.png").exists()


def test_a_scene_without_a_camera_stops_the_job(tmp_path):
    env = farm_node(tmp_path)
    blend = scene_file(tmp_path, env, no_camera=True)
    run = blender(blend, "-o", str(tmp_path / "frame_####"), "-F", "PNG", "-f", "1", env=env)
    assert run.returncode != 0
    assert "camera" in (run.stdout + run.stderr).lower()
