"""Every standard scene's FMU runs unchanged in the partner importers — libcosim (libcosimpy),
ecos (ecospy) and fmi-sim — and agrees with fmpy (see docs/interoperability.md):

- on the partner's own communication grid (fmpy's FMU2Slave replaying exactly the communication
  points and step sizes the partner passes: libcosim's integer nanoseconds converted to double,
  ecos' t += h, fmi-sim's k·h), to 1e-9 relative with an absolute floor of 1e-9 × the output's
  largest magnitude over the run (partners.REL, partners.ABS_FLOOR);
- on fmpy's nominal grid t_k = k·h, to the same bound: a partner's grid differs from it by a
  few ulps, and the FMU takes every communication point within 256 ulps of a short decimal as
  that decimal (vibrofric::model canonical_time), so the results are in fact bit-identical.

fmi-sim built for Windows runs under Wine every FMU as the Linux fmi-sim does, and writes the same
CSV files byte for byte (test_fmi_sim_on_windows_writes_the_linux_csv_files).

A string of contacts (a copy of DrillString cut to 8 sections, exported by the test around dist's
libraries) runs in libcosim, ecos and fmi-sim (FMI 2.0 scalars x[1] ...) and through fmpy's FMI
3.0 arrays, each output element bit for bit as fmpy's FMI 2.0 run, on the partner's grid and on
k·h; fmi-sim under Wine writes the Linux CSV file. fmi-sim 0.7.0 cannot read FMI 3.0 arrays
(test_known_difference_fmi_sim_reads_fmi3_arrays_as_scalars).

A partner that is not installed fails its tests unless VIBROFRIC_SKIP_PARTNERS names it
(comma-separated: libcosim, ecos, fmi-sim, fmi-sim-windows); tests/all.sh installs all of them.

Two optional partners, built by hand (neither is on PyPI or in Debian), run when found and are
skipped otherwise: fmusim ($FMUSIM or `fmusim` on PATH; FMI 2.0 and FMI 3.0 Co-Simulation, its
`validate`) and the FMU Compliance Checker ($FMU_CHECK or `fmuCheck.linux64` on PATH; FMI 2.0,
its XML check and Co-Simulation): the same checks as above, the string bit for bit (fmusim's
FMI 3.0 arrays too), and no model-description warning from either.
"""

import os
import pathlib
import subprocess
import tomllib

import numpy as np
import pytest

import partners
from conftest import DIST, SCENES, fmu_path, vibrofric_exe

# Strings of contacts (`[string]`) have the tests at the end of this file: a small copy of
# DrillString exported here (the 100-section standard scene is test_string.py's).
SCENE_FILES = sorted(p for p in SCENES.glob("*.toml") if "string" not in tomllib.loads(p.read_text()))
IDENTIFIERS = [tomllib.loads(p.read_text())["model_identifier"] for p in SCENE_FILES]

# The grid: 0.1 ms (a fifth of the 2 kHz vibration period; 1e-4 is not a binary fraction, so
# a master's t += h drifts), 300 steps = 60 vibration periods.
H, N = 1e-4, 300
# Model Exchange: fmi-sim's forward Euler with steps h and h/2 up to 2 ms.
ME_STOP, ME_STEPS = 2e-3, (1e-6, 5e-7)

SKIP = set(filter(None, os.environ.get("VIBROFRIC_SKIP_PARTNERS", "").split(",")))

_nominal = {}


def nominal(ident):
    if ident not in _nominal:
        _nominal[ident] = partners.run_fmpy(fmu_path(ident), H, N)
    return _nominal[ident]


def need(partner):
    if partner in SKIP:
        pytest.skip(f"{partner} left out by VIBROFRIC_SKIP_PARTNERS")
    if partner in ("fmi-sim", "fmi-sim-windows") and partners.fmi_sim_exe() is None:
        pytest.fail("fmi-sim is not installed (tests/all.sh installs it; or set FMI_SIM)")
    if partner == "fmi-sim-windows" and partners.fmi_sim_windows_exe() is None:
        pytest.fail("fmi-sim for Windows is not built (tests/all.sh builds it; or set FMI_SIM_WINDOWS)")


