"""A drill-string section against the borehole wall, driven by a small host model through fmpy.

The host owns what the friction contact does not: the section's lateral motion in the borehole
and the string's axial vibration.

- Lateral: an unbalanced section (mass m_l on the string's lateral stiffness k_l, damping c_l)
  whirls under its unbalance force m_e*e*Omega^2*cos(Omega*t). Where its displacement y exceeds
  the clearance, the wall pushes back: the side force F_N = k_w*(y - clearance), 0 off the wall.
- Axial: the string vibrates axially at the contact, v_sx = a*w*cos(w*t) (bit bounce), taken
  as the motion of the surface the section rubs on (x along F_d, ground frame; a vibration of the
  section itself would enter as -du/dt: only v_r = v - v_sx matters, docs/using.md).

The contact FMU (DrillStringContact: LuGre, longitudinal, force drive) gets F_N and v_sx with
their input derivatives at every communication point, is pushed along the hole by F_d, and returns
the section's axial motion and the friction. The FMU owns the section's mass m (the host must not
integrate it again); for its own balance the host uses the step mean F_Fx_step, the friction's
impulse over the step divided by the step, not a sample of a force that vibrates between samples.
docs/using.md ("Coupling a drill string") shows the other pattern, where the host owns the mass.

    python examples/drill_string/host.py [--stop 0.5] [--step 2e-4] [--csv out.csv]

Needs fmpy and dist/DrillStringContact.fmu (`cargo run --release` writes it).
"""

import argparse
import math
import pathlib
import shutil
import sys

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU = ROOT / "dist" / "DrillStringContact.fmu"

# Host model (SI units).
M_L, K_L, C_L = 40.0, 4.0e5, 200.0  # lateral mass, string stiffness, damping
M_E_E = 0.005  # unbalance m_e*e [kg*m]
OMEGA = 2 * math.pi * 20.0  # rotation: 1200 rpm
CLEARANCE = 2e-4  # radial clearance to the wall [m]
K_W = 1e6  # wall stiffness [N/m]
AXIAL_A, AXIAL_W = 20e-6, 2 * math.pi * 150.0  # axial vibration amplitude [m], frequency
F_D = 5.0  # axial push on the section [N]


def lateral_rhs(t, y, v):
    f_wall = -K_W * max(0.0, y - CLEARANCE)
    return v, (M_E_E * OMEGA**2 * math.cos(OMEGA * t) - K_L * y - C_L * v + f_wall) / M_L


def side_force(y, v):
    """F_N and its time derivative from the lateral state."""
    if y > CLEARANCE:
        return K_W * (y - CLEARANCE), K_W * v
    return 0.0, 0.0


def run(stop=0.5, step=2e-4, fmu_path=FMU):
    md = read_model_description(str(fmu_path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzipdir = extract(str(fmu_path))
    fmu = FMU2Slave(
        guid=md.guid,
        unzipDirectory=unzipdir,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="drill-string-host",
    )
    rows = []
    try:
        fmu.instantiate()
        fmu.setupExperiment(tolerance=1e-8, startTime=0.0)
        fmu.enterInitializationMode()
        fmu.setReal([vr["F_d"]], [F_D])
        fmu.exitInitializationMode()
        y, v = CLEARANCE, 0.0  # lateral state: starting against the wall
        n = round(stop / step)
        for k in range(n):
            t = k * step
            f_n, df_n = side_force(y, v)
            v_sx = AXIAL_A * AXIAL_W * math.cos(AXIAL_W * t)
            a_sx = -AXIAL_A * AXIAL_W**2 * math.sin(AXIAL_W * t)
            fmu.setReal([vr["F_N"], vr["v_sx"]], [f_n, v_sx])
            fmu.setRealInputDerivatives([vr["F_N"], vr["v_sx"]], [1, 1], [df_n, a_sx])
            v_x0 = fmu.getReal([vr["v_x"]])[0]
            fmu.doStep(currentCommunicationPoint=t, communicationStepSize=(k + 1) * step - t)
            x, v_x, f_step, f_mean = fmu.getReal(
                [vr["x"], vr["v_x"], vr["F_Fx_step"], vr["F_mean"]]
            )
            rows.append((t + step, f_n, df_n, v_sx, x, v_x0, v_x, f_step, f_mean))
            # The host's lateral motion over the same step (RK4).
            h = step
            k1 = lateral_rhs(t, y, v)
            k2 = lateral_rhs(t + h / 2, y + h / 2 * k1[0], v + h / 2 * k1[1])
            k3 = lateral_rhs(t + h / 2, y + h / 2 * k2[0], v + h / 2 * k2[1])
            k4 = lateral_rhs(t + h, y + h * k3[0], v + h * k3[1])
            y += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            v += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        fmu.terminate()
        fmu.freeInstance()
    finally:
        shutil.rmtree(unzipdir, ignore_errors=True)
    return rows


COLUMNS = "t,F_N,dF_N_dt,v_sx,x,v_x_start,v_x,F_Fx_step,F_mean"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stop", type=float, default=0.5)
    ap.add_argument("--step", type=float, default=2e-4)
    ap.add_argument("--csv", type=pathlib.Path)
    args = ap.parse_args()
    if not FMU.exists():
        sys.exit(f"{FMU} is missing: run `cargo run --release` first")
    rows = run(args.stop, args.step)
    if args.csv:
        args.csv.write_text(COLUMNS + "\n" + "\n".join(",".join(f"{v:.12g}" for v in r) for r in rows) + "\n")
    off = sum(1 for r in rows if r[1] == 0.0)
    impulse = sum(r[7] for r in rows) * args.step
    print(f"{len(rows)} steps of {args.step:g} s: off the wall in {off} ({100 * off / len(rows):.0f} %)")
    print(f"mean side force {sum(r[1] for r in rows) / len(rows):.2f} N, "
          f"axial friction impulse {impulse:.4g} N*s, section moved {rows[-1][4] * 1e3:.3f} mm")


if __name__ == "__main__":
    main()
