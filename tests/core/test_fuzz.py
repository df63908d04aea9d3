"""Fuzz of the scene-building API and the Renderer (hypothesis).

Every call gets random arguments, plausible or malformed (wrong types, NaN and
Inf, negative or zero sizes, wrong shapes and dtypes, out-of-range indices,
unknown kinds and names). Each call must either work or raise TypeError,
ValueError, RuntimeError or OverflowError; a crash inside the core would kill
Blender. Whenever the scene accepts a camera, a tiny render (8x6 or smaller,
1-2 passes, a few hundred photons) must give a finite, non-negative image.

Brief by default (derandomised, a few seconds in `make test`). Longer runs:
    PPM_FUZZ_EXAMPLES=5000 pytest tests/core/test_fuzz.py   # random seed
    python bench/run.py stress --set minutes=10             # the benchmark
PPM_FUZZ_LOG=file writes each example before it runs, so that a crash (which
hypothesis cannot report) leaves the input that caused it behind;
PPM_FUZZ_STATS=file writes counts of calls and outcomes (JSON) at exit.
"""

from __future__ import annotations

import atexit
import collections
import json
import math
import os

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import core_scenes
import ppm_core

EXAMPLES = int(os.environ.get("PPM_FUZZ_EXAMPLES", "40"))
LONG = "PPM_FUZZ_EXAMPLES" in os.environ
FUZZ_SETTINGS = settings(
    max_examples=EXAMPLES,
    deadline=None,
    derandomize=not LONG,
    database=None,
    print_blob=True,
    suppress_health_check=list(HealthCheck),
)

# What a bad argument may raise. Anything else (SystemError, IndexError,
# KeyError, ...) means an error path that was never meant to be taken.
ALLOWED = (TypeError, ValueError, RuntimeError, OverflowError)

SPECIAL_FLOATS = [0.0, -0.0, 1.0, -1.0, 0.5, 1e-4, 1e5, 1e-300, 5e-324, 1e300, -1e300, 1e38, 3.5e38,
                  math.inf, -math.inf, math.nan]


# ---------------------------------------------------------------- strategies

def numbers():
    return st.one_of(
        st.floats(-10.0, 10.0),
        st.sampled_from(SPECIAL_FLOATS),
        st.floats(allow_nan=True, allow_infinity=True),
        st.integers(-3, 3),
    )


def sizes():
    """Mostly sensible positive sizes, sometimes zero, negative or absurd."""
    return st.one_of(st.floats(1e-3, 10.0), st.sampled_from(SPECIAL_FLOATS))


def garbage():
    """Values of the wrong kind for almost any parameter."""
    return st.one_of(
        st.none(),
        st.booleans(),
        st.integers(),
        st.sampled_from([2**31, 2**32, 2**63, 2**64, -(2**63) - 1]),
        st.floats(allow_nan=True, allow_infinity=True),
        st.text(max_size=6),
        st.binary(max_size=6),
        st.sampled_from([b"\xff\xfe", "\ud800", "caf\u00e9", np.float32(0.5), np.int64(-1), np.bool_(True)]),
        st.lists(numbers(), max_size=5),
        st.tuples(numbers(), st.text(max_size=2)),
        st.sampled_from([object(), {}, {"a": 1}, [[1, 2], [3]], (), [None] * 3, "diffuse", "point", 1j]),
        arrays(),
    )


DTYPES = [np.float64, np.float32, np.float16, np.int64, np.int32, np.uint8, np.uint64, np.bool_,
          np.complex128, object, "U3"]


@st.composite
def arrays(draw, shape=None, dtype=None, elements=None):
    if shape is None:
        ndim = draw(st.integers(0, 4))
        shape = tuple(draw(st.integers(0, 5)) for _ in range(ndim))
    if dtype is None:
        dtype = draw(st.sampled_from(DTYPES))
    n = int(np.prod(shape)) if shape else 1
    values = draw(st.lists(elements if elements is not None else numbers(), min_size=n, max_size=n))
    with np.errstate(all="ignore"):
        try:
            a = np.array(values, dtype=object).reshape(shape)
            if dtype is object:
                return a
            kind = np.dtype(dtype).kind
            if kind in "iu":
                info = np.iinfo(dtype)
                ints = [min(max(_to_int(v), int(info.min)), int(info.max)) for v in values]
                return np.array(ints, dtype=dtype).reshape(shape)
            if kind == "b":
                return np.array([bool(_to_int(v)) for v in values], dtype=bool).reshape(shape)
            return a.astype(dtype)
        except (ValueError, OverflowError, TypeError):
            return np.zeros(shape, dtype=np.float64)


