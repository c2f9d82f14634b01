"""The user's guide and the FMUs' documentation pages run as written: every Python example of
docs/using.md, the fmpy command line shown there, and the usage snippet inside each exported
FMU's documentation/index.html, each run in a fresh directory that holds copies of dist/*.fmu
(as a user who downloaded the FMUs has them). The examples carry their own asserts."""

import html
import re
import shutil
import subprocess
import sys
import zipfile

import pytest

from conftest import DIST, ROOT, fmu_path

USING = ROOT / "docs" / "using.md"


def python_blocks(text):
    return re.findall(r"```python\n(.*?)```", text, re.S)


def run_in_copy(tmp_path, code):
    for f in DIST.glob("*.fmu"):
        shutil.copy(f, tmp_path / f.name)
    (tmp_path / "fmi3").mkdir()
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


def page_snippet(fmu):
    with zipfile.ZipFile(fmu) as z:
        page = z.read("documentation/index.html").decode()
    m = re.search(r"<h2>Running it</h2>.*?<pre>(.*?)</pre>", page, re.S)
    assert m, f"{fmu}: no usage snippet"
    return html.unescape(m.group(1))


@pytest.mark.parametrize("name", ["PaperLongitudinal", "VibratingContact", "DrillStringAxial",
                                  "RigTransverse"])
def test_fmu_page_snippet_runs(tmp_path, name):
    code = page_snippet(fmu_path(name))
    assert f'"{name}.fmu"' in code
    out = run_in_copy(tmp_path, code)
    assert out.strip(), "the snippet prints its result"


def test_fmu_page_model_exchange_snippet_runs(tmp_path):
    """The Model Exchange snippet of a page runs as written (through fmpy's CVode)."""
    with zipfile.ZipFile(fmu_path("DrillStringAxial")) as z:
        page = z.read("documentation/index.html").decode()
    m = re.search(r"<h2>Model Exchange</h2>.*?<pre>(.*?)</pre>", page, re.S)
    assert m, "no Model Exchange snippet"
    # The snippet's result against the Co-Simulation run of the same FMU.
    code = html.unescape(m.group(1)) + (
        "\ncs = simulate_fmu('DrillStringAxial.fmu', relative_tolerance=1e-8, stop_time=0.1)"
        "\nfor n in ('x', 'F_Fx'):"
        "\n    scale = max(abs(cs[n]).max(), 1e-12)"
        "\n    assert abs(result[n][-1] - cs[n][-1]) <= 1e-5 * scale, (n, result[n][-1], cs[n][-1])\n"
    )
    run_in_copy(tmp_path, code)

