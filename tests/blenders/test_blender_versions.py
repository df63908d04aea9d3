"""The add-on zip in every Blender that users run: Debian's 3.4 binary and the bpy modules 4.2 LTS,
4.5 LTS, 5.0 and 5.2 LTS (Python 3.11, and 3.13 for 5.2), each set up by `make setup`.

In each version the zip is installed the way a user does and enabled, every bundled .blend renders
through it with the core built for that version's Python, PPM agrees with that version's Cycles
light kind by light kind (units changed between 3.x and 4.x), in a room lit indirectly through
lenses from 5 to 5000 mm and tiny and huge orthographic cameras, under image-based light, in fog,
smoke and ink in glass, with materials and texture nodes (all cases in 3.4 and 5.0, a subset of the
slow ones in the others),
and the add-on raises no Python warning (deprecations included). A zip without a core for the
running Python fails with one clear message. See in_blender.py for what runs inside Blender.
"""

import json
import os
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
IN_BLENDER = os.path.join(HERE, "in_blender.py")
BUILD_ADDON = os.path.join(ROOT, "addon", "build_addon.py")
TOLERANCE = 0.03  # cycles_compare.TOLERANCE (not imported: importing it needs bpy)
LENS_TOLERANCE = 0.05  # lens_compare.TOLERANCE
ALPHA_TOLERANCE = 0.01  # alpha_compare.ALPHA_TOLERANCE
MATERIAL_TOLERANCE = 0.05  # materials_compare.TOLERANCE


def bpy_python(venv):
    return os.path.join(ROOT, venv, "bin", "python")


# Blender version -> (the Python it embeds, the command that runs a script in it).
BLENDERS = {
    "3.4": ("3.11", ["blender", "-b", "--factory-startup", "--python-exit-code", "1", "-P", IN_BLENDER, "--"]),
    "4.2": ("3.11", [bpy_python(".venvs/bpy-4.2"), IN_BLENDER]),
    "4.5": ("3.11", [bpy_python(".venvs/bpy-4.5"), IN_BLENDER]),
    "5.0": ("3.11", [bpy_python(".venv"), IN_BLENDER]),
    "5.2": ("3.13", [bpy_python(".venvs/bpy-5.2"), IN_BLENDER]),
}


def build_zip(out, *args):
    run = subprocess.run([sys.executable, BUILD_ADDON, "--out", str(out), *args], capture_output=True, text=True,
                         check=True)
    return run.stdout.split("wrote ")[1].split(" ")[0]


@pytest.fixture(scope="module")
def addon_zip(tmp_path_factory):
    return build_zip(tmp_path_factory.mktemp("zip"))


def run_in_blender(version, zip_path, tmp_path, *args):
    """Runs in_blender.py in a fresh user folder and returns its report."""
    report = tmp_path / "report.json"
    user = tmp_path / "user"
    env = {**os.environ, "BLENDER_USER_RESOURCES": str(user), "BLENDER_USER_SCRIPTS": str(user / "scripts"),
           "BLENDER_USER_CONFIG": str(user / "config")}
    command = BLENDERS[version][1] + ["--zip", zip_path, "--report", str(report), "--workdir", str(tmp_path), *args]
    run = subprocess.run(command, capture_output=True, text=True, timeout=900, env=env, cwd=str(tmp_path))
    assert run.returncode == 0 and report.exists(), run.stdout[-3000:] + run.stderr[-3000:]
    comparisons = ("cycles_compare", "lens_compare", "visibility_compare", "world_compare", "alpha_compare",
                   "stereo_compare", "light_paths_compare", "media_compare", "materials_compare", "nodes_compare",
                   "in_blender")
    print("\n".join(line for line in run.stdout.splitlines() if line.startswith(comparisons)))
    return json.loads(report.read_text()), str(user)


