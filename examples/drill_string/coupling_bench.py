"""A string of contacts three ways, against one monolithic integration of the same equations:
one string FMU, or one contact FMU per section coupled by the host (the host owns the masses,
pattern B, or each FMU owns its section's mass, pattern A), with held inputs or with input
derivatives. Prints each coupling's CPU time per simulated second and its weight on bit (WOB)
against the monolithic one.

The string: N sections of 10 m 5-inch drill pipe (267 kg, EA/L = 7.1e7 N/m, c_s = 2e3 N.s/m),
each on its own LuGre contact at its buoyed weight (F_N = 2280 N, mu = 0.3, F_S = 1.3 F_C,
k_t = 1e8, zeta_t = 1), the top fed at 5 cm/s through k_top = 1e6 N/m, c_top = 1e4 N.s/m, the
bit a spring-dashpot on the rock (k_bottom = 1e7 N/m, c_bottom = 1e4 N.s/m), a tool of 20 kN at
15 Hz on section 3N/4 + 1, from rest, the wall still, tolerance 1e-6. WOB is the mean of
F_bottom over the second half of the run. The monolithic reference is scipy's Radau with a
sparse Jacobian at rtol 1e-10 on the equations of docs/scenes.md, written out below.

    cargo run --release          # builds target/release/vibrofric
    .venv/bin/python examples/drill_string/coupling_bench.py [--sections 20] [--stop 1]
        [--runs string:1e-3,B-held:1e-3,B-held:1e-4,B-careful:3e-4,A-held:1e-4,A-careful:3e-4]

Each run is a coupling and its communication step: `string` (the string FMU), `B-held`,
`B-careful` (pattern B with held inputs or with input derivatives), `A-held`, `A-careful`.
"""

import argparse
import math
import pathlib
import shutil
import subprocess
import tempfile
import time

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from scipy.integrate import solve_ivp
from scipy.sparse import lil_matrix

ROOT = pathlib.Path(__file__).resolve().parents[2]

M, F_N, MU, K_T, V_S = 267.0, 2280.0, 0.3, 1e8, 1e-3
F_C = MU * F_N
F_S = 1.3 * F_C
H_T0 = 2.0 * math.sqrt(M * K_T)  # zeta_t = 1 at the section's load; v_e = v_S
K_S, C_S = 7.1e7, 2e3
K_TOP, C_TOP, V_TOP = 1e6, 1e4, 0.05
K_BOT, C_BOT = 1e7, 1e4
TOOL, FREQ = 20e3, 15.0
TOL = 1e-6

SECTION = """law = "lugre"
motion = "longitudinal"
support = ["input"]
[start]
m = 267.0
F_N = 2280.0
mu = 0.3
F_S = 889.2
k_t = 1e8
"""


def scene_files(n, tmp):
    """Writes the string scene (n sections) and the two single-section scenes into tmp."""
    string = (ROOT / "scenes" / "drill-string.toml").read_text()
    string = string.replace('model_identifier = "DrillString"', 'model_identifier = "BenchString"')
    string = string.replace("sections = 100", f"sections = {n}")
    (tmp / "string.toml").write_text(string)
    (tmp / "a.toml").write_text(
        'model_identifier = "BenchSectionA"\ndescription = "a section, force drive"\n'
        + 'drive = "force"\n' + SECTION)
    (tmp / "b.toml").write_text(
        'model_identifier = "BenchSectionB"\ndescription = "a section, velocity drive"\n'
        + 'drive = "velocity"\n' + SECTION + "v_d = 0.0\n")
    exe = ROOT / "target" / "release" / "vibrofric"
    cmd = [str(exe)] if exe.exists() else ["cargo", "run", "--release", "--quiet", "--"]
    subprocess.run(cmd + ["export", *(str(tmp / f) for f in ("string.toml", "a.toml", "b.toml")),
                          "--out", str(tmp), "--platforms", "linux64"], check=True, cwd=ROOT, stdout=subprocess.DEVNULL)
    return tmp / "BenchString.fmu", tmp / "BenchSectionA.fmu", tmp / "BenchSectionB.fmu"


