"""Every error measure the benchmarks report, in one place. Images are (H, W, 3+) arrays, top row
first; a reference r, an image x; masks are boolean (H, W).

- rmse: sqrt(mean((x - r)^2)), in the scene's radiance units;
- rel_mse: mean((x - r)^2 / (r^2 + EPS)), the relative MSE of the rendering literature; the bundled
  scenes' diffuse radiance is 0.05-2, so EPS = 0.01 only tempers the darkest pixels;
- rel_rmse: sqrt(mean((x - r)^2)) / mean(r) over a mask;
- block_rel_rmse: rel_rmse of k x k block means, leaving out blocks that see a light. Different seeds
  jitter the eye samples differently, so single pixels on edges (worst: a visible light, radiance
  ~250) differ by anti-aliasing noise that no number of photon passes removes; block means and the
  mask keep the measure on the photon estimate.
"""

from __future__ import annotations

import numpy as np

EPS = 0.01


def rgb(image):
    return np.asarray(image)[..., :3]


def _select(d2, mask):
    return d2[mask] if mask is not None else d2


def rmse(image, reference, mask=None):
    return float(np.sqrt(_select((rgb(image) - rgb(reference)) ** 2, mask).mean()))


def rel_mse(image, reference, mask=None):
    r = rgb(reference)
    return float(_select((rgb(image) - r) ** 2 / (r ** 2 + EPS), mask).mean())


def rel_rmse(image, reference, mask=None):
    r = rgb(reference)
    return float(np.sqrt(_select((rgb(image) - r) ** 2, mask).mean()) / _select(r, mask).mean())


def blocks(image, k=4):
    """Means of k x k blocks (the image cropped to whole blocks)."""
    image = np.asarray(image)
    image = image[..., None] if image.ndim == 2 else image
    h, w = image.shape[0] // k * k, image.shape[1] // k * k
    return image[:h, :w].reshape(h // k, k, w // k, k, -1).mean(axis=(1, 3))


def blocks_inside(mask, k=4):
    """The blocks wholly inside a mask."""
    return blocks(mask.astype(float), k)[..., 0] == 1.0


def unlit_blocks(reference, k=4):
    """Blocks that see no light: no channel above 10x the median block."""
    b = blocks(rgb(reference), k)
    return b.max(axis=-1) < 10.0 * np.median(b)


def block_rel_rmse(image, reference, keep=None, k=4):
    """Relative RMSE of block means over the blocks `keep` (default: those that see no light)."""
    keep = unlit_blocks(reference, k) if keep is None else keep
    a, b = blocks(rgb(image), k)[keep], blocks(rgb(reference), k)[keep]
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.mean(b))


def halves_noise(a, b, mask=None):
    """The error of the mean of two independent renders a and b, estimated from their difference:
    Var((a + b) / 2) = E[(a - b)^2] / 4 per pixel. Relative MSE and RMSE."""
    a, b = rgb(a), rgb(b)
    d2 = (a - b) ** 2 / 4.0
    mean = 0.5 * (a + b)
    return {"rel_mse": float(_select(d2 / (mean ** 2 + EPS), mask).mean()),
            "rmse": float(np.sqrt(_select(d2, mask).mean()))}


def log_slope(xs, ys):
    """Slope of log(y) against log(x) by least squares (a convergence rate)."""
    x, y = np.log(np.asarray(xs, dtype=float)), np.log(np.asarray(ys, dtype=float))
    return float(np.polyfit(x, y, 1)[0])
