"""Figs. 13 and 14: the test-rig protocol with the spring-drive FMUs (RigLongitudinal,
RigTransverse), F_d against time.

The far end of the spring moves at v_d = 1 mm/s. A run starts on an immobile support (u0 = 0 or
f = 0), steps the tunable parameter upward between doSteps with fmi2SetReal, holding each level,
and ends on an immobile support again:
  variant 1 (fig13_rig_u0_steps.png): f = 2000 Hz, u0 = 0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1 µm, 0;
  variant 2 (fig14_rig_f_steps.png): u0 = 0.2 µm, f = 0, 500, ..., 5000 Hz, 0.
The spring force F_d is sampled every 1 ms (the FMU resolves the vibration inside each step);
thin lines: the spring force at each sample, thick steps: the Coulomb limit F_C·(limit at the
level's psi = v_d/(2 pi f u0)) (guided formula on the transverse side).
Each variant is two sequential FMU runs (no sweep), so Dask is not used here.

    .venv/bin/python examples/figures/fig_rig.py
"""

import math

import numpy as np

import sweep
from fmurun import F_C_DEFAULT, coulomb_longitudinal, coulomb_transverse, runner

V_D = 1e-3
HOLD = 0.5           # s at each level
H = 1e-3             # communication step (s)
SETTLE = 0.25        # s of plain sliding on the immobile support before the first level

VARIANTS = [
    ("u0", [0.0, 0.05e-6, 0.1e-6, 0.2e-6, 0.3e-6, 0.5e-6, 0.75e-6, 1.0e-6, 0.0], dict(f=2000.0),
     "fig13_rig_u0_steps.png",
     "Fig. 13: rig, $u_0$ stepped at f = 2000 Hz, $v_d$ = 1 mm/s", lambda v: f"{v * 1e6:g} µm"),
    ("f", [0.0] + [500.0 * k for k in range(1, 11)] + [0.0], dict(u0=0.2e-6),
     "fig14_rig_f_steps.png",
     "Fig. 14: rig, $f$ stepped at $u_0$ = 0.2 µm, $v_d$ = 1 mm/s", lambda v: f"{v:g} Hz"),
]


def protocol(model, name, levels, fixed):
    """Returns times, F_d samples and the level index of each sample."""
    r = runner(model)
    start = dict(fixed, v_d=V_D)
    start[name] = levels[0]
    r.start(start)
    t, ts, fd, lev = 0.0, [0.0], [r.get("F_d")[0]], [0]
    durations = [SETTLE + HOLD] + [HOLD] * (len(levels) - 1)
    for k, (level, dur) in enumerate(zip(levels, durations)):
        if k > 0:
            r.set(**{name: level})
        for _ in range(round(dur / H)):
            r.step(t, H)
            t += H
            ts.append(t)
            fd.append(r.get("F_d")[0])
            lev.append(k)
    return np.array(ts), np.array(fd), np.array(lev)


def make(args):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    for name, levels, fixed, png, title, fmt in VARIANTS:
        fig, axes = plt.subplots(1, 2, figsize=(13, 4.6), sharey=True)
        for j, (ax, model) in enumerate(zip(axes, ["RigLongitudinal", "RigTransverse"])):
            ts, fd, lev = protocol(model, name, levels, fixed)
            params = [dict(fixed, **{name: v}) for v in levels]
            va = np.array([2 * math.pi * p["u0"] * p["f"] for p in params])
            with np.errstate(divide="ignore"):
                psi = np.where(va > 0, V_D / np.where(va > 0, va, 1.0), np.inf)
            lim = F_C_DEFAULT * (coulomb_longitudinal(psi) if j == 0 else coulomb_transverse(psi))
            lim = np.where(np.isfinite(psi), lim, F_C_DEFAULT)
            ax.plot(ts, fd, lw=0.8, label="$F_d$ (spring force)")
            ax.step(ts, lim[lev], "k--", lw=1.2, where="post", label="Coulomb limit at the level")
            for k in range(1, len(levels)):
                t0 = ts[np.argmax(lev == k)]
                ax.axvline(t0, color="0.8", lw=0.6)
                ax.text(t0 + 0.01, F_C_DEFAULT * 1.07, fmt(levels[k]), fontsize=7, rotation=90,
                        va="bottom")
            ax.set_title(f"({'ab'[j]}) {'longitudinal' if j == 0 else 'transverse'} vibrations",
                         pad=30)
            ax.set_xlabel("t (s)")
            ax.set_ylim(0, F_C_DEFAULT * 1.3)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8, loc="lower left")
        axes[0].set_ylabel("$F_d$ (N)")
        fig.suptitle(title)
        fig.tight_layout()
        sweep.savefig(fig, png)
        plt.close(fig)


if __name__ == "__main__":
    a = sweep.parser(__doc__.splitlines()[0]).parse_args()
    sweep.configure(a)
    make(a)