def _to_int(v):
    return int(v) if isinstance(v, (int, float)) and math.isfinite(v) and abs(v) < 2**62 else 0


def maybe(strategy, bad_weight=1):
    """Usually the plausible `strategy` (4 in 5), sometimes garbage. (st.one_of would not do:
    it draws its branches about evenly however often one is repeated.)"""
    if bad_weight == 0:
        return strategy
    return st.integers(0, 4).flatmap(lambda i: garbage() if i < bad_weight else strategy)


def pick(*weighted):
    """One of the strategies, with the given weights: pick((3, a), (1, b)). Unlike st.one_of,
    whose branches (nested ones flattened) are drawn about evenly."""
    table = [strategy for weight, strategy in weighted for _ in range(weight)]
    return st.integers(0, len(table) - 1).flatmap(lambda i: table[i])


def vec3():
    finite = st.floats(-3.0, 3.0)
    return pick(
        (4, st.tuples(finite, finite, finite)),
        (1, st.tuples(numbers(), numbers(), numbers())),
        (1, arrays(shape=(3,), dtype=np.float64)),
        (1, arrays(shape=(3,), dtype=np.float32)),
        (1, st.lists(numbers(), min_size=2, max_size=4)),
    )


def colour():
    return pick(
        (4, st.tuples(st.floats(0, 1), st.floats(0, 1), st.floats(0, 1))),
        (2, st.floats(0, 1)),
        (1, vec3()),
        (1, numbers()),
    )


def coords():
    """Coordinates of a small scene, one in ten a special value (0, 1e-300, 1e300, inf, NaN...)."""
    return st.integers(0, 9).flatmap(lambda i: st.sampled_from(SPECIAL_FLOATS) if i == 0 else st.floats(-2.0, 2.0))


@st.composite
def matrices(draw):
    kind = draw(st.integers(0, 5))
    if kind <= 1:
        eye = draw(st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(-5, 5)))
        target = draw(st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)))
        back = np.subtract(eye, target)
        if np.linalg.norm(back) < 1e-3 or np.linalg.norm(np.cross((0, 0, 1), back)) < 1e-6:
            return np.eye(4)
        return core_scenes.look_at(eye, target)
    if kind == 2:
        m = np.eye(4)
        m[:3, :3] *= draw(st.sampled_from([1.0, 1e-4, 1e5, 1e-300, 1e300, 0.0, -1.0]))
        m[:3, 3] = draw(st.tuples(coords(), coords(), coords()))
        return m
    if kind == 3:
        return draw(arrays(shape=(4, 4), dtype=np.float64))
    if kind == 4:
        return draw(arrays(shape=draw(st.sampled_from([(4, 4), (3, 3), (4,), (16,), (4, 4, 1), (0, 4)]))))
    return draw(garbage())


@st.composite
def mesh_args(draw):
    nv = draw(st.integers(0, 12))
    kind = draw(st.integers(0, 9))
    if kind <= 6:
        positions = draw(arrays(shape=(nv, 3), dtype=np.float64, elements=coords()))
    else:
        positions = draw(garbage())
    nt = draw(st.integers(0, 10))
    kind = draw(st.integers(0, 9))
    if kind <= 5:
        triangles = draw(arrays(shape=(nt, 3), dtype=np.int64, elements=st.integers(-1, nv)))
    elif kind <= 7:
        triangles = draw(arrays(shape=(nt, 3), dtype=draw(st.sampled_from(DTYPES)),
                                elements=st.one_of(st.integers(-2, nv + 1), numbers())))
    else:
        triangles = draw(garbage())
    kwargs = {}
    if draw(st.booleans()):
        n = draw(st.sampled_from([nv, 3 * nt, nv + 1]))
        shape = draw(st.sampled_from([(n, 3), (nt, 3, 3), (n,), (n, 2)]))
        kwargs["normals"] = draw(maybe(arrays(shape=shape, dtype=np.float64)))
    if draw(st.booleans()):
        n = draw(st.sampled_from([nv, 3 * nt, nv + 1]))
        shape = draw(st.sampled_from([(n, 2), (nt, 3, 2), (n, 3), (n,)]))
        kwargs["uvs"] = draw(maybe(arrays(shape=shape, dtype=np.float64)))
    if draw(st.booleans()):
        kwargs["materials"] = draw(maybe(st.one_of(
            st.integers(-1, 4),
            arrays(shape=(draw(st.sampled_from([1, nt, nt + 1, 0])),), dtype=np.int64, elements=st.integers(-1, 4)))))
    if draw(st.integers(0, 5)) == 0:
        kwargs["object_id"] = draw(maybe(st.integers(0, 100)))
    return (draw(maybe(st.text(max_size=4))), positions, triangles), kwargs


