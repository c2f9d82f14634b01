"""Every platform inside every FMU, checked from the files themselves with readers independent of
the exporter's (src/binary.rs reads them with the `object` crate; here pefile and macholib, and the
code signature's page hashes with hashlib):

- each FMI 2.0 FMU holds binaries/linux64, win64 and darwin64; each FMI 3.0 FMU x86_64-linux,
  aarch64-linux, x86_64-windows, x86_64-darwin and aarch64-darwin (the FMI 2.0 FMUs for ARM Linux,
  in dist/aarch64-linux, are checked in test_platform.py);
- every library exports every FMI function the Linux library exports (44 FMI 2.0 + 75 FMI 3.0);
- the Windows DLL is a 64-bit DLL that imports only DLLs every Windows 10 has (no mingw run-time);
- the macOS dylibs: x86_64 + arm64 in FMI 2.0's universal darwin64 file, one slice in each FMI 3.0
  folder; macOS 11.0 or older as minimum; linked libraries only under /usr/lib; every arm64 slice
  signed, with each page's SHA-256 equal to its code directory's.

macOS itself cannot run here: what a Mac would do with these files beyond the loader's checks is
untested (docs/platforms.md). The Windows DLL runs under Wine in tests/cross/test.sh.
"""

import hashlib
import struct
import zipfile

import pefile
import pytest
from macholib import mach_o
from macholib.MachO import MachO
from macholib.SymbolTable import SymbolTable

from conftest import DIST
from test_platform import ARM2, elf_sections

FMI2 = {"linux64": "so", "win64": "dll", "darwin64": "dylib"}
FMI3 = {"x86_64-linux": "so", "aarch64-linux": "so", "x86_64-windows": "dll",
        "x86_64-darwin": "dylib", "aarch64-darwin": "dylib"}
WINDOWS_SYSTEM_DLLS = {"kernel32.dll", "ntdll.dll", "msvcrt.dll", "userenv.dll", "ws2_32.dll",
                       "bcryptprimitives.dll", "advapi32.dll", "bcrypt.dll",
                       "api-ms-win-core-synch-l1-2-0.dll"}
MACOS_MIN = (11, 0)

FMUS2 = sorted(DIST.glob("*.fmu"))
FMUS3 = sorted((DIST / "fmi3").glob("*.fmu"))
EDITIONS = [(f, FMI2) for f in FMUS2] + [(f, FMI3) for f in FMUS3]
IDS = [f"fmi2-{f.stem}" for f in FMUS2] + [f"fmi3-{f.stem}" for f in FMUS3]


