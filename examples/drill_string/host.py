"""A drill-string section against the borehole wall, driven by a small host model through fmpy.

The host owns what the friction contact does not: the section's lateral motion in the borehole
and the string's axial vibration. It is sized from the section the FMU declares (the start
values of its model description, `section_load`): DrillStringContact is a 10 m section of
5-inch drill pipe, m = 267 kg lying on the wall with its buoyed weight F_N = 2280 N, mu = 0.3
(F_C = 684 N), F_S = 889.2 N, pushed along the hole with F_d = 300 N (below F_C: on the wall and
without vibration it sticks).

- Lateral: the section (its mass m, on the string's lateral stiffness k_l, damping c_l) lies on
  the wall with its weight W = F_N (the start value: the load the scene gives F_S at) and whirls
  under its unbalance force LIFT*W*cos(Omega*t). Where its displacement y exceeds the clearance,
  the wall pushes back: the side force F_N = k_w*(y - clearance), 0 off the wall; at rest on the
  wall it is W less the string's pull k_l*y (2200 N), and over time its mean is that. With
  LIFT = 0.85 the unbalance alone is less than the weight, yet the section bounces on the stiff
  wall and is off it about a third of the time.
- Axial: the string vibrates axially at the contact, v_sx = a*w*cos(w*t) (bit bounce), taken
  as the motion of the surface the section rubs on (x along F_d, ground frame; a vibration of the
  section itself would enter as -du/dt: only v_r = v - v_sx matters, docs/using.md).

The contact FMU (DrillStringContact: LuGre, longitudinal, force drive) gets F_N and v_sx with
their input derivatives at every communication point, is pushed along the hole by its F_d, and
returns the section's axial motion and the friction. The FMU owns the section's mass m (the host
must not integrate it again); for its own balance the host uses the step mean F_Fx_step, the
friction's impulse over the step divided by the step, not a sample of a force that vibrates
between samples. docs/using.md ("Coupling a drill string") shows the other pattern, where the
host owns the mass.

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

# Host model (SI units), besides the section's own m and weight W = F_N.
K_L = 4.0e5  # the string's lateral stiffness at the section [N/m]
ZETA_L = 0.05  # lateral damping ratio: c_l = 2*ZETA_L*sqrt(k_l*m)
LIFT = 0.85  # unbalance force / weight
OMEGA = 2 * math.pi * 20.0  # rotation: 1200 rpm
CLEARANCE = 2e-4  # radial clearance to the wall [m]
K_W = 1e8  # wall stiffness [N/m]: the weight presses 23 um into it
AXIAL_A, AXIAL_W = 20e-6, 2 * math.pi * 150.0  # axial vibration amplitude [m], frequency


def section_load(fmu_path=FMU):
    """The section the FMU declares: the start values of m, F_N, mu, F_S and F_d."""
    md = read_model_description(str(fmu_path))
    start = {v.name: float(v.start) for v in md.modelVariables if v.start is not None}
    return {k: start[k] for k in ("m", "F_N", "mu", "F_S", "F_d")}


class Lateral:
    """The section's lateral motion: mass m, weight W towards the wall, unbalance LIFT*W."""

    def __init__(self, m, weight):
        self.m, self.weight = m, weight
        self.c_l = 2 * ZETA_L * math.sqrt(K_L * m)

    def rhs(self, t, y, v):
        f_wall = -K_W * max(0.0, y - CLEARANCE)
        f = self.weight * (1 + LIFT * math.cos(OMEGA * t)) - K_L * y - self.c_l * v + f_wall
        return v, f / self.m

    def rest(self):
        """Where the section lies on the wall at rest (no unbalance)."""
        return (self.weight + K_W * CLEARANCE) / (K_L + K_W)


def side_force(y, v):
    """F_N and its time derivative from the lateral state."""
    if y > CLEARANCE:
        return K_W * (y - CLEARANCE), K_W * v
    return 0.0, 0.0


def run(stop=0.5, step=2e-4, fmu_path=FMU):
    load = section_load(fmu_path)
    lateral = Lateral(load["m"], load["F_N"])
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
        fmu.setReal([vr["F_d"]], [load["F_d"]])
        fmu.exitInitializationMode()
        y, v = lateral.rest(), 0.0  # lateral state: lying on the wall
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
            k1 = lateral.rhs(t, y, v)
            k2 = lateral.rhs(t + h / 2, y + h / 2 * k1[0], v + h / 2 * k1[1])
            k3 = lateral.rhs(t + h / 2, y + h / 2 * k2[0], v + h / 2 * k2[1])
            k4 = lateral.rhs(t + h, y + h * k3[0], v + h * k3[1])
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
    load = section_load()
    off = sum(1 for r in rows if r[1] == 0.0)
    on = [r for r in rows if r[1] > 0.0]
    impulse = sum(r[7] for r in rows) * args.step
    print(f"section: m = {load['m']:g} kg, F_N = {load['F_N']:g} N (its weight on the wall), "
          f"mu = {load['mu']:g}, F_C = {load['mu'] * load['F_N']:g} N, F_S = {load['F_S']:g} N, "
          f"pushed with F_d = {load['F_d']:g} N")
    print(f"{len(rows)} steps of {args.step:g} s: off the wall in {off} ({100 * off / len(rows):.0f} %)")
    print(f"side force on the wall: mean {sum(r[1] for r in rows) / len(rows):.0f} N, "
          f"largest {max(r[1] for r in rows):.0f} N; friction on the wall up to "
          f"{max(abs(r[7]) for r in on):.0f} N (step means)")
    print(f"axial friction impulse {impulse:.4g} N*s against the push's {load['F_d'] * args.stop:.4g} N*s, "
          f"section moved {rows[-1][4] * 1e3:.3f} mm at {rows[-1][6] * 1e3:.2f} mm/s")

if __name__ == "__main__":
    main()
