"""Numerical stress of the core, the long version (issue "Accuracy and speed"). Three parts, each
reported as markdown tables:

 1. The fuzz of tests/core/test_fuzz.py for `minutes`, in batches of `batch` examples with random
    seeds, each batch a separate process (pytest under this Python) so that a crash is caught (and the
    input that caused it is left in `fuzz_log`) instead of ending the run.
 2. `passes` passes (10,000) of a closed sphere with a point light (known answer) with `photons` per
    pass, for each of `long_runs` (radius, threads, fixed or stochastic hit points; by default 1 m with
    1 and 2 threads and both kinds of hit points, and the scale extremes 1e-4 m and 1e5 m): after pass
    1, 10, 100, 1000, 10000 the mean radius, the error of the image mean against the analytic
    radiance, that the image is finite and non-negative, and resident memory (/proc/self/statm) and
    the core's own count, which must stay flat.
 3. No leaks: resident memory before and after `leak_calls` malformed builder calls and a tenth as many
    refused Renderers (after a warm-up round of the same), and over `leak_cycles` cycles of building a
    scene, rendering it and dropping both.

The experiment fails when the fuzz found a failure or a long run's image was not finite and >= 0.
`skip_fuzz` leaves part 1 out, `fuzz_only` runs part 1 alone."""

from __future__ import annotations

import json
import math
import os
import random
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402

PAGE = os.sysconf("SC_PAGE_SIZE")
FUZZ_TEST = os.path.join(ROOT, "tests", "core", "test_fuzz.py")
WORKED = ("ok", "rendered, finite")  # the outcomes test_fuzz.py counts as success


def resident_mb():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * PAGE / 2**20


# ------------------------------------------------------------------ 1. fuzz

def read_text(path):
    try:
        with open(path) as f:
            return f.read()
    except OSError:  # the batch failed before its first input
        return "(none logged)"


def fuzz_batch(seed, batch, log_path):
    """One pytest process of `batch` examples per test; (its outcome counts, a failure or None)."""
    with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as f:
        stats_path = f.name
    # The batch imports ppm_core as this process did (installed, or PYTHONPATH, which it inherits).
    env = dict(os.environ, PPM_FUZZ_EXAMPLES=str(batch), PPM_FUZZ_LOG=log_path, PPM_FUZZ_STATS=stats_path)
    p = subprocess.run([sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider",
                        f"--hypothesis-seed={seed}", FUZZ_TEST], cwd=ROOT, env=env, capture_output=True, text=True)
    failure = None
    if p.returncode != 0:
        kind = "crash (signal %d)" % -p.returncode if p.returncode < 0 else "test failure"
        last = read_text(log_path)
        failure = (seed, kind, p.stdout[-3000:] + p.stderr[-2000:], last[:3000])
        print(f"batch seed {seed}: {kind}; last input in {log_path}", file=sys.stderr)
    try:
        with open(stats_path) as f:
            counts = json.load(f)
    except (OSError, ValueError):
        counts = {}
    os.unlink(stats_path)
    return counts, failure


def fuzz(minutes, batch, log_path):
    """Batches with fresh seeds until `minutes` are up (at least one)."""
    start = time.monotonic()
    deadline = start + 60.0 * minutes
    totals, batches, failures = {}, 0, []
    while time.monotonic() < deadline or batches == 0:
        counts, failure = fuzz_batch(random.randrange(2**32), batch, log_path)
        batches += 1
        failures += [failure] if failure else []
        for name, outcomes in counts.items():
            for outcome, n in outcomes.items():
                totals.setdefault(name, {}).setdefault(outcome, 0)
                totals[name][outcome] += n
    return dict(seconds=time.monotonic() - start, batches=batches, examples=2 * batch * batches, totals=totals,
                failures=failures)


def report_fuzz(result, results):
    results.note(f"\n### Fuzz of the scene API and the Renderer\n\n{result['examples']} examples in "
                 f"{result['batches']} batches (random seeds), {result['seconds'] / 60:.1f} minutes; "
                 f"failures: {len(result['failures'])}.")
    rows = []
    for name in sorted(result["totals"]):
        outcomes = result["totals"][name]
        total, ok = sum(outcomes.values()), sum(outcomes.get(k, 0) for k in WORKED)
        raised = ", ".join(f"{k} {v}" for k, v in sorted(outcomes.items()) if k not in WORKED)
        rows.append([name, str(total), str(ok), raised or "-"])
        results.row(part="fuzz", call=name, calls=total, worked=ok, outcomes=outcomes)
    results.table(["call", "calls", "worked", "raised (by type)"], rows)
    for seed, kind, output, last in result["failures"]:
        results.note(f"\nFailure with --hypothesis-seed={seed}: {kind}\n```\n{output}\n```\nlast input:\n"
                     f"```\n{last}\n```")


# ----------------------------------------------------------- 2. long runs

