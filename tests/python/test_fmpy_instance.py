"""The FMU through fmpy's FMU2Slave: a bad call raises with the FMU's message (naming the
variable and the rule) printed by fmpy's logger, the values stay as they were, and a serialized
state restored into a fresh instance continues bit for bit."""

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException


@pytest.fixture
def slave(default_fmu, open_fmu):
    o = open_fmu(default_fmu)
    return o.instance, o.vr, o.outputs


def run(fmu, vr, outputs, t, steps, h=1e-3):
    rows = []
    for k in range(steps):
        fmu.setReal([vr["F_d"]], [3.0 + np.sin(t * 1e3)])
        fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        t += h
        rows.append(fmu.getReal(outputs))
    return np.array(rows), t


def test_bad_call_raises_with_the_fmu_message_and_changes_nothing(slave, capfd):
    make, vr, outputs = slave
    fmu = make("bad")
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    _, t = run(fmu, vr, outputs, 0.0, 3)
    state = fmu.getFMUstate()
    before = fmu.getReal(outputs + [vr["k_t"]])
    capfd.readouterr()
    with pytest.raises(FMICallException):
        fmu.setReal([vr["k_t"]], [2e8])
    out = capfd.readouterr().out
    assert "[ERROR]" in out and "k_t" in out and "variability fixed" in out, out
    assert fmu.getReal(outputs + [vr["k_t"]]) == before
    # The instance is in the standard's error state until a state is restored.
    with pytest.raises(FMICallException):
        fmu.doStep(currentCommunicationPoint=t, communicationStepSize=1e-3)
    assert "not allowed in state Error" in capfd.readouterr().out
    fmu.setFMUstate(state)
    with pytest.raises(FMICallException):
        fmu.setReal([vr["F_d"]], [float("nan")])
    assert "F_d = NaN: must be finite" in capfd.readouterr().out
    fmu.setFMUstate(state)
    fmu.freeFMUstate(state)
    rows, _ = run(fmu, vr, outputs, t, 3)
    assert np.all(np.isfinite(rows))


def test_serialized_state_continues_bit_for_bit_in_a_fresh_instance(slave):
    make, vr, outputs = slave
    a = make("a")
    a.setupExperiment(startTime=0.0)
    a.enterInitializationMode()
    a.exitInitializationMode()
    _, t = run(a, vr, outputs, 0.0, 4)
    state = a.getFMUstate()
    blob = a.serializeFMUstate(state)
    a.freeFMUstate(state)
    straight, _ = run(a, vr, outputs, t, 6)

    b = make("b")
    s = b.deSerializeFMUstate(blob)
    b.setFMUstate(s)
    b.freeFMUstate(s)
    again, _ = run(b, vr, outputs, t, 6)
    np.testing.assert_array_equal(again, straight)
