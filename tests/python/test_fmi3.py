"""The FMI 3.0 edition of every FMU (dist/fmi3/) against the FMI 2.0 one: fmpy validates it, its
Co-Simulation results equal FMI 2.0's bit for bit, and through fmpy's FMU3Slave the bad-input
classes of FMI 2.0 (out-of-range values, fixed parameters after initialization, calls in the
wrong state, unknown value references, foreign saved states, interfaces it does not offer) are
refused naming the variable and the rule, changing nothing; saved states continue bit for bit."""

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu

from conftest import DIST

FMI3 = DIST / "fmi3"


def pairs():
    fmus = sorted(DIST.glob("*.fmu"))
    assert fmus, "no FMU in dist/: run `cargo run --release`"
    for fmu in fmus:
        fmu3 = FMI3 / fmu.name
        assert fmu3.exists(), f"{fmu3} missing: the exporter writes both editions"
        yield fmu, fmu3


def test_every_fmi3_fmu_validates_and_describes_the_same_variables():
    for fmu2, fmu3 in pairs():
        assert validate_fmu(str(fmu3)) == [], fmu3.name
        md2 = read_model_description(str(fmu2))
        md3 = read_model_description(str(fmu3), validate=True)
        assert md3.fmiVersion == "3.0"
        assert md3.instantiationToken == md2.guid
        assert md3.coSimulation.modelIdentifier == md2.coSimulation.modelIdentifier
        v2 = {(v.name, v.valueReference, v.causality, v.variability) for v in md2.modelVariables}
        # A string's arrays (`x` of N) are FMI 2.0's scalars `x[1]` ... `x[N]` at vr + i.
        v3, starts3 = set(), {}
        for v in md3.modelVariables:
            if v.causality == "independent":
                continue
            if v.dimensions:
                n = int(v.dimensions[0].start)
                # der(x) of N: FMI 2.0's der(x[1]) ... der(x[N]).
                base = v.name[4:-1] if v.name.startswith("der(") else None
                names = [(f"der({base}[{i}])" if base else f"{v.name}[{i}]", v.valueReference + i)
                         for i in range(1, n + 1)]
                starts = v.start.split() if v.start is not None else [None] * n
            else:
                names, starts = [(v.name, v.valueReference)], [v.start]
            for (name, vr), start in zip(names, starts):
                v3.add((name, vr, v.causality, v.variability))
                starts3[name] = start
        assert v3 == v2, fmu3.name
        starts2 = {v.name: v.start for v in md2.modelVariables}
        for name, start in starts3.items():
            if start is not None:
                assert float(start) == float(starts2[name]), (fmu3.name, name)


def test_co_simulation_results_equal_fmi2_bit_for_bit():
    for fmu2, fmu3 in pairs():
        md = read_model_description(str(fmu2))
        if any(v.name == "x_top" for v in md.modelVariables):
            # A string of contacts: its arrays are compared in test_string.py.
            continue
        inputs = {v.name for v in md.modelVariables if v.causality == "input"}
        starts = {}
        if "F_d" in inputs:
            starts["F_d"] = 2.5
        if "v_sx" in inputs:
            starts["v_sx"] = 1e-4
        kw = dict(stop_time=0.02, output_interval=1e-3, start_values=starts, relative_tolerance=1e-7)
        r2 = simulate_fmu(str(fmu2), **kw)
        r3 = simulate_fmu(str(fmu3), **kw)
        assert r2.dtype.names == r3.dtype.names
        for name in r2.dtype.names:
            assert np.array_equal(r2[name], r3[name]), (fmu3.name, name)
        assert np.all(np.isfinite(r3["F_Fx"]))


@pytest.fixture
def slave3(open_fmu):
    o = open_fmu(FMI3 / "VibratingContact.fmu")
    return o.instance, o.vr, o.outputs, o.dir


def start(fmu):
    fmu.enterInitializationMode(startTime=0.0)
    fmu.exitInitializationMode()


