"""Finds the compiled renderer core, `ppm_core`, built for the running Python.

Blender embeds Python 3.11 (3.4 to 5.0) or 3.13 (5.1 and later), and a compiled
module loads only into the Python it was built for. The installable zip therefore
carries one build per Python in `ppm_render/lib/` (see addon/build_addon.py), and
this module picks the file whose name ends in one of this interpreter's extension
suffixes (`.cpython-313-x86_64-linux-gnu.so`, `.cp311-win_amd64.pyd`, ...). When none
fits, the error says which Blender and Python are running and which cores the zip
has, instead of an undefined-symbol message. A development checkout has no `lib/`
and uses the `ppm_core` installed in the project's virtual environment.
"""

import glob
import importlib
import importlib.machinery
import importlib.util
import os
import platform
import re
import sys

LIB = os.path.join(os.path.dirname(os.path.abspath(__file__)), "lib")


def running_blender():
    """'Blender 5.2.3 (Python 3.13.0, Linux x86_64)'."""
    try:
        import bpy

        blender = f"Blender {bpy.app.version_string}"
    except ImportError:
        blender = "Python"
    python = ".".join(str(v) for v in sys.version_info[:3])
    return f"{blender} (Python {python}, {platform.system()} {platform.machine()})"


def python_of_core(filename):
    """'3.11' for ppm_core.cpython-311-x86_64-linux-gnu.so or ppm_core.cp311-win_amd64.pyd; None if unknown."""
    match = re.search(r"\.(?:cpython-|cp)(\d)(\d+)", filename)
    return f"{match.group(1)}.{match.group(2)}" if match else None


def bundled_cores():
    """The core files in lib/, whatever Python they were built for."""
    return sorted(glob.glob(os.path.join(LIB, "ppm_core.*")))


def core_for_this_python(paths):
    """The path among `paths` that this interpreter can import, or None."""
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        for path in paths:
            if os.path.basename(path) == "ppm_core" + suffix:
                return path
    return None


def no_matching_core_message(paths):
    built_for = ", ".join(sorted({python_of_core(os.path.basename(p)) or os.path.basename(p) for p in paths}))
    return (f"no compiled core for {running_blender()} in this add-on: it carries cores for Python {built_for} "
            "only. Install the PPM zip for this platform from a release that supports this Blender.")


def _import_file(path):
    spec = importlib.util.spec_from_file_location("ppm_core", path)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except ImportError as error:  # e.g. a C library on this system is older than the build machine's
        raise ImportError(f"the PPM core {os.path.basename(path)} does not load in {running_blender()}: "
                          f"{error}") from error
    sys.modules["ppm_core"] = module
    return module


def load():
    """The ppm_core module; raises ImportError with a message a user can act on if there is none."""
    if "ppm_core" in sys.modules:
        return sys.modules["ppm_core"]
    paths = bundled_cores()
    if paths:  # an installed zip: its own core wins, never a stale build found on sys.path
        path = core_for_this_python(paths)
        if path is None:
            raise ImportError(no_matching_core_message(paths))
        return _import_file(path)
    try:
        return importlib.import_module("ppm_core")
    except ImportError as error:
        raise ImportError(
            f"the compiled core 'ppm_core' was not found for {running_blender()} (install the add-on zip "
            f"built by 'make addon', or put the project's .venv site-packages on sys.path): {error}") from error


def problem():
    """None if the core loads, else the message of why not (for the settings panel)."""
    try:
        load()
    except ImportError as error:
        return str(error)
    return None
