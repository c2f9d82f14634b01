"""One sweep point = one run of an exported FMU through fmpy; plus the Coulomb limits (`docs/model.md`).

Only fmpy, numpy and scipy are needed here (the pinned test packages of tests/python), so that
the CI tests (tests/python/test_paper_claims.py) share this kernel without installing the figure
packages (matplotlib, dask) of examples/figures/requirements.txt.

Each worker process extracts an FMU once and keeps one FMU2Slave instance per FMU; a point resets
that instance, sets its start values, and integrates `periods` vibration periods in one
communication step (the FMU resolves every period itself). F_mean at the end is the exact mean of
F_Fx over the last completed period.
"""

import atexit
import math
import os
import pathlib
import shutil

import numpy as np
from scipy.special import ellipk

ROOT = pathlib.Path(__file__).resolve().parents[2]
DIST = ROOT / "dist"

F_C_DEFAULT = 0.2 * 55.0  # mu·F_N at the defaults of docs/model.md


def coulomb_longitudinal(psi):
    """Rigid-contact F_mean/F_C, support vibrating along the sliding direction."""
    psi = np.asarray(psi, dtype=float)
    return np.where(psi < 1.0, 2.0 / np.pi * np.arcsin(np.minimum(psi, 1.0)), 1.0)


def coulomb_transverse(psi):
    """Rigid-contact F_mean/F_C, support vibrating across, body guided laterally (q = 1/psi)."""
    psi = np.asarray(psi, dtype=float)
    with np.errstate(divide="ignore"):
        q = 1.0 / psi
    m = q * q / (1.0 + q * q)
    return np.where(psi > 0, 2.0 / np.pi * ellipk(m) / np.sqrt(1.0 + q * q), 0.0)


def fmu_file(name, dist=None):
    p = pathlib.Path(dist or os.environ.get("VIBROFRIC_DIST", DIST)) / f"{name}.fmu"
    if not p.exists():
        raise FileNotFoundError(f"{p} is missing: run `cargo run --release` first")
    return str(p)


class Runner:
    """One instantiated FMU, reused across points (fmi2Reset between them)."""

    def __init__(self, path, tolerance=1e-6):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.md = read_model_description(path)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.unzipdir = extract(path)
        self.fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self.unzipdir,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName="sweep",
        )
        self.fmu.instantiate()
        self.tolerance = tolerance
        self.fresh = True
        atexit.register(self.close)

    def close(self):
        if self.fmu is not None:
            try:
                self.fmu.terminate()
                self.fmu.freeInstance()
            except Exception:
                pass
            self.fmu = None
            shutil.rmtree(self.unzipdir, ignore_errors=True)

    def start(self, values, tolerance=None):
        if not self.fresh:
            self.fmu.reset()
        self.fresh = False
        self.fmu.setupExperiment(tolerance=tolerance or self.tolerance, startTime=0.0)
        if values:
            names = list(values)
            self.fmu.setReal([self.vr[n] for n in names], [float(values[n]) for n in names])
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()

    def get(self, *names):
        return self.fmu.getReal([self.vr[n] for n in names])

    def set(self, **values):
        self.fmu.setReal([self.vr[n] for n in values], [float(v) for v in values.values()])

    def step(self, t, h):
        status = self.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        return status


_RUNNERS = {}


def runner(name, dist=None):
    key = (name, dist)
    if key not in _RUNNERS:
        _RUNNERS[key] = Runner(fmu_file(name, dist))
    return _RUNNERS[key]


def f_mean(name, periods=20, tolerance=None, dist=None, output="F_mean", **start):
    """F_mean (N) after `periods` vibration periods of the FMU `name` with the given start values
    (u0, f, v_d, k_t, ...; `f` must be given). One communication step spans all periods.
    `output` reads another output instead (e.g. "reduction" = 1 - F_mean/F_C)."""
    r = runner(name, dist)
    r.start(start, tolerance)
    status = r.step(0.0, periods / float(start["f"]))
    if status not in (0, None):
        raise RuntimeError(f"{name}: fmi2DoStep returned {status} with {start}")
    return r.get(output)[0]


def point(args):
    """A picklable sweep task: (fmu name, dict of start values, periods[, dist dir]) -> F_mean."""
    name, start, periods, *dist = args
    return f_mean(name, periods=periods, dist=dist[0] if dist else None, **start)


def dist_dir():
    """The directory of the FMUs as seen here ($VIBROFRIC_DIST, else dist/ of this checkout)."""
    return str(pathlib.Path(os.environ.get("VIBROFRIC_DIST", DIST)).resolve())


def psi_of(u0, f, v_d):
    return v_d / (2.0 * math.pi * f * u0)
