"""The user's guide and the FMUs' documentation pages run as written: every Python example of
docs/using.md and the fmpy command line shown there, in a fresh directory that holds copies of
dist/*.fmu (as a user who downloaded the FMUs has them); and every snippet and the command line of
each exported FMU's documentation/index.html, FMI 2.0 and FMI 3.0 editions alike, in a directory
that holds only that FMU. The examples carry their own asserts."""

import html
import re
import shutil
import subprocess
import sys
import zipfile

import pytest

from conftest import DIST, ROOT, fmu_path, vibrofric_exe

USING = ROOT / "docs" / "using.md"


def python_blocks(text):
    return re.findall(r"```python\n(.*?)```", text, re.S)


def scene_blocks(text):
    """The guide's scenes: its TOML blocks that name a model."""
    return [b for b in re.findall(r"```toml\n(.*?)```", text, re.S) if "model_identifier" in b]


def run_in_copy(tmp_path, code):
    for f in DIST.glob("*.fmu"):
        shutil.copy(f, tmp_path / f.name)
    # The guide's own scenes, exported as its text says (`vibrofric export ... --out`).
    for k, scene in enumerate(scene_blocks(USING.read_text())):
        (tmp_path / f"scene{k}.toml").write_text(scene)
        subprocess.run([str(vibrofric_exe()), "export", f"scene{k}.toml", "--out", "."],
                       cwd=tmp_path, check=True, capture_output=True, text=True)
    (tmp_path / "fmi3").mkdir(exist_ok=True)
    for f in (DIST / "fmi3").glob("*.fmu"):
        shutil.copy(f, tmp_path / "fmi3" / f.name)
    script = tmp_path / "example.py"
    script.write_text(code)
    r = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 0, f"{code}\n--- stdout\n{r.stdout}\n--- stderr\n{r.stderr[-3000:]}"
    return r.stdout


def test_guide_has_the_examples():
    blocks = python_blocks(USING.read_text())
    assert len(blocks) >= 3
    assert any("setRealInputDerivatives" in b for b in blocks)
    assert any("output_interval" in b for b in blocks)
    # The drill-string recipe: its scene and the loop that uses it.
    scenes = scene_blocks(USING.read_text())
    assert any('model_identifier = "DrillStringHostOwned"' in s for s in scenes)
    assert any("DrillStringHostOwned.fmu" in b and "F_Fx_step" in b for b in blocks)


@pytest.mark.parametrize("k", range(len(python_blocks(USING.read_text()))))
def test_guide_python_example_runs(tmp_path, k):
    fmu_path("PaperLongitudinal")
    out = run_in_copy(tmp_path, python_blocks(USING.read_text())[k])
    print(out)


