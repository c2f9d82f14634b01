"""Figs. 5 and 6: F_mean/F_C against psi = v_d/v_a, longitudinal and transverse side by side.

Fig. 5 (fig05_psi_fixed_vd.png): fixed driving velocity v_d, the vibration velocity amplitude v_a
varied through u0 at f = 2000 Hz. Fig. 6 (fig06_psi_fixed_va.png): fixed v_a (u0 at 2000 Hz),
v_d varied. Solid: PaperLongitudinal / PaperTransverse (lateral free, the paper's Eq. 10);
dotted: PaperTransverseGuided; black dashed: the rigid-contact (Coulomb) limits (`docs/model.md`).

    .venv/bin/python examples/figures/fig_psi.py [--n 60] [--scheduler ADDRESS]
"""

import math

import numpy as np

import sweep
from fmurun import F_C_DEFAULT, coulomb_longitudinal, coulomb_transverse

F = 2000.0
PERIODS = 20
V_DS = [0.5e-3, 1e-3, 2e-3]                  # Fig. 5: fixed v_d (m/s)
U0S = [0.1e-6, 0.2e-6, 0.4e-6]               # Fig. 6: fixed v_a = 2 pi f u0
MODELS = [("PaperLongitudinal", "-"), ("PaperTransverse", "-"), ("PaperTransverseGuided", ":")]


def tasks_fixed_vd(psis):
    out = []
    for v_d in V_DS:
        for psi in psis:
            u0 = v_d / (2 * math.pi * F * psi)
            out.append(dict(u0=u0, f=F, v_d=v_d))
    return out


def tasks_fixed_va(psis):
    out = []
    for u0 in U0S:
        for psi in psis:
            out.append(dict(u0=u0, f=F, v_d=psi * 2 * math.pi * F * u0))
    return out


def draw(psis, results, labels, title, name):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6), sharey=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, side in zip(axes, ["longitudinal", "transverse"]):
        for model, ls in MODELS:
            if (side == "longitudinal") != (model == "PaperLongitudinal"):
                continue
            r = results[model].reshape(len(labels), len(psis))
            for k, lab in enumerate(labels):
                extra = " (guided)" if model.endswith("Guided") else ""
                ax.plot(psis, r[k] / F_C_DEFAULT, ls, color=colors[k], label=lab + extra)
        limit = coulomb_longitudinal(psis) if side == "longitudinal" else coulomb_transverse(psis)
        ax.plot(psis, limit, "k--", lw=1.5,
                label="Coulomb limit" + (" (guided)" if side == "transverse" else ""))
        ax.axvline(1.0, color="0.6", lw=0.8)
        ax.set_title(f"({'a' if side == 'longitudinal' else 'b'}) {side} vibrations")
        ax.set_xlabel(r"$\psi = v_d/v_a$")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_ylabel(r"$F_{mean}/F_C$")
    fig.suptitle(title)
    sweep.savefig(fig, name)
    plt.close(fig)


def make(args):
    n = args.n or 60
    psis = np.linspace(0.02, 2.0, n)
    for tasks_of, labels, title, name in [
        (tasks_fixed_vd, [f"v_d = {v * 1e3:g} mm/s" for v in V_DS],
         f"Fig. 5: fixed $v_d$, $v_a$ varied through $u_0$ (f = {F:g} Hz)", "fig05_psi_fixed_vd.png"),
        (tasks_fixed_va, [f"v_a = {2 * math.pi * F * u * 1e3:.2f} mm/s (u0 = {u * 1e6:g} µm)" for u in U0S],
         f"Fig. 6: fixed $v_a$, $v_d$ varied (f = {F:g} Hz)", "fig06_psi_fixed_va.png"),
    ]:
        starts = tasks_of(psis)
        tasks = [(model, s, PERIODS) for model, _ in MODELS for s in starts]
        values = sweep.run(tasks, label=name)
        results = {model: values[k * len(starts):(k + 1) * len(starts)]
                   for k, (model, _) in enumerate(MODELS)}
        draw(psis, results, labels, title, name)


if __name__ == "__main__":
    a = sweep.parser(__doc__.splitlines()[0]).parse_args()
    sweep.configure(a)
    make(a)
