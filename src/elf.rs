//! What a shared library asks of the C library: the versions of the symbols it imports
//! (`.gnu.version_r`) and the libraries it needs (`DT_NEEDED`), read from the ELF file itself.
//!
//! The exporter prints the highest `GLIBC_` version of the binary it ships (the oldest glibc
//! that can load the FMU), and the tests check it. Only 64-bit little-endian ELF (x86-64 and
//! aarch64 Linux) is read; anything else is an error that says what was found.

use std::fmt;

/// The version needs of a shared library.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Needs {
    /// The processor the code is for (`e_machine`): `x86_64`, `aarch64`, else its number.
    pub machine: String,
    /// `DT_NEEDED` entries, in file order (`libc.so.6`, `libm.so.6`, ...).
    pub libraries: Vec<String>,
    /// Every version name the library requires (`GLIBC_2.2.5`, `GLIBC_2.14`, `GCC_3.0`, ...),
    /// sorted and without duplicates.
    pub versions: Vec<String>,
}

/// A version such as `GLIBC_2.17`, as numbers for comparison: `[2, 17]`.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct GlibcVersion(pub Vec<u32>);

impl fmt::Display for GlibcVersion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<String> = self.0.iter().map(|n| n.to_string()).collect();
        write!(f, "{}", parts.join("."))
    }
}

impl GlibcVersion {
    /// `GLIBC_2.17` → `[2, 17]`; `None` for other names (`GCC_3.0`, `GLIBC_PRIVATE`).
    pub fn parse(name: &str) -> Option<GlibcVersion> {
        let rest = name.strip_prefix("GLIBC_")?;
        let nums: Option<Vec<u32>> = rest.split('.').map(|p| p.parse().ok()).collect();
        nums.filter(|v| !v.is_empty()).map(GlibcVersion)
    }
}

impl Needs {
    /// The highest `GLIBC_x.y[.z]` version required: the oldest glibc that can load the library
    /// (`None` when it requires no versioned glibc symbol).
    pub fn max_glibc(&self) -> Option<GlibcVersion> {
        self.versions
            .iter()
            .filter_map(|v| GlibcVersion::parse(v))
            .max()
    }
}

fn u16_at(b: &[u8], off: usize) -> Result<u16, String> {
    b.get(off..off + 2)
        .map(|s| u16::from_le_bytes([s[0], s[1]]))
        .ok_or_else(|| format!("truncated ELF file (offset {off})"))
}

fn u32_at(b: &[u8], off: usize) -> Result<u32, String> {
    b.get(off..off + 4)
        .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
        .ok_or_else(|| format!("truncated ELF file (offset {off})"))
}

fn u64_at(b: &[u8], off: usize) -> Result<u64, String> {
    b.get(off..off + 8)
        .map(|s| {
            let mut a = [0u8; 8];
            a.copy_from_slice(s);
            u64::from_le_bytes(a)
        })
        .ok_or_else(|| format!("truncated ELF file (offset {off})"))
}

fn cstr_at(b: &[u8], off: usize) -> Result<String, String> {
    let tail = b
        .get(off..)
        .ok_or_else(|| format!("string offset {off} outside the file"))?;
    let end = tail
        .iter()
        .position(|&c| c == 0)
        .ok_or_else(|| format!("unterminated string at offset {off}"))?;
    Ok(String::from_utf8_lossy(&tail[..end]).into_owned())
}

fn usize_of(v: u64) -> Result<usize, String> {
    usize::try_from(v).map_err(|_| format!("ELF offset {v} does not fit in memory"))
}

/// One section header: (type, offset, size, link).
struct Section {
    kind: u32,
    offset: usize,
    size: usize,
    link: usize,
}

const SHT_DYNAMIC: u32 = 6;
const SHT_GNU_VERNEED: u32 = 0x6fff_fffe;
const DT_NEEDED: u64 = 1;
const EM_X86_64: u16 = 62;
const EM_AARCH64: u16 = 183;

