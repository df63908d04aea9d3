"""Builds the installable add-on zip for one platform: out/ppm_render-<version>-<platform>.zip.

    .venv/bin/python addon/build_addon.py [--out out]                     # this machine's cores
    .venv/bin/python addon/build_addon.py --core wheelhouse/*.whl        # cores built elsewhere (CI)

The zip holds one folder, ppm_render/, with the add-on's Python files, its
blender_manifest.toml (an extension for Blender 4.2+, which accepts the manifest
inside a single top folder; `platforms` names the zip's platform) and bl_info (a
legacy add-on for 3.4 to 4.1), plus one compiled core per Python that Blender
embeds, in ppm_render/lib/: CPython 3.10 (blender.org's Blender 3.4 to 4.0), 3.11
(Debian's 3.4, 4.1 to 5.0) and 3.13 (5.1 and later). ppm_render/core.py loads the
one that matches the running Python.

By default the cores are the wheels `make build` left in build/wheels/
(tools/build_cores.sh). `--core` takes other core files or wheels, e.g. those
cibuildwheel made on another platform (.github/workflows/addon.yml). Every
Python in `--pythons` must have a core.
"""

import argparse
import glob
import os
import re
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PACKAGE = os.path.join(HERE, "ppm_render")
BLENDER_PYTHONS = ("3.10", "3.11", "3.13")  # blender.org's 3.4-4.0; Debian's 3.4 and 4.1-5.0; 5.1+

# Blender's platform names, from the tail of a core's file name or a wheel's platform tag.
PLATFORM_PATTERNS = (
    (r"x86_64-linux-gnu\.so$|linux_x86_64\.whl$|manylinux.*_x86_64\.whl$", "linux-x64"),
    (r"aarch64-linux-gnu\.so$|linux_aarch64\.whl$|manylinux.*_aarch64\.whl$", "linux-arm64"),
    (r"win_amd64\.(pyd|whl)$", "windows-x64"),
    (r"win_arm64\.(pyd|whl)$", "windows-arm64"),
    (r"macosx_.*_arm64\.whl$", "macos-arm64"),
    (r"macosx_.*_x86_64\.whl$", "macos-x64"),
)


def version():
    with open(os.path.join(PACKAGE, "blender_manifest.toml")) as f:
        for line in f:
            if line.startswith("version"):
                return line.split("=")[1].strip().strip('"')
    raise ValueError("blender_manifest.toml has no version")


def package_files():
    for folder, dirs, files in os.walk(PACKAGE):
        dirs[:] = [d for d in dirs if d not in ("__pycache__", "lib")]
        for name in files:
            if name.endswith((".py", ".toml")):
                path = os.path.join(folder, name)
                yield path, os.path.join("ppm_render", os.path.relpath(path, PACKAGE))


def python_of(filename):
    """'3.13' for ppm_core.cpython-313-x86_64-linux-gnu.so, ppm_core.cp313-win_amd64.pyd or a cp313 wheel."""
    match = re.search(r"(?:cpython-|cp)(\d)(\d+)", filename)
    if not match:
        raise SystemExit(f"build_addon: cannot tell which Python {filename} is for")
    return f"{match.group(1)}.{match.group(2)}"


def platform_of(filename):
    for pattern, name in PLATFORM_PATTERNS:
        if re.search(pattern, filename):
            return name
    return None


class Core:
    """One compiled core: its file name inside lib/, its bytes, and the Python and platform it is for."""

    def __init__(self, name, data, platform=None):
        self.name, self.data = name, data
        self.python, self.platform = python_of(name), platform_of(name) or platform


def cores_from(path):
    """The cores in a core file or a wheel."""
    if not path.endswith(".whl"):
        with open(path, "rb") as f:
            return [Core(os.path.basename(path), f.read())]
    with zipfile.ZipFile(path) as wheel:  # a macOS core's name has no architecture; the wheel's tag has
        return [Core(n, wheel.read(n), platform_of(os.path.basename(path))) for n in wheel.namelist()
                if re.fullmatch(r"ppm_core\.[^/]+\.(so|pyd)", n)]


def choose_cores(paths, pythons, platform):
    """One core per Python in `pythons` (the first found wins), all for one platform."""
    chosen = {}
    for path in paths:
        for core in cores_from(path):
            if core.python in pythons and core.python not in chosen:
                chosen[core.python] = core
    missing = [p for p in pythons if p not in chosen]
    if missing:
        raise SystemExit(f"build_addon: no ppm_core for Python {', '.join(missing)} (run `make build`, "
                         "or pass --core files or wheels)")
    platforms = {platform or core.platform for core in chosen.values()}
    if len(platforms) != 1 or None in platforms:
        raise SystemExit(f"build_addon: the cores are for platforms {sorted(map(str, platforms))}; "
                         "one zip holds one platform (give --platform for a macOS core file)")
    return [chosen[p] for p in pythons], platforms.pop()


def manifest_for(platform):
    """blender_manifest.toml with `platforms` set to this zip's platform."""
    with open(os.path.join(PACKAGE, "blender_manifest.toml")) as f:
        text = f.read()
    return re.sub(r"(?m)^platforms = .*$", f'platforms = ["{platform}"]', text)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(ROOT, "out"))
    parser.add_argument("--core", nargs="+", help="core files or wheels (default: the wheels `make build` made)")
    parser.add_argument("--pythons", default=",".join(BLENDER_PYTHONS),
                        help="Python versions the zip must carry a core for (default: %(default)s)")
    parser.add_argument("--platform", help="Blender's platform name, when the cores' names do not tell it")
    args = parser.parse_args()
    paths = args.core or sorted(glob.glob(os.path.join(ROOT, "build", "wheels", "ppm_core-*.whl")))
    cores, platform = choose_cores(paths, args.pythons.split(","), args.platform)
    os.makedirs(args.out, exist_ok=True)
    target = os.path.join(args.out, f"ppm_render-{version()}-{platform}.zip")
    with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as zf:
        for path, name in package_files():
            if name == "ppm_render/blender_manifest.toml":
                zf.writestr(name, manifest_for(platform))
            else:
                zf.write(path, name)
        for core in cores:
            zf.writestr(os.path.join("ppm_render", "lib", core.name), core.data)
    print(f"build_addon: wrote {target} (cores: {', '.join(c.name for c in cores)})")


if __name__ == "__main__":
    main()
