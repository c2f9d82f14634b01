"""Work-precision of scipy's solve_ivp (LSODA, Radau, DOP853) on vibrofric's paper-longitudinal
case, against the exact solution: the solvers a Python user would otherwise pick.

Case: longitudinal Dahl contact, velocity drive v_d = 1 mm/s, harmonic support u0 = 0.2 µm at
2 kHz, defaults of SPEC §3 (k_t = 1e8 N/m unless --k-t), PERIODS vibration periods. Measured:
the relative error of F_mean over the last period against the exact piecewise-exponential
solution, and the run time. Writes reports/peers_scipy.csv and prints a table; compare with
`cargo run --release --example core_bench` (same case, 2000 periods).

    .venv/bin/python examples/peers/scipy_peers.py [--periods 20] [--k-t 1e8]
"""

import argparse
import csv
import math
import pathlib
import time

import numpy as np
from scipy.integrate import quad, solve_ivp

M, F_N, MU, U0, F, V_D = 5.6, 55.0, 0.2, 2e-7, 2000.0, 1e-3
F_C = MU * F_N
W = 2 * math.pi * F
V_A = W * U0
PERIOD = 1 / F


def exact_f_mean(k_t, periods):
    """Exact F_mean over the last of `periods` periods (Dahl is rate-independent: between sign
    changes of v_r, w = 1 − sgn(v_r)·s/s_ss decays as exp(−|ΔX_r|/s_ss))."""
    s_ss = F_C / k_t
    psi = V_D / V_A
    base = math.acos(psi) if psi < 1 else None
    roots = [] if base is None else sorted([base / W, (2 * math.pi - base) / W])

    def dx(a, t):  # X_r(t) − X_r(a) in product form
        return V_D * (t - a) - 2 * U0 * math.cos(0.5 * W * (t + a)) * math.sin(0.5 * W * (t - a))

    def piece(a, s_a, t):
        sigma = math.copysign(1.0, V_D - V_A * math.cos(W * 0.5 * (a + t)))
        w_a = 1 - sigma * s_a / s_ss
        return sigma * s_ss * (1 - w_a * math.exp(-abs(dx(a, t)) / s_ss))

    def advance(s, want_integral):
        knots = [0.0] + roots + [PERIOD]
        integral = 0.0
        for a, b in zip(knots[:-1], knots[1:]):
            s_a = s
            if want_integral:
                integral += quad(lambda t: piece(a, s_a, t), a, b, epsabs=0, epsrel=1e-13, limit=500)[0]
            s = piece(a, s_a, b)
        return s, integral

    s = 0.0
    for _ in range(periods - 1):
        s, _ = advance(s, False)
    _, integral = advance(s, True)
    return k_t * integral / PERIOD


def run(method, rtol, k_t, periods):
    s_ss = F_C / k_t
    t_last = (periods - 1) * PERIOD

    def rhs(t, y):
        vr = V_D - V_A * math.cos(W * t)
        ds = vr - abs(vr) * y[0] / s_ss
        return [ds, k_t * y[0] if t >= t_last else 0.0]

    def jac(t, y):
        vr = V_D - V_A * math.cos(W * t)
        return np.array([[-abs(vr) / s_ss, 0.0], [k_t if t >= t_last else 0.0, 0.0]])

    kwargs = dict(method=method, rtol=rtol, atol=[rtol * s_ss, rtol * F_C * PERIOD])
    if method in ("Radau", "LSODA"):
        kwargs["jac"] = jac
    t0 = time.perf_counter()
    # Two legs, so that the quadrature switches on exactly at a step boundary.
    a = solve_ivp(rhs, (0, t_last), [0.0, 0.0], **kwargs)
    b = solve_ivp(rhs, (t_last, periods * PERIOD), [a.y[0, -1], 0.0], **kwargs)
    elapsed = time.perf_counter() - t0
    return b.y[1, -1] / PERIOD, elapsed, a.nfev + b.nfev, a.status == 0 and b.status == 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--periods", type=int, default=20)
    ap.add_argument("--k-t", type=float, default=1e8)
    ap.add_argument("--out", default="reports/peers_scipy.csv")
    args = ap.parse_args()
    truth = exact_f_mean(args.k_t, args.periods)
    print(f"exact F_mean = {truth:.15f} N after {args.periods} periods, k_t = {args.k_t:.0e}")
    rows = []
    print(f"{'method':>7} {'rtol':>7} {'rel.err':>10} {'time[s]':>9} {'per period[ms]':>15} {'nfev':>8}")
    for method in ("LSODA", "Radau", "DOP853"):
        for rtol in (1e-4, 1e-6, 1e-8):
            fm, el, nfev, ok = run(method, rtol, args.k_t, args.periods)
            err = abs(fm - truth) / truth
            rows.append(dict(method=method, rtol=rtol, rel_err=err, time_s=el,
                             ms_per_period=el / args.periods * 1e3, nfev=nfev, ok=ok,
                             k_t=args.k_t, periods=args.periods))
            print(f"{method:>7} {rtol:>7.0e} {err:>10.2e} {el:>9.3f} {el / args.periods * 1e3:>15.3f} {nfev:>8}"
                  + ("" if ok else "  (failed)"))
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
