#!/usr/bin/env bash
# Builds ppm_core (Release, -O3) once per Python that Blender embeds, as a wheel in build/wheels/,
# and installs it into every virtual environment of that Python: 3.10 into .venvs/py-3.10 (blender.org's
# Blender 3.4-4.0), 3.11 into .venv, .venvs/bpy-4.2 and .venvs/bpy-4.5 (Debian's 3.4, bpy 4.2-5.0),
# 3.13 into .venvs/bpy-5.2 (Blender 5.1+). Run by `make build`. With --demo (make demo): the
# Python 3.11 core alone, into .venv.
set -euo pipefail
cd "$(dirname "$0")/.."
builders=(.venv .venvs/py-3.10 .venvs/bpy-5.2)
envs=(.venv .venvs/*)
if [ "${1:-}" = "--demo" ]; then
  builders=(.venv)
  envs=(.venv)
fi
rm -rf build/wheels
# The engine's sources compile the same for every Python: ccache serves the second and third builds.
if command -v ccache >/dev/null; then
  export CMAKE_ARGS="${CMAKE_ARGS:-} -DCMAKE_CXX_COMPILER_LAUNCHER=ccache"
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
fi
for builder in "${builders[@]}"; do
  "$builder/bin/python" -m pip wheel -q --no-build-isolation --no-deps -w build/wheels .
done
for env in "${envs[@]}"; do
  tag=$("$env/bin/python" -c 'import sys; print("cp%d%d" % sys.version_info[:2])')
  "$env/bin/python" -m pip install -q --force-reinstall --no-deps build/wheels/ppm_core-*-"$tag"-*.whl
done
