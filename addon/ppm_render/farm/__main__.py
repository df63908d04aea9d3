"""One still across a Dask cluster: `python -m ppm_render.farm scene.blend --output out.exr`.

    python -m ppm_render.farm scene.blend --output out.exr --scheduler tcp://host:8786 --shares 64
    python -m ppm_render.farm scene.blend --output out.exr --local-workers 2   # a LocalCluster here

Needs bpy (to read the .blend), dask.distributed, ppm_core and OpenImageIO here; on the workers,
ppm_core, numpy and dask only (docs/FARM.md). The scene is exported once, sent to the workers once,
and each share (a range of passes, shares.plan) runs where the scheduler puts it. Shares are merged
as they arrive; the output is rewritten every --write-every seconds and at the end, with the error
estimate of what it holds. A worker that dies loses its share, which the scheduler runs again
elsewhere. At --deadline every share stops with the passes it has (they merge as well as whole
shares'); those not back shortly after (a lost or unreachable worker) are cancelled and left out.
--target-error stops early once the merged image's estimate meets it.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import time


def parse_arguments(argv):
    parser = argparse.ArgumentParser(prog="python -m ppm_render.farm", description=__doc__.splitlines()[0])
    parser.add_argument("blend", help=".blend file to render (its scene camera, settings and size)")
    parser.add_argument("--output", required=True, help="the merged image (.exr)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="address of a dask scheduler, e.g. tcp://host:8786")
    where.add_argument("--local-workers", type=int, default=2, help="without --scheduler: a LocalCluster here")
    parser.add_argument("--shares", type=int, default=16, help="shares to split the passes into")
    parser.add_argument("--passes", type=int, help="passes in all (default: the scene's)")
    parser.add_argument("--resolution", type=int, nargs=2, metavar=("W", "H"), help="image size in pixels")
    parser.add_argument("--threads", type=int, default=0, help="threads a share uses on its worker (0: all)")
    parser.add_argument("--deadline", type=float, default=0.0,
                        help="seconds: shares stop there with the passes they have (0: no deadline)")
    parser.add_argument("--target-error", type=float, default=0.0,
                        help="stop once the merged image's estimate is at most this (default: the scene's)")
    parser.add_argument("--write-every", type=float, default=30.0, help="seconds between rewrites of the output")
    args = parser.parse_args(argv)
    if not args.output.lower().endswith(".exr"):
        parser.error("--output must be an .exr file")
    if args.shares < 1 or args.local_workers < 1:
        parser.error("--shares and --local-workers must be at least 1")
    return args


def export(blend, resolution=None):
    """The Still of `blend` (at `resolution`, or its own), through this add-on registered in the bpy module."""
    import bpy

    from .. import core, register, unregister
    from .still_export import export_still

    if not os.path.isfile(blend):
        raise ValueError(f"'{blend}' does not exist")
    register()  # first: the file's scene then finds its engine
    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(blend))
    try:
        if resolution:
            render = bpy.context.scene.render
            render.resolution_x, render.resolution_y = resolution
            render.resolution_percentage = 100
        return export_still(bpy, core.load(), lambda message: print(f"farm: warning: {message}", flush=True))
    finally:
        unregister()  # bpy 4.2 crashes and 4.5 hangs at exit while a script's classes are registered


@contextlib.contextmanager
def connected(args):
    """A dask Client of the scheduler asked for, or of a LocalCluster made here (closed after)."""
    from dask.distributed import Client, LocalCluster

    if args.scheduler:
        with Client(args.scheduler) as client:
            yield client
        return
    with LocalCluster(n_workers=args.local_workers, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        yield client


def main(argv=None):
    args = parse_arguments(sys.argv[1:] if argv is None else argv)
    try:
        still = export(args.blend, args.resolution)
        with connected(args) as client:
            result = run(client, still, args)
    except Exception as error:  # noqa: BLE001 - a readable message and a failing exit code
        print(f"farm: error: {error}", file=sys.stderr, flush=True)
        return 1
    return 0 if result else 1


def run(client, still, args):
    """Submits the shares, merges them as they come back, writes the output; True if it holds any."""
    from .merge import ProgressiveMerge, submit_shares

    passes = args.passes or still.passes
    # Each share stops at the deadline with the passes it has; shares that are not back soon after
    # it (a worker lost or unreachable) are left out.
    until = time.time() + args.deadline if args.deadline > 0.0 else 0.0
    futures = submit_shares(client, still, passes, args.shares, args.threads, until)
    merge = ProgressiveMerge(args.output, len(futures), args.write_every,
                             report=lambda line: print(f"farm: {line}", flush=True))
    merge.collect(futures, args.deadline * 1.1 + 5.0 if args.deadline > 0.0 else 0.0,
                  args.target_error or still.target_error)
    return merge.finish()


if __name__ == "__main__":
    sys.exit(main())
