"""A horizontal well: the whole drill string in one FMU (DrillString), an axial oscillation tool
off and on, over a sweep of the tool's frequency and placement, run through fmpy on Dask.

The string (100 sections of 10 m 5-inch pipe, each on its own LuGre contact with the wall at its
buoyed weight, 2280 N) is pushed from the surface with a constant force F_PUSH on its first
section (F_d[1]; the top element removed: k_top = c_top = 0). The bit is the scene's spring and
dashpot on the rock, and the rock gives way at the rate of penetration ROP = WOB/R_ROCK, set by
this host as v_bottom at every step (WOB = F_bottom, the weight on bit). The wall's friction
(the drag) takes part of the push; the rest reaches the bit. The tool, a force
F_TOOL*sin(2*pi*f*t) on one section, shakes the string: its sections slip back and forth around
their mean motion and the wall's mean friction against the mean motion falls, so more of the
push reaches the bit.

For every run the script reports, over the last --mean seconds, the mean WOB (F_bottom_step),
the mean drag (the sum of every section's F_Fx_step: the wall's friction on the string), the
mean ROP, and the drag reduction against the tool off: 1 - drag_on / drag_off. It writes a
figure (WOB and drag against time for the tool off and the strongest reduction; the reduction
against frequency per placement) and prints a table.

    cargo run --release                                         # exports dist/DrillString.fmu
    .venv/bin/python -m pip install -r examples/figures/requirements.txt
    .venv/bin/python examples/drill_string/well_study.py [--scheduler ADDRESS] [--workers N]
        [--stop 10] [--mean 4] [--freqs 10,15,20] [--places 0.25,0.5,0.75] [--out docs/figures]

Runs go to local worker processes (one per core) by default, or to a dask.distributed cluster
with --scheduler (its workers must see dist/, or $VIBROFRIC_DIST, at the same path).
"""

import argparse
import math
import os
import pathlib
import shutil
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
DIST = pathlib.Path(os.environ.get("VIBROFRIC_DIST", ROOT / "dist"))

N = 100            # sections of the DrillString scene
F_PUSH = 100e3     # N, the push at the surface (the string's sliding drag is 100 * 684 N)
R_ROCK = 5e6       # N.s/m, WOB per rate of penetration (50 kN: 36 m/h)
F_TOOL = 20e3      # N, the tool's force amplitude
STEP = 1e-3        # s, the communication step
T_MEAN = 4.0       # s, the window of the means at the end of each run (--mean)


