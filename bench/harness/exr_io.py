"""Small half-float EXR files for the accuracy benchmarks (OpenImageIO from PyPI): RGB, rows
top-first, settings and measurements as JSON strings in `ppm:*` header attributes."""

from __future__ import annotations

import json

import numpy as np
import OpenImageIO as oiio


def write_exr(path, rgb, metadata=None, half=True):
    """Writes the first three channels of an (H, W, C) image (ZIP compression)."""
    rgb = np.ascontiguousarray(rgb[..., :3], dtype=np.float32)
    h, w = rgb.shape[:2]
    spec = oiio.ImageSpec(w, h, 3, oiio.HALF if half else oiio.FLOAT)
    spec.attribute("compression", "zip")
    for key, value in (metadata or {}).items():
        spec.attribute(f"ppm:{key}", value if isinstance(value, str) else json.dumps(value))
    out = oiio.ImageOutput.create(path)
    if out is None or not out.open(path, spec):
        raise RuntimeError(f"cannot write {path}: {oiio.geterror()}")
    out.write_image(rgb)
    out.close()


def read_exr(path):
    """(H, W, 3) float32, top row first, and the ppm:* metadata as a dict."""
    inp = oiio.ImageInput.open(path)
    if inp is None:
        raise FileNotFoundError(f"{path}: {oiio.geterror()}")
    pixels = inp.read_image(oiio.FLOAT)
    meta = {}
    for attr in inp.spec().extra_attribs:
        if attr.name.startswith("ppm:"):
            try:
                meta[attr.name[4:]] = json.loads(attr.value)
            except (TypeError, ValueError):
                meta[attr.name[4:]] = attr.value
    inp.close()
    return np.asarray(pixels, dtype=np.float32)[..., :3], meta
