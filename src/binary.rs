//! What a shipped library is, read from the file itself: a Windows DLL (PE) or a macOS dylib
//! (Mach-O, thin or universal) — its architectures, the oldest system that loads it, the
//! libraries it links, the functions it exports and, for Apple silicon, whether its code
//! signature matches its pages. ELF libraries are read by [`crate::elf`] (their glibc symbol
//! versions).
//!
//! The exporter reads every binary it is about to ship and refuses one that an importer could not
//! load ([`Facts::problems`]): an FMI function missing from its exports, a Windows DLL that
//! imports a DLL Windows does not have, a dylib for a macOS newer than [`MACOS_MIN`] or linking
//! outside `/usr/lib`, an arm64 slice without a valid signature (macOS kills such a process).

use object::macho;
use object::read::macho::{
    FatArch, LoadCommandVariant, MachHeader, MachOFatFile32, MachOFile32, MachOFile64,
};
use object::{Endianness, FileKind, Object, ObjectSymbol};
use sha2::{Digest, Sha256};
use std::collections::BTreeSet;

/// The oldest macOS the dylibs are built for (`MACOSX_DEPLOYMENT_TARGET`).
pub const MACOS_MIN: (u16, u8) = (11, 0);

/// The DLLs every Windows 10 and later has, which the FMU's DLL may import.
pub const WINDOWS_SYSTEM_DLLS: &[&str] = &[
    "kernel32.dll",
    "ntdll.dll",
    "msvcrt.dll",
    "userenv.dll",
    "ws2_32.dll",
    "bcryptprimitives.dll",
    "advapi32.dll",
    "bcrypt.dll",
    "api-ms-win-core-synch-l1-2-0.dll",
];

/// The functions FMI 2.0 (44: common, Co-Simulation, Model Exchange) and FMI 3.0 (75) define.
pub const FMI_FUNCTIONS: usize = 44 + 75;

/// The `fmi2*` and `fmi3*` functions a library (ELF, PE or Mach-O) exports; of a universal
/// Mach-O file, those every slice exports.
pub fn fmi_exports(data: &[u8]) -> Result<BTreeSet<String>, String> {
    let fmi = |names: &mut dyn Iterator<Item = String>| -> BTreeSet<String> {
        names
            .filter(|n| n.starts_with("fmi2") || n.starts_with("fmi3"))
            .collect()
    };
    if FileKind::parse(data).map_err(|e| e.to_string())? == FileKind::Elf64 {
        let file = object::File::parse(data).map_err(|e| format!("ELF: {e}"))?;
        let exports = file
            .exports()
            .map_err(|e| format!("ELF exports: {e}"))?
            .map(|e| e.map(|e| export_name(&e)))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| format!("ELF exports: {e}"))?;
        return Ok(fmi(&mut exports.into_iter()));
    }
    let facts = read(data)?;
    let mut sets = facts
        .slices
        .iter()
        .map(|s| fmi(&mut s.exports.iter().cloned()));
    let first = sets.next().unwrap_or_default();
    Ok(sets.fold(first, |a, b| a.intersection(&b).cloned().collect()))
}

/// One architecture's slice of a library.
#[derive(Clone, Debug, PartialEq)]
pub struct Slice {
    /// `x86_64` or `aarch64`.
    pub arch: String,
    /// The oldest macOS that loads it (`LC_BUILD_VERSION` / `LC_VERSION_MIN_MACOSX`), as
    /// (major, minor); `None` for a PE file.
    pub min_os: Option<(u16, u8)>,
    /// Libraries it links (`LC_LOAD_DYLIB` paths; PE import DLL names), in file order.
    pub libraries: Vec<String>,
    /// Exported function names (without the Mach-O leading underscore).
    pub exports: Vec<String>,
    /// Mach-O: `Some(Ok(pages))` when a code signature is present and each page's SHA-256
    /// matches its code directory, `Some(Err(why))` when it does not, `None` without one.
    pub signature: Option<Result<usize, String>>,
}

/// A library file: one slice, or several in a universal Mach-O file.
#[derive(Clone, Debug, PartialEq)]
pub struct Facts {
    /// `PE` or `Mach-O` (`universal` when fat).
    pub format: &'static str,
    pub slices: Vec<Slice>,
}

/// Reads a PE or Mach-O library.
pub fn read(data: &[u8]) -> Result<Facts, String> {
    let kind = FileKind::parse(data).map_err(|e| format!("not an object file: {e}"))?;
    match kind {
        FileKind::Pe64 => Ok(Facts {
            format: "PE",
            slices: vec![pe(data)?],
        }),
        FileKind::MachO64 | FileKind::MachO32 => Ok(Facts {
            format: "Mach-O",
            slices: vec![mach_o(data)?],
        }),
        FileKind::MachOFat32 => {
            let fat = MachOFatFile32::parse(data).map_err(|e| format!("universal Mach-O: {e}"))?;
            let slices = fat
                .arches()
                .iter()
                .map(|a| a.data(data).map_err(|e| e.to_string()).and_then(mach_o))
                .collect::<Result<_, _>>()?;
            Ok(Facts {
                format: "universal Mach-O",
                slices,
            })
        }
        other => Err(format!("{other:?}: not a PE or Mach-O library")),
    }
}

