"""The shipped binaries load on old Linux systems: every dist/*.fmu's linux64 library needs at most
glibc 2.17 (RHEL 7, Ubuntu 18.04 and newer) and no library beyond glibc's own, and it loads and
runs through fmpy. The same holds for the ARM Linux library (aarch64 code): in every FMI 3.0 FMU's
binaries/aarch64-linux and in binaries/linux64 of the FMI 2.0 FMUs of dist/aarch64-linux (the
folder fmpy, the FMI Library and rust-fmi load on ARM Linux), the same file in both; it runs under
qemu in tests/cross/test.sh.

The versions are read from the ELF file here, by a reader written in Python independently of the
exporter's (src/elf.rs): the dynamic section's DT_NEEDED entries and the version needs of
.gnu.version_r, whose GLIBC_x.y names are the oldest glibc that provides each imported symbol.
"""

import struct
import zipfile

import pytest
from fmpy import read_model_description, simulate_fmu

from conftest import DIST

MAX_GLIBC = (2, 17)
# glibc's own libraries (and the dynamic loader); anything else would have to be on the target.
GLIBC_LIBRARIES = {"libc.so.6", "libm.so.6", "libpthread.so.0", "libdl.so.2", "librt.so.1",
                   "libgcc_s.so.1"}
# The dynamic loader of each processor, and its ELF e_machine.
LOADER = {"x86_64": "ld-linux-x86-64.so.2", "aarch64": "ld-linux-aarch64.so.1"}
EM = {62: "x86_64", 183: "aarch64"}


def elf_machine(data):
    """The processor an ELF file's code is for (e_machine)."""
    assert data[:4] == b"\x7fELF", "not ELF"
    machine, = struct.unpack_from("<H", data, 0x12)
    return EM.get(machine, f"e_machine {machine}")


def elf_sections(data):
    """(type, offset, size, link) of each section header of a 64-bit little-endian ELF file."""
    assert data[:4] == b"\x7fELF" and data[4] == 2 and data[5] == 1, "not ELF64 little-endian"
    shoff, = struct.unpack_from("<Q", data, 0x28)
    shentsize, shnum = struct.unpack_from("<HH", data, 0x3A)
    sections = []
    for i in range(shnum):
        off = shoff + i * shentsize
        sh_type, = struct.unpack_from("<I", data, off + 4)
        sh_offset, sh_size = struct.unpack_from("<QQ", data, off + 0x18)
        sh_link, = struct.unpack_from("<I", data, off + 0x28)
        sections.append((sh_type, sh_offset, sh_size, sh_link))
    return sections


def elf_needs(data):
    """(DT_NEEDED names, version-need names) of a 64-bit little-endian ELF file."""
    sections = elf_sections(data)

    def cstr(off):
        return data[off:data.index(b"\0", off)].decode()

    needed, versions = [], set()
    for sh_type, off, size, link in sections:
        strtab = sections[link][1]
        if sh_type == 6:  # SHT_DYNAMIC
            for k in range(size // 16):
                tag, val = struct.unpack_from("<qQ", data, off + 16 * k)
                if tag == 0:
                    break
                if tag == 1:  # DT_NEEDED
                    needed.append(cstr(strtab + val))
        elif sh_type == 0x6FFFFFFE:  # SHT_GNU_verneed
            at = off
            while True:
                _, cnt, _, aux, nxt = struct.unpack_from("<HHIII", data, at)
                a = at + aux
                for _ in range(cnt):
                    _, _, _, name, anext = struct.unpack_from("<IHHII", data, a)
                    versions.add(cstr(strtab + name))
                    a += anext
                if nxt == 0:
                    break
                at += nxt
    return needed, versions


def glibc_version(name):
    return tuple(int(p) for p in name[len("GLIBC_"):].split("."))


FMUS = sorted(DIST.glob("*.fmu"))
ARM2 = DIST / "aarch64-linux"


def check_linux_library(name, so, arch):
    """An ELF library for `arch`: at most glibc 2.17, glibc's libraries only, no private symbol."""
    assert elf_machine(so) == arch, (name, elf_machine(so))
    needed, versions = elf_needs(so)
    glibc = sorted((glibc_version(v) for v in versions
                    if v.startswith("GLIBC_") and v[6].isdigit()))
    assert glibc, "no GLIBC_ version needs: not a dynamically linked glibc library?"
    highest = ".".join(map(str, glibc[-1]))
    print(f"{name} ({arch}): highest GLIBC_{highest}; needs {sorted(needed)}")
    assert glibc[-1] <= MAX_GLIBC, (
        f"{name} needs GLIBC_{highest} > 2.17: export with cargo-zigbuild available "
        "(tests/all.sh installs it into .venv; VIBROFRIC_PORTABLE=1 makes the exporter insist)")
    allowed = GLIBC_LIBRARIES | {LOADER[arch]}
    assert set(needed) <= allowed, set(needed) - allowed
    assert not any(v.startswith("GLIBC_PRIVATE") for v in versions)


def test_dist_has_the_fmus():
    assert len(FMUS) >= 9, "run `cargo run --release` first (tests/all.sh does)"


@pytest.mark.parametrize("fmu", FMUS, ids=[f.stem for f in FMUS])
def test_binary_needs_at_most_glibc_2_17_and_loads(fmu, tmp_path):
    with zipfile.ZipFile(fmu) as z:
        so = z.read(f"binaries/linux64/{fmu.stem}.so")
    check_linux_library(fmu.name, so, "x86_64")
    # and this very binary loads and runs
    # A contact's mean friction force; a string's weight on bit (it has no F_mean).
    names = {v.name for v in read_model_description(str(fmu)).modelVariables}
    out = "F_mean" if "F_mean" in names else "F_bottom"
    res = simulate_fmu(str(fmu), stop_time=0.01, output_interval=1e-3, output=[out])
    assert len(res) == 11
    assert res[out][-1] == res[out][-1]  # finite, not NaN


@pytest.mark.parametrize("fmu", FMUS, ids=[f.stem for f in FMUS])
def test_arm_linux_library_needs_at_most_glibc_2_17_in_both_editions(fmu):
    """FMI 3.0: binaries/aarch64-linux; FMI 2.0: an FMU of its own in dist/aarch64-linux holding
    only binaries/linux64 (fmpy's FMI 2.0 folder on ARM Linux, where the standard FMU has the
    x86-64 library), with the same model description and the same library."""
    with zipfile.ZipFile(DIST / "fmi3" / fmu.name) as z:
        so3 = z.read(f"binaries/aarch64-linux/{fmu.stem}.so")
    check_linux_library(f"fmi3/{fmu.name}", so3, "aarch64")
    arm2 = ARM2 / fmu.name
    assert arm2.exists(), f"{arm2} missing: export with --platforms all (or aarch64-linux)"
    with zipfile.ZipFile(arm2) as z, zipfile.ZipFile(fmu) as main:
        binaries = [n for n in z.namelist() if n.startswith("binaries/") and not n.endswith("/")]
        assert binaries == [f"binaries/linux64/{fmu.stem}.so"], binaries
        assert z.read(binaries[0]) == so3
        assert z.read("modelDescription.xml") == main.read("modelDescription.xml")
        assert elf_machine(main.read(binaries[0])) == "x86_64"