@st.composite
def material_call(draw):
    kw = {}
    if draw(st.booleans()):
        kw["kind"] = draw(maybe(st.sampled_from(["diffuse", "mirror", "metal", "glass", "emission", "plastic", ""])))
    if draw(st.booleans()):
        kw["base_color"] = draw(maybe(colour()))
    if draw(st.integers(0, 3)) == 0:
        kw["texture"] = draw(maybe(st.integers(-2, 3)))
    if draw(st.booleans()):
        kw["roughness"] = draw(maybe(st.one_of(st.floats(0, 1), numbers())))
    if draw(st.integers(0, 3)) == 0:
        kw["ior"] = draw(maybe(st.one_of(st.floats(1, 3), numbers())))
    if draw(st.integers(0, 3)) == 0:
        kw["specular_tint"] = draw(maybe(colour()))
    if draw(st.integers(0, 3)) == 0:
        kw["emission"] = draw(maybe(st.one_of(colour(), st.sampled_from([1e12, 1e-12, 1e30, 1e39]))))
    if draw(st.integers(0, 15)) == 0:
        kw["no_such_argument"] = 1
    return "add_material", (draw(maybe(st.text(max_size=4))),), kw


@st.composite
def texture_call(draw):
    shape = draw(st.sampled_from([(2, 2, 4), (1, 3, 4), (4, 4, 3), (0, 2, 4), (2, 0, 4), (2, 2), (4,), (2, 2, 4, 1)]))
    pixels = draw(maybe(st.one_of(
        arrays(shape=draw(st.sampled_from([(2, 2, 4), (1, 3, 4), (3, 1, 4)])), dtype=np.float32,
               elements=st.floats(0, 4)),
        arrays(shape=shape, dtype=draw(st.sampled_from(DTYPES))))))
    return "add_texture", (draw(maybe(st.text(max_size=4))), pixels), {}


@st.composite
def sphere_call(draw):
    args = (draw(maybe(st.text(max_size=4))), draw(maybe(vec3())), draw(maybe(sizes())),
            draw(maybe(st.integers(-1, 4))))
    return "add_sphere", args, {}


@st.composite
def revolve_call(draw):
    n = draw(st.sampled_from([2, 3, 4, 4, 5, 7, 9, 10, 0, 1, 11]))
    radii = draw(st.lists(st.floats(0.05, 1.0), min_size=n, max_size=n))
    profile = np.stack([radii, np.linspace(0.0, 1.0, n)], axis=1) if n else np.zeros((0, 2))
    points = draw(maybe(st.one_of(st.just(profile), st.just(profile.copy()),
                                  arrays(shape=(n, 2), dtype=np.float64, elements=st.floats(0, 1)),
                                  arrays(shape=(n, 2), dtype=np.float64, elements=coords()))))
    kw = {}
    if draw(st.booleans()):
        kw["kind"] = draw(st.sampled_from(["single", "single", "single", "chain", "chain", "chain", "spline", b"\xff"]))
    if draw(st.integers(0, 2)) == 0:
        kw["matrix"] = draw(matrices())
    if draw(st.booleans()):
        kw["material"] = draw(maybe(st.integers(-1, 4)))
    return "add_bezier_revolve", (draw(maybe(st.text(max_size=4))), points), kw