def check(partner, ident, times, values, grid):
    fmu = fmu_path(ident)
    points, steps, ends = grid
    np.testing.assert_array_equal(times, ends, err_msg=f"{partner} time grid")
    # Strict: the same communication grid, bit for bit.
    ref = partners.run_fmpy_replay(fmu, points, steps)
    worst, worst_rel, where = partners.disagreement(ref, values)
    print(f"DISAGREEMENT same-grid {partner} {ident}: {worst:.3g} x bound, "
          f"max relative {worst_rel:.3g} at {where}")
    assert worst <= 1.0, f"{partner} {ident}: {where} disagrees with fmpy by {worst:.3g} × the bound"
    assert any(np.ptp(v) > 0 for v in ref.values()), f"{ident}: every output constant"
    # The nominal grid k·h: a few ulps from the partner's, the same results.
    t_nom, nom = nominal(ident)
    np.testing.assert_allclose(times, t_nom, rtol=1e-12, atol=0)
    worst, worst_rel, where = partners.disagreement(nom, values)
    print(f"DISAGREEMENT nominal-grid {partner} {ident}: {worst:.3g} x bound, "
          f"max relative {worst_rel:.3g} at {where}")
    assert worst <= 1.0, f"{partner} {ident}: {where} disagrees with fmpy's k·h grid by {worst:.3g} × the bound"


@pytest.mark.parametrize("ident", IDENTIFIERS)
def test_libcosim_agrees_with_fmpy(ident):
    need("libcosim")
    times, values = partners.run_libcosim(fmu_path(ident), H, N)
    # Integer nanoseconds: k·100000 ns exactly, converted to double at each point.
    check("libcosim", ident, times, values, partners.libcosim_grid(H, N))


@pytest.mark.parametrize("ident", IDENTIFIERS)
def test_ecos_agrees_with_fmpy(ident, capfd):
    need("ecos")
    times, values, _ = partners.run_ecos(fmu_path(ident), H, N, capfd)
    grid = partners.accumulated_grid(H, N)
    assert grid[2][-1] != N * H, "ecos accumulates t += h: its time drifts"
    check("ecos", ident, times, values, grid)


@pytest.mark.parametrize("ident", IDENTIFIERS)
def test_fmi_sim_agrees_with_fmpy(ident, tmp_path):
    need("fmi-sim")
    times, values, _ = partners.run_fmi_sim(fmu_path(ident), H, N, tmp_path)
    # fmi-sim computes t_k = k·h: the nominal grid itself.
    check("fmi-sim", ident, times, values, partners.multiplied_grid(H, N))


@pytest.mark.parametrize("ident", IDENTIFIERS)
def test_fmi_sim_runs_the_fmi3_edition_as_the_fmi2_one(ident, tmp_path):
    """fmi-sim imports FMI 3.0 Co-Simulation too: the FMI 3.0 edition of every FMU gives it the
    same numbers as the FMI 2.0 one, bit for bit, on the same grid."""
    need("fmi-sim")
    fmu3 = pathlib.Path(fmu_path(ident)).parent / "fmi3" / f"{ident}.fmu"
    assert fmu3.exists(), fmu3
    t2, v2, _ = partners.run_fmi_sim(fmu_path(ident), H, N, tmp_path)
    t3, v3, _ = partners.run_fmi_sim(str(fmu3), H, N, tmp_path)
    assert np.array_equal(t2, t3)
    for name in v2:
        assert np.array_equal(v2[name], v3[name]), (ident, name)


@pytest.mark.parametrize("ident", IDENTIFIERS)
def test_fmi_sim_model_exchange_converges_to_co_simulation_with_first_order(ident, tmp_path):
    """fmi-sim imports Model Exchange (FMI 2.0 and 3.0) and integrates the states with forward
    Euler: at t = 2 ms the states x, v_x, s_x converge to the FMU's own Co-Simulation run (rtol
    1e-10) with first order (halving the step halves the error) or are exact (the position a
    held v_d imposes); the FMI 3.0 edition gives the same numbers bit for bit."""
    need("fmi-sim")
    from fmpy import simulate_fmu

    stop, h = ME_STOP, ME_STEPS[0]
    fmu = fmu_path(ident)
    names = ["x", "v_x", "s_x"]
    ref = simulate_fmu(fmu, stop_time=stop, output_interval=1e-4, relative_tolerance=1e-10,
                       output=names)
    coarse = partners.run_fmi_sim_model_exchange(fmu, h, stop, tmp_path)
    fine = partners.run_fmi_sim_model_exchange(fmu, h / 2, stop, tmp_path)
    for n in names:
        scale = float(np.max(np.abs(ref[n])))
        if scale == 0.0:
            assert coarse[n] == fine[n] == 0.0, (ident, n)
            continue
        e1, e2 = (abs(r[n] - ref[n][-1]) / scale for r in (coarse, fine))
        print(f"{ident} {n}: forward Euler error {e1:.2e} (h = {h:g}), ratio {e2 / max(e1, 1e-300):.3f}")
        if e1 <= 1e-9:
            assert e2 <= 1e-9, (ident, n, e1, e2)
        else:
            assert e1 <= 5e-2 and 0.15 <= e2 / e1 <= 0.65, (ident, n, e1, e2)
    fmu3 = pathlib.Path(fmu).parent / "fmi3" / f"{ident}.fmu"
    fine3 = partners.run_fmi_sim_model_exchange(str(fmu3), h / 2, stop, tmp_path)
    assert fine3 == fine, ident


