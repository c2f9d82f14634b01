"""Model Exchange of the FMI 2.0 FMUs through fmpy: its CVode integrates the contact's states
and must agree with the FMU's own Co-Simulation solver on every scene, on a stiff contact and on
a stuck drill string; the closed-form directional derivatives must match differences of the
derivatives; bad input is refused as in Co-Simulation.

The agreement bound: both runs solve the same equations with relative tolerance RTOL, CVode
(variable order BDF) and the FMU's Radau IIA or closed form; the global error of each is a
modest multiple of the tolerance times the solution's scale, so the two agree within
BOUND = 2000 * RTOL of each output's scale (its largest magnitude in the run, or the scale of
its kind where the output stays near 0)."""


import numpy as np
import pytest
from conftest import DIST, Exchange, fmu_path, real_p
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi2 import fmi2EventInfo

RTOL = 1e-8
BOUND = 2000 * RTOL


def _offers_model_exchange(p):
    # The single contacts; a string of contacts (DrillString) has its own Model Exchange tests
    # (test_string_model_exchange.py), its variables being arrays.
    from fmpy import read_model_description

    md = read_model_description(str(p))
    return md.modelExchange is not None and not any(v.name == "x_top" for v in md.modelVariables)


SCENES = sorted(p.stem for p in DIST.glob("*.fmu") if _offers_model_exchange(p))
STEP_MEANS = {"F_Fx_step", "F_Fy_step"}  # over communication steps: Co-Simulation only


def outputs(path):
    md = read_model_description(path)
    return [v.name for v in md.modelVariables if v.causality == "output"]


def run(path, kind, stop, interval, **kw):
    names = outputs(path)
    return names, simulate_fmu(
        path,
        fmi_type=kind,
        stop_time=stop,
        output_interval=interval,
        relative_tolerance=RTOL,
        output=names,
        **kw,
    )


def at_times(me, times):
    """The Model Exchange rows at the Co-Simulation times (the last row at an event)."""
    return [np.nonzero(np.abs(me["time"] - t) <= 1e-12 * max(1.0, t))[0][-1] for t in times]


def worst_disagreement(path, stop, interval, floors=None, **kw):
    names, me = run(path, "ModelExchange", stop, interval, **kw)
    _, cs = run(path, "CoSimulation", stop, interval, **kw)
    rows = at_times(me, cs["time"])
    worst = []
    for n in names:
        if n in STEP_MEANS:
            continue
        a, b = me[n][rows], cs[n]
        scale = max(np.max(np.abs(b)), (floors or {}).get(n, 0.0), 1e-300)
        worst.append((float(np.max(np.abs(a - b)) / scale), n))
    return max(worst), me, cs


@pytest.mark.parametrize("name", SCENES)
def test_model_exchange_agrees_with_co_simulation(name):
    path = fmu_path(name)
    # The lateral position y of a transverse scene is the drift of a vibration, far smaller
    # than its swing: its scale is the support's amplitude u0 (0.2 um).
    (err, which), me, _ = worst_disagreement(path, 0.02, 1e-3, floors={"y": 2e-7})
    print(f"{name}: Model Exchange vs Co-Simulation within {err:.2e} ({which}); {len(me)} rows")
    assert err <= BOUND, (name, which, err)


def test_stiff_contact_k_t_1e11_agrees():
    path = fmu_path("VibratingContact")
    (err, which), me, _ = worst_disagreement(
        path, 0.01, 1e-3, start_values={"k_t": 1e11}, floors={"y": 2e-7}
    )
    print(f"k_t = 1e11: within {err:.2e} ({which})")
    assert err <= BOUND, (which, err)


