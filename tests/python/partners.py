"""Runs an FMU in the importers (fmpy, libcosim, ecos, fmi-sim) for n communication steps of
nominal size h and returns the outputs after each step as numpy arrays by name.

Each runner uses the importer as its users do: its own unpacking, instance name, resource URI,
experiment set-up and time keeping, which differ by a few ulps (fmpy's simulate_fmu: points k·h,
steps (k+1)·h − k·h; libcosim: integer nanoseconds; ecos: t += h; fmi-sim: points k·h, steps h).
The *_grid functions give those exact points, steps and end times, and run_fmpy_replay drives
fmpy's FMU2Slave through them. Only outputs are compared; start values are the FMU's own.
"""

import csv
import io
import os
import pathlib
import re
import shutil
import subprocess

import numpy as np
from fmpy import read_model_description, simulate_fmu

# Agreement criterion: |a − b| ≤ REL·|b| + ABS_FLOOR·scale, where scale is max |b| of that output
# over the run (fmpy's values b); for an output that is zero throughout, the floor is 1e-300.
REL = 1e-9
ABS_FLOOR = 1e-9


def outputs_of(fmu):
    md = read_model_description(fmu)
    return [(v.name, v.valueReference) for v in md.modelVariables if v.causality == "output"]


def run_fmpy(fmu, h, n):
    names = [name for name, _ in outputs_of(fmu)]
    res = simulate_fmu(fmu, stop_time=n * h, output_interval=h, step_size=h, output=names)
    assert len(res) == n + 1, (len(res), n)
    return res["time"][1:], {name: res[name][1:] for name in names}


def run_fmpy_replay(fmu, points, steps, instance_name="replay"):
    """fmpy's FMU2Slave driven through exactly the communication points and step sizes a
    partner used (toleranceDefined = 0, stopTimeDefined = 0); outputs after each step."""
    from conftest import opened

    outs = outputs_of(fmu)
    with opened(fmu) as o:
        s = o.instance(instance_name)
        s.setupExperiment(startTime=0.0)
        s.enterInitializationMode()
        s.exitInitializationMode()
        rows = []
        for t, h in zip(points, steps):
            s.doStep(currentCommunicationPoint=float(t), communicationStepSize=float(h))
            rows.append(s.getReal([vr for _, vr in outs]))
        s.terminate()
    rows = np.array(rows)
    return {name: rows[:, k] for k, (name, _) in enumerate(outs)}


def libcosim_grid(h, n):
    """libcosim's communication points and steps: integer nanoseconds converted as its
    cosim::to_double_time_point (ns / 1e9) and to_double_duration (difference of two points)."""
    h_ns = round(h * 1e9)
    t = np.array([k * h_ns / 1e9 for k in range(n + 1)])
    return t[:-1], np.diff(t), t[1:]


def accumulated_grid(h, n):
    """A master's t += h."""
    t, points, ends = 0.0, [], []
    for _ in range(n):
        points.append(t)
        t += h
        ends.append(t)
    return np.array(points), np.full(n, h), np.array(ends)


def multiplied_grid(h, n):
    """A master's t_k = k·h (fmpy's simulate_fmu, fmi-sim)."""
    return np.arange(n) * h, np.full(n, h), np.arange(1, n + 1) * h


def run_libcosim(fmu, h, n, instance_name="libcosim"):
    from libcosimpy.CosimEnums import CosimErrorCode
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimSlave import CosimLocalSlave

    # libcosim fails a step whose fmi2DoStep does not return fmi2OK (checked below) and logs the
    # FMU's messages; warnings and errors only, to keep the test output short.
    log_output_level(CosimLogLevel.WARNING)
    h_ns = round(h * 1e9)
    assert abs(h_ns - h * 1e9) < 1e-6, f"libcosim's time is integer nanoseconds: h = {h}"
    ex = CosimExecution.from_step_size(step_size=h_ns)
    idx = ex.add_local_slave(CosimLocalSlave(fmu_path=str(fmu), instance_name=instance_name))
    assert idx >= 0
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    names = {v.name.decode(): v.reference for v in ex.slave_variables(idx)}
    outs = outputs_of(fmu)
    for name, vr in outs:
        assert names[name] == vr, name
    refs = [vr for _, vr in outs]
    times, rows = [], []
    for _ in range(n):
        assert ex.step(1), f"libcosim step failed: {ex.status()}"
        st = ex.status()
        assert st.error_code == CosimErrorCode.SUCCESS.value, st
        times.append(st.current_time / 1e9)
        rows.append(obs.last_real_values(idx, refs))
    rows = np.array(rows)
    return np.array(times), {name: rows[:, k] for k, (name, _) in enumerate(outs)}


