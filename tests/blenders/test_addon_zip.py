"""addon/build_addon.py makes one zip per platform from the cores of the three Pythons Blender embeds,
as the hosted CI does from cibuildwheel's wheels (.github/workflows/addon.yml). The wheels here are
stand-ins with the real file names; the cores in them are not loaded."""

import os
import subprocess
import sys
import zipfile

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD_ADDON = os.path.join(ROOT, "addon", "build_addon.py")

# platform -> (wheel platform tag, core file name in the wheel with {v} for the Python, e.g. 311)
PLATFORMS = {
    "linux-x64": ("manylinux_2_28_x86_64", "ppm_core.cpython-{v}-x86_64-linux-gnu.so"),
    "linux-arm64": ("manylinux_2_28_aarch64", "ppm_core.cpython-{v}-aarch64-linux-gnu.so"),
    "windows-x64": ("win_amd64", "ppm_core.cp{v}-win_amd64.pyd"),
    "macos-arm64": ("macosx_11_0_arm64", "ppm_core.cpython-{v}-darwin.so"),
}


def fake_wheel(folder, tag, core_name, python):
    path = folder / f"ppm_core-0.1.0-cp{python}-cp{python}-{tag}.whl"
    with zipfile.ZipFile(path, "w") as wheel:
        wheel.writestr(core_name.format(v=python), f"core for {python}")
        wheel.writestr("ppm_core-0.1.0.dist-info/WHEEL", "Wheel-Version: 1.0\n")
    return str(path)


def build(tmp_path, *args):
    return subprocess.run([sys.executable, BUILD_ADDON, "--out", str(tmp_path / "out"), *args],
                          capture_output=True, text=True, check=False)


@pytest.mark.parametrize("platform", PLATFORMS)
def test_one_zip_per_platform_with_every_core(platform, tmp_path):
    tag, core_name = PLATFORMS[platform]
    wheels = [fake_wheel(tmp_path, tag, core_name, v) for v in ("313", "310", "311")]
    run = build(tmp_path, "--core", *wheels)
    assert run.returncode == 0, run.stderr
    target = tmp_path / "out" / f"ppm_render-0.1.0-{platform}.zip"
    with zipfile.ZipFile(target) as zf:
        names = zf.namelist()
        manifest = zf.read("ppm_render/blender_manifest.toml").decode()
        assert zf.read("ppm_render/lib/" + core_name.format(v="311")) == b"core for 311"
    assert f'platforms = ["{platform}"]' in manifest
    assert sorted(n for n in names if n.startswith("ppm_render/lib/")) == sorted(
        "ppm_render/lib/" + core_name.format(v=v) for v in ("310", "311", "313"))
    assert "ppm_render/__init__.py" in names and "ppm_render/core.py" in names
    assert all(n.startswith("ppm_render/") and "__pycache__" not in n for n in names)


def test_a_missing_python_or_mixed_platforms_are_refused(tmp_path):
    linux = [fake_wheel(tmp_path, *PLATFORMS["linux-x64"], v) for v in ("310", "311")]
    run = build(tmp_path, "--core", *linux)
    assert run.returncode != 0 and "no ppm_core for Python 3.13" in run.stderr
    windows = fake_wheel(tmp_path, *PLATFORMS["windows-x64"], "313")
    run = build(tmp_path, "--core", *linux, windows)
    assert run.returncode != 0 and "one zip holds one platform" in run.stderr