@pytest.mark.parametrize("ident", IDENTIFIERS)
def test_fmi_sim_on_windows_writes_the_linux_csv_files(ident, tmp_path):
    """fmi-sim 0.7.0 built for Windows (x86_64-pc-windows-gnu), run by Wine in the prefix of
    tests/cross/setup.sh, imports each FMU its own way: its unzip into Windows' Temp, its platform
    choice (binaries/win64, binaries/x86_64-windows), its resource URI (file:///Z:/...), its
    LoadLibrary. Both editions, Co-Simulation at the grid above and Model Exchange at the Model
    Exchange test's Euler steps: each CSV file is the Linux fmi-sim's byte for byte."""
    need("fmi-sim-windows")
    fmu2 = pathlib.Path(fmu_path(ident))
    fmu3 = fmu2.parent / "fmi3" / fmu2.name
    env = partners.wine_env()
    runs = [(fmu, "co-simulation", H, N * H) for fmu in (fmu2, fmu3)]
    runs += [(fmu, "model-exchange", h, ME_STOP) for fmu in (fmu2, fmu3) for h in ME_STEPS]
    points = values = 0
    for fmu, interface, h, stop in runs:
        linux, windows = partners.fmi_sim_csv_linux_and_windows(fmu, interface, h, stop,
                                                                tmp_path, env)
        rows = [r.split(",") for r in linux.decode().splitlines()[1:] if r]
        # Every grid point from 0 to stop (Model Exchange adds a row at each event it handles).
        assert len(rows) >= round(stop / h) + 1 and float(rows[-1][0]) == pytest.approx(stop), len(rows)
        if windows != linux:
            w, lx = windows.splitlines(), linux.splitlines()
            k = next((k for k, p in enumerate(zip(w, lx)) if p[0] != p[1]), min(len(w), len(lx)))
            pytest.fail(f"{fmu} {interface} h = {h}: Windows fmi-sim's CSV differs from Linux "
                        f"fmi-sim's at line {k} of {len(lx)}: {w[k:k + 1]} against {lx[k:k + 1]}")
        points += len(rows)
        values += sum(len(r) - 1 for r in rows)
    print(f"WINDOWS-FMI-SIM {ident}: {len(runs)} runs, {points} points, {values} values: "
          "Windows (Wine) = Linux, byte for byte")


def test_ecos_errors_are_seen_through_the_log_with_its_full_path_instance_name(capfd):
    """Negative control of the ecos check: ecos ignores the status of a refused call; the FMU's
    log line, naming ecos' instance name (the FMU's full path), is what reveals it."""
    need("ecos")
    from ecospy.EcosSimulation import EcosSimulation
    from ecospy.EcosSimulationStructure import EcosSimulationStructure
    from ecospy.lib import EcosLib

    fmu = fmu_path("PaperLongitudinal")
    EcosLib.set_log_level("debug")
    capfd.readouterr()
    ss = EcosSimulationStructure()
    ss.add_model("m", fmu)
    sim = EcosSimulation(structure=ss, step_size=H)
    try:
        sim.set_real("m::v_d", float("nan"))
        sim.init()
        sim.step(1)  # ecos carries on
        sim.terminate()
    finally:
        sim.free()
    out = capfd.readouterr().out
    assert "fmi2Error fmi2SetReal: v_d = NaN: must be finite" in out, out
    assert f'[instance "{os.path.abspath(fmu)}"]' in out, out
    assert any(m in out for m in partners.ECOS_ERROR_MARKS)


