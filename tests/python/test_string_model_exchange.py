"""Model Exchange of a string of contacts through fmpy: a string of 5 sections of the drill
string (LuGre on the wall, top fed at 0.5 m/s onto the rock), exported from its scene here,
FMI 2.0 (scalars `x[i]`, `der(x[i])`) and FMI 3.0 (arrays `x`, `der(x)`).

- fmpy's validation of both model descriptions: no problem;
- fmpy's CVode integrating the 3N + 2 states agrees with the FMU's own Co-Simulation solver
  (band Radau IIA), both at relative tolerance 1e-8: the positions within 1e-6 of their scale,
  the velocities and forces within BOUND = 2000·RTOL of theirs (measured: x 1.7e-8, v_x 2.6e-6
  relative at the end);
- the FMI 3.0 edition's states and outputs equal the FMI 2.0 edition's, bit for bit;
- the directional derivatives (from the string's banded Jacobian) match central differences
  of the derivatives along every state and input, relative 1e-6;
- a state saved in Model Exchange continues bit for bit; a bad state or input is refused,
  naming its index."""

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu

from conftest import Exchange, drill_string_scene, export_scene, real_p

N = 5
RTOL = 1e-8
BOUND = 2000 * RTOL
STEP_MEANS = {"F_Fx_step", "F_top_step", "F_bottom_step"}  # Co-Simulation's; ME: the forces


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    scene = drill_string_scene("SmallString", "Five sections of the drill string (LuGre on the wall, top feed, bottom on the rock)", N)
    return export_scene(tmp_path_factory.mktemp("string_me"), scene)


def base(name):
    return name.split("[")[0]


def outputs(path):
    md = read_model_description(path)
    return [v.name for v in md.modelVariables if v.causality == "output"]


def run(path, kind):
    return simulate_fmu(path, fmi_type=kind, stop_time=0.05, output_interval=1e-3,
                        relative_tolerance=RTOL, start_values={"v_top": 0.5},
                        output=outputs(path))


@pytest.mark.parametrize("edition", ["fmi2", "fmi3"])
def test_both_model_descriptions_validate_and_declare_the_states(fmus, edition):
    path = fmus[edition]
    assert validate_fmu(path) == []
    md = read_model_description(path)
    assert md.modelExchange is not None
    if edition == "fmi2":  # fmpy reads FMI 3.0's providesDirectionalDerivatives as FMI 2.0's name
        assert md.modelExchange.providesDirectionalDerivative
    assert md.numberOfContinuousStates == 3 * N + 2
    assert md.numberOfEventIndicators == N
    states = [d.variable.derivative.name for d in md.derivatives]
    if edition == "fmi2":
        names = [f"{v}[{i}]" for v in ["x", "v_x", "s_x"] for i in range(1, N + 1)]
        assert states == names + ["x_top", "x_bottom"]
        assert md.derivatives[N].variable.name == "der(v_x[1])"
        # der(v_x[3]): its neighbours' positions and velocities, its own state and inputs.
        deps = {v.name for v in md.derivatives[N + 2].dependencies}
        assert deps == {"x[2]", "x[3]", "x[4]", "v_x[2]", "v_x[3]", "v_x[4]", "s_x[3]",
                        "F_d[3]", "v_sx[3]", "F_N[3]"}
    else:
        assert states == ["x", "v_x", "s_x", "x_top", "x_bottom"]


def test_model_exchange_agrees_with_co_simulation(fmus):
    path = fmus["fmi2"]
    me, cs = run(path, "ModelExchange"), run(path, "CoSimulation")
    rows = [np.nonzero(np.abs(me["time"] - t) <= 1e-12 * max(1.0, t))[0][-1] for t in cs["time"]]
    worst = {}
    for name in outputs(path):
        if base(name) in STEP_MEANS:
            continue
        a, b = me[name][rows], cs[name]
        worst[name] = float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))
    x = max(v for k, v in worst.items() if base(k) == "x")
    rest = max(worst.items(), key=lambda kv: kv[1] if base(kv[0]) != "x" else 0.0)
    print(f"Model Exchange vs Co-Simulation: x within {x:.2e}, the others within {rest[1]:.2e} ({rest[0]})")
    assert x <= 1e-6, worst
    assert rest[1] <= BOUND, worst
    # In Model Exchange the step means are the forces now.
    for k in range(1, N + 1):
        assert np.array_equal(me[f"F_Fx_step[{k}]"], me[f"F_Fx[{k}]"])


def test_fmi3_model_exchange_equals_fmi2(fmus):
    a, b = run(fmus["fmi2"], "ModelExchange"), run(fmus["fmi3"], "ModelExchange")
    assert np.array_equal(a["time"], b["time"])
    for name in ["x", "v_x", "s_x", "F_Fx", "F_link"]:
        size = N - 1 if name == "F_link" else N
        for k in range(size):
            assert np.array_equal(a[f"{name}[{k + 1}]"], b[name][:, k]), name
    for name in ["F_top", "F_bottom"]:
        assert np.array_equal(a[name], b[name])