def test_stuck_drill_string_held_released_held():
    path = fmu_path("DrillStringAxial")
    # A 10 m section of drill pipe (267 kg, F_C = 684 N, F_S = 889.2 N): held at 300 N,
    # released with 1200 N for 0.5 s, held again at 300 N.
    signal = np.array(
        [(0.0, 300.0), (0.5, 300.0), (0.5, 1200.0), (1.0, 1200.0), (1.0, 300.0), (3.0, 300.0)],
        dtype=[("time", np.float64), ("F_d", np.float64)],
    )
    names = outputs(path)
    kw = dict(stop_time=3.0, output_interval=0.01, relative_tolerance=RTOL, output=names, input=signal)
    calls = []
    me = simulate_fmu(path, fmi_type="ModelExchange", fmi_call_logger=calls.append, **kw)
    cs = simulate_fmu(path, fmi_type="CoSimulation", **kw)
    rows = at_times(me, cs["time"])
    t = cs["time"]
    # Away from the switching instants (where fmpy's Co-Simulation loop takes the input at the
    # step's start), the two agree.
    away = (np.abs(t - 0.5) > 0.02) & (np.abs(t - 1.0) > 0.02)
    for n in ["v_x", "x", "F_Fx", "s_x"]:
        a, b = me[n][rows][away], cs[n][away]
        scale = np.max(np.abs(cs[n]))
        err = np.max(np.abs(a - b)) / scale
        print(f"{n}: within {err:.2e} of {scale:.3g}")
        assert err <= BOUND, (n, err)
    # Held: at rest, the contact holds the drive (F_Fx = F_d).
    held = (t > 0.3) & (t < 0.49)
    assert np.max(np.abs(me["v_x"][rows][held])) < 1e-6
    assert np.max(np.abs(me["F_Fx"][rows][held] - 300.0)) < 1e-4 * 60
    # Released: it slides; held again: it stops and sticks to the end.
    assert me["v_x"][rows][np.argmin(np.abs(t - 1.0))] > 0.1
    assert np.max(np.abs(me["v_x"][rows][t > 2.5])) < 1e-6
    # No chattering at the stuck contact: the event updates are the time events at the ends of
    # the averaging windows (T_avg = 1 ms) and a handful of state events (the body stopping).
    event_times, now = [], 0.0
    for c in calls:
        if c.startswith("fmi2SetTime("):
            now = float(c.split("time=")[1].split(")")[0])
        elif c.startswith("fmi2NewDiscreteStates("):
            event_times.append(now)
    windows = [x for x in event_times if abs(x / 1e-3 - round(x / 1e-3)) < 1e-6]
    others = len(event_times) - len(windows)
    print(f"{len(event_times)} event updates: {len(windows)} at window ends, {others} others")
    assert len(windows) >= 3000 and others <= 20, (len(windows), others)


def Model(name, start=None, version=2):
    """A Model Exchange instance of an FMU (FMI 2.0, or the FMI 3.0 edition with version=3), in
    continuous-time mode at t = 0."""
    path = fmu_path(name) if version == 2 else str(DIST / "fmi3" / f"{name}.fmu")
    return Exchange(path, RTOL, start, name=name)


def Model3(name):
    """The FMI 3.0 edition's Model Exchange instance."""
    return Model(name, version=3)


@pytest.mark.parametrize("name", ["VibratingContact", "VibratingContactDupont", "VibratingContactLuGre", "RigLongitudinal", "DrillStringContact"])
def test_directional_derivatives_match_differences_of_the_derivatives(name):
    m = Model(name)
    try:
        f = m.fmu
        f.setTime(1.7e-4)
        inputs = [v.name for v in m.md.modelVariables if v.causality == "input"]
        # A normal force input at 40/55 of the scene's load (DrillStringContact's 2280 N: the
        # states below are scaled by the nominals, which follow that load; at a load far below
        # it the differences lose digits to rounding).
        f_n0 = next((float(v.start) for v in m.md.modelVariables if v.name == "F_N"), 55.0)
        for k in inputs:
            f.setReal([m.vr[k]], [{"F_N": 40.0 / 55.0 * f_n0, "F_d": 3.0, "v_d": 1.2e-3}.get(k, 2e-4)])
        nominal = np.zeros(m.nx)
        f.getNominalsOfContinuousStates(real_p(nominal), m.nx)
        x = nominal * np.array([0.4, -0.3, 0.7, 0.2, -0.5, 0.6, 0.1][: m.nx])
        m.set_states(x)
        unknowns = [m.vr[d] for d in m.derivatives]
        for j, s in enumerate(m.states):
            exact = np.array(f.getDirectionalDerivative(unknowns, [m.vr[s]], [1.0]))
            h = 1e-6 * nominal[j]
            e = np.zeros(m.nx)
            e[j] = h
            fd = (m.derivatives_at(x + e) - m.derivatives_at(x - e)) / (2 * h)
            m.set_states(x)
            scale = np.abs(exact) + np.abs(fd) + 1e-12 * np.max(np.abs(fd))
            assert np.all(np.abs(exact - fd) <= 1e-5 * scale + 1e-30), (s, exact, fd)
        for k in inputs:
            exact = np.array(f.getDirectionalDerivative(unknowns, [m.vr[k]], [1.0]))
            v = f.getReal([m.vr[k]])[0]
            h = 1e-6 * max(abs(v), 1e-3)
            f.setReal([m.vr[k]], [v + h])
            up = m.derivatives_at(x)
            f.setReal([m.vr[k]], [v - h])
            down = m.derivatives_at(x)
            f.setReal([m.vr[k]], [v])
            fd = (up - down) / (2 * h)
            scale = np.abs(exact) + np.abs(fd) + 1e-12 * np.max(np.abs(fd))
            assert np.all(np.abs(exact - fd) <= 1e-5 * scale + 1e-30), (k, exact, fd)
    finally:
        m.close()


