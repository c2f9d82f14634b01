"""The event indicators of a string in Model Exchange (FMI 2.0 and 3.0), against their
definition computed here from the states and inputs set, not by the library.

Section i's indicator is its relative velocity shifted by its hysteresis band, as the single
contact's `event.v_rx`:

    z[i] = v_r[i] + side[i]·band[i],   v_r[i] = v_x[i] − v_sx[i],   band[i] = tol·v_nom[i],

`side[i]` the sign of v_r[i] at the last event update where v_r[i] had left the band (the first
update takes the sign as it is), `tol` the relative tolerance and v_nom[i] the scale of the
section's velocity: the speed at which its contact's stiffness swings its pre-sliding
deformation, `s_nom·sqrt(k_t/m[i])` with `s_nom = max(F_C[i], F_S[i])/k_t` (LuGre), which is the
nominal of the state v_x[i]. So a section hovering at v_r = 0 (stuck) gives no train of events,
and a section whose v_r crosses 0 makes its indicator change sign once, when v_r has gone one
band past 0.

- the indicators of five sections of different masses and static forces, their wall moving at
  different velocities of both signs, at velocities outside and inside each band, on both
  sides, before and after event updates, and after a change of the wall's velocity in
  continuous-time mode: each equals its own v_r plus its side times its band (the sides tracked
  here, the bands from the parameters);
- a short integration (classical Runge–Kutta over the FMU's derivatives, steps of 2 µs),
  sections pushed through v_r = 0 upwards and downwards: every indicator has the sign of its
  v_r plus side times band at every step; each sign change located by bisection to 1e-18 s lies
  where the section's v_r (from the state) crosses the band's edge, within one band of where it
  crosses 0, and no other indicator changes sign there; each section's crossing within 5 % of
  the time its push alone takes to bring v_r to 0;
- FMI 3.0's indicators, and its array `event.v_rx`, equal FMI 2.0's, bit for bit.
"""

import math

import numpy as np
import pytest

from conftest import DRILL_PIPE, Exchange, drill_string_scene, export_scene

N = 5
TOL = 1e-6
MU, F_N, K_T = (DRILL_PIPE[k] for k in ("mu", "F_N", "k_t"))
M = [267.0, 120.0, 400.0, 267.0, 90.0]
F_S = [889.2, 700.0, 1000.0, 889.2, 950.0]
# Each section's band from its parameters: tol·max(F_C, F_S)/k_t·sqrt(k_t/m).
BAND = np.array([TOL * max(MU * F_N, fs) / K_T * math.sqrt(K_T / m) for m, fs in zip(M, F_S)])
# The walls' velocities, of both signs and very different sizes (m/s).
V_SX = [0.3, -0.2, 1e-3, 0.0, -0.05]


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    scene = drill_string_scene("IndicatorString", "Five drill-pipe sections of different masses and static forces", N, m=M, F_S=F_S)
    return export_scene(tmp_path_factory.mktemp("string_indicators"), scene)


def v_x(x):
    return x[N:2 * N]


class Truth:
    """The indicators' definition, from the states and the walls' velocities: the sides of the
    bands as the event updates leave them, and each indicator."""

    def __init__(self, band):
        self.band = band
        self.side = np.zeros(N)

    def v_r(self, x, v_sx):
        return v_x(x) - np.asarray(v_sx)

    def update(self, x, v_sx):
        g = self.v_r(x, v_sx)
        for i in range(N):
            if self.side[i] == 0.0 or g[i] * self.side[i] < -self.band[i]:
                self.side[i] = -1.0 if g[i] < 0.0 else 1.0

    def z(self, x, v_sx):
        return self.v_r(x, v_sx) + self.side * self.band


def open_string(path, v_sx, f_d=None):
    start = {f"v_sx[{i + 1}]": v for i, v in enumerate(v_sx)}
    start.update({f"F_d[{i + 1}]": v for i, v in enumerate(f_d or [])})
    return Exchange(path, TOL, start)


def bands_of(m):
    """The bands from the FMU's nominals of v_x (tol times each), checked against the
    parameters' bands: the same numbers to rounding."""
    band = TOL * m.nominals()[N:2 * N]
    assert np.allclose(band, BAND, rtol=1e-12, atol=0.0), (band, BAND)
    return band


def indicators(m):
    """The indicators, and FMI 2.0's scalars `event.v_rx[i]` or FMI 3.0's array `event.v_rx`:
    the same numbers."""
    z = m.event_indicators()
    if m.fmi3:
        named = m.get_array(m.vr["event.v_rx"])
    else:
        named = [m.get(f"event.v_rx[{i + 1}]") for i in range(N)]
    assert list(named) == list(z), (named, z)
    return z


