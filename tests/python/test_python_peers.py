"""Smoke test of the Python peers of the work-precision report (examples/peers/python_peers.py):
its --quick mode on one non-stiff case, where scipy's Radau on the script's own Python equations
must agree with the FMU (through fmpy) at the same tolerance, and its closed-form Jacobians."""

import csv
import json
import math
import pathlib
import subprocess
import sys

import pytest

from conftest import ROOT, fmu_path

SCRIPT = ROOT / "examples" / "peers" / "python_peers.py"
sys.path.insert(0, str(SCRIPT.parent))
import python_peers  # noqa: E402

PARAMS = {"m": 5.6, "F_N": 55.0, "mu": 0.2, "k_t": 1e8, "kappa": 1.0, "r_ba": 0.5, "F_S": 14.3,
          "v_S": 1e-3, "zeta_t": 1.0, "h_v": 0.0, "v_e": 1e-3, "u0": 2e-7, "f": 2000.0, "angle": 0.0,
          "phase": 0.0, "k_d": 1e5, "c_d": 100.0, "T_avg": 1e-3}


def contact_case():
    """The default scene (Dahl, planar, force drive F_d = 8 N, harmonic and input support), in
    the schema of reports/cases.json, without a truth."""
    return {"name": "contact", "fmu": fmu_path("VibratingContact"),
            "config": {"law": "dahl", "motion": "planar", "drive": "force", "lateral": "free",
                       "harmonic": True, "input_support": True},
            "params": PARAMS, "fmu_start": {},
            "inputs": {"F_d": 8.0, "v_d": 1e-3, "v_sx": 0.0, "v_sy": 0.0},
            "t_end": 1.0, "period": 5e-4}


def test_quick_radau_agrees_with_fmu(tmp_path):
    cases = {"sample_dt": 1e-4, "tolerances": [1e-4, 1e-8], "cases": [contact_case()]}
    (tmp_path / "cases.json").write_text(json.dumps(cases))
    subprocess.run([sys.executable, str(SCRIPT), "--cases", str(tmp_path / "cases.json"),
                    "--out", str(tmp_path), "--quick", "--repeats", "1",
                    # The budget of the timed report (1 s of CPU time) could skip the tighter
                    # tolerance on a loaded machine; this test is about agreement, not time.
                    "--budget", "20"], check=True, cwd=ROOT)
    with (tmp_path / "peers_python.csv").open() as fh:
        reader = csv.DictReader(fh)
        assert reader.fieldnames == python_peers.COLUMNS
        rows = list(reader)
    # 3 scipy methods x 2 tolerances + the FMU x 2 communication steps x 2 tolerances
    assert len(rows) == 3 * 2 + 2 * 2
    assert all(r["status"] == "ok" for r in rows), [r for r in rows if r["status"] != "ok"]

    def f_mean(solver, comm_step=""):
        (r,) = [r for r in rows if r["solver"] == solver and float(r["tol"]) == 1e-8
                and r["comm_step"] == comm_step]
        return float(r["f_mean"])

    radau = f_mean("scipy-Radau")
    # The body creeps at a mean friction force near F_d = 8 N after 20 periods.
    assert 7.9 < radau < 8.1
    for step in ("0.001", "1e-05"):
        fmu = f_mean("fmu-fmpy", step)
        assert math.isclose(fmu, radau, rel_tol=1e-6), (step, fmu, radau)


@pytest.mark.parametrize("law", ["dahl", "lugre", "dupont"])
@pytest.mark.parametrize("motion,drive,lateral", [
    ("longitudinal", "velocity", "guided"), ("longitudinal", "force", "free"),
    ("planar", "velocity", "guided"), ("planar", "velocity", "free"), ("planar", "force", "free")])
def test_jacobian_matches_central_differences(law, motion, drive, lateral):
    config = {"law": law, "motion": motion, "drive": drive, "lateral": lateral,
              "harmonic": True, "input_support": True}
    params = dict(PARAMS, h_v=0.3, angle=0.7, phase=0.1)
    model = python_peers.Model(config, params, {"F_d": 8.0, "v_d": 1e-3, "v_sx": 1e-4, "v_sy": -2e-4})
    assert python_peers.check_jacobian(model) < 1e-6
