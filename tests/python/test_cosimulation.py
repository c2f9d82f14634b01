"""An fmpy master closes a spring drive around the force-drive FMU's F_d input:

    F_d = k_d·(v_d·t − x) + c_d·(v_d − v_x)   (held over each communication step)

and the result converges to the same spring drive computed inside the core (a spring-drive
scene of the same contact), with a coupling error of first order in the communication step."""

import math
import shutil

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from conftest import SCENES, core

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
    md = read_model_description(fmu_file)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzipdir = extract(fmu_file)
    fmu = FMU2Slave(
        guid=md.guid,
        unzipDirectory=unzipdir,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="spring-master",
    )
    try:
        fmu.instantiate()
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
        fmu.freeInstance()
    finally:
        shutil.rmtree(unzipdir, ignore_errors=True)
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
