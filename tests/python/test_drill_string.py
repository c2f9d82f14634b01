"""The drill-string example (examples/drill_string/host.py): a host model feeds the side force
F_N (with lift-off) and the axial vibration v_sx of the string, with input derivatives, to the
DrillStringContact FMU through fmpy."""

import importlib.util
import math

from conftest import ROOT, fmu_path

spec = importlib.util.spec_from_file_location("host", ROOT / "examples" / "drill_string" / "host.py")
host = importlib.util.module_from_spec(spec)
spec.loader.exec_module(host)

# The section DrillStringContact declares: 10 m of 5-inch drill pipe lying on the wall with its
# buoyed weight, pushed below its Coulomb force (the scene's start values).
SECTION = {"m": 267.0, "F_N": 2280.0, "mu": 0.3, "F_S": 889.2, "F_d": 300.0}


def test_drill_string_host_lifts_off_lands_and_keeps_the_momentum_balance():
    step = 2e-4
    path = fmu_path("DrillStringContact")
    # The host sizes itself from the section the FMU declares.
    assert host.section_load(path) == SECTION
    m, f_d, f_c = SECTION["m"], SECTION["F_d"], SECTION["mu"] * SECTION["F_N"]
    rows = host.run(stop=0.2, step=step, fmu_path=path)
    assert all(math.isfinite(v) for r in rows for v in r)
    off = [r for r in rows if r[1] == 0.0 and r[2] == 0.0]
    on = [r for r in rows if r[1] > 0.0]
    assert len(off) > 100 and len(on) > 100, (len(off), len(on))
    # On the wall the side force is of the section's weight (its mean over time, the weight
    # less the string's lateral pull, 2200 N).
    mean = sum(r[1] for r in rows) / len(rows)
    assert 0.8 * SECTION["F_N"] < mean < 1.1 * SECTION["F_N"], mean
    # Off the wall for a whole step: no friction at all.
    assert all(r[7] == 0.0 for r in off)
    # On it, the section is held or dragged: friction of the order of its Coulomb force.
    assert max(abs(r[7]) for r in on) > 0.5 * f_c
    # Every step: m*(v_x - v_x_start) = (F_d - F_Fx_step)*h, F_d held; within 1e-7 of the
    # Coulomb force's impulse over a step.
    worst = max(abs(m * (r[6] - r[5]) - (f_d - r[7]) * step) for r in rows)
    print(f"momentum balance within {worst:.3e} N*s over {len(rows)} steps "
          f"({worst / (f_c * step):.1e} of F_C*h)")
    assert worst <= 1e-7 * f_c * step, worst


def test_negative_normal_force_is_refused(capfd, open_fmu):
    import pytest

    o = open_fmu(fmu_path("DrillStringContact"))
    f_n = next(v for v in o.md.modelVariables if v.name == "F_N")
    assert (f_n.causality, f_n.variability, f_n.valueReference) == ("input", "continuous", 2)
    fmu = o.instance("negative-load")
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    fmu.doStep(0.0, 1e-3)
    capfd.readouterr()
    with pytest.raises(Exception, match="status 3"):
        fmu.setReal([2], [-1.0])
    out = capfd.readouterr().out
    assert "F_N = -1" in out and ">= 0" in out, out
