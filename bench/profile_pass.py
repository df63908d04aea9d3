"""A fixed, small workload for profilers: instruction counts are stable on a
noisy machine where timings are not.

    valgrind --tool=callgrind --callgrind-out-file=out/cg.txt .venv/bin/python bench/profile_pass.py
    callgrind_annotate --inclusive=yes out/cg.txt | grep ppm::
    perf record -g .venv/bin/python bench/profile_pass.py --passes 10

cornell_3spheres at 320x240, 100,000 photons per pass, 3 passes, 1 thread,
direct light sampled: the eye pass, three photon passes (trace, index build,
gather) and three direct-light passes. For symbols, build the module with
`cmake -S . -B build/prof -G Ninja -DPPM_BUILD_PYTHON=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
-DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O3 -g -DNDEBUG"` (plus -DPython_EXECUTABLE and -Dpybind11_DIR
from the virtual environment) and run with PYTHONPATH=build/prof.
"""

from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--passes", type=int, default=3)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()
    r = ppm_core.Renderer(core_scenes.cornell_3spheres(320, 240), threads=args.threads, photons_per_pass=100_000,
                          direct_light="sampled", seed=1)
    r.run(passes=args.passes)
    print(f"image mean {float(r.image().mean()):.6f}; seconds {r.stats()['seconds']}")


if __name__ == "__main__":
    main()
