"""Ray casting throughput of ppm_core's Scene.intersect against Embree 4.

    .venv/bin/python bench/run.py raycast [--quick] [--set 'meshes=["asteroid"]'] [--set embree=false]

Two meshes (the list `meshes`; float32 vertices, so both libraries see the same geometry):
  asteroid  ~10^5 triangles: a watertight cube-sphere displaced by fractal
            noise, the typical closed scanned/sculpted object;
  terrain   ~10^6 triangles: a fractal height field (720k triangles) with 280k
            small randomly oriented "leaf" triangles floating above it, a soup
            whose boxes overlap, which is the hard case for an SAH build.
`rays` rays (fixed seed, float32 so both libraries cast the same rays): 80% start on a
sphere twice the mesh's bounding radius and aim at a uniform point in its box,
20% start anywhere in the box and go in a uniform direction. Times are the best of `repeats`.

Embree comes from the `embreex` wheel (bench/requirements.txt: pip install embreex==4.4.0.post1),
used here only; `embree = false` measures ppm_core alone. Its `EmbreeScene.run` loops over the rays
in Cython on the calling thread (rtcIntersect1 one ray at a time, GIL held, no thread option), so
the 1-thread rows compare like for like. For the all-threads row Embree runs in
forked worker processes that share the built scene, each casting its share; the
time is the slowest worker's own loop (fork and result transfer left out). The
Embree build (rtcCommitScene) always uses all cores through TBB; ppm's build
is single-threaded. Throughput is given by wall clock and, for 1 thread, by the
casting thread's CPU time, which a shared machine disturbs much less.

Both libraries must agree: the second table counts rays whose nearest hits
differ and checks that each lies within rounding reach of a triangle edge or
meets its triangle at a grazing angle, where float (Embree) and double (ppm)
arithmetic can legitimately decide differently. The throughput kind borrows the terrain.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import time

import numpy as np

import ppm_core

SEED = 20261122


# ---------------------------------------------------------------- meshes

def fractal(points, octaves, rng, amplitude=1.0, base_freq=1.0, dims=3):
    """Sum of random plane waves, halving amplitude and doubling frequency per octave."""
    out = np.zeros(len(points))
    for o in range(octaves):
        for _ in range(4):
            w = rng.normal(size=dims)
            w *= base_freq * 2.0**o / np.linalg.norm(w)
            out += amplitude * 0.5**o * np.sin(points @ w + rng.uniform(0, 2 * np.pi))
    return out


def asteroid(k, rng):
    """Cube-sphere with k x k quads per face, vertices shared across faces."""
    g = np.arange(-k, k + 1, 2)
    u, v = np.meshgrid(g, g, indexing="ij")
    faces_pts, faces_tris, base = [], [], 0
    for axis in range(3):
        for sign in (-1, 1):
            p = np.zeros((k + 1, k + 1, 3), dtype=np.int64)
            p[..., axis] = sign * k
            p[..., (axis + 1) % 3] = u
            p[..., (axis + 2) % 3] = v
            idx = base + np.arange((k + 1) ** 2).reshape(k + 1, k + 1)
            a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[:-1, 1:], idx[1:, 1:]
            tris = np.concatenate([np.stack([a, b, d], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
            if sign < 0:
                tris = tris[:, ::-1]
            faces_pts.append(p.reshape(-1, 3))
            faces_tris.append(tris)
            base += (k + 1) ** 2
    pts = np.concatenate(faces_pts)
    # Seam vertices appear on two or three faces with the same integer coordinates.
    uniq, inverse = np.unique(pts, axis=0, return_inverse=True)
    tris = inverse.reshape(-1)[np.concatenate(faces_tris)]
    dirs = uniq / np.linalg.norm(uniq, axis=1)[:, None]
    r = 1.0 + 0.12 * fractal(dirs, 6, rng, base_freq=2.0)
    return (dirs * r[:, None]).astype(np.float32), tris.astype(np.int32)


def terrain(n, leaves, rng):
    """Height field on an n x n grid over [-1, 1]^2 plus a soup of small triangles above it."""
    x = np.linspace(-1, 1, n + 1)
    X, Y = np.meshgrid(x, x, indexing="ij")
    xy = np.stack([X.ravel(), Y.ravel()], -1)
    Z = 0.15 * fractal(xy, 7, rng, base_freq=2.0, dims=2)
    pts = np.stack([X.ravel(), Y.ravel(), Z], -1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[:-1, 1:], idx[1:, 1:]
    tris = np.concatenate([np.stack([a, b, d], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
    # Leaves: centres in a layer above the terrain, edges about two grid cells long.
    cxy = rng.uniform(-1, 1, size=(leaves, 2))
    cz = 0.4 + rng.uniform(0.05, 0.35, size=leaves)  # a flat canopy layer above the peaks
    centres = np.concatenate([cxy, cz[:, None]], 1)
    size = 2.0 * 2.0 / n
    corners = centres[:, None, :] + rng.normal(scale=size, size=(leaves, 3, 3))
    leaf_pts = corners.reshape(-1, 3)
    leaf_tris = len(pts) + np.arange(3 * leaves).reshape(-1, 3)
    return (np.concatenate([pts, leaf_pts]).astype(np.float32),
            np.concatenate([tris, leaf_tris]).astype(np.int32))


def make_rays(vertices, count, rng):
    lo, hi = vertices.min(0).astype(np.float64), vertices.max(0).astype(np.float64)
    centre, radius = 0.5 * (lo + hi), 0.5 * np.linalg.norm(hi - lo)
    outside = int(0.8 * count)
    s = rng.normal(size=(outside, 3))
    o1 = centre + 2.0 * radius * s / np.linalg.norm(s, axis=1)[:, None]
    d1 = rng.uniform(lo, hi, size=(outside, 3)) - o1
    o2 = rng.uniform(lo, hi, size=(count - outside, 3))
    d2 = rng.normal(size=(count - outside, 3))
    o = np.concatenate([o1, o2])
    d = np.concatenate([d1, d2])
    d /= np.linalg.norm(d, axis=1)[:, None]
    return o.astype(np.float32), d.astype(np.float32)


# ---------------------------------------------------------------- runners

def best_of(repeats, fn):
    """Best wall time and best CPU time of the calling thread over `repeats` runs.

    The 1-thread casts of both libraries run on the calling thread, so its CPU
    time leaves out the time other processes on a shared machine took.
    """
    wall, cpu, result = float("inf"), float("inf"), None
    for _ in range(repeats):
        c0, t0 = time.thread_time(), time.perf_counter()
        result = fn()
        wall = min(wall, time.perf_counter() - t0)
        cpu = min(cpu, time.thread_time() - c0)
    return (wall, cpu), result


def run_ppm(vertices, tris, origins, dirs, repeats, threads, layout="auto"):
    scene = ppm_core.Scene()
    if layout != "auto":  # (a core from before the layouts has no such property: A/B runs)
        scene.geometry_layout = layout
    mat = scene.add_material("grey")
    t0 = time.perf_counter()
    scene.add_mesh("mesh", vertices.astype(np.float64), tris, materials=mat)
    add_time = time.perf_counter() - t0
    t0 = time.perf_counter()
    scene.build()
    build = time.perf_counter() - t0
    o64, d64 = origins.astype(np.float64), dirs.astype(np.float64)
    rows = {}
    result = None
    for th in threads:
        (wall, cpu), result = best_of(repeats, lambda th=th: scene.intersect(o64, d64, threads=th))
        rows[th] = (wall, cpu if th == 1 else None)
    return dict(add=add_time, build=build, cast=rows, t=result["t"], prim=result["primitive"])


_EMBREE = {}


def _embree_worker(args):
    begin, end = args
    scene = _EMBREE["scene"]
    o, d = _EMBREE["o"][begin:end], _EMBREE["d"][begin:end]
    t0 = time.perf_counter()
    scene.run(o, d, output=1)
    return time.perf_counter() - t0


def run_embree(vertices, tris, origins, dirs, repeats, threads):
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    t0 = time.perf_counter()
    scene = rtcore_scene.EmbreeScene()
    TriangleMesh(scene, vertices, tris)
    scene.run(origins[:1], dirs[:1])  # the first run commits (builds) the scene
    build = time.perf_counter() - t0
    rows = {}
    secs, result = best_of(repeats, lambda: scene.run(origins, dirs, output=1))
    rows[1] = secs
    workers = max(threads)
    if workers > 1:
        _EMBREE.update(scene=scene, o=origins, d=dirs)
        n = len(origins)
        chunks = [(n * k // workers, n * (k + 1) // workers) for k in range(workers)]
        with mp.get_context("fork").Pool(workers) as pool:
            best = float("inf")
            for _ in range(repeats):
                best = min(best, max(pool.map(_embree_worker, chunks, chunksize=1)))
            rows[workers] = (best, None)
        _EMBREE.clear()
    t = np.where(result["primID"] >= 0, result["tfar"].astype(np.float64), np.inf)
    return dict(build=build, cast=rows, t=t, prim=result["primID"].astype(np.int64))


def near_edge_or_grazing(vertices, tris, prim, origins, dirs):
    """Whether each ray meets its triangle within rounding reach of an edge, or at a grazing angle.

    There a float test (Embree) and a double test (ppm) can legitimately disagree:
    the smallest barycentric coordinate of the ray's crossing with the triangle's
    plane is within 1e-4 of 0, or the ray makes less than 0.6 degrees with the plane.
    """
    v = vertices.astype(np.float64)[tris[prim]]
    o, d = origins.astype(np.float64), dirs.astype(np.float64)
    e1, e2 = v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    s = o - v[:, 0]
    u = np.einsum("ij,ij->i", s, p) / det
    w = np.einsum("ij,ij->i", d, np.cross(s, e1)) / det
    edge = np.abs(np.minimum(np.minimum(u, w), 1.0 - u - w))
    n = np.cross(e1, e2)
    cos = np.abs(np.einsum("ij,ij->i", n, d)) / (np.linalg.norm(n, axis=1) * np.linalg.norm(d, axis=1))
    return (edge < 1e-4) | (cos < 1e-2)


def agreement(p, e, vertices, tris, origins, dirs):
    hit_p, hit_e = np.isfinite(p["t"]), np.isfinite(e["t"])
    both = hit_p & hit_e
    # t differences relative to the mesh size: Embree's float arithmetic has an
    # absolute error of a few float ulps of the coordinates, whatever t is.
    size = float(np.linalg.norm(vertices.max(0).astype(np.float64) - vertices.min(0)))
    rel = np.zeros(len(hit_p))
    rel[both] = np.abs(p["t"][both] - e["t"][both]) / size
    # Rays whose nearest hits differ: one library found a hit the other did not.
    differ = (hit_p != hit_e) | (rel > 1e-5)
    p_closer = differ & (np.where(hit_p, p["t"], np.inf) < np.where(hit_e, e["t"], np.inf))
    e_closer = differ & ~p_closer
    # The nearer of the two hits is the one the other library missed.
    explained = int(
        near_edge_or_grazing(vertices, tris, p["prim"][p_closer], origins[p_closer], dirs[p_closer]).sum()
        + near_edge_or_grazing(vertices, tris, e["prim"][e_closer], origins[e_closer], dirs[e_closer]).sum())
    same_t_other_tri = both & (rel <= 1e-5) & (p["prim"] != e["prim"])
    return dict(rays=len(hit_p), hit_frac=hit_p.mean(), miss_mismatch=int((hit_p != hit_e).sum()),
                t_off=int((rel > 1e-5).sum()), p_closer=int(p_closer.sum()), e_closer=int(e_closer.sum()),
                explained=explained,
                rel_med=float(np.median(rel[both])), rel_p999=float(np.quantile(rel[both], 0.999)),
                prim_diff=int(same_t_other_tri.sum()))


# ---------------------------------------------------------------- run

MESHES = {"asteroid": lambda rng: asteroid(91, rng), "terrain": lambda rng: terrain(600, 280_000, rng)}


def embree_available(results):
    try:
        import embreex  # noqa: F401
    except ImportError:
        results.note("embreex is not installed, so only ppm_core is measured. For the comparison:\n"
                     "    .venv/bin/python -m pip install -r bench/requirements.txt   (benchmark only; "
                     "the core never uses it)")
        return False
    return True


def fmt(x, spec=".2f"):
    return "-" if x is None else format(x, spec)


def with_cpu(x):
    """A 1-thread figure by the casting thread's CPU time, in brackets after the wall-clock one."""
    return f" ({fmt(x)})" if x is not None else ""


