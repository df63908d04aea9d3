"""The merged still written as a 32-bit float EXR (OpenImageIO), with its error estimate in the
header: ppm:passes, ppm:shares, ppm:error_relative and ppm:error_bound (the image's estimated
mean absolute error over its mean brightness, and its bound at ppm:error_confidence)."""

from __future__ import annotations

import os

import numpy as np


def write_exr(path, share, confidence=0.95, shares=0):
    import OpenImageIO as oiio

    error = share.error_stats(confidence)
    pixels = np.ascontiguousarray(share.image(), dtype=np.float32)
    spec = oiio.ImageSpec(share.width, share.height, 4, oiio.FLOAT)
    spec.channelnames = ("R", "G", "B", "A")
    spec.attribute("compression", "zip")
    spec.attribute("ppm:passes", int(share.passes))
    spec.attribute("ppm:shares", int(shares))
    spec.attribute("ppm:error_relative", float(error["relative"]))
    spec.attribute("ppm:error_bound", float(error["bound"]))
    spec.attribute("ppm:error_confidence", float(confidence))
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    partial = path + ".part.exr"  # renamed when complete: a reader never sees half a file
    out = oiio.ImageOutput.create(partial)
    if out is None or not out.open(partial, spec):
        raise RuntimeError(f"cannot write {path}: {oiio.geterror()}")
    ok = out.write_image(pixels)
    out.close()
    if not ok:
        raise RuntimeError(f"cannot write {path}: {oiio.geterror()}")
    os.replace(partial, path)
    return error