def test_fmi_sim_errors_are_seen_through_its_log_and_exit_status(tmp_path):
    """Negative control of the fmi-sim check: a refused start value (k_t = -1) shows as the FMU's
    log line through fmi-sim's logger, and fmi-sim exits non-zero."""
    need("fmi-sim")
    p = partners.run_fmi_sim(fmu_path("PaperLongitudinal"), H, 3, tmp_path,
                             extra=["--init-values", "k_t=-1"])
    assert p.returncode != 0
    assert "ERROR [logger] fmi2SetReal: k_t = -1: must be finite and > 0" in p.stderr, p.stderr


def test_importer_habits_do_not_change_the_results(open_fmu):
    """fmpy's FMU2Slave driven as a sloppy master — visible = 1, a 1000-character instance name,
    toleranceDefined = 0, stopTimeDefined = 0 — and as a careful one — visible = 0, a short name,
    the default tolerance given explicitly, stopTime defined — on the same t += h grid, each
    ending with a shortened last step at a stop time that is not a multiple of h: equal to the
    partners' bound. Against exact k·h points, the same bound. (Resource location
    variants, names up to 100000 characters and the acceptance of rounded communication points
    are tested in tests/fmi_calls.rs.)"""
    ident = "VibratingContact"
    opened_fmu = open_fmu(fmu_path(ident))
    md = opened_fmu.md
    outs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    names = [v.name for v in md.modelVariables if v.causality == "output"]
    n, h = 1000, 1e-4
    stop = n * h + h / 3

    def run(name, visible, sloppy, accumulate):
        s = opened_fmu.instance(name, visible=visible)
        if sloppy:
            s.setupExperiment(startTime=0.0)  # toleranceDefined = 0, stopTimeDefined = 0
        else:
            s.setupExperiment(tolerance=float(md.defaultExperiment.tolerance), startTime=0.0,
                              stopTime=stop)
        s.enterInitializationMode()
        s.exitInitializationMode()
        t, rows = 0.0, []
        for k in range(n):
            tk = t if accumulate else k * h
            s.doStep(currentCommunicationPoint=tk, communicationStepSize=h)
            t += h
            rows.append(s.getReal(outs))
        last = t if accumulate else n * h
        assert last < stop
        s.doStep(currentCommunicationPoint=last, communicationStepSize=stop - last)
        rows.append(s.getReal(outs))
        s.terminate()
        opened_fmu.free(s)
        rows = np.array(rows)
        return {nm: rows[:, k] for k, nm in enumerate(names)}, t

    sloppy, t_end = run("s" * 1000, True, True, True)
    careful, _ = run("careful", False, False, True)
    exact, _ = run("exact", False, False, False)
    assert t_end != n * h, "the master's time drifted"
    worst, worst_rel, where = partners.disagreement(careful, sloppy)
    print(f"DISAGREEMENT habits {ident}: {worst:.3g} x bound, max relative {worst_rel:.3g} at {where}")
    assert worst <= 1.0, (where, worst)
    worst, worst_rel, where = partners.disagreement(exact, sloppy)
    print(f"DISAGREEMENT habits-vs-exact-grid {ident}: {worst:.3g} x bound, "
          f"max relative {worst_rel:.3g} at {where}")
    assert worst <= 1.0, (where, worst)


def test_partner_versions_are_the_documented_ones():
    """docs/interoperability.md states these versions; a pin change must update it."""
    import ctypes
    import importlib.metadata as md
    import pathlib
    import subprocess

    doc = (pathlib.Path(__file__).resolve().parents[2] / "docs" / "interoperability.md").read_text()
    found = {"fmpy": md.version("fmpy")}
    if "libcosim" not in SKIP:
        import libcosimpy

        lib = ctypes.CDLL(str(pathlib.Path(libcosimpy.__file__).parent / "libcosimc" / "libcosimc.so"))

        class Version(ctypes.Structure):
            _fields_ = [("major", ctypes.c_int), ("minor", ctypes.c_int), ("patch", ctypes.c_int)]

        lib.cosim_libcosim_version.restype = Version
        v = lib.cosim_libcosim_version()
        found["libcosimpy"] = md.version("libcosimpy")
        found["libcosim"] = f"{v.major}.{v.minor}.{v.patch}"
    if "ecos" not in SKIP:
        from ecospy.lib import EcosLib

        found["ecospy"] = md.version("ecospy")
        found["ecos"] = repr(EcosLib.version()).lstrip("v")
    if "fmi-sim" not in SKIP and partners.fmi_sim_exe() is not None:
        # fmi-sim 0.7.0 prints its version as an error ("Error: fmi-sim 0.7.0", exit status 1).
        p = subprocess.run([str(partners.fmi_sim_exe()), "--version"], capture_output=True,
                           text=True, env=dict(os.environ, RUST_BACKTRACE="0"))
        words = (p.stdout + p.stderr).split()
        found["fmi-sim"] = words[words.index("fmi-sim") + 1]
    if "fmusim" not in SKIP and partners.fmusim_exe() is not None and partners.fmusim_version():
        found["fmusim"] = partners.fmusim_version()
    for name, version in found.items():
        assert f"{name} {version}" in doc, f"docs/interoperability.md does not state {name} {version}"