ECOS_ERROR_MARKS = ("fmi2Error", "fmi2Fatal", "fmi2Discard")


def run_ecos(fmu, h, n, capfd):
    """ecos ignores fmi2DoStep's status: the FMU's log lines (forwarded by ecos at log level
    debug, on stdout) are checked for an error status instead."""
    from ecospy.EcosSimulation import EcosSimulation
    from ecospy.EcosSimulationStructure import EcosSimulationStructure
    from ecospy.lib import EcosLib

    EcosLib.set_log_level("debug")
    capfd.readouterr()
    ss = EcosSimulationStructure()
    ss.add_model("m", str(fmu))
    sim = EcosSimulation(structure=ss, step_size=h)
    try:
        assert sim.init(), EcosLib.get_last_error()
        outs = outputs_of(fmu)
        times, rows = [], []
        for _ in range(n):
            times.append(sim.step(1))
            rows.append([sim.get_real(f"m::{name}") for name, _ in outs])
        sim.terminate()
    finally:
        sim.free()
    log = capfd.readouterr()
    text = log.out + log.err
    bad = [l for l in text.splitlines() if any(m in l for m in ECOS_ERROR_MARKS)]
    assert not bad, "\n".join(bad)
    rows = np.array(rows)
    return np.array(times), {name: rows[:, k] for k, (name, _) in enumerate(outs)}, text


def fmi_sim_exe():
    """$FMI_SIM (tests/all.sh sets it), else the one tests/all.sh installed (in
    $VIBROFRIC_CACHE, default ~/.cache/vibrofric), else PATH's."""
    if os.environ.get("FMI_SIM"):
        return pathlib.Path(os.environ["FMI_SIM"])
    cache = pathlib.Path(os.environ.get("VIBROFRIC_CACHE", pathlib.Path.home() / ".cache" / "vibrofric"))
    installed = sorted(cache.glob("fmi-sim-*/bin/fmi-sim"))
    if installed:
        return installed[-1]
    exe = shutil.which("fmi-sim")
    return pathlib.Path(exe) if exe else None


def fmi_sim_args(fmu, out, interface, h, stop):
    """fmi-sim's command line after the executable: `interface` is co-simulation or
    model-exchange, `h` the output interval (and Model Exchange's Euler step), from 0 to `stop`."""
    return ["--model", str(fmu), "--output-file", str(out), interface,
            "--output-interval", repr(h), "-s", "0", "-f", repr(stop)]


def run_checked(args, env=None):
    """Runs an fmi-sim command (RUST_LOG=info: the FMU's log lines come through the `log` crate,
    "ERROR [logger] ..." for its errors); it must exit 0 and log no error or warning."""
    p = subprocess.run(args, capture_output=True, text=True, timeout=300,
                       env=dict(env or os.environ, RUST_BACKTRACE="0", RUST_LOG="info"))
    assert p.returncode == 0, f"{args}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}"
    bad = [l for l in (p.stdout + p.stderr).splitlines() if "ERROR" in l or "WARN" in l]
    assert not bad, "\n".join(bad)
    return p


def run_fmi_sim(fmu, h, n, tmp_path, extra=()):
    """fmi-sim's Co-Simulation of n steps of h; a run with `extra` arguments is returned as it
    ended (the negative controls), any other must succeed without an error or warning."""
    out = tmp_path / "fmi-sim.csv"
    args = [str(fmi_sim_exe()), *fmi_sim_args(fmu, out, "co-simulation", h, n * h), *extra]
    if extra:
        return subprocess.run(args, capture_output=True, text=True, timeout=300,
                              env=dict(os.environ, RUST_BACKTRACE="0", RUST_LOG="info"))
    p = run_checked(args)
    rows = list(csv.reader(io.StringIO(out.read_text())))
    header = [c.strip() for c in rows[0]]
    data = np.array([[float(x) for x in r] for r in rows[1:] if r])
    col = {name: k for k, name in enumerate(header)}
    t = data[:, col["time"]]
    keep = t > 0.5 * h  # the grid t_k, k ≥ 1
    return t[keep], {name: data[keep, col[name]] for name, _ in outputs_of(fmu)}, p