def test_bad_input_is_refused_naming_the_rule_and_changes_nothing(capfd):
    m = Model("VibratingContact")
    try:
        f = m.fmu
        x = m.get_states()
        capfd.readouterr()
        # A state that is not finite: refused, nothing changes.
        bad = x.copy()
        bad[1] = np.nan
        with pytest.raises(Exception, match="status 3"):
            m.set_states(bad)
        out = capfd.readouterr().out
        assert "contact.s_y = NaN" in out and "must be finite" in out, out
        assert np.array_equal(m.get_states(), x)
    finally:
        m.close()
    m = Model("VibratingContact")
    try:
        f = m.fmu
        capfd.readouterr()
        # The wrong number of states.
        with pytest.raises(Exception, match="status 3"):
            z = np.zeros(m.nx + 1)
            f.setContinuousStates(real_p(z), m.nx + 1)
        out = capfd.readouterr().out
        assert f"nx = {m.nx + 1}" in out and f"has {m.nx} continuous states" in out, out
    finally:
        m.close()
    m = Model("VibratingContact")
    try:
        f = m.fmu
        capfd.readouterr()
        # A parameter in continuous-time mode; a fixed one is refused in every mode.
        with pytest.raises(Exception, match="status 3"):
            f.setReal([m.vr["mu"]], [0.3])
        out = capfd.readouterr().out
        assert "ContinuousTimeMode only inputs" in out, out
    finally:
        m.close()
    m = Model("VibratingContact")
    try:
        f = m.fmu
        capfd.readouterr()
        # An input out of its range.
        with pytest.raises(Exception, match="status 3"):
            f.setReal([m.vr["v_sx"]], [np.inf])
        out = capfd.readouterr().out
        assert "v_sx = inf" in out, out
    finally:
        m.close()
    m = Model("VibratingContact")
    try:
        f = m.fmu
        capfd.readouterr()
        # A call out of sequence: the event update belongs to event mode.
        with pytest.raises(Exception, match="status 3"):
            f.newDiscreteStates()
        out = capfd.readouterr().out
        assert "not allowed in state ContinuousTimeMode" in out, out
    finally:
        m.close()


def test_saved_state_continues_bit_for_bit_in_a_fresh_instance():
    a, b = Model("VibratingContactLuGre"), Model("VibratingContactLuGre")
    try:
        x = a.get_states() + 1e-9
        a.fmu.setTime(3e-4)
        a.set_states(x)
        saved = a.fmu.serializeFMUstate(a.fmu.getFMUstate())
        b.fmu.setFMUstate(b.fmu.deSerializeFMUstate(saved))
        assert np.array_equal(b.get_states(), x)
        dx_a, dx_b = a.derivatives_at(x), b.derivatives_at(x)
        assert np.array_equal(dx_a, dx_b)
        names = outputs(fmu_path("VibratingContactLuGre"))
        vrs = [a.vr[n] for n in names]
        assert a.fmu.getReal(vrs) == b.fmu.getReal(vrs)
    finally:
        a.close()
        b.close()


# ---- FMI 3.0 Model Exchange ----------------------------------------------------------------


@pytest.mark.parametrize("name", SCENES)
def test_fmi3_model_exchange_equals_fmi2_model_exchange(name):
    """The FMI 3.0 edition computes with the same instance: through fmpy's CVode, the same
    numbers bit for bit at every output point and event."""
    path2, path3 = fmu_path(name), str(DIST / "fmi3" / f"{name}.fmu")
    _, a = run(path2, "ModelExchange", 0.02, 1e-3)
    names, b = run(path3, "ModelExchange", 0.02, 1e-3)
    assert len(a) == len(b), (len(a), len(b))
    for n in ["time", *names]:
        assert np.array_equal(a[n], b[n]), n