def test_known_difference_fmi_sim_rejects_standard_scalar_variable_attributes(tmp_path):
    """fmi-sim's parser knows only name, valueReference, description, causality, variability and
    initial on a ScalarVariable: an attribute the FMI 2.0 schema allows, such as
    canHandleMultipleSetPerTimeInstant on an input, makes it refuse the FMU, while fmpy's
    validator accepts it. The standard wins: our FMUs may carry such attributes. Today they
    carry none (the fmi-sim runs above pass); this test pins the partner's limitation so that a
    future failure of those runs is recognised."""
    need("fmi-sim")
    import subprocess
    import zipfile

    from fmpy.validation import validate_fmu

    src = fmu_path("VibratingContact")
    dst = tmp_path / "VibratingContact.fmu"
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w", zipfile.ZIP_DEFLATED) as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == "modelDescription.xml":
                xml = data.decode()
                assert "canHandleMultipleSetPerTimeInstant" not in xml
                xml = xml.replace('causality="input"',
                                  'causality="input" canHandleMultipleSetPerTimeInstant="false"', 1)
                assert "canHandleMultipleSetPerTimeInstant" in xml
                data = xml.encode()
            zout.writestr(item, data)
    assert validate_fmu(str(dst)) == []
    p = subprocess.run(
        [str(partners.fmi_sim_exe()), "--model", str(dst), "--output-file", str(tmp_path / "o.csv"),
         "co-simulation", "--output-interval", "1e-3", "-s", "0", "-f", "2e-3"],
        capture_output=True, text=True, env=dict(os.environ, RUST_BACKTRACE="0"), timeout=120)
    assert p.returncode != 0
    assert 'unknown field "canHandleMultipleSetPerTimeInstant" in element "ScalarVariable"' in p.stderr, p.stderr


# ---- a string of contacts -----------------------------------------------------------------------

STRING_SECTIONS = 8
_string = {}


def string_fmus(tmp_path_factory):
    """The small string's FMUs (FMI 2.0, FMI 3.0), exported once per session."""
    if "fmus" not in _string:
        out = tmp_path_factory.mktemp("string")
        _string["fmus"] = partners.export_string_fmus(DIST, vibrofric_exe(), out, STRING_SECTIONS)
    return _string["fmus"]


def string_nominal(fmu2):
    """fmpy's FMI 2.0 Co-Simulation of the string on the nominal grid k·h (simulate_fmu)."""
    if "nominal" not in _string:
        _string["nominal"] = partners.run_fmpy(fmu2, H, N)
    return _string["nominal"]


def first_difference(ref, other):
    """The first output element and step where two runs differ in bits, or None."""
    for name, b in ref.items():
        a = other[name]
        assert a.shape == b.shape, (name, a.shape, b.shape)
        bad = np.flatnonzero(a.view(np.uint64) != b.view(np.uint64))
        if bad.size:
            k = int(bad[0])
            return f"{name} at step {k + 1}: {a[k]!r} against {b[k]!r}"
    return None


def check_string(partner, values, times, grid, fmu2):
    """Bit for bit: against fmpy's FMI 2.0 run replaying the partner's grid, and against
    fmpy's run on the nominal grid k·h."""
    points, steps, ends = grid
    np.testing.assert_array_equal(times, ends, err_msg=f"{partner} time grid")
    ref = partners.run_fmpy_replay(fmu2, points, steps)
    names = [f"{v}[{i}]" for v in ("x", "v_x", "s_x", "F_Fx", "F_Fx_step") for i in range(1, STRING_SECTIONS + 1)]
    assert set(names) <= set(ref), sorted(set(names) - set(ref))
    assert set(values) == set(ref), sorted(set(values) ^ set(ref))
    moving = [n for n in names if np.ptp(ref[n]) > 0]
    assert len(moving) == len(names), f"outputs constant throughout: {sorted(set(names) - set(moving))}"
    diff = first_difference(ref, values)
    assert diff is None, f"{partner}: {diff} (fmpy, the same grid)"
    t_nom, nom = string_nominal(fmu2)
    np.testing.assert_allclose(times, t_nom, rtol=1e-12, atol=0)
    diff = first_difference(nom, values)
    assert diff is None, f"{partner}: {diff} (fmpy, the grid k·h)"
    print(f"STRING {partner}: {len(values)} outputs x {len(times)} steps bit for bit as fmpy's")


