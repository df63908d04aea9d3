"""The figures the experiments draw (matplotlib, Agg)."""

from __future__ import annotations

import numpy as np

from . import metrics


def pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def tone(image):
    """A display version of a linear image: Reinhard, then gamma 2.2."""
    return np.clip(image / (1.0 + image), 0.0, 1.0) ** (1 / 2.2)


def error_against_time(curves, path, title, measures=(("rel_mse", "relative MSE (eps 0.01)"),)):
    """Log-log error against wall time: `curves` maps a label to rows with "wall" and the measures;
    one panel per measure. A row's "ref_noise" draws the reference's own noise as a thin line."""
    plt = pyplot()
    fig, axes = plt.subplots(1, len(measures), figsize=(5.5 * len(measures), 4.5), squeeze=False)
    for i, (label, rows) in enumerate(curves.items()):
        t = [r["wall"] for r in rows]
        for ax, (key, _) in zip(axes[0], measures):
            ax.loglog(t, [r[key] for r in rows], "o-" if i < 10 else "s--", color=f"C{i % 10}", label=label)
            if key == "rel_mse" and np.isfinite(rows[0].get("ref_noise", np.nan)):
                ax.axhline(rows[0]["ref_noise"], color=f"C{i % 10}", lw=0.6, alpha=0.5)
    for ax, (_, name) in zip(axes[0], measures):
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel(name)
        ax.grid(True, which="both", alpha=0.3)
    axes[0][-1].legend(fontsize=7, loc="lower left")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def regions(name, reference, masks, path):
    """The reference and its region masks side by side."""
    plt = pyplot()
    shown = [k for k in masks if k != "all"]
    fig, axes = plt.subplots(1, len(shown) + 1, figsize=(2.6 * (len(shown) + 1), 2.3))
    axes[0].imshow(tone(reference))
    axes[0].set_title(f"{name} reference", fontsize=8)
    for ax, key in zip(axes[1:], shown):
        ax.imshow(masks[key], cmap="gray")
        ax.set_title(f"{key} ({int(masks[key].sum())} px)", fontsize=8)
    for ax in axes:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def agreement(ppm, cycles, path):
    """Both references and their relative difference of 4x4 block means (PPM / Cycles - 1), where a
    bias of one would show as a pattern rather than noise."""
    plt = pyplot()
    a, b = metrics.blocks(ppm).mean(axis=-1), metrics.blocks(cycles).mean(axis=-1)
    fig, axes = plt.subplots(1, 3, figsize=(11, 3))
    axes[0].imshow(tone(ppm))
    axes[0].set_title("PPM reference", fontsize=9)
    axes[1].imshow(tone(cycles))
    axes[1].set_title("Cycles reference", fontsize=9)
    ratio = np.where(b > 1e-3, a / np.maximum(b, 1e-3) - 1.0, np.nan)  # blank where both see nothing
    shown = axes[2].imshow(ratio, cmap="RdBu_r", vmin=-0.1, vmax=0.1)
    axes[2].set_title("PPM / Cycles - 1, 4x4 block means", fontsize=9)
    fig.colorbar(shown, ax=axes[2], fraction=0.04)
    for ax in axes:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