# The tool's force as the string FMU sees it: the sine's value and slope at the start of each
# communication step of 1 ms, extrapolated linearly over the step (an input with its
# derivative). Every coupling and the reference get this same function of time.
GRID = 1e-3


def tool_piece(t):
    """The start of the 1 ms piece holding t, the force there and its slope."""
    t0 = math.floor(t / GRID + 1e-9) * GRID
    w = 2 * math.pi * FREQ
    return t0, TOOL * math.sin(w * t0), TOOL * w * math.cos(w * t0)


def tool_force(t):
    t0, f, df = tool_piece(t)
    return f + df * (t - t0)


def tool_rate(t):
    return tool_piece(t)[2]


def reference(n, stop):
    """The monolithic integration, state [x, v, s] per section and the integral of F_bottom,
    piece by piece of the tool's force; returns the times of the pieces' ends, F_bottom there
    and F_bottom's mean over each piece."""
    piece = [0.0, 0.0, 0.0]

    def rhs(t, y):
        y, dy = y[:-1], np.empty_like(y)
        x, v, s = y[0::3], y[1::3], y[2::3]
        e = np.exp(-(v / V_S) ** 2)
        g = (F_C + (F_S - F_C) * e) / K_T
        ds = v - np.abs(v) * s / g
        f = K_T * s + H_T0 * e * ds
        force, bottom = chain_forces(t, x, v, piece[1] + piece[2] * (t - piece[0]))
        dy[0:-1:3], dy[1:-1:3], dy[2:-1:3], dy[-1] = v, (force - f) / M, ds, bottom
        return dy

    pattern = lil_matrix((3 * n + 1, 3 * n + 1))
    pattern[3 * n, 3 * n - 3] = pattern[3 * n, 3 * n - 2] = 1
    for i in range(n):
        k = 3 * i
        pattern[k, k + 1] = pattern[k + 2, k + 1] = pattern[k + 2, k + 2] = 1
        for j in range(max(0, k - 3), min(3 * n, k + 5)):
            pattern[k + 1, j] = 1
    atol = np.append(np.tile([1e-14, 1e-12, 1e-16], n), 1e-12)
    y, h0 = np.zeros(3 * n + 1), None
    ends, wob, means = [], [], []
    for k in range(int(round(stop / GRID))):
        t0, t1 = k * GRID, (k + 1) * GRID
        piece[:] = tool_piece(t0 + GRID / 2)
        sol = solve_ivp(rhs, (t0, t1), y, method="Radau", rtol=1e-10, atol=atol,
                        jac_sparsity=pattern, first_step=h0)
        if not sol.success:
            raise RuntimeError(sol.message)
        h0 = min(GRID, max(sol.t[-1] - sol.t[-2], 1e-9))
        means.append((sol.y[-1, -1] - y[-1]) / GRID)
        y = sol.y[:, -1]
        ends.append(t1)
        wob.append(K_BOT * y[3 * n - 3] + C_BOT * y[3 * n - 2])
    return np.array(ends), np.array(wob), np.array(means)