def disagreement(ref, other):
    """Largest |a − b| / (REL·|b| + ABS_FLOOR·scale) over every output and point (≤ 1 agrees),
    and the largest plain relative difference |a − b| / max(|b|, ABS_FLOOR·scale)."""
    worst, worst_rel, where = 0.0, 0.0, None
    for name, b in ref.items():
        a = other[name]
        assert a.shape == b.shape, (name, a.shape, b.shape)
        scale = float(np.max(np.abs(b))) if np.any(b) else 0.0
        floor = ABS_FLOOR * scale if scale > 0 else 1e-300
        d = np.abs(a - b)
        ratio = d / (REL * np.abs(b) + floor)
        rel = d / np.maximum(np.abs(b), floor)
        k = int(np.argmax(ratio))
        if ratio[k] > worst:
            worst, where = float(ratio[k]), (name, k)
        worst_rel = max(worst_rel, float(np.max(rel)))
    return worst, worst_rel, where




def run_fmi_sim_model_exchange(fmu, h, stop, tmp_path):
    """fmi-sim's Model Exchange: forward Euler with step `h` (its output interval), events
    located on the step grid. Returns the row at `stop` of every output (the last row: after
    the event handling there)."""
    out = tmp_path / "fmi-sim-me.csv"
    run_checked([str(fmi_sim_exe()), *fmi_sim_args(fmu, out, "model-exchange", h, stop)])
    rows = list(csv.reader(io.StringIO(out.read_text())))
    header = [c.strip() for c in rows[0]]
    data = np.array([[float(x) for x in r] for r in rows[1:] if r])
    assert abs(data[-1, header.index("time")] - stop) <= 1e-12, data[-1]
    return {name: data[-1, k] for k, name in enumerate(header)}


def fmi_sim_windows_exe():
    """fmi-sim built for Windows (x86_64-pc-windows-gnu): $FMI_SIM_WINDOWS (tests/all.sh sets
    it), else the one tests/all.sh built into $VIBROFRIC_CACHE (default ~/.cache/vibrofric)."""
    if os.environ.get("FMI_SIM_WINDOWS"):
        return pathlib.Path(os.environ["FMI_SIM_WINDOWS"])
    cache = pathlib.Path(os.environ.get("VIBROFRIC_CACHE", pathlib.Path.home() / ".cache" / "vibrofric"))
    installed = sorted(cache.glob("fmi-sim-*-x86_64-pc-windows-gnu/bin/fmi-sim.exe"))
    return installed[-1] if installed else None


def wine_env():
    """The environment tests/cross/env.sh sets for Wine (its prefix, made by
    tests/cross/setup.sh), read from the script itself."""
    root = pathlib.Path(__file__).resolve().parents[2]
    p = subprocess.run(["bash", "-c", 'source tests/cross/env.sh && env -0'], cwd=root,
                       capture_output=True, check=True)
    return dict(kv.split("=", 1) for kv in p.stdout.decode().split("\0") if "=" in kv)


def windows_path(path):
    """The path Wine gives a Unix file on its drive Z: (the root of the Unix file system)."""
    return "Z:" + str(pathlib.Path(path).resolve()).replace("/", "\\")


def fmi_sim_csv_linux_and_windows(fmu, interface, h, stop, tmp_path, env):
    """The CSV files (bytes) fmi-sim writes for one run on Linux and, built for Windows, under
    Wine (given the FMU and the output file by their Windows paths on drive Z:)."""
    linux, windows = tmp_path / "linux.csv", tmp_path / "windows.csv"
    run_checked([str(fmi_sim_exe()), *fmi_sim_args(fmu, linux, interface, h, stop)])
    args = fmi_sim_args(windows_path(fmu), windows_path(windows), interface, h, stop)
    run_checked(["wine", str(fmi_sim_windows_exe()), *args], env=env)
    return linux.read_bytes(), windows.read_bytes()


def string_scene_text(sections, ident):
    """scenes/drill-string.toml cut to `sections` sections under the model identifier `ident`,
    with start values that move it without any input from the importer (the partners set
    none): the top fed at 0.5 m/s, the wall under each section moving at its own velocity."""
    root = pathlib.Path(__file__).resolve().parents[2]
    text = (root / "scenes" / "drill-string.toml").read_text()
    for old, new in [('model_identifier = "DrillString"', f'model_identifier = "{ident}"'),
                     ("\nsections = 100\n", f"\nsections = {sections}\n"),
                     ("100 sections", f"{sections} sections")]:
        assert old in text, old
        text = text.replace(old, new)
    # [start] is the last table: these lines go into it.
    walls = ", ".join(repr(0.01 * ((-1) ** i) * (1 + i) / sections) for i in range(sections))
    return text + f"v_top = 0.5\nv_sx = [{walls}]\n"


