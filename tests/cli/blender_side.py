"""What the scripts Blender 3.4 runs here share (passes_compare.py, denoising_compare.py,
light_passes_compare.py): this checkout's .venv packages (numpy, OpenImageIO, ppm_core; the same
Python 3.11) and its add-on on the path, and reading one pass of a multilayer EXR."""

import glob
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
for site in glob.glob(os.path.join(ROOT, ".venv", "lib", "python3*", "site-packages")):
    if site not in sys.path:
        sys.path.append(site)  # appended: Blender's own modules keep priority
sys.path.insert(0, os.path.join(ROOT, "addon"))

import OpenImageIO as oiio  # noqa: E402


def read_pass(path, prefix, channels):
    """(H, W, len(channels)) float32 of the pass named `prefix` (e.g. "Denoising Albedo", "RGB")."""
    buf = oiio.ImageBuf(str(path))
    names = buf.spec().channelnames
    index = [next(i for i, n in enumerate(names) if n.endswith(f"{prefix}.{c}")) for c in channels]
    return buf.get_pixels(oiio.FLOAT)[..., index]
