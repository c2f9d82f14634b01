"""An fmpy master closes a spring drive around the force-drive FMU's F_d input:

    F_d = k_d·(v_d·t − x) + c_d·(v_d − v_x)   (held over each communication step)

and the result converges to the same spring drive computed inside the core (a spring-drive
scene of the same contact), with a coupling error of first order in the communication step."""

import math

import numpy as np

import pytest

from conftest import SCENES, core, fmu_path, opened

K_D, C_D, V_D = 1e5, 100.0, 1e-3  # the spring drive's defaults (`docs/model.md`)
TOL = 1e-9
# Communication steps of 4.8, 2.4, ... 0.3 periods of the 2 kHz excitation: the master samples
# x and v_x, which vibrate, at phases that do not repeat; steps that are whole multiples of the
# period would sample the vibration in phase and bias the held force differently per step.
STEPS = [2.4e-3, 1.2e-3, 6e-4, 3e-4, 1.5e-4]
STOP = 40 * STEPS[0]


def spring_scene(tmp_path):
    """The default contact (planar Dahl, harmonic and input support) with a spring drive."""
    text = (SCENES / "contact.toml").read_text()
    text = text.replace('model_identifier = "VibratingContact"', 'model_identifier = "SpringContact"')
    text = text.replace('drive = "force"', 'drive = "spring"')
    # In a spring drive F_d is the spring force, an output: no start value.
    text = "\n".join(l for l in text.splitlines() if not l.startswith("F_d ="))
    assert 'drive = "spring"' in text
    p = tmp_path / "spring.toml"
    p.write_text(text)
    return p