def test_string_libcosim_agrees_with_fmpy_bit_for_bit(tmp_path_factory):
    """A string of 8 sections (FMI 2.0 scalars x[1] ... x[8]) in libcosim: every output
    element after every step is fmpy's, bit for bit."""
    need("libcosim")
    fmu2, _ = string_fmus(tmp_path_factory)
    times, values = partners.run_libcosim(fmu2, H, N)
    check_string("libcosim", values, times, partners.libcosim_grid(H, N), fmu2)


def test_string_ecos_agrees_with_fmpy_bit_for_bit(tmp_path_factory, capfd):
    need("ecos")
    fmu2, _ = string_fmus(tmp_path_factory)
    times, values, _ = partners.run_ecos(fmu2, H, N, capfd)
    check_string("ecos", values, times, partners.accumulated_grid(H, N), fmu2)


def test_string_fmi_sim_agrees_with_fmpy_bit_for_bit(tmp_path_factory, tmp_path):
    need("fmi-sim")
    fmu2, _ = string_fmus(tmp_path_factory)
    times, values, _ = partners.run_fmi_sim(fmu2, H, N, tmp_path)
    check_string("fmi-sim", values, times, partners.multiplied_grid(H, N), fmu2)


def test_string_fmpy_fmi3_arrays_agree_with_fmpy_fmi2_bit_for_bit(tmp_path_factory):
    """The FMI 3.0 edition through fmpy's FMU3Slave, each output an array read whole: element
    i of each array is the FMI 2.0 edition's scalar name[i], bit for bit."""
    fmu2, fmu3 = string_fmus(tmp_path_factory)
    grid = partners.multiplied_grid(H, N)
    values = partners.run_fmpy3(fmu3, grid[0], grid[1])
    check_string("fmpy FMI 3.0", values, grid[2], grid, fmu2)


def test_string_fmi_sim_on_windows_writes_the_linux_csv_file(tmp_path_factory, tmp_path):
    """fmi-sim built for Windows, under Wine, runs the string's FMI 2.0 edition (its Windows
    library) and writes the Linux fmi-sim's CSV file byte for byte."""
    need("fmi-sim-windows")
    fmu2, _ = string_fmus(tmp_path_factory)
    linux, windows = partners.fmi_sim_csv_linux_and_windows(fmu2, "co-simulation", H, N * H,
                                                            tmp_path, partners.wine_env())
    rows = [r for r in linux.decode().splitlines()[1:] if r]
    assert len(rows) == N + 1, len(rows)
    assert windows == linux, "Windows fmi-sim's CSV differs from Linux fmi-sim's"
    print(f"WINDOWS-FMI-SIM string: {len(rows)} rows: Windows (Wine) = Linux, byte for byte")


def test_known_difference_fmi_sim_reads_fmi3_arrays_as_scalars(tmp_path_factory, tmp_path):
    """fmi-sim 0.7.0 reads every FMI 3.0 output with nValues = 1: the string's FMI 3.0 edition,
    whose outputs are arrays, refuses the call (naming the count it holds) and fmi-sim stops.
    Its FMI 2.0 edition (scalars x[1] ...) is the one to give fmi-sim (tested above); fmpy reads
    the arrays (test_string_fmpy_fmi3_arrays_agree_with_fmpy_fmi2_bit_for_bit). This pins the
    partner's limitation so that a release which lifts it is noticed."""
    need("fmi-sim")
    _, fmu3 = string_fmus(tmp_path_factory)
    import subprocess

    args = [str(partners.fmi_sim_exe()),
            *partners.fmi_sim_args(fmu3, tmp_path / "o.csv", "co-simulation", H, 3 * H)]
    p = subprocess.run(args, capture_output=True, text=True, timeout=120,
                       env=dict(os.environ, RUST_BACKTRACE="0", RUST_LOG="info"))
    assert p.returncode != 0
    assert (f"fmi3GetFloat64: nValues = 1: the 1 value references hold {STRING_SECTIONS} values"
            in p.stderr), p.stderr[-2000:]