def per_second(rays, seconds):
    return rays / seconds / 1e6 if seconds else None


def speed_rows(name, triangles, rays, threads, p, e, results):
    """Table rows of one mesh: Mrays/s by wall clock and (1 thread) by CPU time, Embree / ppm."""
    rows = []
    for th in threads:
        pw, pc = (per_second(rays, s) for s in p["cast"][th])
        ew, ec = (per_second(rays, s) for s in e["cast"][th]) if e else (None, None)
        eb = e["build"] if e else None
        results.row(table="speed", mesh=name, triangles=triangles, threads=th, ppm_build_s=p["build"],
                    ppm_mrays_wall=pw, ppm_mrays_cpu=pc, embree_build_s=eb, embree_mrays_wall=ew,
                    embree_mrays_cpu=ec)
        ratio = f"{ew / pw:.2f}" if ew is not None else "-"
        cpu_ratio = None if ec is None or pc is None else ec / pc
        rows.append([name, f"{triangles:,}", str(th), f"{p['build']:.3f}", fmt(pw) + with_cpu(pc), fmt(eb, ".3f"),
                     fmt(ew) + with_cpu(ec), ratio + with_cpu(cpu_ratio)])
    return rows


def agreement_row(name, a, results):
    results.row(table="agreement", mesh=name, **a)
    return [name, f"{a['rays']:,}", f"{a['hit_frac']:.3f}", str(a["miss_mismatch"]), str(a["t_off"]),
            f"{a['p_closer']} / {a['e_closer']}", str(a["explained"]), f"{a['rel_med']:.1e} / {a['rel_p999']:.1e}",
            str(a["prim_diff"])]


