"""Figs. 7 and 10: F_mean as a surface, longitudinal and transverse side by side.

Fig. 7 (fig07_surface_va_vd.png): over (v_a, v_d) at f = 2000 Hz (v_a = 2 pi f u0).
Fig. 10 (fig10_surface_u0_f.png): over (u0, f) at v_d = 1 mm/s.
Coloured surface: PaperLongitudinal / PaperTransverse (lateral free); black wireframe: the
rigid-contact (Coulomb) limit (`docs/model.md`) (guided, for the transverse side). Default grid 50 x 50
per side (5000 FMU runs per figure).

    .venv/bin/python examples/figures/fig_surfaces.py [--n 50] [--scheduler ADDRESS]
"""

import math

import numpy as np

import sweep
from fmurun import F_C_DEFAULT, coulomb_longitudinal, coulomb_transverse

PERIODS = 20
MODELS = ["PaperLongitudinal", "PaperTransverse"]


def grid_va_vd(n):
    va = np.linspace(0.1e-3, 10e-3, n)
    vd = np.linspace(0.1e-3, 10e-3, n)
    return np.meshgrid(va, vd, indexing="ij")


def grid_u0_f(n):
    u0 = np.linspace(0.01e-6, 1.0e-6, n)
    f = np.linspace(50.0, 5000.0, n)
    return np.meshgrid(u0, f, indexing="ij")


def sweep_surface(starts, label):
    tasks = [(m, s, PERIODS) for m in MODELS for s in starts]
    values = sweep.run(tasks, label=label)
    k = len(starts)
    return {m: values[i * k:(i + 1) * k] for i, m in enumerate(MODELS)}


def draw(X, Y, Z, psi, xlabel, ylabel, title, name, xs=1.0, ys=1.0):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(13, 5.6))
    for j, (m, side) in enumerate(zip(MODELS, ["longitudinal", "transverse"])):
        ax = fig.add_subplot(1, 2, j + 1, projection="3d")
        ax.plot_surface(X * xs, Y * ys, Z[m], cmap="viridis", linewidth=0, alpha=0.9,
                        rcount=50, ccount=50)
        limit = F_C_DEFAULT * (coulomb_longitudinal(psi) if j == 0 else coulomb_transverse(psi))
        ax.plot_wireframe(X * xs, Y * ys, limit, color="k", linewidth=0.4, rcount=12, ccount=12)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_zlabel(r"$F_{mean}$ (N)")
        ax.set_zlim(0, F_C_DEFAULT * 1.02)
        ax.set_title(f"({'ab'[j]}) {side} vibrations  [wireframe: Coulomb limit]")
        ax.view_init(elev=25, azim=-125)
    fig.suptitle(title)
    sweep.savefig(fig, name)
    plt.close(fig)


def make_fig7(args):
    n = args.n or 50
    f = 2000.0
    VA, VD = grid_va_vd(n)
    starts = [dict(u0=va / (2 * math.pi * f), f=f, v_d=vd) for va, vd in zip(VA.ravel(), VD.ravel())]
    Z = {m: z.reshape(VA.shape) for m, z in sweep_surface(starts, "fig07_surface_va_vd.png").items()}
    draw(VA, VD, Z, VD / VA, r"$v_a$ (mm/s)", r"$v_d$ (mm/s)",
         f"Fig. 7: mean friction force over ($v_a$, $v_d$), f = {f:g} Hz, grid {n}x{n}",
         "fig07_surface_va_vd.png", 1e3, 1e3)
    return VA, VD, Z


def make_fig10(args):
    n = args.n or 50
    v_d = 1e-3
    U0, FF = grid_u0_f(n)
    starts = [dict(u0=u, f=f, v_d=v_d) for u, f in zip(U0.ravel(), FF.ravel())]
    Z = {m: z.reshape(U0.shape) for m, z in sweep_surface(starts, "fig10_surface_u0_f.png").items()}
    draw(U0, FF, Z, v_d / (2 * math.pi * FF * U0), r"$u_0$ (µm)", r"$f$ (Hz)",
         f"Fig. 10: mean friction force over ($u_0$, $f$), $v_d$ = 1 mm/s, grid {n}x{n}",
         "fig10_surface_u0_f.png", 1e6, 1.0)
    return U0, FF, Z


def make(args):
    make_fig7(args)
    make_fig10(args)


if __name__ == "__main__":
    a = sweep.parser(__doc__.splitlines()[0]).parse_args()
    sweep.configure(a)
    make(a)