@st.composite
def light_call(draw):
    kind = draw(maybe(st.sampled_from(["point", "sphere", "spot", "rectangle", "disk", "sun", "laser", "Point"])))
    kw = {}
    if draw(st.booleans()):
        kw["power"] = draw(maybe(st.one_of(st.floats(0, 1000), st.sampled_from([1e12, 1e-12, 0.0, 1e30, 1e39]),
                                           colour())))
    if draw(st.integers(0, 3)) == 0:
        kw["color"] = draw(maybe(colour()))
    if draw(st.booleans()):
        kw["position"] = draw(maybe(vec3()))
    if draw(st.booleans()):
        kw["direction"] = draw(maybe(vec3()))
    if draw(st.integers(0, 3)) == 0:
        kw["matrix"] = draw(matrices())
    if draw(st.integers(0, 2)) == 0:
        kw["size"] = draw(maybe(st.one_of(sizes(), st.tuples(sizes(), sizes()), st.lists(sizes(), max_size=3))))
    if draw(st.integers(0, 2)) == 0:
        kw["radius"] = draw(maybe(st.one_of(st.floats(0, 1), sizes())))
    for name in ("spot_angle", "spot_blend", "angle"):
        if draw(st.integers(0, 3)) == 0:
            kw[name] = draw(maybe(st.one_of(st.floats(0, 7), numbers())))
    for name in ("spot_cosine_falloff", "soft_falloff"):
        if draw(st.integers(0, 3)) == 0:
            kw[name] = draw(maybe(st.booleans()))
    return "add_light", (kind,), kw


@st.composite
def camera_call(draw):
    kw = {}
    if draw(st.booleans()):
        kw["projection"] = draw(maybe(st.sampled_from(["perspective", "orthographic", "fisheye"])))
    for name, good in [("fov", st.floats(0.01, 3.1)), ("ortho_scale", st.floats(0.01, 10)),
                       ("shift_x", st.floats(-1, 1)), ("shift_y", st.floats(-1, 1)),
                       ("clip_start", st.floats(0, 1)), ("clip_end", st.floats(1, 1e3)),
                       ("focus_distance", st.floats(0.1, 10)), ("aperture_radius", st.floats(0, 0.5)),
                       ("focal_length", st.floats(0, 0.1))]:
        if draw(st.integers(0, 3)) == 0:
            kw[name] = draw(maybe(st.one_of(good, numbers())))
    if draw(st.integers(0, 3)) == 0:
        kw["sensor_fit"] = draw(maybe(st.sampled_from(["auto", "horizontal", "vertical", "diagonal"])))
    size = st.one_of(st.integers(1, 8), st.sampled_from([0, -1, 2**31 - 1, 2**31, 100000]))
    return "set_camera", (draw(matrices()), draw(maybe(size)), draw(maybe(size))), kw


@st.composite
def background_call(draw):
    return "set_background", (draw(maybe(st.one_of(colour(), st.sampled_from([1e12, 1e-12, 1e39])))),), {}


@st.composite
def intersect_call(draw):
    n = draw(st.integers(0, 6))
    shape = draw(st.sampled_from([(n, 3), (n, 3), (n, 3), (n, 2), (n,), (3,)]))
    good = st.floats(-3, 3)
    o = draw(maybe(st.one_of(arrays(shape=shape, dtype=np.float64, elements=good),
                             arrays(shape=shape, dtype=np.float64, elements=coords()))))
    d = draw(maybe(st.one_of(arrays(shape=shape, dtype=np.float64, elements=good),
                             arrays(shape=shape, dtype=np.float64, elements=coords()))))
    return "intersect", (o, d), {}


def calls():
    return st.one_of(
        material_call(), material_call(), mesh_call(), mesh_call(), mesh_call(), sphere_call(), sphere_call(),
        revolve_call(), light_call(), light_call(), light_call(), camera_call(), camera_call(), texture_call(),
        background_call(), intersect_call(), st.just(("build", (), {})), st.just(("build", (), {})),
        replace_mesh_call(), remove_call(),
    )


@st.composite
def mesh_call(draw):
    args, kw = draw(mesh_args())
    return "add_mesh", args, kw


@st.composite
def replace_mesh_call(draw):
    """A mesh in place of an object's, of the few ids the other calls mostly use."""
    args, kw = draw(mesh_args())
    kw["object_id"] = draw(maybe(st.integers(0, 3)))
    return "replace_mesh", args, kw


@st.composite
def remove_call(draw):
    return "remove_object", (draw(maybe(st.integers(0, 3))),), {}


