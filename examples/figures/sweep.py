"""Parallel sweeps through Dask, shared by the figure scripts.

`run(tasks, scheduler=None)` evaluates a list of `fmurun.point` tasks and returns their F_mean
values as a numpy array, in order. Points are grouped into chunks (one Dask task each, a few
hundred FMU runs) so that Dask's per-task overhead does not swamp FMU runs of a few milliseconds.

- default: Dask's local multiprocessing scheduler, one worker process per core
  (`--workers N` to change), each keeping its extracted FMU instances for the whole sweep,
  with `dask.diagnostics.ProgressBar`;
- `--scheduler ADDRESS` (e.g. tcp://host:8786): a `dask.distributed` cluster. fmurun.py is
  uploaded to the workers; the FMUs are read from the path resolved here (dist/ of this
  checkout, or $VIBROFRIC_DIST), so the workers must see that file system at the same path.
"""

import argparse
import os
import pathlib
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import fmurun  # noqa: E402

OUT = fmurun.ROOT / "docs" / "figures"
# The FMU directory, resolved at import: Client.upload_file may reload fmurun in this process
# (a scheduler in-process imports the uploaded copy), which would move its default path.
DIST = fmurun.dist_dir()

_CLIENT = None
_ARGS = None


def parser(description):
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--scheduler", default=None,
                   help="address of a dask.distributed scheduler (default: local processes)")
    p.add_argument("--workers", type=int, default=os.cpu_count(),
                   help="local worker processes (default: one per core)")
    p.add_argument("--n", type=int, default=None, help="grid points per axis (default: per figure)")
    p.add_argument("--out", default=str(OUT), help="directory of the PNGs (default: docs/figures)")
    return p


def configure(args):
    global _ARGS, _CLIENT
    _ARGS = args
    pathlib.Path(args.out).mkdir(parents=True, exist_ok=True)
    if args.scheduler and _CLIENT is None:
        from dask.distributed import Client

        _CLIENT = Client(args.scheduler)
        _CLIENT.upload_file(str(HERE / "fmurun.py"))


def _chunk(tasks):
    return [fmurun.point(t) for t in tasks]


def run(tasks, label="sweep", chunk=None):
    """F_mean of every task (fmurun.point arguments), computed in parallel; prints the wall time."""
    import dask
    from dask import delayed

    args = _ARGS
    workers = max(1, args.workers if args else (os.cpu_count() or 1))
    if chunk is None:
        chunk = max(1, min(100, -(-len(tasks) // (16 * workers))))
    tasks = [tuple(t[:3]) + (DIST,) for t in tasks]  # workers read the FMUs from this path
    parts = [delayed(_chunk)(tasks[i:i + chunk]) for i in range(0, len(tasks), chunk)]
    t0 = time.perf_counter()
    print(f"{label}: {len(tasks)} FMU runs in {len(parts)} Dask tasks", flush=True)
    if _CLIENT is not None:
        from dask.distributed import progress

        futures = _CLIENT.compute(parts)
        progress(futures)
        results = _CLIENT.gather(futures)
    else:
        from dask.diagnostics import ProgressBar

        with ProgressBar():
            results = dask.compute(*parts, scheduler="processes", num_workers=workers)
    dt = time.perf_counter() - t0
    print(f"{label}: {len(tasks)} FMU runs, wall {dt:.1f} s "
          f"({1e3 * dt / max(1, len(tasks)):.2f} ms per run)", flush=True)
    return np.array([v for part in results for v in part])


def savefig(fig, name):
    p = pathlib.Path(_ARGS.out if _ARGS else OUT) / name
    fig.savefig(p, dpi=110, bbox_inches="tight")
    print(f"wrote {p}", flush=True)
    return p
