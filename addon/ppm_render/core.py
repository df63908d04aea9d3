"""Finds the compiled renderer core, `ppm_core`.

The installable zip carries a copy in `ppm_render/lib/` (see addon/build_addon.py);
a development checkout uses the one installed in the project's .venv. The
bundled copy wins so that an installed add-on never picks up a stale build.
"""

import glob
import importlib
import importlib.util
import os
import sys


def _load_bundled():
    here = os.path.join(os.path.dirname(__file__), "lib")
    for path in sorted(glob.glob(os.path.join(here, "ppm_core*.so")) + glob.glob(os.path.join(here, "ppm_core*.pyd"))):
        spec = importlib.util.spec_from_file_location("ppm_core", path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        sys.modules["ppm_core"] = module
        return module
    return None


def load():
    """The ppm_core module; raises ImportError with a readable message if there is none."""
    if "ppm_core" in sys.modules:
        return sys.modules["ppm_core"]
    module = _load_bundled()
    if module is not None:
        return module
    try:
        return importlib.import_module("ppm_core")
    except ImportError as error:
        raise ImportError(
            "PPM: the compiled core 'ppm_core' was not found (install the add-on zip built by "
            f"'make addon', or put the project's .venv site-packages on sys.path): {error}") from error