/// An export's name (an export by ordinal only has none: "").
fn export_name(e: &object::Export) -> String {
    String::from_utf8_lossy(e.name().name().unwrap_or_default()).into_owned()
}

fn arch_name(a: object::Architecture) -> String {
    match a {
        object::Architecture::X86_64 => "x86_64".into(),
        object::Architecture::Aarch64 => "aarch64".into(),
        other => format!("{other:?}").to_lowercase(),
    }
}

fn pe(data: &[u8]) -> Result<Slice, String> {
    let file = object::File::parse(data).map_err(|e| format!("PE: {e}"))?;
    let mut libraries: Vec<String> = vec![];
    for import in file.imports().map_err(|e| format!("PE imports: {e}"))? {
        let import = import.map_err(|e| format!("PE imports: {e}"))?;
        let lib = String::from_utf8_lossy(import.library()).into_owned();
        if !libraries.iter().any(|l| l.eq_ignore_ascii_case(&lib)) {
            libraries.push(lib);
        }
    }
    let exports = file
        .exports()
        .map_err(|e| format!("PE exports: {e}"))?
        .map(|e| e.map(|e| export_name(&e)))
        .collect::<Result<_, _>>()
        .map_err(|e| format!("PE exports: {e}"))?;
    Ok(Slice {
        arch: arch_name(file.architecture()),
        min_os: None,
        libraries,
        exports,
        signature: None,
    })
}

fn mach_o(data: &[u8]) -> Result<Slice, String> {
    match FileKind::parse(data).map_err(|e| e.to_string())? {
        FileKind::MachO64 => {
            let f = MachOFile64::<Endianness>::parse(data).map_err(|e| format!("Mach-O: {e}"))?;
            mach_o_slice(&f, data)
        }
        FileKind::MachO32 => {
            let f = MachOFile32::<Endianness>::parse(data).map_err(|e| format!("Mach-O: {e}"))?;
            mach_o_slice(&f, data)
        }
        other => Err(format!("{other:?} inside a universal file")),
    }
}

fn mach_o_slice<'a, Mach: MachHeader<Endian = Endianness>>(
    file: &object::read::macho::MachOFile<'a, Mach, &'a [u8]>,
    data: &'a [u8],
) -> Result<Slice, String> {
    let endian = file.endian();
    let mut min_os = None;
    let mut libraries = vec![];
    let mut signature = None;
    let mut cmds = file
        .macho_load_commands()
        .map_err(|e| format!("Mach-O load commands: {e}"))?;
    while let Some(cmd) = cmds.next().map_err(|e| e.to_string())? {
        match cmd.variant().map_err(|e| e.to_string())? {
            LoadCommandVariant::Dylib(d) => {
                let name = cmd
                    .string(endian, d.dylib.name)
                    .map_err(|e| e.to_string())?;
                libraries.push(String::from_utf8_lossy(name).into_owned());
            }
            LoadCommandVariant::BuildVersion(b, _) => min_os = Some(version(b.minos.get(endian).0)),
            LoadCommandVariant::VersionMin(v) if cmd.cmd() == macho::LC_VERSION_MIN_MACOSX => {
                min_os = Some(version(v.version.get(endian).0))
            }
            LoadCommandVariant::LinkeditData(l) if cmd.cmd() == macho::LC_CODE_SIGNATURE => {
                let (off, len) = (
                    l.dataoff.get(endian) as usize,
                    l.datasize.get(endian) as usize,
                );
                signature = Some(check_signature(data, off, len));
            }
            _ => {}
        }
    }
    let exports = file
        .symbols()
        .filter(|s| s.is_global() && s.is_definition() && s.kind() == object::SymbolKind::Text)
        .filter_map(|s| s.name().ok())
        .map(|n| n.strip_prefix('_').unwrap_or(n).to_string())
        .collect();
    Ok(Slice {
        arch: arch_name(file.architecture()),
        min_os,
        libraries,
        exports,
        signature,
    })
}

/// Mach-O's `xxxx.yy.zz` nibble encoding → (major, minor).
fn version(v: u32) -> (u16, u8) {
    ((v >> 16) as u16, (v >> 8) as u8)
}