def test_fmi3_counts_states_and_event_indicators_and_refuses_bad_input(capfd):
    m = Model3("VibratingContactDupont")
    try:
        import ctypes

        f = m.fmu
        n = ctypes.c_size_t()
        f.fmi3GetNumberOfContinuousStates(f.component, ctypes.byref(n))
        assert n.value == m.nx == 7
        f.fmi3GetNumberOfEventIndicators(f.component, ctypes.byref(n))
        assert n.value == len(m.md.eventIndicators) == 2
        x = m.get_states()
        capfd.readouterr()
        bad = x.copy()
        bad[0] = np.inf
        with pytest.raises(Exception):
            m.set_states(bad)
        out = capfd.readouterr().out
        assert "contact.s_x = inf" in out and "must be finite" in out, out
        assert np.array_equal(m.get_states(), x)
    finally:
        m.close()
    m = Model3("VibratingContactDupont")
    try:
        capfd.readouterr()
        with pytest.raises(Exception):
            m.set_states(np.zeros(m.nx - 1))
        out = capfd.readouterr().out
        assert f"has {m.nx} continuous states" in out, out
    finally:
        m.close()
    m = Model3("VibratingContactDupont")
    try:
        capfd.readouterr()
        import ctypes

        # fmpy's FMU3Model binds no fmi3DoStep: call it from the library.
        do_step = m.fmu.dll.fmi3DoStep
        do_step.restype = ctypes.c_int
        flags = [ctypes.c_bool() for _ in range(3)]
        last = ctypes.c_double()
        status = do_step(
            m.fmu.component, ctypes.c_double(0.0), ctypes.c_double(1e-3), ctypes.c_bool(False),
            *[ctypes.byref(b) for b in flags], ctypes.byref(last))
        assert status == 3  # fmi3Error
        out = capfd.readouterr().out
        assert "a function of Co-Simulation only, and this instance was instantiated for Model Exchange" in out, out
    finally:
        m.close()


def test_fmi3_directional_derivatives_equal_fmi2():
    a, b = Model("VibratingContactLuGre"), Model3("VibratingContactLuGre")
    try:
        x = a.get_states() + np.array([1e-8, -2e-8, 1e-7, 0, 1e-3, -2e-3, 1e-6])[: a.nx]
        for m in (a, b):
            m.fmu.setTime(2.5e-4)
            m.set_states(x)
        unknowns = [a.vr[d] for d in a.derivatives] + [a.vr[n] for n in ("F_Fx", "P_diss", "F_mean")]
        for known in a.states + ["v_sx"]:
            d2 = a.fmu.getDirectionalDerivative(unknowns, [a.vr[known]], [1.0])
            d3 = b.fmu.getDirectionalDerivative(unknowns, [b.vr[known]], [1.0])
            assert list(d2) == list(d3), known
            # Nothing depends on the body's position under a force drive.
            assert any(v != 0.0 for v in d2) == (known not in ("body.x", "body.y")), known
    finally:
        a.close()
        b.close()


# ---- bad input, replayed on Model Exchange of both editions ---------------------------------