SETTING_VALUES = {
    "photons_per_pass": st.one_of(st.integers(1, 400), st.sampled_from([0, -1, 2**32 + 1, 2**64])),
    "alpha": st.one_of(st.floats(0.01, 0.99), st.sampled_from([0.0, 1.0, 1e-300, math.nan, -0.5])),
    "threshold": st.one_of(st.integers(1, 30), st.sampled_from([0, -1, 2**32 - 1, 2**32])),
    "max_bounces": st.one_of(st.integers(1, 12), st.sampled_from([0, 1000, 1001, -5])),
    "samples_per_pixel": st.one_of(st.integers(1, 4), st.sampled_from([0, 4097, -1])),
    "seed": st.one_of(st.integers(0, 2**64 - 1), st.sampled_from([-1, 2**64])),
    "threads": st.sampled_from([0, 1, 2, 2, -1, 1025]),
    "initial_radius": st.one_of(st.floats(0, 1), st.sampled_from([1e-300, 1e300, 1e200, -1.0, math.inf, math.nan])),
    "initial_radius_pixels": st.one_of(st.floats(0.1, 10), st.sampled_from([0.0, 1e-300, 1e300, math.nan])),
    "progress_interval": st.one_of(st.floats(1e-3, 1), st.sampled_from([0.0, math.inf, 1e-300])),
    "direct_light": st.sampled_from(["sampled", "photons", "both"]),
    "gather": st.sampled_from(["hit_points", "photons", "Photons"]),
    "hit_points": st.sampled_from(["fixed", "stochastic", "adaptive"]),
    "dof_mode": st.sampled_from(["off", "post", "lens", "on"]),
    "dof_post_preset": st.sampled_from(["thin_lens", "report_thirds", "x"]),
    "dof_max_radius": st.sampled_from([1, 32, 256, 0, 257]),
    "scene_analysis": st.booleans(),
    "grid": st.sampled_from(["quantile", "hash", "kd"]),
}


@st.composite
def render_settings(draw):
    names = draw(st.lists(st.sampled_from(sorted(SETTING_VALUES) + ["photon_count", ""]), max_size=6, unique=True))
    out = {}
    for name in names:
        good = SETTING_VALUES.get(name, st.integers())
        out[name] = draw(maybe(good, bad_weight=1 if draw(st.integers(0, 4)) == 0 else 0))
    return out


@st.composite
def run_args(draw):
    passes = draw(st.sampled_from([1, 2, 2, 0, -1, 1.5, "2", None, 2**64, 2**64 - 1]))
    seconds = draw(st.sampled_from([0.0, 0, 0.02, -1.0, math.nan, math.inf, "1", None]))
    callback = draw(st.sampled_from(["none", "true", "false", "raise", "string", "noncallable", "image"]))
    return passes, seconds, callback


# ---------------------------------------------------------------- the checks

STATS = collections.defaultdict(collections.Counter)  # call name -> outcome -> count


def _write_stats():
    path = os.environ.get("PPM_FUZZ_STATS")
    if path:
        with open(path, "w") as f:
            json.dump({k: dict(v) for k, v in STATS.items()}, f)


atexit.register(_write_stats)


def call(target, name, args, kwargs):
    """Calls target.name(*args, **kwargs); returns (ok, result). Only ALLOWED may escape."""
    try:
        result = getattr(target, name)(*args, **kwargs)
        STATS[name]["ok"] += 1
        return True, result
    except ALLOWED as e:
        assert str(e), f"{name}: {type(e).__name__} without a message"
        STATS[name][type(e).__name__] += 1
        return False, None


def bounded(passes, seconds):
    """Does run(passes, seconds) finish quickly (or raise at once)?"""
    valid_passes = isinstance(passes, int) and not isinstance(passes, bool) and 0 <= passes < 2**64
    valid_seconds = isinstance(seconds, (int, float)) and not isinstance(seconds, bool) and seconds >= 0
    if not (valid_passes and valid_seconds) or (passes == 0 and seconds == 0):
        return True  # a TypeError or ValueError before any pass
    return 1 <= passes <= 2 or 0 < seconds <= 0.05


def make_callback(kind, renderer):
    if kind == "none":
        return None
    if kind == "noncallable":
        return 5
    if kind == "image":
        return lambda info: renderer.image() is not None
    value = {"true": True, "false": False, "string": "yes"}.get(kind)

    def callback(info):
        assert set(info) == {"passes", "photons_emitted", "seconds", "pass_done"}
        assert 0.0 <= info["pass_done"] <= 1.0
        if kind == "raise":
            raise ValueError("stop from the callback")
        return value
    return callback