def sequence(path):
    """Sets states and walls' velocities, with event updates between, and compares each
    section's indicator with its definition; returns every indicator read."""
    m = open_string(path, V_SX)
    try:
        truth = Truth(bands_of(m))
        v_sx = list(V_SX)
        # The first event update (after initialization): the string at rest, v_r = −v_sx.
        x = m.get_states()
        assert np.array_equal(v_x(x), np.zeros(N))
        truth.update(x, v_sx)
        rng = np.random.default_rng(7)
        read = []

        def check(offsets, what):
            """v_x[i] = v_sx[i] + offsets[i]·band[i], the positions and deformations anything."""
            y = x.copy()
            y[:N] = rng.uniform(-1e-3, 1e-3, N)
            y[2 * N:3 * N] = rng.uniform(-5e-6, 5e-6, N)
            y[N:2 * N] = np.asarray(v_sx) + np.asarray(offsets) * truth.band
            m.set_states(y)
            z, want = indicators(m), truth.z(y, v_sx)
            err = np.abs(z - want) / truth.band
            assert np.all(err <= 1e-9), (what, z, want)
            # Where the definition is clearly off zero, the signs agree.
            clear = np.abs(want) > 1e-6 * truth.band
            assert np.all(np.sign(z[clear]) == np.sign(want[clear])), (what, z, want)
            read.append(z)
            return y

        side0 = truth.side.copy()
        assert list(side0) == [-1.0, 1.0, -1.0, 1.0, 1.0]  # v_r = −v_sx; 0 counts as +
        check([1e6, -1e6, 3.0, -3.0, 0.0], "outside the bands, both signs, and at v_r = 0")
        # Inside the band on the side opposite to the last event's: the indicator keeps its
        # side's sign; just beyond the band: it changes sign.
        check(-0.5 * side0, "inside the bands, opposite side")
        check(0.999 * -side0, "at the bands' edges, inside")
        y = check(-1.5 * side0, "beyond the bands, opposite side")
        z = read[-1]
        assert np.all(np.sign(z) == -side0), z
        # The event update: every section left its band, each takes its new side.
        m.event_update()
        truth.update(y, v_sx)
        assert np.array_equal(truth.side, -side0)
        check(0.5 * side0, "inside the bands after the update, back towards the old side")
        assert np.all(np.sign(read[-1]) == -side0)
        # Mixed: two sections leave their bands, the others stay inside; an update flips only
        # those two.
        y = check([1.5, 0.2, -0.4, 1.5, 0.9] * -truth.side, "mixed")
        m.event_update()
        before = truth.side.copy()
        truth.update(y, v_sx)
        assert list(truth.side == before) == [False, True, True, False, True]
        check([0.0, 0.0, 0.0, 0.0, 0.0], "v_r = 0 after the mixed update")
        # The walls change velocity in continuous-time mode: v_r follows the input.
        v_sx = [-0.4, 0.25, -2e-3, 1e-4, 0.0]
        for i, v in enumerate(v_sx):
            m.set(f"v_sx[{i + 1}]", v)
        check([7.0, -7.0, 0.3, -0.3, 2.0], "after the walls' velocities changed")
        m.fmu.setTime(1e-3)
        check([-2.0, 2.0, -0.3, 0.3, -1e3], "at a later time")
        return read
    finally:
        m.close()


@pytest.fixture(scope="module")
def sequences(fmus):
    return {edition: sequence(path) for edition, path in fmus.items()}


@pytest.mark.parametrize("edition", ["fmi2", "fmi3"])
def test_each_indicator_is_its_sections_v_r_shifted_by_its_band(sequences, edition):
    print(f"bands {BAND} m/s; {len(sequences[edition])} sets of states checked")
    assert len(sequences[edition]) == 9


def test_fmi3_indicators_equal_fmi2(sequences):
    for a, b in zip(sequences["fmi2"], sequences["fmi3"]):
        assert np.array_equal(a, b)


def rk4(m, t, x, h):
    def f(s, y):
        m.fmu.setTime(s)
        return m.derivatives_at(y)

    k1 = f(t, x)
    k2 = f(t + h / 2, x + h / 2 * k1)
    k3 = f(t + h / 2, x + h / 2 * k2)
    k4 = f(t + h, x + h * k3)
    return x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


def indicators_at(m, t, x):
    m.fmu.setTime(t)
    m.set_states(x)
    return m.event_indicators()


# The integration: walls slow, sections moving against them (v_r = ∓DELTA), pushed back
# through v_r = 0 by F_d = ±2500 N (above every section's static force).
V_SX_RUN = [1e-3, -1e-3, 2e-3, 0.0, -2e-3]
DIRECTION = np.array([1.0, -1.0, 1.0, -1.0, 1.0])  # +: v_r rises through 0
DELTA = np.array([2e-4, 3e-4, 4e-4, 1e-4, 5e-4])
H = 2e-6


