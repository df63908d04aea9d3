#!/usr/bin/env bash
# Takes a fresh Debian 12 machine to a working state: Debian packages, a
# Python 3.11 virtual environment in .venv with the PyPI packages, and the
# ppm_core module built and installed into it. Safe to run again.
set -euo pipefail
cd "$(dirname "$0")/.."

DEBIAN_PACKAGES=(build-essential cmake ninja-build libglm-dev libgtest-dev googletest)
# The add-on's tests: Debian's Blender 3.4 (embeds the system Python 3.11, so it gets numpy from
# python3-numpy) and Xvfb for the GUI test.
DEBIAN_PACKAGES+=(blender python3-numpy xvfb)

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
.venv/bin/python -m pip install -q -r requirements.txt
echo "setup: Python packages installed"