def check_image(renderer, scene_w_h=None):
    image = renderer.image()
    assert image.dtype == np.float32 and image.ndim == 3 and image.shape[2] == 4
    if scene_w_h:
        assert image.shape[:2] == (scene_w_h[1], scene_w_h[0])
    assert np.isfinite(image).all(), f"non-finite pixels: {np.argwhere(~np.isfinite(image))[:5].tolist()}"
    assert (image >= 0.0).all(), f"negative pixels: {image.min()}"
    assert (image[..., 3] == 1.0).all()
    stats = renderer.stats()
    assert math.isfinite(stats["radius_mean"]) and stats["radius_mean"] >= 0.0
    return image


def exercise(ops, camera, settings_kw, run, threads, log=None, materials=0, dynamic=False):
    if log:
        with open(log, "w") as f:
            f.write(repr((ops, camera, settings_kw, run, threads, materials, dynamic)) + "\n")
    scene = ppm_core.Scene()
    scene.dynamic = dynamic  # (built ones take edits object by object)
    for i in range(materials):  # so that calls naming material 0, 1... can succeed
        scene.add_material(f"base{i}", base_color=(0.5, 0.6, 0.7))
    for name, args, kwargs in ops:
        ok, result = call(scene, name, args, kwargs)
        if ok and name == "intersect":
            t = result["t"]
            assert np.all((t > 0) | np.isnan(t)), t  # inf on a miss, never <= 0
            assert not np.isnan(t).any()
            assert set(np.unique(result["object"][np.isinf(t)])) <= {-1}
    # A camera the renderer can use, whatever the fuzzed calls left behind.
    ok, _ = call(scene, "set_camera", (camera[0], camera[1], camera[2]), {})
    w_h = (camera[1], camera[2]) if ok else None  # else an earlier camera (if any) stays
    try:  # small defaults (this is a fuzz, not a benchmark), then the fuzzed settings over them
        renderer = ppm_core.Renderer(scene, **{"photons_per_pass": 200, "threads": threads, "samples_per_pixel": 1,
                                               **settings_kw})
        STATS["Renderer(fuzzed settings)"]["ok"] += 1
    except ALLOWED as e:
        STATS["Renderer(fuzzed settings)"][type(e).__name__] += 1
        renderer = None
    if renderer is not None:
        s = renderer.settings
        small = (w_h is not None and s["photons_per_pass"] <= 400 and s["samples_per_pixel"] <= 4
                 and s["threads"] in (1, 2) and s["max_bounces"] <= 12)
        if small:
            passes, seconds, kind = run
            if bounded(passes, seconds):
                cb = make_callback(kind, renderer)
                try:
                    renderer.run(passes=passes, seconds=seconds, callback=cb)
                    STATS["run(fuzzed arguments)"]["ok"] += 1
                except ALLOWED as e:
                    STATS["run(fuzzed arguments)"][type(e).__name__] += 1
            check_image(renderer, w_h)
    # The same scene with small, valid settings: the scene itself must render.
    try:
        renderer = ppm_core.Renderer(scene, photons_per_pass=300, threads=threads, samples_per_pixel=1, seed=7)
    except ALLOWED as e:  # only a scene the core refuses to render (say, a 1e39 W light)
        assert "camera" in str(e) or "light" in str(e) or "material" in str(e) or "background" in str(e), e
        STATS["render (valid settings)"]["refused: " + str(e).split(":")[0]] += 1
        return
    if w_h is None:  # a camera from the fuzzed calls may be 100000 pixels wide: not rendered
        return
    renderer.run(passes=2)
    check_image(renderer, w_h)
    STATS["render (valid settings)"]["rendered, finite"] += 1


@st.composite
def cameras(draw):
    return (draw(matrices().filter(lambda m: isinstance(m, np.ndarray))),
            draw(st.integers(1, 8)), draw(st.integers(1, 6)))


@FUZZ_SETTINGS
@given(
    ops=st.lists(calls(), min_size=1, max_size=14),
    camera=cameras(),
    settings_kw=render_settings(),
    run=run_args(),
    threads=st.sampled_from([1, 2]),
    materials=st.integers(0, 3),
    dynamic=st.booleans(),
)
def test_fuzz_scene_api_and_render(ops, camera, settings_kw, run, threads, materials, dynamic):
    exercise(ops, camera, settings_kw, run, threads, log=os.environ.get("PPM_FUZZ_LOG"), materials=materials,
             dynamic=dynamic)


