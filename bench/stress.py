"""Numerical stress, the long version (issue "Accuracy and speed").

    .venv/bin/python bench/stress.py                 # about 10 minutes
    .venv/bin/python bench/stress.py --quick         # under a minute
    .venv/bin/python bench/stress.py --minutes 30    # a longer fuzz

Three parts, each printed as a markdown table:
 1. The fuzz of tests/core/test_fuzz.py for --minutes, in batches of random
    seeds, each batch a separate process so that a crash is caught (and the
    input that caused it is left in --fuzz-log) instead of ending the run.
 2. 10,000 passes (--passes) of a closed sphere with a point light (known
    answer) with few photons per pass, 1 and 2 threads, fixed and stochastic
    hit points, at radius 1 m and at the scale extremes 1e-4 m and 1e5 m:
    after pass 1, 10, 100, 1000, 10000 the mean radius, the error of the image
    mean against the analytic radiance, that the image is finite and
    non-negative, and resident memory (/proc/self/statm) and the core's own
    count, which must stay flat.
 3. No leaks: resident memory before and after 20,000 malformed builder
    calls and 2,000 refused Renderers (after a warm-up round of the same), and
    over 300 cycles of building a scene, rendering it and dropping both.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import random
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402

PAGE = os.sysconf("SC_PAGE_SIZE")


def resident_mb():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * PAGE / 2**20


# ------------------------------------------------------------------ 1. fuzz

def fuzz(minutes, batch, log_path):
    """Runs tests/core/test_fuzz.py with PPM_FUZZ_EXAMPLES=batch and fresh seeds until time is up."""
    deadline = time.monotonic() + 60.0 * minutes
    totals, batches, examples, failures = {}, 0, 0, []
    # The batches import ppm_core as this process did (installed, or PYTHONPATH, which they inherit).
    env = dict(os.environ, PPM_FUZZ_EXAMPLES=str(batch), PPM_FUZZ_LOG=log_path)
    start = time.monotonic()
    while time.monotonic() < deadline or batches == 0:
        seed = random.randrange(2**32)
        with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as f:
            stats_path = f.name
        env["PPM_FUZZ_STATS"] = stats_path
        p = subprocess.run([sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider",
                            f"--hypothesis-seed={seed}", os.path.join(ROOT, "tests", "core", "test_fuzz.py")],
                           cwd=ROOT, env=env, capture_output=True, text=True)
        batches += 1
        examples += 2 * batch
        if p.returncode != 0:
            kind = "crash (signal %d)" % -p.returncode if p.returncode < 0 else "test failure"
            with open(log_path) as f:
                last = f.read()
            failures.append((seed, kind, p.stdout[-3000:] + p.stderr[-2000:], last[:3000]))
            print(f"batch seed {seed}: {kind}; last input in {log_path}", file=sys.stderr)
            print(p.stdout[-3000:], p.stderr[-2000:], file=sys.stderr)
        try:
            with open(stats_path) as f:
                for name, outcomes in json.load(f).items():
                    for outcome, n in outcomes.items():
                        totals.setdefault(name, {}).setdefault(outcome, 0)
                        totals[name][outcome] += n
        except (OSError, ValueError):
            pass
        os.unlink(stats_path)
    return dict(seconds=time.monotonic() - start, batches=batches, examples=examples, totals=totals,
                failures=failures)


def print_fuzz(result):
    print("\n### Fuzz of the scene API and the Renderer\n")
    print(f"{result['examples']} examples in {result['batches']} batches (random seeds), "
          f"{result['seconds'] / 60:.1f} minutes; failures: {len(result['failures'])}.\n")
    print("| call | calls | worked | raised (by type) |")
    print("|---|---|---|---|")
    for name in sorted(result["totals"]):
        outcomes = result["totals"][name]
        total = sum(outcomes.values())
        ok = outcomes.get("ok", 0) + outcomes.get("rendered, finite", 0)
        raised = ", ".join(f"{k} {v}" for k, v in sorted(outcomes.items()) if k not in ("ok", "rendered, finite"))
        print(f"| {name} | {total} | {ok} | {raised or '-'} |")
    for seed, kind, output, last in result["failures"]:
        print(f"\nFailure with --hypothesis-seed={seed}: {kind}\n```\n{output}\n```\nlast input:\n```\n{last}\n```")


# ----------------------------------------------------------- 2. long runs

def closed_sphere(radius, width=16, height=16):
    scene = ppm_core.Scene()
    wall = scene.add_material("wall", "diffuse", base_color=(0.5, 0.5, 0.5))
    scene.add_sphere("room", (0.0, 0.0, 0.0), radius, wall)
    scene.add_light("point", name="lamp", power=100.0, position=(0.0, 0.0, 0.0))
    scene.set_camera(core_scenes.look_at((0.0, -0.1 * radius, 0.0), (0.0, radius, 0.0)), width, height,
                     fov=math.radians(60), clip_start=1e-3 * radius)
    return scene


def long_run(radius, threads, hit_points, passes, photons):
    renderer = ppm_core.Renderer(closed_sphere(radius), photons_per_pass=photons, threads=threads, seed=1,
                                 hit_points=hit_points, samples_per_pixel=1)
    expected = core_scenes.expected_closed_sphere_radiance(radius, 0.5, 100.0)
    rows, done, start = [], 0, time.perf_counter()
    checkpoints = [c for c in (1, 10, 100, 1000, 10000, 100000) if c <= passes]
    if passes not in checkpoints:
        checkpoints.append(passes)
    for target in checkpoints:
        renderer.run(passes=target - done)
        done = target
        image = renderer.image()
        stats = renderer.stats()
        finite = bool(np.isfinite(image).all() and (image >= 0).all())
        rows.append(dict(passes=done, seconds=time.perf_counter() - start, radius=stats["radius_mean"] / radius,
                         error=image[..., :3].mean() / expected - 1.0, finite=finite,
                         rss=resident_mb(), core=stats["memory_bytes"] / 2**20,
                         emitted=stats["photons_emitted"]))
        del image
    return rows


def print_long(configs, photons):
    print(f"\n### Long runs: closed sphere with a point light, {photons} photons per pass, 16x16 pixels\n")
    print("Radius as a fraction of the sphere's radius R; error of the image mean against the analytic "
          "radiance rho Phi / (4 pi^2 R^2 (1 - rho)).\n")
    print("| R (m) | threads | hit points | after pass | s | mean radius / R | mean error | finite, >= 0 "
          "| resident MB | core MB |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for (radius, threads, hit_points), rows in configs:
        for r in rows:
            print(f"| {radius:g} | {threads} | {hit_points} | {r['passes']} | {r['seconds']:.1f} | "
                  f"{r['radius']:.4g} | {100 * r['error']:+.2f}% | {'yes' if r['finite'] else '**NO**'} | "
                  f"{r['rss']:.1f} | {r['core']:.2f} |")


# ------------------------------------------------------ 3. error-path leaks

def error_path_leaks(calls):
    scene = ppm_core.Scene()
    scene.add_material("m")
    bad = [
        lambda: scene.add_mesh("m", np.zeros((1000, 3)), np.array([[0, 1, 5000]])),
        lambda: scene.add_mesh("m", np.full((1000, 3), np.nan), np.array([[0, 1, 2]])),
        lambda: scene.add_mesh("m", np.zeros((10, 3)), np.array([[0.5, 1, 2]])),
        lambda: scene.add_texture("t", np.full((64, 64, 4), -1.0)),
        lambda: scene.add_light("spot", direction=(0, 0, 0)),
        lambda: scene.add_light("point", power=1e30),
        lambda: scene.add_sphere("s", (0, 0, 0), 1e300, 0),
        lambda: scene.add_bezier_revolve("v", np.zeros((12, 2))),
        lambda: scene.set_camera(np.zeros((4, 4)), 8, 8),
        lambda: scene.intersect(np.zeros((100, 3)), np.zeros((100, 3))),
    ]
    good = closed_sphere(1.0, 8, 8)

    def loop(n):
        for i in range(n):
            try:
                bad[i % len(bad)]()
            except (ValueError, TypeError, RuntimeError):
                pass
        for i in range(n // 10):
            try:
                ppm_core.Renderer(good, alpha=1.5 if i % 2 else math.nan)
            except ValueError:
                pass

    loop(calls)  # warm-up: allocator pools, pybind11's type caches
    before = resident_mb()
    loop(calls)
    after = resident_mb()
    return before, after


def build_render_drop(cycles):
    rss = []
    for i in range(1, cycles + 1):
        scene = closed_sphere(1.0, 16, 16)
        scene.add_mesh("tri", np.array([[0, 0, 0.5], [0.2, 0, 0.5], [0, 0.2, 0.5]]), np.array([[0, 1, 2]]))
        renderer = ppm_core.Renderer(scene, photons_per_pass=2000, threads=2, seed=i)
        renderer.run(passes=2)
        assert np.isfinite(renderer.image()).all()
        del renderer, scene
        if i in (1, cycles // 3, 2 * cycles // 3, cycles):
            rss.append((i, resident_mb()))
    return rss


# ------------------------------------------------------------------- main

def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--minutes", type=float, default=3.0, help="fuzz duration (default 3)")
    parser.add_argument("--batch", type=int, default=100, help="fuzz examples per test per process")
    parser.add_argument("--passes", type=int, default=10_000)
    parser.add_argument("--photons", type=int, default=1_000, help="photons per pass in the long runs")
    parser.add_argument("--quick", action="store_true", help="under a minute: 0.3 min fuzz, 1,000 passes")
    parser.add_argument("--fuzz-log", default=os.path.join(tempfile.gettempdir(), "ppm_fuzz_last_input.txt"))
    parser.add_argument("--skip-fuzz", action="store_true")
    parser.add_argument("--fuzz-only", action="store_true")
    args = parser.parse_args()
    if args.quick:
        args.minutes, args.batch, args.passes, args.photons = 0.3, 25, 1000, 500

    print(f"ppm_core from {ppm_core.__file__}; {os.cpu_count()} cores; load average "
          f"{os.getloadavg()[0]:.1f}")
    ok = True
    if not args.skip_fuzz:
        result = fuzz(args.minutes, args.batch, args.fuzz_log)
        print_fuzz(result)
        ok &= not result["failures"]
    if args.fuzz_only:
        return 0 if ok else 1

    configs = []
    for radius, threads, hit_points in [(1.0, 1, "fixed"), (1.0, 2, "fixed"), (1.0, 2, "stochastic"),
                                        (1e-4, 2, "fixed"), (1e5, 2, "fixed")]:
        if args.quick and (radius != 1.0 or hit_points != "fixed"):
            continue
        rows = long_run(radius, threads, hit_points, args.passes, args.photons)
        configs.append(((radius, threads, hit_points), rows))
        ok &= all(r["finite"] for r in rows)
    print_long(configs, args.photons)

    calls = 2_000 if args.quick else 20_000
    before, after = error_path_leaks(calls)
    print(f"\n### Leaks\n\n{calls} malformed builder calls and {calls // 10} refused Renderers (after a "
          f"warm-up round of the same): resident memory {before:.1f} MB before, {after:.1f} MB after "
          f"({after - before:+.1f} MB).\n")
    rss = build_render_drop(60 if args.quick else 300)
    print("Building a scene, rendering 2 passes, dropping both, repeated: resident MB after cycle "
          + ", ".join(f"{i}: {mb:.1f}" for i, mb in rss) + ".")
    if not ok:
        print("\n**FAILURES above.**")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
