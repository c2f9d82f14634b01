"""fmpy's `simulate_fmu` runs the default FMU with communication steps from 1 µs to 1 s, and
its results equal the core called directly, bit for bit."""

import pathlib

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


# A string of contacts: `vibrofric simulate` runs the string its FMU runs, a column per element.
DAHL_STRING = """model_identifier = "DahlString"
description = "Three sections on Dahl contacts, the wall vibrating and moving, held at both ends"
law = "dahl"
motion = "longitudinal"
drive = "force"
support = ["harmonic", "input"]

[string]
sections = 3

[start]
m = [5.6, 2.0, 9.0]
mu = [0.2, 0.3, 0.25]
k_s = [1e5, 3e5]
c_s = 20.0
k_top = 1e4
c_bottom = 50.0
"""


def string_cases(tmp_path_factory):
    from conftest import export_scene, fmu_path

    dahl = export_scene(tmp_path_factory.mktemp("dahl_string"), DAHL_STRING)["fmi2"]
    return [
        # The drill string (100 sections): the top fed, a push on section 3, the wall moving
        # under section 7, section 5's load lowered.
        (SCENES / "drill-string.toml", fmu_path("DrillString"),
         {"v_top": 0.5, "F_d[3]": 1000.0, "v_sx[7]": 0.01, "F_N[5]": 1500.0}),
        (pathlib.Path(dahl).parent / "scene.toml", dahl,
         {"F_d": 3.0, "F_d[2]": -4.0, "v_sx[1]": 2e-4, "v_top": 1e-3, "k_t": 2e8}),
    ]


def test_a_string_scene_simulates_through_fmpy_like_the_core(tmp_path_factory):
    """A string FMU through fmpy's Co-Simulation, with start values on whole arrays, single
    elements and shared parameters, equals `vibrofric simulate` of its scene bit for bit:
    every element of every output at every communication point."""
    for scene, fmu, start in string_cases(tmp_path_factory):
        md = read_model_description(fmu)
        outputs = [v.name for v in md.modelVariables if v.causality == "output"]
        # fmpy sets an array's every element by its FMI 2.0 names.
        sets = {}
        for k, v in start.items():
            elements = [n.name for n in md.modelVariables if n.name.startswith(k + "[")]
            sets.update({e: v for e in elements} if elements and "[" not in k else {k: v})
        step, stop = 1e-3, 0.02
        res = simulate_fmu(fmu, stop_time=stop, output_interval=step, start_values=sets,
                           output=outputs)
        ref = core(scene, step, stop, sets=start, tolerance=float(md.defaultExperiment.tolerance))
        assert list(ref) == ["time", *outputs]
        assert len(res) == len(ref["time"]) == round(stop / step) + 1
        np.testing.assert_array_equal(res["time"], ref["time"])
        for name in outputs:
            np.testing.assert_array_equal(res[name], ref[name], err_msg=f"{fmu}: {name}")
        moved = max(abs(res[n][-1]) for n in outputs if n.startswith("x["))
        print(f"{pathlib.Path(fmu).name}: {len(outputs)} outputs x {len(res)} points equal; "
              f"largest |x| {moved:.3e} m")
        assert moved > 0.0
