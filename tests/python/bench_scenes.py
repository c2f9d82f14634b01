"""Cost per vibration period of every FMU of dist/ through fmpy, as a multiple of
PaperLongitudinal's in the same run, and its accuracy: each FMU co-simulated for 0.5 s in
communication steps of 1 ms at tolerance 1e-6 (best CPU time of 3 runs), and the largest
|F_Fx - F_Fx(tolerance 1e-10)| over the communication points, divided by F_C = mu * F_N.

    .venv/bin/python tests/python/bench_scenes.py [dist]

A benchmark, not a test: it prints a table and asserts nothing.
"""

import shutil
import sys
import time
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description, simulate_fmu

STOP = 0.5
STEP = 1e-3
NOMINAL_F = 2000.0  # scenes without a harmonic source: the default 2 kHz


def start(md, name, default):
    for v in md.modelVariables:
        if v.name == name and v.start is not None:
            return float(v.start)
    return default


def run(unzipdir, md, tol):
    return simulate_fmu(
        unzipdir,
        model_description=md,
        stop_time=STOP,
        output_interval=STEP,
        relative_tolerance=tol,
        output=["F_Fx"],
        fmi_type="CoSimulation",
    )


def main():
    folder = Path(sys.argv[1] if len(sys.argv) > 1 else "dist")
    rows = []
    for path in sorted(folder.glob("*.fmu")):
        md = read_model_description(str(path))
        unzipdir = extract(str(path))
        try:
            best = float("inf")
            for _ in range(3):
                t0 = time.process_time()
                r = run(unzipdir, md, 1e-6)
                best = min(best, time.process_time() - t0)
            ref = run(unzipdir, md, 1e-10)
            f_c = start(md, "mu", 0.2) * start(md, "F_N", 10.0)
            err = float(np.max(np.abs(r["F_Fx"] - ref["F_Fx"]))) / f_c
            periods = STOP * start(md, "f", NOMINAL_F)
            rows.append((md.modelName, best / periods * 1e6, err))
        finally:
            shutil.rmtree(unzipdir, ignore_errors=True)
    base = dict((n, c) for n, c, _ in rows).get("PaperLongitudinal")
    print("| scene | µs per period | × PaperLongitudinal | max F_Fx error / F_C vs tol 1e-10 |")
    print("|---|---|---|---|")
    for name, cost, err in rows:
        ratio = f"{cost / base:.1f}×" if base else "–"
        print(f"| {name} | {cost:.2f} | {ratio} | {err:.1e} |")


if __name__ == "__main__":
    main()
