"""fmpy's `simulate_fmu` runs the default FMU with communication steps from 1 µs to 1 s, and
its results equal the core called directly, bit for bit."""

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

from conftest import SCENES, core

START = {"F_d": 2.0, "mu": 0.25, "k_t": 1.2e8, "v_sx": 1e-4}

# (communication step, stop time): at least two vibration periods (1 ms) and at most ~2000 steps.
CASES = [
    (1e-6, 2e-3),
    (1e-5, 1e-2),
    (1e-4, 0.1),
    (1e-3, 0.1),
    (1e-2, 0.1),
    (1e-1, 0.3),
    (1.0, 1.0),  # one step across 2000 periods of the 2 kHz excitation
]


@pytest.mark.parametrize("step,stop", CASES)
def test_simulate_fmu_equals_the_core(default_fmu, step, stop):
    md = read_model_description(default_fmu)
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    res = simulate_fmu(
        default_fmu,
        stop_time=stop,
        output_interval=step,
        start_values=START,
        output=outputs,
    )
    ref = core(SCENES / "contact.toml", step, stop, sets=START, tolerance=float(md.defaultExperiment.tolerance))
    assert len(res) == len(ref["time"]) == round(stop / step) + 1
    np.testing.assert_array_equal(res["time"], ref["time"])
    for name in outputs:
        np.testing.assert_array_equal(res[name], ref[name], err_msg=name)
    # The run did something: the body moved and friction acted.
    assert np.all(np.isfinite(res["x"]))
    assert np.max(np.abs(res["F_Fx"])) > 0.0


def test_a_step_that_is_not_a_multiple_of_the_stop_time(default_fmu):
    res = simulate_fmu(default_fmu, stop_time=0.0105, output_interval=1e-3, output=["x"])
    assert res["time"][-1] == pytest.approx(0.0105, abs=1e-15)
    ref = core(SCENES / "contact.toml", 1e-3, 0.0105, tolerance=1e-6)
    np.testing.assert_array_equal(res["x"], ref["x"])


def standard_scenes():
    import tomllib

    # A string of contacts (`[string]`) has its own tests (test_string.py).
    scenes = ((p, tomllib.loads(p.read_text())) for p in SCENES.glob("*.toml"))
    return sorted((p, t["model_identifier"]) for p, t in scenes if "string" not in t)


@pytest.mark.parametrize("scene,identifier", standard_scenes(), ids=lambda v: getattr(v, "name", v))
def test_every_standard_scene_simulates_through_fmpy_like_the_core(scene, identifier):
    """Each scene's FMU, with its own start values, through fmpy, equals the core bit for bit."""
    from conftest import fmu_path

    fmu = fmu_path(identifier)
    md = read_model_description(fmu)
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    step, stop = 1e-3, 0.02
    res = simulate_fmu(fmu, stop_time=stop, output_interval=step, output=outputs)
    ref = core(scene, step, stop, tolerance=float(md.defaultExperiment.tolerance))
    assert len(res) == round(stop / step) + 1
    for name in outputs:
        assert np.all(np.isfinite(res[name])), name
        np.testing.assert_array_equal(res[name], ref[name], err_msg=f"{identifier}: {name}")
