"""LuGre's static force follows the load, through fmpy: the drill-string section (given at
2280 N) at a load of 1000 N, pushed with 100 N (no vibration), sticks, and pushed above its
static force there, slides; and a static
force below the Coulomb force at the scene's load is refused at the end of initialization with
a message that names both forces, in both editions."""

import pytest
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException

from conftest import DIST, fmu_path


def test_a_lighter_load_holds_the_section_below_its_own_static_force():
    # Given at 2280 N (F_S = 889.2 N = 1.3*F_C at mu = 0.3); at 1000 N F_C = 300 N and F_S
    # follows the load to 889.2*1000/2280 = 390 N: a 100 N push is held; the section moves
    # only by its elastic deformation 100 N/k_t = 1 um and micro-slip (0.36 um), then stays.
    r = simulate_fmu(fmu_path("DrillStringAxial"), stop_time=0.2, output_interval=1e-3,
                     start_values={"F_N": 1000.0, "F_d": 100.0}, output=["x", "v_x", "F_Fx"])
    assert 1e-6 < r["x"][-1] < 2e-6, r["x"][-1]
    assert abs(r["x"][-1] - r["x"][100]) < 1e-10
    assert abs(r["F_Fx"][-1] - 100.0) < 1e-6
    # Above that static force it slides (at 2280 N it would still be held: 400 N < 684 N).
    r = simulate_fmu(fmu_path("DrillStringAxial"), stop_time=0.2, output_interval=1e-3,
                     start_values={"F_N": 1000.0, "F_d": 400.0}, output=["v_x"])
    assert r["v_x"][-1] > 1e-3


@pytest.mark.parametrize("edition", ["2.0", "3.0"])
def test_a_static_force_below_the_coulomb_force_is_refused(capfd, open_fmu, edition):
    fmu_path("VibratingContactLuGre")
    path = DIST / "VibratingContactLuGre.fmu" if edition == "2.0" else DIST / "fmi3" / "VibratingContactLuGre.fmu"
    o = open_fmu(path)
    vr = o.vr
    fmu = o.instance("fs")
    if edition == "2.0":
        fmu.setupExperiment(startTime=0.0)
        fmu.setReal([vr["F_S"]], [5.0])
        fmu.enterInitializationMode()
    else:
        fmu.setFloat64([vr["F_S"]], [5.0])
        fmu.enterInitializationMode(startTime=0.0)
    capfd.readouterr()
    with pytest.raises(FMICallException):
        fmu.exitInitializationMode()
    out = capfd.readouterr().out
    assert "F_S = 5 N is below the Coulomb force F_C = mu·F_N = 11 N" in out, out
    assert "ExitInitializationMode" in out, out