# ---- fmusim and the FMU Compliance Checker (optional) -------------------------------------------
#
# Neither is on PyPI or in Debian, and both are built from their sources (fmusim: Rust with
# SUNDIALS and libxml2; the Checker: C with the FMI Library): the tests run when they are found
# ($FMUSIM or `fmusim` on PATH, $FMU_CHECK or `fmuCheck.linux64` on PATH) and are skipped,
# with the reason, otherwise. docs/interoperability.md says how they were built and run.


def need_optional(tool):
    if tool in SKIP:
        pytest.skip(f"{tool} left out by VIBROFRIC_SKIP_PARTNERS")
    if tool == "fmusim":
        exe = partners.fmusim_exe()
        if exe is None:
            pytest.skip("fmusim not found: set FMUSIM or put fmusim (github.com/modelica/fmusim) on PATH")
        if partners.fmusim_version() is None:
            # The Reference FMUs' former C fmusim has another command line.
            why = f"{exe} is not modelica/fmusim's command line (`fmusim --version`: `fmusim 0.8.0`)"
            if os.environ.get("FMUSIM"):
                pytest.fail(why)
            pytest.skip(why)
    elif partners.fmu_check_exe() is None:
        pytest.skip("the FMU Compliance Checker not found: set FMU_CHECK or put fmuCheck.linux64 on PATH")


def fmi3_path(ident):
    fmu3 = pathlib.Path(fmu_path(ident)).parent / "fmi3" / f"{ident}.fmu"
    assert fmu3.exists(), fmu3
    return str(fmu3)


@pytest.mark.parametrize("ident", IDENTIFIERS)
def test_fmusim_agrees_with_fmpy(ident, tmp_path):
    """fmusim's Co-Simulation: points k·h, steps t_(k+1) − t_k, as fmpy's simulate_fmu."""
    need_optional("fmusim")
    grid = partners.differenced_grid(H, N)
    columns = partners.run_fmusim_checked(fmu_path(ident), H, N, tmp_path)
    values = partners.outputs_after_each_step(columns, fmu_path(ident), grid[2])
    check("fmusim", ident, grid[2], values, grid)


@pytest.mark.parametrize("ident", IDENTIFIERS)
def test_fmusim_runs_the_fmi3_edition_as_the_fmi2_one(ident, tmp_path):
    need_optional("fmusim")
    ends = partners.differenced_grid(H, N)[2]
    v2 = partners.outputs_after_each_step(partners.run_fmusim_checked(fmu_path(ident), H, N, tmp_path),
                                          fmu_path(ident), ends)
    v3 = partners.outputs_after_each_step(partners.run_fmusim_checked(fmi3_path(ident), H, N, tmp_path),
                                          fmu_path(ident), ends)
    for name in v2:
        assert np.array_equal(v2[name].view(np.uint64), v3[name].view(np.uint64)), (ident, name)


@pytest.mark.parametrize("ident", IDENTIFIERS)
def test_fmusim_validate_finds_no_problem(ident):
    """`fmusim validate`: the ZIP archive's paths, the model description against the FMI
    schema (libxml2) and fmusim's own rules, both editions."""
    need_optional("fmusim")
    for fmu in (fmu_path(ident), fmi3_path(ident)):
        p = subprocess.run([str(partners.fmusim_exe()), "validate", fmu],
                           capture_output=True, text=True, timeout=120)
        text = p.stdout + p.stderr
        assert p.returncode == 0 and "error" not in text.lower(), text
        assert "Validating model description" in text, text


@pytest.mark.parametrize("ident", IDENTIFIERS)
def test_fmu_check_agrees_with_fmpy(ident, tmp_path):
    """The Compliance Checker's XML check (no warning, no error) and Co-Simulation: t += h,
    the last step to the stop time n·h."""
    need_optional("fmu-check")
    grid = partners.fmu_check_grid(H, N * H)
    columns = partners.run_fmu_check_cs(fmu_path(ident), H, N, tmp_path)
    values = partners.outputs_after_each_step(columns, fmu_path(ident), grid[2])
    check("fmu-check", ident, grid[2], values, grid)