@st.composite
def plausible_scene_ops(draw):
    """Mostly valid calls (so that most scenes render): random boxes, spheres, lights, revolves, and in
    half of them edits after a build (meshes replaced with other triangles, objects removed), in a
    dynamic scene or not."""
    ops = [("add_material", ("m0",), {"base_color": draw(colour().filter(lambda c: isinstance(c, tuple)))}),
           ("add_material", ("m1",), {"kind": draw(st.sampled_from(["mirror", "glass", "metal", "diffuse"])),
                                      "roughness": draw(st.floats(0, 1))}),
           ("add_material", ("m2",), {"emission": draw(st.floats(0, 10))})]
    scale = draw(st.sampled_from([1e-4, 1e-2, 1.0, 1e3, 1e5]))
    meshes = draw(st.integers(1, 5))
    for i in range(meshes):
        pos = draw(arrays(shape=(4, 3), dtype=np.float64, elements=st.floats(-1, 1))) * scale
        tris = np.array([[0, 1, 2], [0, 2, 3], [1, 2, 3]])
        ops.append(("add_mesh", (f"mesh{i}", pos, tris), {"materials": draw(st.integers(0, 2)), "object_id": i}))
    for i in range(draw(st.integers(0, 3))):
        c = draw(st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)))
        radius = draw(st.floats(1e-3, 1)) * scale
        ops.append(("add_sphere", (f"s{i}", np.multiply(c, scale), radius, draw(st.integers(0, 1))),
                    {"object_id": 10 + i}))
    for _ in range(draw(st.integers(0, 3))):
        kind = draw(st.sampled_from(["point", "sphere", "spot", "rectangle", "disk", "sun"]))
        c = draw(st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)))
        ops.append(("add_light", (kind,), {"position": np.multiply(c, scale), "radius": 0.1 * scale,
                                          "size": 0.2 * scale, "direction": (0.1, 0.2, -1.0),
                                          "power": draw(st.sampled_from([1e-12, 1.0, 100.0, 1e12]))}))
    for i in range(draw(st.integers(0, 2))):
        n = draw(st.sampled_from([2, 3, 5, 9, 4, 7]))
        kind = "chain" if (n - 1) % 3 == 0 and draw(st.booleans()) else "single"
        radii = draw(st.lists(st.floats(0.0, 1.0), min_size=n, max_size=n))
        profile = np.stack([radii, np.linspace(-0.5, 0.5, n)], axis=1) * scale
        matrix = np.eye(4)
        matrix[:3, 3] = np.multiply(draw(st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1))), scale)
        ops.append(("add_bezier_revolve", (f"vase{i}", profile), {"kind": kind, "matrix": matrix,
                                                                    "material": draw(st.integers(0, 1)),
                                                                    "object_id": 20 + i}))
    if draw(st.booleans()):
        ops.append(("set_background", (draw(st.floats(0, 2)),), {}))
    if draw(st.booleans()):  # what the viewport does to its scene once built
        ops.append(("build", (), {}))
        for _ in range(draw(st.integers(1, 4))):
            if draw(st.booleans()):
                n = draw(st.integers(3, 6))
                pos = draw(arrays(shape=(n, 3), dtype=np.float64, elements=st.floats(-1, 1))) * scale
                tris = draw(arrays(shape=(draw(st.integers(1, 6)), 3), dtype=np.int64, elements=st.integers(0, n - 1)))
                ops.append(("replace_mesh", (f"mesh{draw(st.integers(0, meshes - 1))}", pos, tris),
                            {"materials": draw(st.integers(0, 2)), "object_id": draw(st.integers(0, meshes - 1))}))
            else:
                ops.append(("remove_object", (draw(st.sampled_from([0, 1, 2, 10, 11, 20])),), {}))
    camera = core_scenes.look_at(np.array([0.3, -3.0, 0.7]) * scale, (0, 0, 0))
    return ops, (camera, draw(st.integers(1, 8)), draw(st.integers(1, 6))), draw(st.booleans())


@FUZZ_SETTINGS
@given(scene=plausible_scene_ops(), settings_kw=render_settings(), threads=st.sampled_from([1, 2]))
def test_fuzz_random_scenes_render_finite(scene, settings_kw, threads):
    ops, camera, dynamic = scene
    exercise(ops, camera, settings_kw, (2, 0.0, "none"), threads, log=os.environ.get("PPM_FUZZ_LOG"),
             dynamic=dynamic)