# The versions whose Cycles agreement is checked case by case; the others run a subset of the slow
# comparisons (in_blender.py's SUBSET_*), which keeps five Blenders within minutes.
CHECKED_IN_FULL = ("3.4", "5.0")


@pytest.mark.parametrize("version", BLENDERS)
def test_zip_installs_renders_and_agrees_with_cycles(version, addon_zip, tmp_path):
    full = version in CHECKED_IN_FULL
    report, user = run_in_blender(version, addon_zip, tmp_path, *([] if full else ["--subset"]))
    assert report["blender"].startswith(version + "."), report["blender"]
    python = BLENDERS[version][0]
    assert report["python"] == python
    # The installed add-on and the core it carries for this Python, not the checkout's.
    assert report["addon_file"].startswith(user) and report["core_file"].startswith(user)
    assert f"cpython-{python.replace('.', '')}" in os.path.basename(report["core_file"])
    assert len(report["scenes"]) >= 5
    for name, scene in report["scenes"].items():
        assert scene["engine"] == "PPM", name
        assert scene["shape"] == [57, 76], name  # 12% of 640x480
        assert scene["finite"] and scene["min"] >= 0.0, (name, scene)
        assert scene["lit"] > 0.5 and 0.01 < scene["mean"] < 50.0 and scene["std"] > 0.01, (name, scene)
    kinds = {row["kind"]: row["max_block_error"] for row in report["cycles"]}
    assert {"point", "sphere", "spot", "area_square", "area_disk", "sun", "emissive_mesh", "world"} <= set(kinds)
    assert all(error <= TOLERANCE for error in kinds.values()), kinds
    lenses = {row["case"]: max(abs(row["mean_error"]), abs(row["median_error"])) for row in report["lenses"]}
    assert len(lenses) == 5 and all(error <= LENS_TOLERANCE for error in lenses.values()), lenses
    visibility = {row["case"]: row["max_block_error"] for row in report["visibility"]}
    assert len(visibility) == 7 and all(error <= TOLERANCE for error in visibility.values()), visibility
    worlds = {row["case"]: row["max_block_error"] for row in report["worlds"]}
    assert len(worlds) == (8 if full else 2) and all(error <= TOLERANCE for error in worlds.values()), worlds
    alpha = {row["case"]: (row["max_block_error"], row["max_alpha_error"]) for row in report["alpha"]}
    assert len(alpha) == 8 and all(c <= TOLERANCE and a <= ALPHA_TOLERANCE for c, a in alpha.values()), alpha
    stereo = report["stereo"]
    assert max(stereo["max_block_error_L"], stereo["max_block_error_R"]) <= TOLERANCE and stereo["views_differ"] > 0.01
    light_paths = {row["case"]: row["max_block_error"] for row in report["light_paths"]}
    assert len(light_paths) == (7 if full else 3), light_paths
    assert all(error <= TOLERANCE for error in light_paths.values()), light_paths
    media = {row["case"]: (row["max_block_error"], row["tolerance"]) for row in report["media"]}
    # The smoke ball in a fog room from 4.5 on (media_compare.FROM_BLENDER); simulated smoke and fire where
    # Blender runs fluid simulations: the blender binary (3.4), not Blender as a Python module.
    assert report["fluid_simulates"] == (BLENDERS[version][1][0] == "blender"), report["fluid_simulates"]
    full_media = (12 if tuple(map(int, version.split("."))) >= (4, 5) else 11) + 2 * report["fluid_simulates"]
    assert len(media) == (full_media if full else 4) and all(e <= tolerance for e, tolerance in media.values()), media
    materials = {row["case"]: row["error"] for row in report["materials"] if not row["approximated"]}
    assert len(materials) >= (40 if full else 12), materials
    assert all(e <= MATERIAL_TOLERANCE for e in materials.values()), materials
    # Every texture and utility node case this Blender has, per pixel (3.4 lacks the 4.x noise types).
    nodes = {row["case"]: (row["p99"], row["warnings"]) for row in report["nodes"]}
    assert len(nodes) >= 45 and all(row["ok"] for row in report["nodes"]), nodes
    assert report["addon_warnings"] == []
    # Cycles' images of every case are stored for this version (cycles_references.py): a case new or
    # changed since was rendered by Cycles and its image written for the next run.
    references = report["cycles_references"]
    assert references["found"] >= 40 and references["rendered"] == [], (
        f"Cycles rendered {len(references['rendered'])} cases ({', '.join(references['rendered'][:5])}, ...) that "
        f"tests/blenders/cycles_references/{report['blender'].split()[0]}/ had no image of for their scene: this "
        "run wrote them there, commit them")


