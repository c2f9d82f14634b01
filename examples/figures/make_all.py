"""Regenerates every figure of docs/figures/ (see docs/figures.md) through the FMUs of dist/.

    cargo run --release                                   # exports dist/*.fmu
    .venv/bin/python -m pip install -r examples/figures/requirements.txt
    .venv/bin/python examples/figures/make_all.py [--scheduler ADDRESS] [--workers N] [--out DIR]

Sweeps run through Dask: local worker processes by default (one per core), or a dask.distributed
cluster with --scheduler (its workers must see dist/, or $VIBROFRIC_DIST, at the same path).
--n overrides every figure's grid size (points per axis); without it each figure uses its own
(Figs. 7 and 10: 50 x 50 per side, 5000 FMU runs each).
"""

import time

import fig_psi
import fig_rig
import fig_surfaces
import fig_u0_f
import sweep


def main():
    args = sweep.parser(__doc__.splitlines()[0]).parse_args()
    sweep.configure(args)
    t0 = time.perf_counter()
    for module in (fig_psi, fig_surfaces, fig_u0_f, fig_rig):
        module.make(args)
    print(f"all figures: wall {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