def elf_fmi_exports(data):
    """The defined global `fmi2*`/`fmi3*` symbols of an ELF64 library's .dynsym."""
    sections = elf_sections(data)
    names = set()
    for sh_type, off, size, link in sections:
        if sh_type != 11:  # SHT_DYNSYM
            continue
        strtab = sections[link][1]
        for k in range(size // 24):
            name, info, _, shndx = struct.unpack_from("<IBBH", data, off + 24 * k)
            if shndx != 0 and info >> 4 == 1:  # defined, STB_GLOBAL
                s = data[strtab + name:data.index(b"\0", strtab + name)].decode()
                if s.startswith(("fmi2", "fmi3")):
                    names.add(s)
    return names


def pe_facts(data):
    pe = pefile.PE(data=data)
    assert pe.FILE_HEADER.Machine == pefile.MACHINE_TYPE["IMAGE_FILE_MACHINE_AMD64"]
    assert pe.FILE_HEADER.Characteristics & 0x2000, "not a DLL"  # IMAGE_FILE_DLL
    exports = {e.name.decode() for e in pe.DIRECTORY_ENTRY_EXPORT.symbols if e.name}
    imports = {i.dll.decode().lower() for i in pe.DIRECTORY_ENTRY_IMPORT}
    return exports, imports


def code_signature_pages(data, off, size):
    """Checks an LC_CODE_SIGNATURE super blob: every page hash of the code directory."""
    magic, _, count = struct.unpack_from(">III", data, off)
    assert magic == 0xFADE0CC0, hex(magic)
    for i in range(count):
        slot, blob = struct.unpack_from(">II", data, off + 12 + 8 * i)
        cd = off + blob
        if slot != 0:
            continue
        magic, _, _, _, hash_off, _, _, n_code, limit = struct.unpack_from(">9I", data, cd)
        assert magic == 0xFADE0C02, hex(magic)
        hash_size, hash_type, _, page_log2 = struct.unpack_from(">BBBB", data, cd + 36)
        assert (hash_type, hash_size) == (2, 32), "not SHA-256"
        page = 1 << page_log2
        assert n_code == -(-limit // page) and limit <= off + size
        for k in range(n_code):
            want = data[cd + hash_off + 32 * k:cd + hash_off + 32 * (k + 1)]
            assert hashlib.sha256(data[k * page:min((k + 1) * page, limit)]).digest() == want, \
                f"page {k} does not match its hash"
        return n_code
    raise AssertionError("no code directory")


def macho_slices(path):
    """(arch, min macOS, linked libraries, exported fmi functions, signed pages) of each slice."""
    data = path.read_bytes()
    m = MachO(str(path))
    out = []
    for h in m.headers:
        arch = {mach_o.CPU_TYPE_NAMES.get(h.header.cputype, "?")}.pop()
        minos, libs, pages = None, [], None
        for lc, cmd, extra in h.commands:
            if lc.cmd == mach_o.LC_BUILD_VERSION:
                minos = (cmd.minos >> 16, (cmd.minos >> 8) & 0xFF)
            elif lc.cmd == mach_o.LC_VERSION_MIN_MACOSX:
                minos = (cmd.version >> 16, (cmd.version >> 8) & 0xFF)
            elif lc.cmd in (mach_o.LC_LOAD_DYLIB, mach_o.LC_LOAD_WEAK_DYLIB,
                            mach_o.LC_REEXPORT_DYLIB):
                libs.append(extra.rstrip(b"\0").decode())
            elif lc.cmd == mach_o.LC_CODE_SIGNATURE:
                slice_data = data[h.offset:h.offset + h.size] if h.size else data
                pages = code_signature_pages(slice_data, cmd.dataoff, cmd.datasize)
        symbols = SymbolTable(m, h)
        exports = {name.decode().lstrip("_") for _, name in symbols.extdefsyms}
        exports = {e for e in exports if e.startswith(("fmi2", "fmi3"))}
        out.append((arch, minos, libs, exports, pages))
    return out


def test_dist_has_the_fmus_of_both_editions():
    assert len(FMUS2) >= 10 and len(FMUS3) == len(FMUS2), "run tests/all.sh (it exports dist/)"


@pytest.mark.parametrize("fmu,folders", EDITIONS, ids=IDS)
def test_every_platform_is_inside_and_loadable_there(fmu, folders, tmp_path):
    with zipfile.ZipFile(fmu) as z:
        names = set(z.namelist())
        for folder, ext in folders.items():
            assert f"binaries/{folder}/{fmu.stem}.{ext}" in names, f"{folder} missing"
        z.extractall(tmp_path)
    lib = {f: tmp_path / "binaries" / f / f"{fmu.stem}.{ext}" for f, ext in folders.items()}
    linux = next(p for f, p in lib.items() if f.endswith("linux64") or f.endswith("-linux"))
    fmi = elf_fmi_exports(linux.read_bytes())
    assert len(fmi) == 44 + 75, len(fmi)
    if folders is FMI2:  # the ARM Linux library of FMI 2.0 is in an FMU of its own
        with zipfile.ZipFile(ARM2 / fmu.name) as z:
            arm = z.read(f"binaries/linux64/{fmu.stem}.so")
    else:
        arm = lib["aarch64-linux"].read_bytes()
    assert elf_fmi_exports(arm) == fmi, "the aarch64 library exports other FMI functions"

    windows = next(p for f, p in lib.items() if f in ("win64", "x86_64-windows"))
    exports, imports = pe_facts(windows.read_bytes())
    assert fmi <= exports, sorted(fmi - exports)[:5]
    assert imports <= WINDOWS_SYSTEM_DLLS, sorted(imports - WINDOWS_SYSTEM_DLLS)

    archs = []
    for f, p in lib.items():
        if not f.endswith("darwin64") and not f.endswith("-darwin"):
            continue
        slices = macho_slices(p)
        if f == "darwin64":
            assert sorted(s[0] for s in slices) == ["ARM64", "x86_64"], [s[0] for s in slices]
        else:
            assert len(slices) == 1
            assert slices[0][0] == {"x86_64-darwin": "x86_64", "aarch64-darwin": "ARM64"}[f]
        for arch, minos, libs, fexports, pages in slices:
            archs.append(arch)
            assert minos is not None and minos <= MACOS_MIN, (f, arch, minos)
            assert libs and all(lib_.startswith("/usr/lib/") for lib_ in libs), (f, arch, libs)
            assert fmi <= fexports, (f, arch, sorted(fmi - fexports)[:5])
            if arch == "ARM64":
                assert pages and pages > 10, (f, "arm64 code must be signed", pages)
    assert "ARM64" in archs and "x86_64" in archs


def test_the_signature_check_sees_a_changed_byte(tmp_path):
    """The page-hash check is not vacuous: one byte changed in the signed arm64 code fails it."""
    with zipfile.ZipFile(FMUS3[0]) as z:
        data = bytearray(z.read(f"binaries/aarch64-darwin/{FMUS3[0].stem}.dylib"))
    path = tmp_path / "lib.dylib"
    path.write_bytes(data)
    (_, _, _, _, pages), = macho_slices(path)
    assert pages > 10
    data[0x4321] ^= 0x01
    path.write_bytes(data)
    with pytest.raises(AssertionError, match="page 4 does not match its hash"):
        macho_slices(path)