def export_string_fmus(dist, exe, out, sections, ident="DrillStringShort"):
    """A small string FMU in both editions, `out/<ident>.fmu` and `out/fmi3/<ident>.fmu`,
    written by the exporter (`vibrofric export --library`) around the Linux library of
    dist/DrillString.fmu, with the other platforms' libraries of dist's DrillString FMUs added
    (every FMU of an export holds the same libraries, named after its model identifier): the
    libraries dist/ was tested with, Windows' among them for fmi-sim under Wine."""
    import zipfile

    out = pathlib.Path(out)
    scene = out / "scene.toml"
    scene.write_text(string_scene_text(sections, ident))
    src2, src3 = pathlib.Path(dist) / "DrillString.fmu", pathlib.Path(dist) / "fmi3" / "DrillString.fmu"
    lib = out / "libvibrofric.so"
    with zipfile.ZipFile(src2) as z:
        lib.write_bytes(z.read("binaries/linux64/DrillString.so"))
    p = subprocess.run([str(exe), "export", str(scene), "--out", str(out), "--library", str(lib),
                        "--platforms", "linux64"], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    fmus = out / f"{ident}.fmu", out / "fmi3" / f"{ident}.fmu"
    for src, fmu in zip((src2, src3), fmus):
        with zipfile.ZipFile(fmu) as z:
            have = {i.filename: z.read(i.filename) for i in z.infolist()}
        with zipfile.ZipFile(src) as z:
            for name in z.namelist():
                if not name.startswith("binaries/") or name.endswith("/"):
                    continue
                folder, file = name.rsplit("/", 1)
                mine = f"{folder}/{file.replace('DrillString', ident, 1)}"
                if mine in have:
                    assert have[mine] == z.read(name), f"{mine}: not dist's library"
                else:
                    have[mine] = z.read(name)
        with zipfile.ZipFile(fmu, "w", zipfile.ZIP_DEFLATED) as z:
            for name, data in have.items():
                z.writestr(name, data)
    return fmus


def run_fmpy3(fmu, points, steps):
    """fmpy's FMU3Slave through the communication points and step sizes given; each output
    array read whole (`getFloat64([vr], nValues=n)`) and split into the FMI 2.0 edition's
    scalars `name[i]`; outputs after each step."""
    from conftest import opened

    with opened(fmu) as o:
        outs = []
        for v in o.md.modelVariables:
            if v.causality != "output":
                continue
            n = int(np.prod([int(d.start) for d in v.dimensions])) if v.dimensions else None
            outs.append((v.name, v.valueReference, n))
        s = o.instance("fmi3")
        s.enterInitializationMode(startTime=0.0)
        s.exitInitializationMode()
        rows = []
        for t, h in zip(points, steps):
            s.doStep(currentCommunicationPoint=float(t), communicationStepSize=float(h))
            row = {}
            for name, vr, n in outs:
                values = s.getFloat64([vr], nValues=n or 1)
                if n is None:
                    row[name] = values[0]
                else:
                    row.update({f"{name}[{i + 1}]": x for i, x in enumerate(values)})
            rows.append(row)
        s.terminate()
    return {name: np.array([r[name] for r in rows]) for name in rows[0]}


# ---- fmusim and the FMU Compliance Checker: optional, run when installed -----------------------


def optional_exe(variable, name):
    """An optional importer's executable: $variable, else `name` on PATH, else None."""
    if os.environ.get(variable):
        return pathlib.Path(os.environ[variable])
    exe = shutil.which(name)
    return pathlib.Path(exe) if exe else None


def fmusim_exe():
    """fmusim (github.com/modelica/fmusim, the Rust command line tool that took over from the
    Reference FMUs' C fmusim): $FMUSIM, else `fmusim` on PATH."""
    return optional_exe("FMUSIM", "fmusim")


def fmu_check_exe():
    """The FMU Compliance Checker (github.com/modelica-tools/FMUComplianceChecker, FMI 2.0 only):
    $FMU_CHECK, else `fmuCheck.linux64` on PATH."""
    return optional_exe("FMU_CHECK", "fmuCheck.linux64")


def fmusim_version():
    """`fmusim --version` prints `fmusim 0.8.0`; None for another program of that name (the
    Reference FMUs' C fmusim has another command line)."""
    p = subprocess.run([str(fmusim_exe()), "--version"], capture_output=True, text=True, timeout=60)
    m = re.fullmatch(r"fmusim (\d+\.\d+\.\d+)", p.stdout.strip())
    return m.group(1) if p.returncode == 0 and m else None


def read_tool_csv(text):
    """A CSV file of fmusim or the Compliance Checker: columns by name (the Checker quotes the
    names); a cell of space-separated numbers (fmusim's FMI 3.0 array of n values) becomes the
    columns name[1] ... name[n], as the FMI 2.0 edition names them."""
    rows = [r for r in csv.reader(io.StringIO(text)) if r]
    columns = {}
    for k, name in enumerate(c.strip().strip('"') for c in rows[0]):
        cells = [r[k].split() for r in rows[1:]]
        n = len(cells[0])
        assert all(len(c) == n for c in cells), f"{name}: arrays of different lengths"
        for i in range(n):
            columns[name if n == 1 else f"{name}[{i + 1}]"] = np.array([float(c[i]) for c in cells])
    return columns


def differenced_grid(h, n):
    """A master's points t_k = k·h and steps t_(k+1) − t_k (fmpy's simulate_fmu, fmusim)."""
    t = np.arange(n + 1) * h
    return t[:-1], np.diff(t), t[1:]


def fmu_check_grid(h, stop):
    """The Compliance Checker's Co-Simulation loop (src/FMI2/fmi2_cs_sim.c): t += h, and the
    step that would end past stop − 1e-3·h shortened or lengthened to end on stop."""
    t, points, steps, ends = 0.0, [], [], []
    while t < stop:
        t_next = t + h
        step = h
        if t_next > stop - 1e-3 * h:
            step, t_next = stop - t, stop
        points.append(t)
        steps.append(step)
        ends.append(t_next)
        t = t_next
    return np.array(points), np.array(steps), np.array(ends)


def outputs_after_each_step(columns, fmu, ends):
    """The rows after each step (time > 0) of every output of the FMI 2.0 edition `fmu`; the
    time column must be `ends`."""
    t = columns.pop("time")
    keep = t > 0
    np.testing.assert_array_equal(t[keep], ends)
    names = {name for name, _ in outputs_of(fmu)}
    assert set(columns) == names, sorted(set(columns) ^ names)
    return {name: v[keep] for name, v in columns.items()}


def run_fmusim(fmu, h, n, tmp_path, interface="cs", extra=()):
    """fmusim's run of n steps of h (--output-interval h, --stop-time n·h); returns the process
    and the columns of its CSV file."""
    out = tmp_path / "fmusim.csv"
    out.unlink(missing_ok=True)
    args = [str(fmusim_exe()), "simulate", "--interface-type", interface,
            "--output-interval", repr(h), "--stop-time", repr(n * h), "--output-file", str(out),
            *extra, str(fmu)]
    p = subprocess.run(args, capture_output=True, text=True, timeout=300)
    return p, (read_tool_csv(out.read_text()) if p.returncode == 0 else None)


def run_fmusim_checked(fmu, h, n, tmp_path):
    """fmusim's Co-Simulation, which must exit 0 and print nothing (it stops with `error: ...`
    when an FMI call fails)."""
    p, columns = run_fmusim(fmu, h, n, tmp_path)
    assert p.returncode == 0 and not (p.stdout + p.stderr).strip(), p.stdout + p.stderr
    return columns


# The end of the Compliance Checker's log when neither the FMU nor the Checker reported a problem.
FMU_CHECK_CLEAN = ("FMU reported:\n\t0 warning(s) and error(s)\n"
                   "Checker reported:\n\t0 Warning(s)\n\t0 Error(s)")


def run_fmu_check(fmu, tmp_path, *options):
    """The Compliance Checker with `options` (log level 3: warnings and errors); returns its
    exit status, its log and its output file's text."""
    out, log, unzip = tmp_path / "check.csv", tmp_path / "check.log", tmp_path / "check-unzipped"
    unzip.mkdir(exist_ok=True)
    args = [str(fmu_check_exe()), *options, "-l", "3", "-o", str(out), "-e", str(log),
            "-z", str(unzip), str(fmu)]
    p = subprocess.run(args, capture_output=True, text=True, timeout=300)
    return (p.returncode, log.read_text() if log.exists() else p.stdout + p.stderr,
            out.read_text() if out.exists() else "")


def run_fmu_check_cs(fmu, h, n, tmp_path):
    """The Checker's XML check and Co-Simulation with step h to n·h, every step written (-n 0,
    values as %.16E: exact); it must report no warning and no error."""
    status, log, text = run_fmu_check(fmu, tmp_path, "-k", "cs", "-h", repr(h), "-s", repr(n * h),
                                      "-n", "0")
    assert status == 0 and log.strip().endswith(FMU_CHECK_CLEAN), log
    return read_tool_csv(text)
