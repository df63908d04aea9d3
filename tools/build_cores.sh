#!/usr/bin/env bash
# Builds ppm_core (Release, -O3) once per Python that Blender embeds, as a wheel in build/wheels/,
# and installs it into every virtual environment of that Python: 3.11 into .venv, .venvs/bpy-4.2
# and .venvs/bpy-4.5 (Blender 3.4-5.0), 3.13 into .venvs/bpy-5.2 (Blender 5.1+). Run by `make build`.
set -euo pipefail
cd "$(dirname "$0")/.."
rm -rf build/wheels
for builder in .venv .venvs/bpy-5.2; do
  "$builder/bin/python" -m pip wheel -q --no-build-isolation --no-deps -w build/wheels .
done
for env in .venv .venvs/bpy-*; do
  tag=$("$env/bin/python" -c 'import sys; print("cp%d%d" % sys.version_info[:2])')
  "$env/bin/python" -m pip install -q --force-reinstall --no-deps build/wheels/ppm_core-*-"$tag"-*.whl
done
