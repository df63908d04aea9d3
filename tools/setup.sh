#!/usr/bin/env bash
# Takes a fresh Debian 12 machine to a working state: Debian packages, a
# Python 3.11 virtual environment in .venv with the PyPI packages, and one
# virtual environment per Blender version the add-on is tested in (.venvs/,
# see tests/blenders). The Makefile then builds ppm_core for Python 3.10, 3.11 and
# 3.13 and installs it into all of them (tools/build_cores.sh). Safe to run again.
#
# With --demo (make demo): only what rendering a bundled scene through the add-on needs, the
# compiler's packages and .venv with Blender 5.0 as the bpy module (requirements-demo.txt).
set -euo pipefail
cd "$(dirname "$0")/.."
DEMO=0
[ "${1:-}" = "--demo" ] && DEMO=1

# ccache: the engine's objects are the same for every Python's core (tools/build_cores.sh), compiled once.
DEBIAN_PACKAGES=(build-essential cmake ninja-build ccache libglm-dev)
if ((DEMO == 0)); then
  # The C++ tests.
  DEBIAN_PACKAGES+=(libgtest-dev googletest)
  # The add-on's tests: Debian's Blender 3.4 (embeds the system Python 3.11, so it gets numpy from
  # python3-numpy) and Xvfb for the GUI test.
  DEBIAN_PACKAGES+=(blender python3-numpy xvfb)
  # make test-cross: the C++ tests built for Linux aarch64 and run under qemu-user.
  DEBIAN_PACKAGES+=(g++-aarch64-linux-gnu qemu-user)
  # The Flamenco job type's test runs its JavaScript (addon/farm/flamenco) with Node.
  DEBIAN_PACKAGES+=(nodejs)
fi

missing=()
for p in "${DEBIAN_PACKAGES[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing Debian packages: ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}"
fi

# bpy 5.0 and Debian's Blender 3.4 both embed Python 3.11: the core is built for 3.11.
PYTHON="${PYTHON:-}"
if [ -z "$PYTHON" ]; then
  for candidate in python3.11 python3; do
    if command -v "$candidate" >/dev/null && "$candidate" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))'; then
      PYTHON="$candidate"
      break
    fi
  done
fi
if [ -z "$PYTHON" ]; then
  echo "setup: Python 3.11 not found; installing Debian's python3.11" >&2
  apt-get install -y -qq python3.11 python3.11-venv python3.11-dev
  PYTHON=python3.11
fi

if [ ! -x .venv/bin/python ]; then
  "$PYTHON" -m venv .venv
fi
.venv/bin/python -m pip install -q --upgrade pip
if ((DEMO)); then
  .venv/bin/python -m pip install -q -r requirements-demo.txt
  echo "setup: the demo's packages installed"
  exit 0
fi
.venv/bin/python -m pip install -q -r requirements.txt

# Python 3.X from $3 (an override), PATH or pyenv, or exit naming what needs it ($2).
find_python() {
  local version=$1 why=$2 override=$3 candidate
  for candidate in "$override" "python$version" "$(pyenv root 2>/dev/null)"/versions/"$version"*/bin/python"$version"; do
    if [ -n "$candidate" ] && "$candidate" -c "import sys; sys.exit(sys.version_info[:2] != (3, ${version#3.}))" 2>/dev/null
    then
      echo "$candidate"
      return
    fi
  done
  echo "setup: Python $version not found ($why)." >&2
  echo "setup: install it, e.g. 'pyenv install $version', or set PYTHON${version/./}=/path/to/python$version" >&2
  exit 1
}
# Blender 5.1 and later embed Python 3.13, which Debian 12 does not package: take it from PATH
# or from pyenv.
PYTHON313=$(find_python 3.13 "Blender 5.1+ embed it; the add-on's core is built for it too" "${PYTHON313:-}")
# blender.org's own builds of Blender 3.4 to 4.0 (3.6 LTS among them) embed Python 3.10: the core is
# built for it too (no bpy module of those versions is served for 3.10, so only the core is tested).
PYTHON310=$(find_python 3.10 "blender.org's Blender 3.4-4.0 embed it; the add-on's core is built for it" \
  "${PYTHON310:-}")

# bpy modules for the version matrix (tests/blenders): a virtual environment each, made once.
blender_venv() {
  local dir=$1 python=$2
  shift 2
  [ -x "$dir/bin/python" ] || "$python" -m venv "$dir"
  "$dir/bin/python" -m pip install -q "$@"
}
# Each runs the add-on's tests (pytest, OpenImageIO: 3.0 for numpy < 2, as in requirements.txt; hypothesis).
blender_venv .venvs/bpy-4.2 "$PYTHON" "bpy==4.2.23" "numpy<2" "pytest>=8" "openimageio==3.0.*" "hypothesis>=6.100"
blender_venv .venvs/bpy-4.5 "$PYTHON" "bpy==4.5.15" "numpy<2" "pytest>=8" "openimageio==3.0.*" "hypothesis>=6.100"
# Blender 5.2 LTS; this Python 3.13 environment also builds the core for 3.13 and runs its tests.
blender_venv .venvs/bpy-5.2 "$PYTHON313" "bpy==5.2.3" "numpy>=2" "pytest>=8" "openimageio>=3.0" \
  "scikit-build-core>=0.10" "pybind11>=2.12" "hypothesis>=6.100"
# Python 3.10 (Blender 3.4-4.0 from blender.org, numpy 1.x as they bundle): builds the core and runs its tests.
blender_venv .venvs/py-3.10 "$PYTHON310" "numpy<2" "pytest>=8" "scikit-build-core>=0.10" "pybind11>=2.12" \
  "hypothesis>=6.100"
echo "setup: Python packages installed"