def run(fmu, vr, outputs, t, steps, h=1e-3):
    rows = []
    for _ in range(steps):
        fmu.setFloat64([vr["F_d"]], [3.0 + np.sin(t * 1e3)])
        fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        t += h
        rows.append(fmu.getFloat64(outputs))
    return np.array(rows), t


def test_bad_input_is_refused_naming_the_rule_and_changes_nothing(slave3, capfd):
    make, vr, outputs, _ = slave3
    fmu = make("bad")
    # Out of range before initialization.
    capfd.readouterr()
    with pytest.raises(FMICallException):
        fmu.setFloat64([vr["k_t"]], [-1.0])
    assert "k_t" in capfd.readouterr().out
    fmu.reset()
    start(fmu)
    _, t = run(fmu, vr, outputs, 0.0, 3)
    before = fmu.getFloat64(outputs + [vr["k_t"]])
    state = fmu.getFMUState()
    # A fixed parameter after initialization, an unknown value reference, a wrong time.
    for bad in (
        lambda: fmu.setFloat64([vr["k_t"]], [2e8]),
        lambda: fmu.setFloat64([999], [1.0]),
        lambda: fmu.doStep(currentCommunicationPoint=t + 1.0, communicationStepSize=1e-3),
    ):
        capfd.readouterr()
        with pytest.raises(FMICallException):
            bad()
        assert "fmi3" in capfd.readouterr().out
        fmu.setFMUState(state)
        assert fmu.getFloat64(outputs + [vr["k_t"]]) == before
    # A non-finite input is refused, naming the variable.
    capfd.readouterr()
    with pytest.raises(FMICallException):
        fmu.setFloat64([vr["F_d"]], [float("nan")])
    assert "F_d" in capfd.readouterr().out
    fmu.setFMUState(state)
    assert fmu.getFloat64(outputs + [vr["k_t"]]) == before
    fmu.freeFMUState(state)


def test_serialized_state_continues_bit_for_bit_in_a_fresh_instance(slave3):
    make, vr, outputs, _ = slave3
    a = make("a")
    start(a)
    _, t = run(a, vr, outputs, 0.0, 5)
    blob = a.serializeFMUState(a.getFMUState())
    rows_a, _ = run(a, vr, outputs, t, 5)
    b = make("b")
    start(b)
    b.setFMUState(b.deserializeFMUState(blob))
    rows_b, _ = run(b, vr, outputs, t, 5)
    assert np.array_equal(rows_a, rows_b)
    # The FMI 2.0 edition's states are the same bytes: the instance is one.
    with pytest.raises(FMICallException):
        b.deserializeFMUState(blob[:-1])


def test_time_is_the_independent_variable(slave3, capfd):
    make, vr, outputs, _ = slave3
    fmu = make("time")
    start(fmu)
    _, t = run(fmu, vr, outputs, 0.0, 3)
    assert fmu.getFloat64([0, vr["x"]])[0] == t
    capfd.readouterr()
    with pytest.raises(FMICallException):
        fmu.setFloat64([0], [1.0])
    assert "independent variable" in capfd.readouterr().out


def test_output_derivatives_match_the_fmi2_edition(slave3):
    make, vr, outputs, _ = slave3
    fmu = make("der")
    start(fmu)
    run(fmu, vr, outputs, 0.0, 4)
    x, v = vr["x"], vr["v_x"]
    d = fmu.getOutputDerivatives([x], [1])
    assert d[0] == fmu.getFloat64([v])[0]


def test_interfaces_not_offered_say_so(slave3, capfd):
    make, vr, outputs, unzipdir = slave3
    fmu = make("only-cs")
    capfd.readouterr()
    with pytest.raises(FMICallException):
        fmu.getFloat32([vr["k_t"]], 1)
    assert "Float32" in capfd.readouterr().out
    fmu.reset()
    start(fmu)
    with pytest.raises(FMICallException):
        fmu.enterEventMode()
    out = capfd.readouterr().out
    assert "a function of Model Exchange only, and this instance was instantiated for Co-Simulation" in out, out
