"""Figs. 8 and 9: F_mean against u0 at several f, and against f at several u0 (v_d = 1 mm/s),
longitudinal and transverse side by side.

Fig. 8 (fig08_vs_u0.png), Fig. 9 (fig09_vs_f.png). Solid: PaperLongitudinal / PaperTransverse
(lateral free); dashed, same colour: the rigid-contact (Coulomb) limit (`docs/model.md`) at the same
(u0, f) (guided, on the transverse side); the grey vertical marks of the longitudinal side are the
thresholds v_a = v_d (Eq. 12).

    .venv/bin/python examples/figures/fig_u0_f.py [--n 80] [--scheduler ADDRESS]
"""

import math

import numpy as np

import sweep
from fmurun import F_C_DEFAULT, coulomb_longitudinal, coulomb_transverse

V_D = 1e-3
PERIODS = 20
MODELS = ["PaperLongitudinal", "PaperTransverse"]
FS = [500.0, 1000.0, 2000.0, 5000.0]          # Fig. 8 curves
U0S = [0.05e-6, 0.1e-6, 0.2e-6, 0.5e-6]       # Fig. 9 curves


def draw(x, curves, xs, xlabel, labels, thresholds, title, name):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6), sharey=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for j, (ax, m) in enumerate(zip(axes, MODELS)):
        limit_of = coulomb_longitudinal if j == 0 else coulomb_transverse
        for k, lab in enumerate(labels):
            ys, psi = curves[m][k]
            ax.plot(x * xs, ys, "-", color=colors[k], label=lab)
            ax.plot(x * xs, F_C_DEFAULT * limit_of(psi), "--", color=colors[k], lw=1)
            if j == 0:
                ax.axvline(thresholds[k] * xs, color=colors[k], lw=0.6, alpha=0.5)
        ax.plot([], [], "k--", lw=1, label="Coulomb limit" + (" (guided)" if j else ""))
        ax.set_title(f"({'ab'[j]}) {'longitudinal' if j == 0 else 'transverse'} vibrations")
        ax.set_xlabel(xlabel)
        ax.set_ylim(0, F_C_DEFAULT * 1.05)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_ylabel(r"$F_{mean}$ (N)")
    fig.suptitle(title)
    sweep.savefig(fig, name)
    plt.close(fig)


def make(args):
    n = args.n or 80
    u0 = np.linspace(0.0, 1.0e-6, n + 1)[1:]
    starts = [dict(u0=u, f=f, v_d=V_D) for f in FS for u in u0]
    values = sweep.run([(m, s, PERIODS) for m in MODELS for s in starts], label="fig08_vs_u0.png")
    curves = {}
    for i, m in enumerate(MODELS):
        v = values[i * len(starts):(i + 1) * len(starts)].reshape(len(FS), n)
        curves[m] = [(v[k], V_D / (2 * math.pi * f * u0)) for k, f in enumerate(FS)]
    draw(u0, curves, 1e6, r"$u_0$ (µm)", [f"f = {f:g} Hz" for f in FS],
         [V_D / (2 * math.pi * f) for f in FS],
         r"Fig. 8: mean friction force against $u_0$, $v_d$ = 1 mm/s", "fig08_vs_u0.png")

    f = np.linspace(0.0, 5000.0, n + 1)[1:]
    starts = [dict(u0=u, f=ff, v_d=V_D) for u in U0S for ff in f]
    values = sweep.run([(m, s, PERIODS) for m in MODELS for s in starts], label="fig09_vs_f.png")
    curves = {}
    for i, m in enumerate(MODELS):
        v = values[i * len(starts):(i + 1) * len(starts)].reshape(len(U0S), n)
        curves[m] = [(v[k], V_D / (2 * math.pi * f * u)) for k, u in enumerate(U0S)]
    draw(f, curves, 1.0, r"$f$ (Hz)", [f"u0 = {u * 1e6:g} µm" for u in U0S],
         [V_D / (2 * math.pi * u) for u in U0S],
         r"Fig. 9: mean friction force against $f$, $v_d$ = 1 mm/s", "fig09_vs_f.png")


if __name__ == "__main__":
    a = sweep.parser(__doc__.splitlines()[0]).parse_args()
    sweep.configure(a)
    make(a)