def run(freq, place, stop, fmu_path, t_mean=T_MEAN):
    """One run: the tool at `freq` Hz (0: off) on the section at the fraction `place` of the
    string's length. Returns the time series (t, WOB, drag, ROP) of the step means and their
    means over the last `t_mean` seconds."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    md = read_model_description(str(fmu_path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzip = extract(str(fmu_path), unzipdir=tempfile.mkdtemp(prefix="well_"))
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzip,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="well")
    try:
        fmu.instantiate()
        fmu.setupExperiment(startTime=0.0)
        fmu.setReal([vr["k_top"], vr["c_top"]], [0.0, 0.0])
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        tool = min(N, max(1, round(place * N)))
        fmu.setReal([vr["F_d[1]"]], [F_PUSH])
        out_vrs = [vr["F_bottom"], vr["F_bottom_step"]] + [vr[f"F_Fx_step[{i}]"]
                                                           for i in range(1, N + 1)]
        series = []
        steps = round(stop / STEP)
        wob = 0.0
        for k in range(steps):
            t = k * STEP
            rop = max(wob, 0.0) / R_ROCK
            fmu.setReal([vr["v_bottom"]], [rop])
            if freq > 0:
                w = 2 * math.pi * freq
                fmu.setReal([vr[f"F_d[{tool}]"]], [F_TOOL * math.sin(w * t)])
                fmu.setRealInputDerivatives([vr[f"F_d[{tool}]"]], [1],
                                            [F_TOOL * w * math.cos(w * t)])
            fmu.doStep(currentCommunicationPoint=t, communicationStepSize=STEP)
            values = fmu.getReal(out_vrs)
            wob = values[0]
            series.append((t + STEP, values[1], sum(values[2:]), rop))
        fmu.terminate()
    finally:
        fmu.freeInstance()
        shutil.rmtree(unzip, ignore_errors=True)
    last = [s for s in series if s[0] > stop - t_mean + 1e-12]
    mean = [sum(s[j] for s in last) / len(last) for j in (1, 2, 3)]
    return {"freq": freq, "place": place, "series": series,
            "wob": mean[0], "drag": mean[1], "rop": mean[2]}


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scheduler", default=None,
                   help="address of a dask.distributed scheduler (default: local processes)")
    p.add_argument("--workers", type=int, default=os.cpu_count(),
                   help="local worker processes (default: one per core)")
    p.add_argument("--stop", type=float, default=10.0, help="simulated seconds per run")
    p.add_argument("--mean", type=float, default=T_MEAN,
                   help="the window of the means at the end of each run, s")
    p.add_argument("--freqs", default="10,15,20", help="tool frequencies, Hz")
    p.add_argument("--places", default="0.25,0.5,0.75",
                   help="tool placements, as fractions of the length from the top")
    p.add_argument("--out", default=str(ROOT / "docs" / "figures"),
                   help="directory of the figure")
    args = p.parse_args()

    import dask
    from dask import delayed

    fmu_path = DIST / "DrillString.fmu"
    freqs = [float(f) for f in args.freqs.split(",")]
    places = [float(x) for x in args.places.split(",")]
    cases = [(0.0, 0.0)] + [(f, x) for x in places for f in freqs]
    tasks = [delayed(run)(f, x, args.stop, fmu_path, args.mean) for f, x in cases]
    t0 = time.perf_counter()
    print(f"{len(tasks)} runs of {args.stop} s, {N} sections, steps of {STEP} s", flush=True)
    if args.scheduler:
        from dask.distributed import Client, progress

        client = Client(args.scheduler)
        futures = client.compute(tasks)
        progress(futures)
        results = client.gather(futures)
    else:
        from dask.diagnostics import ProgressBar

        with ProgressBar():
            results = dask.compute(*tasks, scheduler="processes", num_workers=args.workers)
    print(f"wall {time.perf_counter() - t0:.1f} s", flush=True)

    off = results[0]
    print(f"\nmeans over the last {args.mean:g} s of {args.stop:g} s (push {F_PUSH / 1e3:.0f} kN, "
          f"tool {F_TOOL / 1e3:.0f} kN)")
    print("| tool | WOB (kN) | drag (kN) | ROP (m/h) | drag reduction |")
    print("|---|---|---|---|---|")
    for r in results:
        label = "off" if r["freq"] == 0 else f"{r['freq']:g} Hz at {r['place']:g} L"
        reduction = 1 - r["drag"] / off["drag"]
        r["reduction"] = reduction
        print(f"| {label} | {r['wob'] / 1e3:.2f} | {r['drag'] / 1e3:.2f} "
              f"| {3600 * r['rop']:.1f} | {100 * reduction:.1f} % |")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    best = max(results[1:], key=lambda r: r["reduction"])
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
    for r, style in ((off, "-"), (best, "--")):
        label = "tool off" if r is off else f"tool {r['freq']:g} Hz at {r['place']:g} L"
        t = [s[0] for s in r["series"]]
        a1.plot(t, [s[1] / 1e3 for s in r["series"]], "C0" + style, label=f"WOB, {label}")
        a1.plot(t, [s[2] / 1e3 for s in r["series"]], "C1" + style, label=f"drag, {label}")
    a1.set_xlabel("t (s)")
    a1.set_ylabel("force (kN), step means")
    a1.legend(fontsize=8)
    for x in places:
        rs = [r for r in results[1:] if r["place"] == x]
        a2.plot([r["freq"] for r in rs], [100 * r["reduction"] for r in rs], "o-",
                label=f"tool at {x:g} L")
    a2.set_xlabel("tool frequency (Hz)")
    a2.set_ylabel(f"drag reduction over the last {args.mean:g} s (%)")
    a2.legend(fontsize=8)
    fig.suptitle(f"DrillString: {N} sections, push {F_PUSH / 1e3:.0f} kN, "
                 f"tool {F_TOOL / 1e3:.0f} kN")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "well_study.png", dpi=110, bbox_inches="tight")
    print(f"wrote {out / 'well_study.png'}")


if __name__ == "__main__":
    main()