class Model(Exchange):
    """A Model Exchange instance of either edition in continuous-time mode, the top fed at
    0.5 m/s, the wall moving and a push on every section, at states near the trajectory 2 ms
    in (explicit Euler from rest in steps of 1 us), so that every section moves and is
    deformed."""

    INPUTS = {"v_top": 0.5, "v_bottom": 1e-3}

    def __init__(self, path):
        start = dict(self.INPUTS)
        for k in range(1, N + 1):
            start.update({f"F_d[{k}]": 1e3 * k, f"v_sx[{k}]": 1e-3 * (k - 3),
                          f"F_N[{k}]": 2000.0 + 100.0 * k})
        super().__init__(path, RTOL, start)
        x = self.get_states()
        for k in range(2000):
            self.fmu.setTime(k * 1e-6)
            x = x + 1e-6 * self.derivatives_at(x)
        self.fmu.setTime(2e-3)
        self.set_states(x)


STATES = [f"{v}[{i}]" for v in ["x", "v_x", "s_x"] for i in range(1, N + 1)] + ["x_top", "x_bottom"]
INPUTS = [f"{v}[{i}]" for v in ["F_d", "v_sx", "F_N"] for i in range(1, N + 1)] + ["v_top", "v_bottom"]


def test_directional_derivatives_match_central_differences(fmus):
    """FMI 2.0, each state and input alone: the derivatives' column from
    fmi2GetDirectionalDerivative against central differences of fmi2GetDerivatives, relative
    1e-6 (with the differences' rounding); FMI 3.0's arrays give the same columns."""
    m, m3 = Model(fmus["fmi2"]), Model(fmus["fmi3"])
    try:
        f = m.fmu
        x = m.get_states()
        assert np.array_equal(x, m3.get_states())
        nominal = np.zeros(m.nx)
        f.getNominalsOfContinuousStates(real_p(nominal), m.nx)
        unknowns = [m.vr[f"der({s})"] for s in STATES]
        unknowns3 = [m3.vr[d] for d in ["der(x)", "der(v_x)", "der(s_x)", "der(x_top)", "der(x_bottom)"]]
        worst = 0.0
        for j, name in enumerate(STATES + INPUTS):
            exact = np.array(f.getDirectionalDerivative(unknowns, [m.vr[name]], [1.0]))
            # FMI 3.0: the whole array of the known, the seed on one element.
            vr3, i3 = m3.ref(name)
            seed = [0.0] * (N if i3 is not None else 1)
            seed[i3 or 0] = 1.0
            exact3 = m3.fmu.getDirectionalDerivative(unknowns3, [vr3], seed, m.nx)
            assert list(exact3) == list(exact), name
            if j < m.nx:
                h = 1e-6 * nominal[j]
                e = np.zeros(m.nx)
                e[j] = h
                fd = (m.derivatives_at(x + e) - m.derivatives_at(x - e)) / (2 * h)
                m.set_states(x)
            else:
                v = m.get(name)
                h = 1e-6 * max(abs(v), 1e-3)
                m.set(name, v + h)
                up = m.derivatives_at(x)
                m.set(name, v - h)
                down = m.derivatives_at(x)
                m.set(name, v)
                fd = (up - down) / (2 * h)
            # Relative 1e-6, and entries far below the column's largest (differences of
            # nearly equal derivatives) to 1e-10 of it.
            floor = 1e-10 * np.abs(fd).max()
            err = np.abs(exact - fd) / (np.abs(exact) + np.abs(fd) + floor + 1e-300)
            assert np.all(err <= 1e-6), (name, err.max(), exact, fd)
            worst = max(worst, float(err.max()))
        print(f"directional derivatives vs central differences: worst {worst:.1e} relative")
    finally:
        m.close()
        m3.close()


@pytest.mark.parametrize("edition", ["fmi2", "fmi3"])
def test_saved_state_continues_bit_for_bit_in_a_fresh_instance(fmus, edition):
    a, b = Model(fmus[edition]), Model(fmus[edition])
    try:
        x = a.get_states() * (1 + 1e-6)
        a.fmu.setTime(2.5e-3)
        a.set_states(x)
        if edition == "fmi2":
            saved = a.fmu.serializeFMUstate(a.fmu.getFMUstate())
            b.fmu.setFMUstate(b.fmu.deSerializeFMUstate(saved))
        else:
            saved = a.fmu.serializeFMUState(a.fmu.getFMUState())
            b.fmu.setFMUState(b.fmu.deserializeFMUState(saved))
        assert np.array_equal(b.get_states(), x)
        assert np.array_equal(a.derivatives_at(x), b.derivatives_at(x))
        for name in ["F_bottom", "F_top", "F_Fx[3]", "F_link[2]", "der(v_x[2])", "event.v_rx[4]"]:
            assert a.get(name) == b.get(name), name
    finally:
        a.close()
        b.close()


def test_a_bad_state_or_input_is_refused_naming_its_index(fmus, capfd):
    from fmpy.fmi1 import FMICallException

    m = Model(fmus["fmi2"])
    try:
        x = m.get_states()
        bad = x.copy()
        bad[N + 2] = np.nan
        with pytest.raises(FMICallException):
            m.set_states(bad)
        assert "v_x[3] = NaN" in capfd.readouterr().out
        m.fmu.reset()
        m.fmu.setupExperiment(tolerance=RTOL, startTime=0.0)
        m.fmu.enterInitializationMode()
        with pytest.raises(FMICallException):
            m.set("v_sx[4]", np.inf)
        assert "v_sx[4] = inf" in capfd.readouterr().out
    finally:
        m.close()
