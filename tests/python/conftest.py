"""Shared fixtures of the fmpy tests: the exported FMUs in dist/ and the core's reference runs.

The reference is the core library called directly (`vibrofric simulate`), with the same
communication points as fmpy's co-simulation loop, so that its numbers can be compared with
the FMU's bit for bit.
"""

import contextlib
import csv
import io
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
DIST = ROOT / "dist"
SCENES = ROOT / "scenes"


def target_dir():
    return pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))


def vibrofric_exe():
    exe = target_dir() / "release" / "vibrofric"
    if not exe.exists():
        pytest.fail(f"{exe} is missing: run `cargo build --release` (tests/all.sh does)")
    return exe


def fmu_path(name):
    p = DIST / f"{name}.fmu"
    if not p.exists():
        pytest.fail(f"{p} is missing: run `cargo run --release` first (tests/all.sh does)")
    return str(p)


@pytest.fixture(scope="session")
def default_fmu():
    return fmu_path("VibratingContact")


class Opened:
    """An FMU (FMI 2.0 or 3.0) unpacked into a temporary folder with its model description read:
    `vr` maps names to value references, `outputs` lists the outputs' references, and
    `instance(name)` makes an instantiated fmpy instance (Co-Simulation, or Model Exchange with
    `model_exchange=True`). `close()` frees every instance still live and removes the folder."""

    def __init__(self, path):
        from fmpy import extract, read_model_description

        self.md = read_model_description(str(path))
        self.fmi3 = self.md.fmiVersion.startswith("3")
        self.dir = extract(str(path))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.outputs = [v.valueReference for v in self.md.modelVariables if v.causality == "output"]
        self.live = []

    def instance(self, name, visible=False, model_exchange=False):
        from fmpy.fmi2 import FMU2Model, FMU2Slave
        from fmpy.fmi3 import FMU3Model, FMU3Slave

        kind = [[FMU2Slave, FMU2Model], [FMU3Slave, FMU3Model]][self.fmi3][model_exchange]
        interface = self.md.modelExchange if model_exchange else self.md.coSimulation
        fmu = kind(
            guid=self.md.instantiationToken if self.fmi3 else self.md.guid,
            unzipDirectory=self.dir,
            modelIdentifier=interface.modelIdentifier,
            instanceName=name,
        )
        fmu.instantiate(visible=visible)
        self.live.append(fmu)
        return fmu

    def free(self, fmu):
        """Frees one instance now."""
        self.live.remove(fmu)
        fmu.freeInstance()

    def close(self):
        while self.live:
            self.free(self.live[-1])
        shutil.rmtree(self.dir, ignore_errors=True)


# A 10 m section of 5-inch drill pipe on the borehole wall (LuGre, F_S = 1.3·mu·F_N at its load),
# and the links and ends of scenes/drill-string.toml.
DRILL_PIPE = {"m": 267.0, "F_N": 2280.0, "mu": 0.3, "F_S": 889.2, "k_t": 1e8, "k_s": 7.1e7,
              "c_s": 2e3, "k_top": 1e6, "c_top": 1e4, "k_bottom": 1e7, "c_bottom": 1e4}


def drill_string_scene(identifier, description, sections, **start):
    """A string scene of `sections` drill-pipe sections (DRILL_PIPE, with `start` over it: a
    number, or a list of one per element) on LuGre wall contacts, force drive, the normal force
    and the wall's velocity as inputs."""
    values = "\n".join(f"{k} = {v!r}" for k, v in {**DRILL_PIPE, **start}.items())
    return f"""model_identifier = "{identifier}"
description = "{description}"
law = "lugre"
motion = "longitudinal"
drive = "force"
normal = "input"
support = ["input"]

[string]
sections = {sections}

[start]
{values}
"""


def export_scene(directory, text):
    """Exports the scene `text` (written to directory/scene.toml) for linux64; returns the
    paths of its FMI 2.0 and 3.0 FMUs by edition ("fmi2", "fmi3")."""
    (directory / "scene.toml").write_text(text)
    subprocess.run([str(vibrofric_exe()), "export", "scene.toml", "--out", ".", "--platforms",
                    "linux64"], cwd=directory, check=True, capture_output=True, text=True)
    identifier = text.split('"')[1]
    return {"fmi2": str(directory / f"{identifier}.fmu"),
            "fmi3": str(directory / "fmi3" / f"{identifier}.fmu")}


def real_p(array):
    """A numpy float64 array as a `double*` for the FMI functions that take vectors."""
    import ctypes

    return array.ctypes.data_as(ctypes.POINTER(ctypes.c_double))


