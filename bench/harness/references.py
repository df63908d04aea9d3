"""The stored reference images, bench/references/: small half-float EXRs whose header holds how each
was made and its own noise (`rel_mse_noise`, from two independent halves). Made by the `references`
kind (experiments references_blend and references_core).

Names: {scene}_ppm.exr and {scene}_cycles.exr for the bundled .blend files (the add-on route),
core_{scene}.exr for the scenes of blend_scenes/core_scenes.py (the core route)."""

from __future__ import annotations

import os

from .exr_io import read_exr

BENCH_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REF_DIR = os.environ.get("PPM_BENCH_REFERENCES", os.path.join(BENCH_DIR, "references"))  # tests override it


def reference_path(scene, engine, folder=None):
    """engine: 'ppm' or 'cycles' (a .blend scene) or 'core' (a core_scenes scene)."""
    filename = f"core_{scene}.exr" if engine == "core" else f"{scene}_{engine}.exr"
    return os.path.join(folder or REF_DIR, filename)


def has_reference(scene, engine):
    return os.path.exists(reference_path(scene, engine))


def load_reference(scene, engine):
    """(image, header metadata)."""
    path = reference_path(scene, engine)
    if not os.path.exists(path):
        raise SystemExit(f"missing {path}: run bench/run.py references_blend (or references_core) first")
    return read_exr(path)


def reference_noise(meta):
    """The reference's own estimated relative MSE (from its two independent halves), or nan."""
    return float(meta.get("rel_mse_noise", float("nan")))
