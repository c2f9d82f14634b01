"""Right-hand-side evaluations of a stiff contact integrated through Model Exchange, with and
without the FMU's closed-form Jacobian (fmi2GetDirectionalDerivative).

An importer's implicit integrator needs the Jacobian of the derivatives; without directional
derivatives it builds it from finite differences, one extra derivative evaluation per state per
Jacobian. This script integrates the VibratingContact FMU (k_t = 1e11 N/m, 7 states) with
scipy's BDF and Radau through fmpy's FMU2Model, once with `jac` from the FMU's directional
derivatives and once without, and prints the work of each and the final deformation against a
Co-Simulation reference at tolerance 1e-10.

    .venv/bin/python examples/model_exchange/jacobian_counts.py [dist/VibratingContact.fmu]
"""

import ctypes
import shutil
import sys
import time

import numpy as np
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Model
from scipy.integrate import solve_ivp

PATH = sys.argv[1] if len(sys.argv) > 1 else "dist/VibratingContact.fmu"
K_T, STOP, RTOL = 1e11, 2e-3, 1e-7
P = ctypes.POINTER(ctypes.c_double)


def run(method, use_jacobian):
    md = read_model_description(PATH)
    unzip = extract(PATH)
    fmu = FMU2Model(guid=md.guid, unzipDirectory=unzip,
                    modelIdentifier=md.modelExchange.modelIdentifier, instanceName="jac")
    vr = {v.name: v.valueReference for v in md.modelVariables}
    ders = [vr[d.variable.name] for d in md.derivatives]
    states = [vr[d.variable.derivative.name] for d in md.derivatives]
    nx = len(ders)
    fmu.instantiate()
    fmu.setupExperiment(tolerance=RTOL, startTime=0.0)
    fmu.enterInitializationMode()
    fmu.setReal([vr["k_t"]], [K_T])
    fmu.setReal([vr["F_d"]], [5.0])
    fmu.exitInitializationMode()
    fmu.newDiscreteStates()
    fmu.enterContinuousTimeMode()
    x0, nominal = np.zeros(nx), np.zeros(nx)
    fmu.getContinuousStates(x0.ctypes.data_as(P), nx)
    fmu.getNominalsOfContinuousStates(nominal.ctypes.data_as(P), nx)
    count = {"rhs": 0, "directional": 0}

    def load(t, x):
        fmu.setTime(t)
        x = np.ascontiguousarray(x)
        fmu.setContinuousStates(x.ctypes.data_as(P), nx)

    def rhs(t, x):
        count["rhs"] += 1
        load(t, x)
        dx = np.zeros(nx)
        fmu.getDerivatives(dx.ctypes.data_as(P), nx)
        return dx

    def jac(t, x):
        load(t, x)
        j = np.zeros((nx, nx))
        for k in range(nx):
            count["directional"] += 1
            j[:, k] = fmu.getDirectionalDerivative(ders, [states[k]], [1.0])
        return j

    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, STOP), x0, method=method, rtol=RTOL, atol=RTOL * nominal,
                    jac=jac if use_jacobian else None)
    wall = time.perf_counter() - t0
    fmu.freeInstance()
    shutil.rmtree(unzip, ignore_errors=True)
    return sol, count, wall


def main():
    ref = simulate_fmu(PATH, stop_time=STOP, output_interval=STOP / 4, relative_tolerance=1e-10,
                       start_values={"k_t": K_T, "F_d": 5.0}, output=["s_x"])
    s_ref = ref["s_x"][-1]
    print(f"VibratingContact, k_t = {K_T:g} N/m, F_d = 5 N, 0 to {STOP} s, rtol {RTOL:g}")
    print("| integrator | Jacobian | derivative calls | directional-derivative calls | Jacobians | LU | steps | time | s_x error |")
    print("|---|---|---|---|---|---|---|---|---|")
    for method in ["BDF", "Radau"]:
        for use in [False, True]:
            sol, count, wall = run(method, use)
            err = abs(sol.y[0, -1] - s_ref) / abs(s_ref)
            print(f"| scipy {method} | {'closed form' if use else 'finite differences'} | {count['rhs']} | "
                  f"{count['directional']} | {sol.njev} | {sol.nlu} | {len(sol.t) - 1} | {wall:.2f} s | {err:.1e} |")


if __name__ == "__main__":
    main()
