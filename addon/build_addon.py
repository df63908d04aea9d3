"""Builds the installable add-on zip: out/ppm_render-<version>.zip.

    .venv/bin/python addon/build_addon.py [--out out]

The zip holds one folder, ppm_render/, with the add-on's Python files, its
blender_manifest.toml (an extension for Blender 4.2+, which accepts the
manifest inside a single top folder) and bl_info (a legacy add-on for 3.4),
plus the compiled core copied from this environment into ppm_render/lib/
(found there by ppm_render/core.py). The core is built for CPython 3.11 on
this platform: Blender 3.4-5.0 (Python 3.11) on Linux x86-64.
"""

import argparse
import os
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE = os.path.join(HERE, "ppm_render")


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


def core_library():
    import ppm_core

    if sys.version_info[:2] != (3, 11):
        raise SystemExit(f"build_addon: Blender 3.4-5.0 embed Python 3.11; this is {sys.version.split()[0]}")
    return ppm_core.__file__


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(os.path.dirname(HERE), "out"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    target = os.path.join(args.out, f"ppm_render-{version()}.zip")
    library = core_library()
    with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as zf:
        for path, name in package_files():
            zf.write(path, name)
        zf.write(library, os.path.join("ppm_render", "lib", os.path.basename(library)))
    print(f"build_addon: wrote {target} (core: {os.path.basename(library)})")


if __name__ == "__main__":
    main()
