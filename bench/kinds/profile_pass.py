"""A fixed, small workload for profilers: instruction counts are stable on a noisy machine where
timings are not.

    valgrind --tool=callgrind --callgrind-out-file=out/cg.txt .venv/bin/python bench/run.py profile_pass
    callgrind_annotate --inclusive=yes out/cg.txt | grep ppm::
    perf record -g .venv/bin/python bench/run.py profile_pass --set passes=10

cornell_3spheres at 320x240, 100,000 photons per pass, `passes` passes (3), `threads` threads (1),
direct light sampled, seed 1: the eye pass, three photon passes (trace, index build, gather) and
three direct-light passes. Keep the workload as it is, so that instruction counts stay comparable
from one commit to the next. For symbols, build the module with
`cmake -S . -B build/prof -G Ninja -DPPM_BUILD_PYTHON=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O3 -g -DNDEBUG"` (plus -DPython_EXECUTABLE and -Dpybind11_DIR
from the virtual environment) and run with PYTHONPATH=build/prof.
"""

from __future__ import annotations

import ppm_core
from harness.core_route import build_scene


def run(experiment, results):
    r = ppm_core.Renderer(build_scene("cornell_3spheres", 320, 240), threads=experiment["threads"],
                          photons_per_pass=100_000, direct_light="sampled", seed=1)
    r.run(passes=experiment["passes"])
    mean, seconds = float(r.image().mean()), r.stats()["seconds"]
    results.row(passes=experiment["passes"], threads=experiment["threads"], image_mean=mean, seconds=seconds)
    results.note(f"image mean {mean:.6f}; seconds {seconds}")