/// Reads the needs of a 64-bit little-endian ELF shared library.
pub fn needs(bytes: &[u8]) -> Result<Needs, String> {
    if bytes.get(0..4) != Some(b"\x7fELF") {
        return Err("not an ELF file".into());
    }
    if bytes.get(4) != Some(&2) || bytes.get(5) != Some(&1) {
        return Err("not a 64-bit little-endian ELF file (x86-64 or aarch64 Linux)".into());
    }
    let machine = match u16_at(bytes, 0x12)? {
        EM_X86_64 => "x86_64".to_string(),
        EM_AARCH64 => "aarch64".to_string(),
        other => format!("ELF machine {other}"),
    };
    let shoff = usize_of(u64_at(bytes, 0x28)?)?;
    let shentsize = u16_at(bytes, 0x3a)? as usize;
    let shnum = u16_at(bytes, 0x3c)? as usize;
    if shentsize < 64 {
        return Err(format!("section header size {shentsize} < 64"));
    }
    let mut sections = Vec::with_capacity(shnum);
    for i in 0..shnum {
        let h = shoff + i * shentsize;
        sections.push(Section {
            kind: u32_at(bytes, h + 4)?,
            offset: usize_of(u64_at(bytes, h + 0x18)?)?,
            size: usize_of(u64_at(bytes, h + 0x20)?)?,
            link: u32_at(bytes, h + 0x28)? as usize,
        });
    }
    let strtab = |s: &Section| -> Result<usize, String> {
        sections
            .get(s.link)
            .map(|t| t.offset)
            .ok_or_else(|| format!("section link {} out of range", s.link))
    };
    let mut out = Needs {
        machine,
        ..Needs::default()
    };
    for s in &sections {
        match s.kind {
            SHT_DYNAMIC => {
                let str_off = strtab(s)?;
                for k in 0..s.size / 16 {
                    let e = s.offset + 16 * k;
                    let tag = u64_at(bytes, e)?;
                    if tag == 0 {
                        break;
                    }
                    if tag == DT_NEEDED {
                        let name = usize_of(u64_at(bytes, e + 8)?)?;
                        out.libraries.push(cstr_at(bytes, str_off + name)?);
                    }
                }
            }
            SHT_GNU_VERNEED => {
                let str_off = strtab(s)?;
                // Verneed entries (vn_version, vn_cnt, vn_file, vn_aux, vn_next), each with
                // vn_cnt Vernaux entries (vna_hash, vna_flags, vna_other, vna_name, vna_next).
                let mut at = s.offset;
                for _ in 0..4096 {
                    let cnt = u16_at(bytes, at + 2)? as usize;
                    let aux = u32_at(bytes, at + 8)? as usize;
                    let next = u32_at(bytes, at + 12)? as usize;
                    let mut a = at + aux;
                    for _ in 0..cnt {
                        let name = u32_at(bytes, a + 8)? as usize;
                        out.versions.push(cstr_at(bytes, str_off + name)?);
                        let anext = u32_at(bytes, a + 12)? as usize;
                        if anext == 0 {
                            break;
                        }
                        a += anext;
                    }
                    if next == 0 {
                        break;
                    }
                    at += next;
                }
            }
            _ => {}
        }
    }
    out.versions.sort();
    out.versions.dedup();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn versions_compare_numerically() {
        let v = |s| GlibcVersion::parse(s).unwrap();
        assert!(v("GLIBC_2.17") > v("GLIBC_2.3.4"));
        assert!(v("GLIBC_2.34") > v("GLIBC_2.17"));
        assert!(v("GLIBC_2.2.5") < v("GLIBC_2.3"));
        assert_eq!(v("GLIBC_2.2.5").to_string(), "2.2.5");
        assert_eq!(GlibcVersion::parse("GCC_3.0"), None);
        assert_eq!(GlibcVersion::parse("GLIBC_PRIVATE"), None);
    }

    #[test]
    fn refuses_what_is_not_elf64() {
        assert_eq!(needs(b"MZ\x90\x00").unwrap_err(), "not an ELF file");
        assert!(needs(b"\x7fELF\x01\x01\x01\x00")
            .unwrap_err()
            .starts_with("not a 64-bit"));
        assert!(needs(b"\x7fELF\x02\x01\x01\x00")
            .unwrap_err()
            .starts_with("truncated"));
    }
}