class Exchange:
    """A Model Exchange instance of an FMU of either edition, initialized with relative
    `tolerance` at t = 0 and the values of `start` (names as FMI 2.0 spells them: `F_d[3]`
    is element 3 of the FMI 3.0 array `F_d`), after its first event update, in
    continuous-time mode. `close()` frees it and removes the unpacked folder."""

    def __init__(self, path, tolerance, start=None, name="me"):
        self.opened = Opened(path)
        self.md, self.fmi3, self.vr = self.opened.md, self.opened.fmi3, self.opened.vr
        self.fmu = f = self.opened.instance(name, model_exchange=True)
        self.states = [d.variable.derivative.name for d in self.md.derivatives]
        self.derivatives = [d.variable.name for d in self.md.derivatives]
        self.nx = self.md.numberOfContinuousStates
        self.nz = self.md.numberOfEventIndicators
        self.sizes = {v.name: self._size(v) for v in self.md.modelVariables}
        if self.fmi3:
            f.enterInitializationMode(tolerance=tolerance, startTime=0.0)
        else:
            f.setupExperiment(tolerance=tolerance, startTime=0.0)
            f.enterInitializationMode()
        for k, v in (start or {}).items():
            self.set(k, v)
        f.exitInitializationMode()
        self.update_discrete_states()
        f.enterContinuousTimeMode()

    def _size(self, v):
        """The number of elements of an FMI 3.0 variable (1 for a scalar)."""
        size = 1
        for d in getattr(v, "dimensions", None) or []:
            start = d.start if d.start is not None else d.variable.start
            size *= int(start)
        return size

    def ref(self, name):
        """The value reference of `name` and its element (0-based) in an FMI 3.0 array, or
        None: `der(v_x[2])` is element 1 of `der(v_x)`, `x[3]` element 2 of `x`."""
        if self.fmi3 and "[" in name:
            head, i = name.rstrip(")").rstrip("]").split("[")
            base = f"{head})" if name.startswith("der(") else head
            return self.vr[base], int(i) - 1
        return self.vr[name], None

    def set(self, name, value):
        vr, i = self.ref(name)
        if i is None:
            (self.fmu.setFloat64 if self.fmi3 else self.fmu.setReal)([vr], [value])
        else:
            values = self.get_array(vr)
            values[i] = value
            self.fmu.setFloat64([vr], values)

    def get(self, name):
        vr, i = self.ref(name)
        if self.fmi3:
            return self.get_array(vr)[i or 0]
        return self.fmu.getReal([vr])[0]

    def get_array(self, vr):
        """Every element of the FMI 3.0 variable of value reference `vr`."""
        name = next(v.name for v in self.md.modelVariables if v.valueReference == vr)
        return list(self.fmu.getFloat64([vr], nValues=self.sizes[name]))

    def get_states(self):
        x = np.zeros(self.nx)
        self.fmu.getContinuousStates(real_p(x), self.nx)
        return x

    def set_states(self, x):
        x = np.ascontiguousarray(x, dtype=np.float64)
        return self.fmu.setContinuousStates(real_p(x), len(x))

    def derivatives_at(self, x):
        self.set_states(x)
        dx = np.zeros(self.nx)
        get = self.fmu.getContinuousStateDerivatives if self.fmi3 else self.fmu.getDerivatives
        get(real_p(dx), self.nx)
        return dx

    def nominals(self):
        x = np.zeros(self.nx)
        self.fmu.getNominalsOfContinuousStates(real_p(x), self.nx)
        return x

    def event_indicators(self):
        z = np.zeros(self.nz)
        self.fmu.getEventIndicators(real_p(z), self.nz)
        return z

    def update_discrete_states(self):
        (self.fmu.updateDiscreteStates if self.fmi3 else self.fmu.newDiscreteStates)()

    def event_update(self):
        """From continuous-time mode through an event update back into it."""
        self.fmu.enterEventMode()
        self.update_discrete_states()
        self.fmu.enterContinuousTimeMode()

    def close(self):
        self.opened.close()


@contextlib.contextmanager
def opened(path):
    """`with opened(path) as fmu:` an `Opened` FMU, closed at the end of the block."""
    fmu = Opened(path)
    try:
        yield fmu
    finally:
        fmu.close()


@pytest.fixture
def open_fmu():
    """Opens FMUs for a test: `open_fmu(path)` returns an `Opened` FMU; every one is closed
    (instances freed, folder removed) when the test ends, passed or failed."""
    with contextlib.ExitStack() as stack:
        yield lambda path: stack.enter_context(opened(path))


def core(scene, step, stop, sets=None, tolerance=None):
    """Runs `scene` (a path) through the core; returns a dict of numpy arrays by column."""
    args = [str(vibrofric_exe()), "simulate", str(scene), "--step", repr(step), "--stop", repr(stop)]
    if tolerance is not None:
        args += ["--tolerance", repr(tolerance)]
    for k, v in (sets or {}).items():
        args += ["--set", f"{k}={v!r}"]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    rows = list(csv.reader(io.StringIO(out)))
    header, data = rows[0], np.array([[float(x) for x in r] for r in rows[1:]])
    return {name: data[:, k] for k, name in enumerate(header)}


EXPECTED = "(expected: provoked on purpose by this passing test) "


def label_expected(text):
    """Marks the FMU's error lines in a passing test's captured output as expected: fmpy prints
    every log message of an FMU as `[ERROR] ...`, and a negative test that passed got exactly
    the refusals it asked for (fmpy raises on any error status the test did not catch)."""
    return "\n".join(
        line.replace("[ERROR] ", "[ERROR] " + EXPECTED, 1).replace("[DISCARD] ", "[DISCARD] " + EXPECTED, 1)
        if line.startswith(("[ERROR] ", "[DISCARD] ")) else line
        for line in text.split("\n")
    )


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """The `-rA` report of the test command shows each test's captured output: there, the
    `[ERROR]` lines of negative tests that passed read as expected, not as failures."""
    outcome = yield
    report = outcome.get_result()
    if report.passed:
        report.sections = [
            (title, label_expected(content) if title.startswith("Captured") else content)
            for title, content in report.sections
        ]
