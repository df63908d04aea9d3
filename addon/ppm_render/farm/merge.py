"""The client's side of a sharded still on dask.distributed: the shares submitted, and merged as
they come back (ppm_core.merge_shares' arithmetic, one share at a time)."""

from __future__ import annotations

import time

import cloudpickle

from . import shares

# Sent by value: a worker runs them without this add-on (or Blender) installed.
cloudpickle.register_pickle_by_value(shares)


class ByValue:
    """A function that pickles by value (cloudpickle) whichever pickler carries it: dask pickles a
    task with the standard pickler first, which would name the function's module for the worker
    to import, and the worker has no ppm_render (whose package needs bpy)."""

    def __init__(self, function):
        self.function = function

    def __call__(self, *args, **kwargs):
        return self.function(*args, **kwargs)

    def __reduce__(self):
        return cloudpickle.loads, (cloudpickle.dumps(self.function),)


def submit_shares(client, still, passes, count, threads=0, until=0.0, first_pass=0):
    """One future a share, each (Share, facts), for passes first_pass .. first_pass + passes - 1;
    the scene goes to the cluster once. `until`: the shares' deadline (shares.render_share)."""
    calls = client.scatter(still.calls, hash=False)
    render_share = ByValue(shares.render_share)
    return [client.submit(render_share, calls, still.settings, first_pass + first, n, threads, until,
                          key=f"ppm-share-{first}-{n}-{time.time_ns()}", pure=False)
            for first, n in shares.plan(passes, count)]


class ProgressiveMerge:
    """Merges shares as they arrive and keeps the output file current."""

    def __init__(self, output, expected, write_every, report):
        self.output, self.expected, self.write_every, self.report = output, expected, write_every, report
        self.merged, self.count, self.start, self.written = None, 0, time.perf_counter(), 0.0
        self.worker_seconds = 0.0

    def add(self, share, facts):
        import ppm_core

        self.merged = share if self.merged is None else ppm_core.merge_shares([self.merged, share])
        self.count += 1
        self.worker_seconds += facts["replay_seconds"] + facts["render_seconds"]
        error = self.merged.error_stats()["relative"] if self.merged.passes >= 2 else float("inf")
        self.report(f"{self.count}/{self.expected} shares, {self.merged.passes} passes, est. error "
                    f"{100 * error:.2f}%, {time.perf_counter() - self.start:.1f} s")
        if time.perf_counter() - self.written >= self.write_every:
            self.write()
        return error

    def collect(self, futures, deadline=0.0, target_error=0.0):
        """Merges `futures` as they complete; cancels those left at `deadline` seconds (0: none) or
        once the estimate meets `target_error` (0: off). A share that fails is reported and left out."""
        from dask.distributed import wait

        pending = set(futures)
        try:
            while pending:
                timeout = None if deadline <= 0.0 else max(0.0, deadline - (time.perf_counter() - self.start))
                try:
                    done, pending = wait(pending, timeout=timeout, return_when="FIRST_COMPLETED")
                except TimeoutError:
                    return
                for future in done:
                    if future.status == "error":
                        self.report(f"a share failed: {future.exception()}")
                        continue
                    error = self.add(*future.result())
                    future.release()
                    if 0.0 < error <= target_error:
                        self.report(f"target error {100 * target_error:.2f}% reached")
                        return
        finally:
            left = [f for f in futures if not f.done()]
            if left:
                self.report(f"{len(left)} shares not back by the deadline or the target: cancelled")
                for f in left:
                    f.cancel()

    def write(self):
        from .exr import write_exr

        if self.merged is not None:
            write_exr(self.output, self.merged, shares=self.count)
            self.written = time.perf_counter()

    def finish(self):
        if self.merged is None:
            self.report("no share came back: nothing written")
            return False
        self.write()
        error = self.merged.error_stats()
        self.report(f"wrote {self.output}: {self.merged.passes} passes from {self.count} shares, est. error "
                    f"{100 * error['relative']:.2f}% (bound {100 * error['bound']:.2f}% at 95%), "
                    f"{time.perf_counter() - self.start:.1f} s ({self.worker_seconds:.1f} s on the workers)")
        return True