/// Checks an embedded code signature (`LC_CODE_SIGNATURE`): the super blob's code directory
/// holds one hash per page of the file up to `codeLimit`; every one must match. Returns the
/// number of pages checked.
fn check_signature(data: &[u8], off: usize, len: usize) -> Result<usize, String> {
    let be = |at: usize| -> Result<u32, String> {
        data.get(at..at + 4)
            .map(|b| u32::from_be_bytes([b[0], b[1], b[2], b[3]]))
            .ok_or_else(|| format!("code signature truncated at byte {at}"))
    };
    if off.checked_add(len).is_none_or(|end| end > data.len()) {
        return Err("code signature outside the file".into());
    }
    const SUPER_BLOB: u32 = 0xfade_0cc0;
    const CODE_DIRECTORY: u32 = 0xfade_0c02;
    if be(off)? != SUPER_BLOB {
        return Err(format!(
            "code signature magic {:#x}, not a super blob",
            be(off)?
        ));
    }
    let count = be(off + 8)? as usize;
    for i in 0..count.min(64) {
        let (slot, blob) = (be(off + 12 + 8 * i)?, be(off + 16 + 8 * i)? as usize);
        let cd = off + blob;
        if slot != 0 || be(cd)? != CODE_DIRECTORY {
            continue;
        }
        let hash_offset = be(cd + 16)? as usize;
        let n_code = be(cd + 28)? as usize;
        let code_limit = be(cd + 32)? as usize;
        let head = data
            .get(cd + 36..cd + 40)
            .ok_or("code directory truncated")?;
        let (hash_size, hash_type, page_log2) = (head[0] as usize, head[1], head[3]);
        if hash_type != 2 || hash_size != 32 {
            return Err(format!(
                "hash type {hash_type} (size {hash_size}): not SHA-256"
            ));
        }
        let page = 1usize << page_log2.min(31);
        if code_limit > data.len() || n_code != code_limit.div_ceil(page) {
            return Err(format!(
                "code directory covers {code_limit} bytes in {n_code} pages of a {}-byte file",
                data.len()
            ));
        }
        for k in 0..n_code {
            let page_bytes = &data[k * page..((k + 1) * page).min(code_limit)];
            let at = cd + hash_offset + k * hash_size;
            let want = data
                .get(at..at + hash_size)
                .ok_or("code directory truncated")?;
            if Sha256::digest(page_bytes).as_slice() != want {
                return Err(format!("page {k} does not match its hash"));
            }
        }
        return Ok(n_code);
    }
    Err("no code directory in the code signature".into())
}

impl Facts {
    /// Why an importer on the platform could not load this library; empty when nothing is
    /// wrong. (Which FMI functions it exports is compared across platforms by the exporter.)
    pub fn problems(&self) -> Vec<String> {
        let mut out = vec![];
        for s in &self.slices {
            if self.format == "PE" {
                for l in &s.libraries {
                    if !WINDOWS_SYSTEM_DLLS
                        .iter()
                        .any(|d| d.eq_ignore_ascii_case(l))
                    {
                        out.push(format!("imports {l}, which is not a Windows system DLL"));
                    }
                }
                continue;
            }
            match s.min_os {
                Some(v) if v <= MACOS_MIN => {}
                Some((a, b)) => out.push(format!(
                    "{}: needs macOS {a}.{b}, newer than {}.{}",
                    s.arch, MACOS_MIN.0, MACOS_MIN.1
                )),
                None => out.push(format!("{}: no minimum macOS version", s.arch)),
            }
            for l in &s.libraries {
                if !l.starts_with("/usr/lib/") {
                    out.push(format!("{}: links {l}, outside /usr/lib", s.arch));
                }
            }
            match (&s.signature, s.arch.as_str()) {
                (Some(Err(e)), _) => out.push(format!("{}: invalid code signature: {e}", s.arch)),
                (None, "aarch64") => out.push(format!(
                    "{}: no code signature (macOS on Apple silicon loads only signed code)",
                    s.arch
                )),
                _ => {}
            }
        }
        out
    }

    /// One line for the exporter: `PE x86_64, imports KERNEL32.dll, …` or
    /// `universal Mach-O x86_64 + aarch64, macOS >= 11.0, links /usr/lib/libSystem.B.dylib, …`.
    pub fn summary(&self) -> String {
        let archs: Vec<&str> = self.slices.iter().map(|s| s.arch.as_str()).collect();
        let mut libs: Vec<&str> = vec![];
        for s in &self.slices {
            for l in &s.libraries {
                if !libs.contains(&l.as_str()) {
                    libs.push(l);
                }
            }
        }
        let mut line = format!("{} {}", self.format, archs.join(" + "));
        if let Some((a, b)) = self.slices.iter().filter_map(|s| s.min_os).max() {
            line.push_str(&format!(", macOS >= {a}.{b}"));
        }
        let signed: Vec<String> = self
            .slices
            .iter()
            .filter_map(|s| match &s.signature {
                Some(Ok(pages)) => Some(format!("{} signed ({pages} pages verified)", s.arch)),
                _ => None,
            })
            .collect();
        if !signed.is_empty() {
            line.push_str(&format!(", {}", signed.join(", ")));
        }
        let exports = self.slices.first().map_or(0, |s| s.exports.len());
        line.push_str(&format!(
            ", {exports} exported functions, links {}",
            libs.join(", ")
        ));
        line
    }
}