def closed_sphere(radius, width=16, height=16):
    scene = ppm_core.Scene()
    wall = scene.add_material("wall", "diffuse", base_color=(0.5, 0.5, 0.5))
    scene.add_sphere("room", (0.0, 0.0, 0.0), radius, wall)
    scene.add_light("point", name="lamp", power=100.0, position=(0.0, 0.0, 0.0))
    scene.set_camera(core_scenes.look_at((0.0, -0.1 * radius, 0.0), (0.0, radius, 0.0)), width, height,
                     fov=math.radians(60), clip_start=1e-3 * radius)
    return scene


def checkpoints(passes):
    """Passes after which a long run is measured: the powers of ten up to `passes`, and `passes`."""
    points = [c for c in (1, 10, 100, 1000, 10000, 100000) if c <= passes]
    return points if passes in points else points + [passes]


def long_run(radius, threads, hit_points, passes, photons):
    renderer = ppm_core.Renderer(closed_sphere(radius), photons_per_pass=photons, threads=threads, seed=1,
                                 hit_points=hit_points, samples_per_pixel=1)
    expected = core_scenes.expected_closed_sphere_radiance(radius, 0.5, 100.0)
    rows, done, start = [], 0, time.perf_counter()
    for target in checkpoints(passes):
        renderer.run(passes=target - done)
        done = target
        image = renderer.image()
        stats = renderer.stats()
        finite = bool(np.isfinite(image).all() and (image >= 0).all())
        rows.append(dict(passes=done, seconds=time.perf_counter() - start, radius=stats["radius_mean"] / radius,
                         error=float(image[..., :3].mean() / expected - 1.0), finite=finite,
                         rss=resident_mb(), core=stats["memory_bytes"] / 2**20,
                         emitted=stats["photons_emitted"]))
        del image
    return rows


def long_run_cells(radius, threads, hit_points, r):
    return [f"{radius:g}", str(threads), hit_points, str(r["passes"]), f"{r['seconds']:.1f}", f"{r['radius']:.4g}",
            f"{100 * r['error']:+.2f}%", "yes" if r["finite"] else "**NO**", f"{r['rss']:.1f}", f"{r['core']:.2f}"]


def long_runs(experiment, results):
    """Part 2; True if every image was finite and non-negative."""
    ok, rows = True, []
    for config in experiment["long_runs"]:
        radius, threads, hit_points = config["radius"], config["threads"], config["hit_points"]
        for r in long_run(radius, threads, hit_points, experiment["passes"], experiment["photons"]):
            results.row(part="long run", R=radius, threads=threads, hit_points=hit_points, **r)
            rows.append(long_run_cells(radius, threads, hit_points, r))
            ok &= r["finite"]
    results.note(f"\n### Long runs: closed sphere with a point light, {experiment['photons']} photons per pass, "
                 "16x16 pixels\n\nRadius as a fraction of the sphere's radius R; error of the image mean against "
                 "the analytic radiance rho Phi / (4 pi^2 R^2 (1 - rho)).")
    results.table(["R (m)", "threads", "hit points", "after pass", "s", "mean radius / R", "mean error",
                   "finite, >= 0", "resident MB", "core MB"], rows)
    return ok


# ------------------------------------------------------ 3. error-path leaks

def malformed_calls(scene):
    """Builder calls that must each raise."""
    return [
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


def error_path_leaks(calls):
    """Resident MB before and after `calls` malformed builder calls and calls // 10 refused Renderers."""
    scene = ppm_core.Scene()
    scene.add_material("m")
    bad, good = malformed_calls(scene), closed_sphere(1.0, 8, 8)

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
    return before, resident_mb()


def build_render_drop(cycles):
    """Resident MB after cycles 1, a third, two thirds and all of build, render 2 passes, drop."""
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


def leaks(experiment, results):
    calls, cycles = experiment["leak_calls"], experiment["leak_cycles"]
    before, after = error_path_leaks(calls)
    results.row(part="leaks", calls=calls, rss_before=before, rss_after=after)
    results.note(f"\n### Leaks\n\n{calls} malformed builder calls and {calls // 10} refused Renderers (after a "
                 f"warm-up round of the same): resident memory {before:.1f} MB before, {after:.1f} MB after "
                 f"({after - before:+.1f} MB).\n")
    rss = build_render_drop(cycles)
    results.row(part="build, render, drop", cycles=cycles, rss_after_cycle=rss)
    results.note("Building a scene, rendering 2 passes, dropping both, repeated: resident MB after cycle "
                 + ", ".join(f"{i}: {mb:.1f}" for i, mb in rss) + ".")


# ------------------------------------------------------------------- run

def run(experiment, results):
    results.note(f"ppm_core from {ppm_core.__file__}; {os.cpu_count()} cores; load average "
                 f"{os.getloadavg()[0]:.1f}")
    ok = True
    if not experiment["skip_fuzz"]:
        # An empty fuzz_log is the temporary folder's ppm_fuzz_last_input.txt.
        log_path = experiment["fuzz_log"] or os.path.join(tempfile.gettempdir(), "ppm_fuzz_last_input.txt")
        result = fuzz(experiment["minutes"], experiment["batch"], log_path)
        report_fuzz(result, results)
        ok &= not result["failures"]
    if not experiment["fuzz_only"]:
        ok &= long_runs(experiment, results)
        leaks(experiment, results)
    if not ok:
        results.note("\n**FAILURES above.**")
    return ok