def run(experiment, results):
    rays, repeats = experiment["rays"], experiment["repeats"]
    unknown = set(experiment["meshes"]) - set(MESHES)
    if unknown:
        raise SystemExit(f"unknown meshes {sorted(unknown)}; there are: {', '.join(MESHES)}")
    have_embree = experiment["embree"] and embree_available(results)
    hw = os.cpu_count() or 1
    threads = [1, hw] if hw > 1 else [1]
    results.note(f"{rays:,} rays, best of {repeats}, {hw} hardware threads")
    speed, agree = [], []
    for name in experiment["meshes"]:
        rng = np.random.default_rng(SEED)
        vertices, tris = MESHES[name](rng)
        origins, dirs = make_rays(vertices, rays, rng)
        p = run_ppm(vertices, tris, origins, dirs, repeats, threads, experiment["geometry_layout"])
        e = run_embree(vertices, tris, origins, dirs, repeats, threads) if have_embree else None
        speed += speed_rows(name, len(tris), rays, threads, p, e, results)
        if e:
            agree.append(agreement_row(name, agreement(p, e, vertices, tris, origins, dirs), results))
    results.table(["mesh", "triangles", "threads", "ppm build s", "ppm Mrays/s wall (CPU)", "Embree build s",
                   "Embree Mrays/s wall (CPU)", "Embree / ppm wall (CPU)"], speed)
    if agree:
        results.table(["mesh", "rays", "hit fraction", "hit/miss differ", "both hit, t differs > 1e-5 x mesh size",
                       "nearer hit from ppm / Embree", "of those, near an edge or grazing",
                       "both hit: median / 99.9% t diff / mesh size", "same t, other triangle"], agree)