def crossings(path):
    """Integrates until every section's v_r has crossed 0; locates each sign change of an
    indicator by bisection and checks it against the section's v_r there. Returns the
    crossings (section, time, v_r) and the largest |v_r| at them in bands."""
    m = open_string(path, V_SX_RUN, list(2500.0 * DIRECTION))
    try:
        truth = Truth(bands_of(m))
        t, x = 0.0, m.get_states()
        x[N:2 * N] = np.asarray(V_SX_RUN) - DIRECTION * DELTA
        m.set_states(x)
        m.event_update()
        truth.update(x, V_SX_RUN)
        assert np.array_equal(truth.side, -DIRECTION)
        z = indicators_at(m, t, x)
        found, worst = [], 0.0
        for _ in range(200):
            x1 = rk4(m, t, x, H)
            z1 = indicators_at(m, t + H, x1)
            want = truth.z(x1, V_SX_RUN)
            clear = np.abs(want) > 1e-6 * truth.band
            assert np.all(np.sign(z1[clear]) == np.sign(want[clear])), (t, z1, want)
            changed = np.sign(z1) != np.sign(z)
            if changed.any():
                # Bisection on the step's fraction: the earliest sign change in the step.
                lo, hi = 0.0, 1.0
                while (hi - lo) * H > 1e-18:
                    mid = 0.5 * (lo + hi)
                    zm = indicators_at(m, t + mid * H, rk4(m, t, x, mid * H))
                    if np.any(np.sign(zm) != np.sign(z)):
                        hi = mid
                    else:
                        lo = mid
                xl, xr = rk4(m, t, x, lo * H), rk4(m, t, x, hi * H)
                zl, zr = indicators_at(m, t + lo * H, xl), indicators_at(m, t + hi * H, xr)
                sections = np.nonzero(np.sign(zr) != np.sign(zl))[0]
                assert len(sections) == 1, (t, zl, zr)
                i = sections[0]
                # The section's own v_r, from the states, crosses the band's edge −side·band
                # in the same bracket, and no other section's does.
                gl, gr = truth.z(xl, V_SX_RUN), truth.z(xr, V_SX_RUN)
                assert np.sign(gl[i]) == np.sign(zl[i]) and np.sign(gr[i]) == np.sign(zr[i]), (
                    i, gl[i], gr[i], zl[i], zr[i])
                others = [j for j in range(N) if j != i]
                assert np.all(np.sign(gl[others]) == np.sign(gr[others]))
                v_r = truth.v_r(xr, V_SX_RUN)[i]
                assert abs(v_r) <= truth.band[i] * (1 + 1e-6), (i, v_r, truth.band[i])
                assert np.sign(v_r) == DIRECTION[i]  # it has crossed 0, one band on
                worst = max(worst, abs(abs(v_r) - truth.band[i]) / truth.band[i])
                found.append((int(i), t + hi * H, v_r))
                # The importer's event at the root: the section takes its new side.
                t, x = t + hi * H, xr
                m.fmu.setTime(t)
                m.set_states(x)
                m.event_update()
                truth.update(x, V_SX_RUN)
                z = indicators_at(m, t, x)
                continue
            t, x, z = t + H, x1, z1
            if len(found) == N:
                break
        return found, worst
    finally:
        m.close()


@pytest.fixture(scope="module")
def runs(fmus):
    return {edition: crossings(path) for edition, path in fmus.items()}


@pytest.mark.parametrize("edition", ["fmi2", "fmi3"])
def test_an_indicator_changes_sign_where_its_sections_v_r_crosses(runs, edition):
    found, worst = runs[edition]
    for i, t, v_r in found:
        print(f"section {i + 1}: indicator changes sign at t = {t:.9e} s, v_r = {v_r:+.4e} m/s "
              f"(band {BAND[i]:.4e})")
    print(f"|v_r| at the sign changes within {worst:.1e} of the band")
    assert worst <= 1e-6
    # Each section once, about when its push alone brings v_r to 0 (t = DELTA·m/F_d: the
    # friction and the links are small over these microseconds), in that order.
    predicted = DELTA * np.array(M) / 2500.0
    assert [i for i, _, _ in found] == list(np.argsort(predicted))
    for i, t, _ in found:
        assert abs(t - predicted[i]) <= 0.05 * predicted[i], (i, t, predicted[i])


def test_fmi3_crossings_equal_fmi2(runs):
    assert runs["fmi2"] == runs["fmi3"]
