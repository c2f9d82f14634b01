"""The shipped binaries load on old Linux systems: every dist/*.fmu's linux64 library needs at most
glibc 2.17 (RHEL 7, Ubuntu 18.04 and newer) and no library beyond glibc's own, and it loads and
runs through fmpy.

The versions are read from the ELF file here, by a reader written in Python independently of the
exporter's (src/elf.rs): the dynamic section's DT_NEEDED entries and the version needs of
.gnu.version_r, whose GLIBC_x.y names are the oldest glibc that provides each imported symbol.
"""

import struct
import zipfile

import pytest
from fmpy import simulate_fmu

from conftest import DIST

MAX_GLIBC = (2, 17)
# glibc's own libraries (and the dynamic loader); anything else would have to be on the target.
GLIBC_LIBRARIES = {"libc.so.6", "libm.so.6", "libpthread.so.0", "libdl.so.2", "librt.so.1",
                   "ld-linux-x86-64.so.2", "libgcc_s.so.1"}


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


def test_dist_has_the_fmus():
    assert len(FMUS) >= 9, "run `cargo run --release` first (tests/all.sh does)"


@pytest.mark.parametrize("fmu", FMUS, ids=[f.stem for f in FMUS])
def test_binary_needs_at_most_glibc_2_17_and_loads(fmu, tmp_path):
    with zipfile.ZipFile(fmu) as z:
        so = z.read(f"binaries/linux64/{fmu.stem}.so")
    needed, versions = elf_needs(so)
    glibc = sorted((glibc_version(v) for v in versions
                    if v.startswith("GLIBC_") and v[6].isdigit()))
    assert glibc, "no GLIBC_ version needs: not a dynamically linked glibc library?"
    highest = ".".join(map(str, glibc[-1]))
    print(f"{fmu.name}: highest GLIBC_{highest}; needs {sorted(needed)}")
    assert glibc[-1] <= MAX_GLIBC, (
        f"{fmu.name} needs GLIBC_{highest} > 2.17: export with cargo-zigbuild available "
        "(tests/all.sh installs it into .venv; VIBROFRIC_PORTABLE=1 makes the exporter insist)")
    assert set(needed) <= GLIBC_LIBRARIES, set(needed) - GLIBC_LIBRARIES
    assert not any(v.startswith("GLIBC_PRIVATE") for v in versions)
    # and this very binary loads and runs
    res = simulate_fmu(str(fmu), stop_time=0.01, output_interval=1e-3, output=["F_mean"])
    assert len(res) == 11
    assert res["F_mean"][-1] == res["F_mean"][-1]  # finite, not NaN
