"""Fits the table of Cycles' microfiber sheen (Blender 4.0 and later: the Sheen BSDF's default mode
and the Principled BSDF's sheen) and writes engine/shading/sheen_ltc_table.inc.

The model is Zeltner, Burley and Chiang, "Practical Multiple-Scattering Sheen Using Linearly
Transformed Cosines" (SIGGRAPH 2022 talk): the reference is a layer of fibres standing along the
normal, a unit-thick, unit-density, non-absorbing volume with a specular SGGX microflake phase
function, S = diag(1, 1, sigma^2) with sigma = roughness^2, followed for at most 16 scatterings. Its
reflection towards the upper hemisphere, for a viewer at cos(theta) = mu, is approximated by

    f cos(theta_l) = R(mu, roughness) D(M^-1 l / |M^-1 l|) |M^-1| / |M^-1 l|^3,
    M^-1 = [[a, 0, b], [0, a, 0], [0, 0, 1]],  D(w) = max(w.z, 0) / pi,

with x towards the viewer. This script simulates the layer by random walks, takes R as the share
of walks that come back up and fits (a, b) to the walks' histogram over 32 x 32 outgoing
directions by Nelder-Mead on the cubed error, on the same 32 x 32 grid of mu and roughness in
[0.01, 1] as the talk's authors (roughness from high to low, each fit starting from the last).

Run: .venv/bin/python tools/sheen_ltc/fit_sheen_ltc.py [--walks N]. The committed table took
800,000 walks per entry (about 40 minutes on this project's 2-core machine); its R then has a
standard error below 0.001. tests/core/microfiber_sheen_test.cpp checks entries against walks
simulated independently.
"""
import argparse
import multiprocessing
import pathlib

import numpy as np

STEPS = 32
GRID = np.maximum(0.01, np.linspace(0.0, 1.0, STEPS))  # both mu and roughness, as the talk's fit
MAX_SCATTERINGS = 16
THETA_BINS, PHI_BINS = 32, 32
OUT = pathlib.Path(__file__).resolve().parents[2] / "engine" / "shading" / "sheen_ltc_table.inc"


def sample_visible_normals(v, s_half, rng):
    """Microflake normals seen from v (rows, unit) for S = diag(1, 1, s_half^2). The flakes are the
    normals of the ellipsoid x^T S x = 1, which S^1/2 maps to the unit sphere: a point uniform in
    the sphere's projected disk along S^1/2 v is lifted onto its visible side and its normal mapped
    back (n ~ S^1/2 p)."""
    d = v * np.array([1.0, 1.0, s_half])
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    # A frame around d.
    helper = np.where(np.abs(d[:, :1]) < 0.9, np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]]))
    e1 = np.cross(helper, d)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(d, e1)
    r = np.sqrt(rng.random(len(v)))
    phi = 2.0 * np.pi * rng.random(len(v))
    x, y = r * np.cos(phi), r * np.sin(phi)
    p = x[:, None] * e1 + y[:, None] * e2 + np.sqrt(np.maximum(0.0, 1.0 - x * x - y * y))[:, None] * d
    m = p * np.array([1.0, 1.0, s_half])
    return m / np.linalg.norm(m, axis=1, keepdims=True)


def random_walks(mu, roughness, walks, rng):
    """Directions in which the walks entering at cos(theta) = mu end (rows); those pointing up
    are the reflected ones (escaped at the top, or still inside, going up, after 16 scatterings)."""
    s_half = roughness * roughness  # S_zz = sigma^2 = roughness^4
    s_zz = s_half * s_half
    view = np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])
    d = np.tile(-view, (walks, 1))
    depth = np.zeros(walks)  # 0 at the top, 1 at the bottom
    inside = np.ones(walks, dtype=bool)
    for _ in range(MAX_SCATTERINGS):
        idx = np.flatnonzero(inside)
        if idx.size == 0:
            break
        di = d[idx]
        sigma_t = np.sqrt(di[:, 0] ** 2 + di[:, 1] ** 2 + s_zz * di[:, 2] ** 2)
        distance = -np.log1p(-rng.random(idx.size)) / sigma_t
        depth[idx] += distance * -di[:, 2]
        left = (depth[idx] < 0.0) | (depth[idx] > 1.0)
        inside[idx[left]] = False
        stay = idx[~left]
        back = -d[stay]
        m = sample_visible_normals(back, s_half, rng)
        d[stay] = 2.0 * np.sum(m * back, axis=1, keepdims=True) * m - back
    return d