def test_zip_without_a_core_for_this_python_says_so(tmp_path):
    """Blender 5.2 (Python 3.13) with a zip that carries only the Python 3.11 core."""
    import ppm_core

    zip_path = build_zip(tmp_path / "zip", "--pythons", "3.11", "--core", ppm_core.__file__)
    report, _ = run_in_blender("5.2", zip_path, tmp_path, "--no-core")
    error = report["render_error"]
    assert error is not None and "undefined symbol" not in error
    for words in ("no compiled core for Blender 5.2", "Python 3.13", "carries cores for Python 3.11"):
        assert words in error, error
    assert report["panel_message"] in error
    assert report["addon_warnings"] == []


def test_the_zips_python_310_core_loads_and_renders(addon_zip, tmp_path):
    """blender.org's Blender 3.4 to 4.0 (3.6 LTS among them) embed Python 3.10. No bpy of theirs is served
    for it here, so the zip's core is loaded by the add-on's own loader (core.py) in Python 3.10, outside
    Blender, and renders."""
    import zipfile

    with zipfile.ZipFile(addon_zip) as archive:
        archive.extractall(tmp_path)
    script = (
        "import importlib.util, sys\n"
        f"spec = importlib.util.spec_from_file_location('loader', {str(tmp_path / 'ppm_render' / 'core.py')!r})\n"
        "loader = importlib.util.module_from_spec(spec); spec.loader.exec_module(loader)\n"
        "core = loader.load(); print(core.__file__)\n"
        "import numpy as np\n"
        "scene = core.Scene(); scene.add_material('grey', 'diffuse', base_color=(0.8, 0.8, 0.8))\n"
        "scene.add_mesh('floor', np.array([[-1., -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]), "
        "np.array([[0, 1, 2], [0, 2, 3]]))\n"
        "scene.add_light('point', position=(0.0, 0.0, 1.0), power=50.0)\n"
        "camera = np.eye(4); camera[2, 3] = 2.0; scene.set_camera(camera, 16, 16)\n"
        "renderer = core.Renderer(scene, photons_per_pass=2000, seed=1); renderer.run(passes=2)\n"
        "print(float(renderer.image()[..., :3].mean()))\n")
    run = subprocess.run([bpy_python(".venvs/py-3.10"), "-c", script], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    core_file, mean = run.stdout.split()[-2:]
    assert core_file.startswith(str(tmp_path)) and "cpython-310" in core_file
    assert float(mean) > 0.01


@pytest.mark.parametrize("version", ["4.2", "4.5", "5.2"])
def test_render_py_with_the_bpy_module(version, tmp_path):
    """render.py registers the checkout's add-on and unregisters it before exit (bpy 4.2 crashed and
    4.5 hung at exit otherwise)."""
    out = tmp_path / "cornell.exr"
    scene = os.path.join(ROOT, "blend_scenes", "cornell_3spheres.blend")
    python = BLENDERS[version][1][0]
    run = subprocess.run([python, os.path.join(ROOT, "render.py"),
                          scene, "--output", str(out), "--passes", "2", "--resolution", "64", "48",
                          "--photons", "10000"], capture_output=True, text=True, timeout=300, cwd=str(tmp_path))
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    assert f"Blender {version}." in run.stdout and out.stat().st_size > 0