def test_guide_fmpy_command_line_runs(tmp_path):
    lines = USING.read_text().splitlines()
    starts = [i for i, line in enumerate(lines) if line.startswith("fmpy simulate ")]
    assert starts, "no `fmpy simulate` line in docs/using.md"
    command, i = "", starts[0]
    while True:  # join the shell's continuation lines
        command += lines[i].rstrip("\\") + " "
        if not lines[i].endswith("\\"):
            break
        i += 1
    args = command.split()[2:]
    shutil.copy(fmu_path("PaperLongitudinal"), tmp_path / "PaperLongitudinal.fmu")
    fmpy = pathlib_fmpy()
    r = subprocess.run([fmpy, "simulate", *args], cwd=tmp_path, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    lines = (tmp_path / "out.csv").read_text().splitlines()
    assert lines[0].replace('"', "").split(",") == ["time", "F_mean", "reduction"]
    assert len(lines) == 102  # header, t = 0 and 100 steps of 1 ms
    f_mean, reduction = map(float, lines[-1].split(",")[1:])
    assert reduction == pytest.approx(1 - f_mean / 11.0, rel=1e-12)


def pathlib_fmpy():
    exe = shutil.which("fmpy", path=str(__import__("pathlib").Path(sys.executable).parent))
    assert exe, "fmpy's command line is not installed next to this Python"
    return exe


def page_of(fmu):
    with zipfile.ZipFile(fmu) as z:
        return z.read("documentation/index.html").decode()


def page_snippets(page):
    """Every Python snippet of an FMU page (`<pre class="python">`), as a user copies it."""
    return [html.unescape(m) for m in re.findall(r'<pre class="python">(.*?)</pre>', page, re.S)]


def page_command_line(page):
    """The page's `fmpy simulate` command line (`<code class="shell">`)."""
    m = re.search(r'<code class="shell">(.*?)</code>', page, re.S)
    assert m, "no command line on the page"
    return html.unescape(m.group(1))


def page_cases():
    """(edition, FMU name) of every exported FMU, both editions."""
    fmus = sorted(DIST.glob("*.fmu"))
    assert fmus, "no FMU in dist/: run `cargo run --release`"
    return [(ed, f.stem) for ed in ("2.0", "3.0") for f in fmus]


def page_path(edition, name):
    fmu_path(name)
    return DIST / f"{name}.fmu" if edition == "2.0" else DIST / "fmi3" / f"{name}.fmu"


def run_as_user(tmp_path, fmu, code):
    """Runs `code` in a fresh directory that holds only the FMU the page came from, under the
    name its page uses, as a partner who received that one file has it."""
    shutil.copy(fmu, tmp_path / fmu.name)
    script = tmp_path / "snippet.py"
    script.write_text(code)
    r = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 0, f"{code}\n--- stdout\n{r.stdout}\n--- stderr\n{r.stderr[-3000:]}"
    return r.stdout


@pytest.mark.parametrize("edition,name", page_cases())
def test_every_snippet_of_every_fmu_page_runs_as_written(tmp_path, edition, name):
    """Each snippet of the page, verbatim, in a directory with that edition's FMU: the usage
    snippet (and the co-simulation loop with input support), the LuGre swing measurement and the
    Model Exchange run; each prints its results. The page's calls are its own edition's."""
    fmu = page_path(edition, name)
    page = page_of(fmu)
    snippets = page_snippets(page)
    # A string of contacts' page has its one usage snippet.
    string = "a string of" in page and "integrated together inside the FMU" in page
    lugre = 'law <code>lugre</code>' in page and not string
    assert len(snippets) == (1 if string else 3 if lugre else 2), f"{fmu}: {len(snippets)} snippets"
    outs = []
    for code in snippets:
        assert f'"{name}.fmu"' in code
        if edition == "3.0":
            assert "FMU2Slave" not in code and "setReal(" not in code and "setupExperiment" not in code
        out = run_as_user(tmp_path, fmu, code)
        assert out.strip(), f"{fmu}: the snippet prints its result"
        assert "nan" not in out.lower(), out
        print(out)
        outs.append(out)
    if "co-simulation loop" in snippets[0]:
        slave = "FMU2Slave" if edition == "2.0" else "FMU3Slave"
        assert slave in snippets[0], f"{fmu}: the loop uses {slave}"
    if lugre:
        # The swing snippet measures three cases and prints a line for each.
        rows = [line for line in outs[1].splitlines() if "F_Fx from" in line]
        assert len(rows) == 3, outs[1]


@pytest.mark.parametrize("edition,name", page_cases())
def test_fmu_page_command_line_runs(tmp_path, edition, name):
    fmu = page_path(edition, name)
    command = page_command_line(page_of(fmu))
    args = command.split()
    assert args[:3] == ["fmpy", "simulate", f"{name}.fmu"], command
    shutil.copy(fmu, tmp_path / fmu.name)
    r = subprocess.run([pathlib_fmpy(), *args[1:], "--output-file", "out.csv"], cwd=tmp_path,
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    rows = (tmp_path / "out.csv").read_text().splitlines()
    step = float(args[args.index("--output-interval") + 1])
    assert len(rows) == 1 + round(0.1 / step) + 1, (len(rows), step)


def test_fmu_page_model_exchange_snippet_agrees_with_co_simulation(tmp_path):
    """The Model Exchange snippet of a page, run as written (through fmpy's CVode), against the
    Co-Simulation run of the same FMU at the same settings."""
    fmu = page_path("2.0", "DrillStringAxial")
    page = page_of(fmu)
    m = re.search(r"<h2>Model Exchange</h2>.*?<pre class=\"python\">(.*?)</pre>", page, re.S)
    assert m, "no Model Exchange snippet"
    code = html.unescape(m.group(1))
    stop = re.search(r"stop_time=([0-9.e-]+)", code).group(1)
    code += (
        f"\ncs = simulate_fmu('DrillStringAxial.fmu', relative_tolerance=1e-8, stop_time={stop})"
        "\nfor n in ('x', 'F_Fx'):"
        "\n    scale = max(abs(cs[n]).max(), 1e-12)"
        "\n    assert abs(result[n][-1] - cs[n][-1]) <= 1e-5 * scale, (n, result[n][-1], cs[n][-1])\n"
    )
    run_as_user(tmp_path, fmu, code)