def reflected_histogram(d, walks):
    """f cos(theta) of the reflected walks on a THETA_BINS x PHI_BINS grid over theta in
    [0, pi/2] and phi in [0, pi] (the other half mirrored): count / (walks * solid angle)."""
    up = d[d[:, 2] > 0.0]
    theta = np.arccos(np.clip(up[:, 2], -1.0, 1.0))
    phi = np.abs(np.arctan2(up[:, 1], up[:, 0]))
    counts, _, _ = np.histogram2d(theta, phi, bins=[THETA_BINS, PHI_BINS], range=[[0.0, np.pi / 2], [0.0, np.pi]])
    edges = np.linspace(0.0, np.pi / 2, THETA_BINS + 1)
    solid = (np.cos(edges[:-1]) - np.cos(edges[1:]))[:, None] * (np.pi / PHI_BINS) * 2.0  # both mirrored halves
    values = counts / (walks * solid)
    values[0, :] = values[0, :].mean()  # near the pole the azimuth bins are one direction
    return values, len(up) / walks


def bin_directions():
    theta = (np.arange(THETA_BINS) + 0.5) / THETA_BINS * (np.pi / 2)
    phi = (np.arange(PHI_BINS) + 0.5) / PHI_BINS * np.pi
    t, p = np.meshgrid(theta, phi, indexing="ij")
    return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)


def ltc_values(a, b, albedo, w):
    x = a * w[..., 0] + b * w[..., 2]
    y = a * w[..., 1]
    z = w[..., 2]
    length = np.sqrt(x * x + y * y + z * z)
    return albedo * np.maximum(z / length, 0.0) / np.pi * (a * a) / length**3


def nelder_mead(f, x0, step=0.1, tolerance=1e-10, iterations=2000):
    """A plain downhill simplex in two dimensions (no SciPy in the project)."""
    simplex = [np.array(x0, dtype=float)]
    for i in range(len(x0)):
        x = np.array(x0, dtype=float)
        x[i] += step
        simplex.append(x)
    values = [f(x) for x in simplex]
    for _ in range(iterations):
        order = np.argsort(values)
        simplex = [simplex[i] for i in order]
        values = [values[i] for i in order]
        if abs(values[-1] - values[0]) <= tolerance * (abs(values[0]) + 1e-30):
            break
        centroid = np.mean(simplex[:-1], axis=0)
        reflected = centroid + (centroid - simplex[-1])
        fr = f(reflected)
        if fr < values[0]:
            expanded = centroid + 2.0 * (centroid - simplex[-1])
            fe = f(expanded)
            simplex[-1], values[-1] = (expanded, fe) if fe < fr else (reflected, fr)
        elif fr < values[-2]:
            simplex[-1], values[-1] = reflected, fr
        else:
            contracted = centroid + 0.5 * (simplex[-1] - centroid)
            fc = f(contracted)
            if fc < values[-1]:
                simplex[-1], values[-1] = contracted, fc
            else:
                for i in range(1, len(simplex)):
                    simplex[i] = simplex[0] + 0.5 * (simplex[i] - simplex[0])
                    values[i] = f(simplex[i])
    return simplex[int(np.argmin(values))]


def fit_row(args):
    """One mu: R and (a, b) for every roughness, fitted from the roughest down."""
    mu_index, walks = args
    rng = np.random.default_rng(1000 + mu_index)
    w = bin_directions()
    row = np.zeros((STEPS, 3))
    x = np.array([1.0, 0.0])
    for r_index in range(STEPS - 1, -1, -1):
        d = random_walks(GRID[mu_index], GRID[r_index], walks, rng)
        reference, albedo = reflected_histogram(d, walks)
        row[r_index, 2] = albedo
        if albedo < 3e-6:  # (nothing comes back: the fit would be noise)
            row[r_index, :2] = x
            continue
        x = nelder_mead(lambda p, albedo=albedo, reference=reference:
                        np.sum(np.abs(ltc_values(p[0], p[1], albedo, w) - reference) ** 3), x)
        row[r_index, :2] = x
    return mu_index, row


def write_table(table, walks, out):
    lines = [
        "// Generated by tools/sheen_ltc/fit_sheen_ltc.py (do not edit): the microfiber sheen's LTC",
        f"// table, {STEPS} x {STEPS} entries [roughness][cos_theta] of (a, b, R), fitted to {walks} random",
        "// walks per entry (see the script for the model).",
    ]
    for r_index in range(STEPS):
        lines.append("  // roughness row %d" % r_index)
        for mu_index in range(STEPS):
            a, b, albedo = table[mu_index, r_index]
            lines.append(f"  {{{a:.6f}f, {b:.6f}f, {albedo:.6f}f}},")
    out.write_text("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--walks", type=int, default=800_000, help="random walks per table entry")
    parser.add_argument("--processes", type=int, default=2)
    parser.add_argument("--out", type=pathlib.Path, default=OUT)
    args = parser.parse_args()
    table = np.zeros((STEPS, STEPS, 3))
    with multiprocessing.Pool(args.processes) as pool:
        for mu_index, row in pool.imap_unordered(fit_row, [(m, args.walks) for m in range(STEPS)]):
            table[mu_index] = row
            print(f"mu {GRID[mu_index]:.3f}: R from {row[:, 2].min():.4f} to {row[:, 2].max():.4f}", flush=True)
    write_table(table, args.walks, args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