def open_fmu(path, name):
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzip = extract(str(path))
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzip,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
    fmu.instantiate()
    fmu.setupExperiment(tolerance=TOL, startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    return fmu, vr, unzip


def close(fmus):
    for fmu, _, unzip in fmus:
        fmu.terminate()
        fmu.freeInstance()
        shutil.rmtree(unzip, ignore_errors=True)


def run_string(path, n, stop, h=1e-3):
    fmu, vr, unzip = open_fmu(path, "string")
    tool = vr[f"F_d[{3 * n // 4 + 1}]"]
    fmu.setReal([vr["v_top"]], [V_TOP])
    steps = int(round(stop / h))
    wob, means = [], []
    out = [vr["F_bottom"], vr["F_bottom_step"]]
    clock = time.process_time()
    for c in range(steps):
        t = c * h
        fmu.setReal([tool], [tool_force(t)])
        fmu.setRealInputDerivatives([tool], [1], [tool_rate(t)])
        fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        end, mean = fmu.getReal(out)
        wob.append(end)
        means.append(mean)
    cpu = time.process_time() - clock
    close([(fmu, vr, unzip)])
    return cpu, np.arange(1, steps + 1) * h, np.array(wob), np.array(means)


def chain_forces(t, x, v, tool=None):
    """The links, ends and tool on every section of a chain at t (the tool's force `tool`, or
    the piecewise-linear one at t); and F_bottom."""
    n = len(x)
    force = np.zeros(n)
    link = K_S * np.diff(x) + C_S * np.diff(v)
    force[:-1] += link
    force[1:] -= link
    force[0] += K_TOP * (V_TOP * t - x[0]) + C_TOP * (V_TOP - v[0])
    bottom = K_BOT * x[-1] + C_BOT * v[-1]
    force[-1] -= bottom
    force[3 * n // 4] += tool_force(t) if tool is None else tool
    return force, bottom


def run_host_owned(path, n, stop, h, careful):
    """Pattern B: the host integrates the masses (semi-implicit Euler), each FMU (velocity
    drive) gets its section's velocity (and its acceleration as the input derivative) and
    returns the friction's mean over the step."""
    fmus = [open_fmu(path, f"section{i}") for i in range(n)]
    vd, vsx, fstep = (fmus[0][1][k] for k in ("v_d", "v_sx", "F_Fx_step"))
    x, v, a = np.zeros(n), np.zeros(n), np.zeros(n)
    steps = int(round(stop / h))
    wob = []
    clock = time.process_time()
    for c in range(steps):
        t = c * h
        friction = np.empty(n)
        for i, (fmu, _, _) in enumerate(fmus):
            fmu.setReal([vd, vsx], [v[i], 0.0])
            if careful:
                fmu.setRealInputDerivatives([vd], [1], [a[i]])
            fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            friction[i] = fmu.getReal([fstep])[0]
        force, _ = chain_forces(t, x, v)
        a = (force - friction) / M
        v = v + h * a
        x = x + h * v
        wob.append(chain_forces(t + h, x, v)[1])
    cpu = time.process_time() - clock
    close(fmus)
    return cpu, np.arange(1, steps + 1) * h, np.array(wob), None


def run_fmu_owned(path, n, stop, h, careful):
    """Pattern A: each FMU (force drive) integrates its section; the host sets F_d from the
    neighbours' last x and v (and its rate from their last velocities and accelerations)."""
    fmus = [open_fmu(path, f"section{i}") for i in range(n)]
    fd, vsx, xr, vxr = (fmus[0][1][k] for k in ("F_d", "v_sx", "x", "v_x"))
    x, v, a = np.zeros(n), np.zeros(n), np.zeros(n)
    steps = int(round(stop / h))
    wob = []
    clock = time.process_time()
    for c in range(steps):
        t = c * h
        force, _ = chain_forces(t, x, v)
        if careful:
            rate = np.zeros(n)
            dlink = K_S * np.diff(v) + C_S * np.diff(a)
            rate[:-1] += dlink
            rate[1:] -= dlink
            rate[0] += K_TOP * (V_TOP - v[0]) - C_TOP * a[0]
            rate[-1] -= K_BOT * v[-1] + C_BOT * a[-1]
            rate[3 * n // 4] += tool_rate(t)
        v_old = v.copy()
        for i, (fmu, _, _) in enumerate(fmus):
            fmu.setReal([fd, vsx], [force[i], 0.0])
            if careful:
                fmu.setRealInputDerivatives([fd], [1], [rate[i]])
            fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            x[i], v[i] = fmu.getReal([xr, vxr])
        a = (v - v_old) / h
        wob.append(chain_forces(t + h, x, v)[1])
    cpu = time.process_time() - clock
    close(fmus)
    return cpu, np.arange(1, steps + 1) * h, np.array(wob), None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sections", type=int, default=20)
    ap.add_argument("--stop", type=float, default=1.0)
    ap.add_argument("--no-reference", action="store_true",
                    help="skip the monolithic integration (CPU times only)")
    ap.add_argument("--runs", default="string:1e-3,B-held:1e-3,B-held:1e-4,B-careful:3e-4,"
                    "A-held:1e-4,A-careful:3e-4")
    args = ap.parse_args()
    n, stop = args.sections, args.stop
    with tempfile.TemporaryDirectory() as tmp:
        string_fmu, a_fmu, b_fmu = scene_files(n, pathlib.Path(tmp))
        clock = time.process_time()
        if args.no_reference:  # a stand-in: the CPU times only, the errors meaningless
            t_ref = np.arange(1, int(round(stop / GRID)) + 1) * GRID
            wob_ref, means_ref = np.ones_like(t_ref), np.ones_like(t_ref)
        else:
            t_ref, wob_ref, means_ref = reference(n, stop)
        print(f"{n} sections, {stop} s, tool {TOOL / 1e3:.0f} kN at {FREQ:.0f} Hz, tol {TOL:g}; "
              + ("no reference" if args.no_reference else "monolithic reference (scipy Radau, "
                 f"rtol 1e-10): {time.process_time() - clock:.1f} s CPU"))
        half = t_ref > stop / 2 + 1e-9
        mean_ref = means_ref[half].mean()
        scale = np.abs(means_ref).max()
        if not args.no_reference:
            print(f"reference WOB: mean over the second half {mean_ref:.3f} N, "
                  f"at the end {wob_ref[-1]:.3f} N, largest 1 ms mean {scale:.1f} N")
        print(f"{'coupling':<10} {'step (s)':>9} {'CPU s/s':>8} {'WOB mean (N)':>13} "
              f"{'off':>9} {'WOB end (N)':>12} {'worst 1 ms mean off':>20}")
        runs = {
            "string": lambda h: run_string(string_fmu, n, stop, h),
            "B-held": lambda h: run_host_owned(b_fmu, n, stop, h, False),
            "B-careful": lambda h: run_host_owned(b_fmu, n, stop, h, True),
            "A-held": lambda h: run_fmu_owned(a_fmu, n, stop, h, False),
            "A-careful": lambda h: run_fmu_owned(a_fmu, n, stop, h, True),
        }
        for run in args.runs.split(","):
            name, h = run.split(":")
            h = float(h)
            try:
                cpu, t, wob, means = runs[name](h)
            except Exception as e:  # an unstable coupling fails in the FMU: report it
                print(f"{name:<10} {h:>9g} failed: {str(e)[:60]}")
                continue
            if args.no_reference:
                print(f"{name:<10} {h:>9g} {cpu / stop:>8.3f}")
                continue
            if means is not None and h == GRID:  # exact step means on the reference's pieces
                mean = means[half].mean()
                worst = f"{np.abs(means - means_ref).max() / scale:.1e} of the largest"
            else:
                sel = t >= stop / 2 - 1e-9
                mean = np.trapezoid(wob[sel], t[sel]) / (t[sel][-1] - t[sel][0])
                worst = ""
            if not np.isfinite(mean):
                print(f"{name:<10} {h:>9g} {cpu / stop:>8.3f} unstable")
                continue
            print(f"{name:<10} {h:>9g} {cpu / stop:>8.3f} {mean:>13.3f} "
                  f"{(mean - mean_ref) / abs(mean_ref):>9.2e} {wob[-1]:>12.3f} {worst:>20}")


if __name__ == "__main__":
    main()