def _bad_input_cases(p):
    """(what, call, words of the log line) for the prefix `p` (fmi2 or fmi3); each call gets
    the instance `m` and returns the status."""
    import ctypes

    c_double_p = ctypes.POINTER(ctypes.c_double)

    def fn(m, name):
        f = getattr(m.fmu.dll, name)
        f.restype = ctypes.c_int
        return f

    def vrs(*v):
        return (ctypes.c_uint * len(v))(*v)

    def doubles(*v):
        return (ctypes.c_double * len(v))(*v)

    set_real = "fmi2SetReal" if p == "fmi2" else "fmi3SetFloat64"
    get_real = "fmi2GetReal" if p == "fmi2" else "fmi3GetFloat64"

    def set_values(m, names, values):
        v = [m.vr[n] for n in names]
        if p == "fmi2":
            return fn(m, set_real)(m.fmu.component, vrs(*v), len(v), doubles(*values))
        return fn(m, set_real)(m.fmu.component, vrs(*v), len(v), doubles(*values), len(v))

    def get_value(m, vr):
        out = doubles(0.0)
        if p == "fmi2":
            return fn(m, get_real)(m.fmu.component, vrs(vr), 1, out)
        return fn(m, get_real)(m.fmu.component, vrs(vr), 1, out, 1)

    def ddx(m, unknowns, knowns, seed, out):
        f = fn(m, f"{p}GetDirectionalDerivative")
        if p == "fmi2":
            return f(m.fmu.component, unknowns, 1, knowns, 1, seed, out)
        return f(m.fmu.component, unknowns, 1, knowns, 1, seed, 1, out, 1)

    derivatives = f"{p}GetDerivatives" if p == "fmi2" else "fmi3GetContinuousStateDerivatives"
    update = "fmi2NewDiscreteStates" if p == "fmi2" else "fmi3UpdateDiscreteStates"
    return [
        ("NULL states with nx > 0",
         lambda m: fn(m, f"{p}SetContinuousStates")(m.fmu.component, None, m.nx),
         ["SetContinuousStates", "NULL"]),
        ("NULL derivatives with nx > 0",
         lambda m: fn(m, derivatives)(m.fmu.component, None, m.nx),
         ["derivatives", "NULL"]),
        ("NULL event indicators",
         lambda m: fn(m, f"{p}GetEventIndicators")(m.fmu.component, None, 1),
         ["eventIndicators", "NULL"]),
        ("NULL seed",
         lambda m: ddx(m, vrs(m.vr["F_Fx"]), vrs(m.vr["contact.s_x"]), None, doubles(0.0)),
         ["GetDirectionalDerivative", "NULL"]),
        ("unknown value reference",
         lambda m: get_value(m, 999),
         ["unknown value reference 999"]),
        ("a state set as a variable",
         lambda m: set_values(m, ["contact.s_x"], [1e-9]),
         ["contact.s_x", "causality local", "SetContinuousStates"]),
        ("a known that is no state or input",
         lambda m: ddx(m, vrs(m.vr["F_Fx"]), vrs(m.vr["mu"]), doubles(1.0), doubles(0.0)),
         ["mu", "not a known"]),
        ("an unknown that is no derivative or output",
         lambda m: ddx(m, vrs(m.vr["k_t"]), vrs(m.vr["contact.s_x"]), doubles(1.0), doubles(0.0)),
         ["k_t", "not an unknown"]),
        ("NaN input",
         lambda m: set_values(m, ["v_sx"], [float("nan")]),
         ["v_sx = NaN"]),
        ("a parameter in continuous-time mode",
         lambda m: set_values(m, ["mu"], [0.3]),
         ["mu", "ContinuousTimeMode only inputs"]),
        ("NaN time",
         lambda m: fn(m, f"{p}SetTime")(m.fmu.component, ctypes.c_double(float("nan"))),
         ["time = NaN", "finite"]),
        ("the event update in continuous-time mode",
         lambda m: fn(m, update)(m.fmu.component, *[ctypes.byref(ctypes.c_bool()) for _ in range(5)],
                                 ctypes.byref(ctypes.c_double())) if p == "fmi3"
         else fn(m, update)(m.fmu.component, ctypes.byref(fmi2EventInfo())),
         ["not allowed in state ContinuousTimeMode"]),
        ("too many states",
         lambda m: fn(m, f"{p}SetContinuousStates")(
             m.fmu.component, (ctypes.c_double * (m.nx + 1))(), m.nx + 1),
         [f"continuous states"]),
    ]


@pytest.mark.parametrize("version", [2, 3])
def test_every_bad_input_class_is_refused_on_model_exchange_and_changes_nothing(version, capfd):
    prefix = f"fmi{version}"
    for what, bad, words in _bad_input_cases(prefix):
        m = Model("VibratingContact") if version == 2 else Model3("VibratingContact")
        try:
            f = m.fmu
            f.setTime(1e-4)
            x0 = m.get_states() + 1e-9
            m.set_states(x0)
            names = [v.name for v in m.md.modelVariables if v.causality == "output"]
            vr = [m.vr[n] for n in names]
            before = list(f.getReal(vr) if version == 2 else f.getFloat64(vr))
            capfd.readouterr()
            status = bad(m)
            out = capfd.readouterr().out
            assert status == 3, (what, status, out)
            for w in words:
                assert w in out, (what, w, out)
            # Nothing changed: a saved state of the refused instance is the one before.
            restored = Model("VibratingContact") if version == 2 else Model3("VibratingContact")
            try:
                restored.fmu.setTime(1e-4)
                restored.set_states(x0)
                after = list(restored.fmu.getReal(vr) if version == 2 else restored.fmu.getFloat64(vr))
            finally:
                restored.close()
            assert after == before, what
            assert np.array_equal(m.get_states(), x0), what
        finally:
            m.close()


@pytest.mark.parametrize("version", [2, 3])
def test_a_corrupted_serialized_state_is_refused_on_model_exchange(version, capfd):
    m = Model("VibratingContact") if version == 2 else Model3("VibratingContact")
    try:
        f = m.fmu
        get, ser = (f.getFMUstate, f.serializeFMUstate) if version == 2 else (f.getFMUState, f.serializeFMUState)
        data = bytearray(ser(get()))
        data[len(data) // 2] ^= 0x10
        capfd.readouterr()
        with pytest.raises(Exception):
            (f.deSerializeFMUstate if version == 2 else f.deserializeFMUState)(bytes(data))
        out = capfd.readouterr().out
        assert "serialized state" in out or "checksum" in out, out
    finally:
        m.close()