def broken_copy(tmp_path):
    """VibratingContact.fmu with its first output's causality misspelt "outptu"."""
    import zipfile

    src, fmu = fmu_path("VibratingContact"), tmp_path / "Broken.fmu"
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(fmu, "w", zipfile.ZIP_DEFLATED) as zout:
        for name in zin.namelist():
            data = zin.read(name)
            if name == "modelDescription.xml":
                assert b'causality="output"' in data
                data = data.replace(b'causality="output"', b'causality="outptu"', 1)
            zout.writestr(name, data)
    return fmu


def test_fmusim_validate_reports_a_broken_model_description(tmp_path):
    """The negative control of test_fmusim_validate_finds_no_problem."""
    need_optional("fmusim")
    p = subprocess.run([str(partners.fmusim_exe()), "validate", str(broken_copy(tmp_path))],
                       capture_output=True, text=True, timeout=120)
    assert ("error: Element 'ScalarVariable', attribute 'causality': [facet 'enumeration'] The value "
            "'outptu' is not an element of the set") in p.stderr, p.stderr


def test_fmu_check_reports_a_broken_model_description_in_its_log_only(tmp_path):
    """The negative control of the Checker's clean log: the error is in the log and the summary,
    while the exit status stays 0 (hence the log is read)."""
    need_optional("fmu-check")
    status, log, _ = partners.run_fmu_check(broken_copy(tmp_path), tmp_path, "-k", "xml")
    assert status == 0
    assert ("[ERROR][FMI2XML] XML element 'ScalarVariable': could not parse value for enumeration "
            "attribute 'causality'='outptu'") in log, log
    assert log.strip().endswith("Checker reported:\n\t0 Warning(s)\n\t1 Error(s)"), log


def test_string_fmusim_agrees_with_fmpy_bit_for_bit(tmp_path_factory, tmp_path):
    need_optional("fmusim")
    fmu2, _ = string_fmus(tmp_path_factory)
    grid = partners.differenced_grid(H, N)
    columns = partners.run_fmusim_checked(fmu2, H, N, tmp_path)
    values = partners.outputs_after_each_step(columns, fmu2, grid[2])
    check_string("fmusim", values, grid[2], grid, fmu2)


def test_string_fmusim_fmi3_arrays_agree_with_fmpy_fmi2_bit_for_bit(tmp_path_factory, tmp_path):
    """fmusim reads the FMI 3.0 edition's arrays whole and writes each as one CSV cell of
    space-separated numbers: element i is the FMI 2.0 edition's name[i], bit for bit."""
    need_optional("fmusim")
    fmu2, fmu3 = string_fmus(tmp_path_factory)
    grid = partners.differenced_grid(H, N)
    columns = partners.run_fmusim_checked(fmu3, H, N, tmp_path)
    values = partners.outputs_after_each_step(columns, fmu2, grid[2])
    check_string("fmusim FMI 3.0", values, grid[2], grid, fmu2)


def test_string_fmu_check_agrees_with_fmpy_bit_for_bit(tmp_path_factory, tmp_path):
    need_optional("fmu-check")
    fmu2, _ = string_fmus(tmp_path_factory)
    grid = partners.fmu_check_grid(H, N * H)
    columns = partners.run_fmu_check_cs(fmu2, H, N, tmp_path)
    values = partners.outputs_after_each_step(columns, fmu2, grid[2])
    check_string("fmu-check", values, grid[2], grid, fmu2)


def test_known_difference_fmusim_stops_every_fmi3_model_exchange_run(tmp_path):
    """fmusim 0.8.0 stops every FMI 3.0 Model Exchange run with `error: FMI call failed` right
    after fmi3InstantiateModelExchange returned an instance: fmi-rs (d94fd12, fmusim's
    submodule) tests the FMU3's instance field, not yet set at that point, instead of the
    instance returned. The FMI 2.0 edition runs. This pins the partner's limitation so that a
    release which lifts it is noticed."""
    need_optional("fmusim")
    p, _ = partners.run_fmusim(fmi3_path("VibratingContact"), 1e-3, 2, tmp_path, "me", ("--log-fmi-calls",))
    assert p.returncode != 0
    assert "fmi3InstantiateModelExchange(" in p.stderr and ") -> 0x0\n" not in p.stderr, p.stderr
    assert p.stderr.rstrip().endswith("error: FMI call failed"), p.stderr
    p, columns = partners.run_fmusim(fmu_path("VibratingContact"), 1e-3, 2, tmp_path, "me")
    assert p.returncode == 0 and columns["time"][-1] == 2e-3, p.stderr