def cosimulate(fmu_file, h):
    """Returns x at the communication points t = k·h."""
    with opened(fmu_file) as o:
        vr = o.vr
        fmu = o.instance("spring-master")
        fmu.setupExperiment(tolerance=TOL, startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        n = round(STOP / h)
        xs = [0.0]
        for k in range(n):
            t = k * h
            x, v_x = fmu.getReal([vr["x"], vr["v_x"]])
            f_d = K_D * (V_D * t - x) + C_D * (V_D - v_x)
            fmu.setReal([vr["F_d"]], [f_d])
            fmu.doStep(currentCommunicationPoint=t, communicationStepSize=(k + 1) * h - t)
            xs.append(fmu.getReal([vr["x"]])[0])
        fmu.terminate()
    return np.array(xs)


def test_spring_drive_closed_by_fmpy_converges_to_the_core_with_first_order(default_fmu, tmp_path):
    coarse = STEPS[0]
    ref = core(
        spring_scene(tmp_path),
        min(STEPS),
        STOP,
        sets={"k_d": K_D, "c_d": C_D, "v_d": V_D},
        tolerance=TOL,
    )
    stride = round(coarse / min(STEPS))
    x_ref = ref["x"][::stride]
    scale = np.max(np.abs(x_ref))
    assert scale > 1e-7, "the body must move"
    errors = []
    for h in STEPS:
        x = cosimulate(default_fmu, h)[:: round(coarse / h)]
        assert len(x) == len(x_ref)
        errors.append(np.max(np.abs(x - x_ref)))
    orders = [math.log2(errors[k] / errors[k + 1]) for k in range(len(errors) - 1)]
    fitted = np.polyfit(np.log(STEPS), np.log(errors), 1)[0]
    print("communication step, max |x - x_core| [m], observed order")
    for k, h in enumerate(STEPS):
        print(f"{h:9.2e}  {errors[k]:.3e}  {orders[k - 1] if k else float('nan'):.2f}")
    print(f"fitted order {fitted:.3f}")
    assert all(e1 < e0 for e0, e1 in zip(errors, errors[1:])), errors
    assert fitted >= 0.8, fitted
    assert min(orders) >= 0.8, orders
    assert errors[-1] < 0.02 * scale, (errors[-1], scale)


# ---- A host that integrates the body itself ---------------------------------------------------
#
# The host (an fmpy loop here, a drill-string or machine-tool model in practice) owns the body:
# m·dv/dt = k_d·(v_d·t − x) + c_d·(v_d − v) − F, stepped explicitly over each communication step
# with the body velocity handed to the contact FMU as its imposed velocity v_d (held). F is either
# the sampled F_Fx at the end of the step ("sampled") or the step mean F_Fx_step, the contact's
# impulse over the step divided by its length. The reference is the same spring-driven body inside
# the core (RigLongitudinal: the same contact, the same defaults). The body is a heavy section
# (500 kg): an explicit host is stable only while it resolves the body bouncing on the contact
# stiffness, sqrt(k_t/m), and at 500 kg that allows steps over several vibration periods.

HOST_MASS = 500.0


def host_body(fmu_file, h, coupling, mass=HOST_MASS):
    """x of the host's body at t = k·h, the contact in `fmu_file` (a velocity drive)."""
    with opened(fmu_file) as o:
        vr = o.vr
        fmu = o.instance("host-body")
        force = vr["F_Fx_step" if coupling == "step mean" else "F_Fx"]
        fmu.setupExperiment(tolerance=TOL, startTime=0.0)
        fmu.setReal([vr["v_d"]], [0.0])
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        x, v = 0.0, 0.0
        xs = [x]
        for k in range(round(STOP / h)):
            t = k * h
            fmu.setReal([vr["v_d"]], [v])
            fmu.doStep(currentCommunicationPoint=t, communicationStepSize=(k + 1) * h - t)
            f = fmu.getReal([force])[0]
            spring = K_D * (V_D * t - x) + C_D * (V_D - v)
            x, v = x + h * v, v + h * (spring - f) / mass
            xs.append(x)
        fmu.terminate()
    return np.array(xs)


def test_host_body_closed_through_the_step_mean_converges_with_first_order():
    ref = core(
        SCENES / "rig-longitudinal.toml", min(STEPS), STOP, sets={"m": HOST_MASS}, tolerance=TOL
    )
    x_ref = ref["x"][:: round(STEPS[0] / min(STEPS))]
    scale = np.max(np.abs(x_ref))
    assert scale > 1e-6, "the body must move"
    fmu = fmu_path("PaperLongitudinal")
    table = {}
    for coupling in ("step mean", "sampled"):
        errors = []
        for h in STEPS:
            x = host_body(fmu, h, coupling)[:: round(STEPS[0] / h)]
            assert len(x) == len(x_ref)
            errors.append(float(np.max(np.abs(x - x_ref))))
        table[coupling] = errors
    print("communication step, max |x - x_core| [m]: step mean, sampled F_Fx")
    for k, h in enumerate(STEPS):
        print(f"{h:9.2e}  {table['step mean'][k]:.3e}  {table['sampled'][k]:.3e}")
    fitted = {c: np.polyfit(np.log(STEPS), np.log(e), 1)[0] for c, e in table.items()}
    print("fitted order: " + ", ".join(f"{c} {o:.3f}" for c, o in fitted.items()))
    errors = table["step mean"]
    orders = [math.log2(errors[k] / errors[k + 1]) for k in range(len(errors) - 1)]
    assert min(orders) >= 0.9, orders
    assert errors[-1] < 0.01 * scale, (errors[-1], scale)
    # The sampled force aliases the 2 kHz vibration: worse at every step.
    assert all(m < s for m, s in zip(errors, table["sampled"])), table


def test_output_derivatives_match_finite_differences_through_fmpy(default_fmu, open_fmu):
    """x' = v_x exactly; v_x' and the step mean's derivative against differences over small
    steps taken from a saved state; F_Fx has none and says so."""
    o = open_fmu(default_fmu)
    vr = o.vr
    fmu = o.instance("derivatives")
    fmu.setupExperiment(tolerance=1e-12, startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    t = 0.0
    for k in range(10):
        fmu.doStep(currentCommunicationPoint=t, communicationStepSize=1e-3 + 3.7e-5)
        t += 1e-3 + 3.7e-5
    names = ["x", "v_x", "y", "v_y"]
    refs = [vr[n] for n in names]
    d = fmu.getRealOutputDerivatives(refs, [1] * len(refs))
    now = fmu.getReal(refs)
    assert d[0] == now[1] and d[2] == now[3]
    state = fmu.getFMUstate()
    delta = 2e-7

    def ahead(dt):
        fmu.setFMUstate(state)
        fmu.doStep(currentCommunicationPoint=t, communicationStepSize=dt)
        return np.array(fmu.getReal(refs))

    fd = 2 * (ahead(delta / 2) - now) / (delta / 2) - (ahead(delta) - now) / delta
    f_c = 0.2 * 55.0
    for k, n in enumerate(names):
        natural = f_c / 5.6 if n.startswith("v_") else 1e-3
        assert abs(d[k] - fd[k]) <= 1e-5 * max(abs(d[k]), abs(fd[k]), natural), (n, d[k], fd[k])
    fmu.freeFMUstate(state)
    # An output without an exact derivative is an error (the instance then needs a reset).
    with pytest.raises(Exception, match="status 3"):
        fmu.getRealOutputDerivatives([vr["F_Fx"]], [1])


def test_a_start_time_of_1e9_s_keeps_full_accuracy(default_fmu, open_fmu):
    """Stepped from t = 1e9 s and from 0 on a grid both represent exactly (2^-10 s): the same
    outputs, bit for bit (the FMU counts time from its start)."""
    names = ["F_Fx", "F_mean", "x", "v_x", "F_Fx_step"]
    h = 2.0**-10
    runs = []
    for t0 in (0.0, 1e9):
        o = open_fmu(default_fmu)
        vr = o.vr
        fmu = o.instance("late-start")
        fmu.setupExperiment(startTime=t0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        rows = []
        for k in range(40):
            fmu.doStep(currentCommunicationPoint=t0 + k * h, communicationStepSize=h)
            rows.append(fmu.getReal([vr[n] for n in names]))
        fmu.terminate()
        runs.append(np.array(rows))
    diff = np.argwhere(runs[0] != runs[1])
    assert len(diff) == 0, (diff[:5], runs[0][tuple(diff[0])], runs[1][tuple(diff[0])])
    assert np.all(np.isfinite(runs[1]))
