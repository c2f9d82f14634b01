//! `fmuResourceLocation`: the `file:` URI of the unpacked FMU's `resources/` folder (FMI 2.0;
//! FMI 3.0 passes a native path instead).
//!
//! The standard asks for an RFC 3986 URI (`file:///path/to/resources/`, RFC 8089 for the `file`
//! scheme). Importers differ, so every spelling of a local file URI seen in the wild is accepted,
//! each with or without the trailing slash and with percent-encoding (`%20`, `%3A`) decoded:
//!
//! | URI | Unix path | Windows path |
//! |---|---|---|
//! | `file:///p/x/`, `file:/p/x/`, `file://localhost/p/x/` | `/p/x/` | `\p\x\` (the current drive) |
//! | `file:////p/x/` (an empty authority and a doubled slash) | `/p/x/` | `\\p\x\` (a UNC share) |
//! | `file:///C:/x/` (fmpy, `pathlib.Path.as_uri()`), `file:/C:/x/`, `file://localhost/C:/x/`, `file:///C|/x/`, `file:C:/x/`, `file://C:/x/` | refused: no drive letters | `C:\x\` |
//! | `file://server/share/x/` | refused: a remote host | `\\server\share\x\` |
//!
//! A URI with another scheme, a remote host on Unix, a relative path or a bad escape is refused
//! with the reason. The grammar is one function of the URI and the platform's rules
//! ([`Os`]), so the rules of every platform are tested on every platform.

use std::path::PathBuf;

use crate::description::scene::shown;

/// Whose path rules turn the URI into a path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Os {
    /// `/`-separated absolute paths, no drives, no hosts.
    Unix,
    /// Drive letters (`C:\`), UNC shares (`\\server\share\`), `\` separators.
    Windows,
}

impl Os {
    /// The rules of the platform this library was built for.
    pub const HOST: Os = if cfg!(windows) { Os::Windows } else { Os::Unix };
}

/// The local folder a `file:` URI names, on this platform.
pub fn resource_dir(uri: &str) -> Result<PathBuf, String> {
    let bytes = resource_path(uri, Os::HOST)?;
    bytes_to_path(bytes).map_err(|e| format!("fmuResourceLocation = \"{}\": {e}", shown(uri)))
}

/// The path a `file:` URI names under the rules of `os`, as bytes (UTF-8 on Windows).
pub fn resource_path(uri: &str, os: Os) -> Result<Vec<u8>, String> {
    let fail = |why: String| format!("fmuResourceLocation = \"{}\": {why}", shown(uri));
    // `get` and not an index: a multi-byte character may straddle byte 5.
    let Some(rest) = uri
        .get(..5)
        .filter(|s| s.eq_ignore_ascii_case("file:"))
        .and_then(|_| uri.get(5..))
    else {
        return Err(fail(
            "must be a file: URI such as file:///path/to/resources/".into(),
        ));
    };
    // Query and fragment have no meaning for a folder.
    let rest = rest.split(['?', '#']).next().unwrap_or(rest);
    let (host, path) = match rest.strip_prefix("//") {
        Some(p) => {
            let (host, path) = p.split_at(p.find('/').unwrap_or(p.len()));
            (percent_decode(host).map_err(&fail)?, path)
        }
        None => (vec![], rest),
    };
    let path = percent_decode(path).map_err(&fail)?;
    let local = host.is_empty() || host.eq_ignore_ascii_case(b"localhost");
    match os {
        Os::Unix => {
            if !local {
                return Err(fail(format!(
                    "host \"{}\" is not supported, only local files (file:///path/ or file://localhost/path/)",
                    String::from_utf8_lossy(&host)
                )));
            }
            if path.first() != Some(&b'/') {
                return Err(fail(
                    "must name an absolute path (file:///path/to/resources/)".into(),
                ));
            }
            // Collapse the leading slashes of file:////p to one.
            let start = path.iter().position(|&b| b != b'/').unwrap_or(path.len());
            let mut norm = vec![b'/'];
            norm.extend_from_slice(&path[start..]);
            Ok(norm)
        }
        Os::Windows => windows_path(&host, local, &path).map_err(fail),
    }
}

/// A Windows path from a decoded host and path: a drive-letter path, a UNC share or a path from
/// the current drive's root, with `\` separators.
fn windows_path(host: &[u8], local: bool, path: &[u8]) -> Result<Vec<u8>, String> {
    let sep = |b: &u8| if *b == b'/' { b'\\' } else { *b };
    let drive = |p: &[u8]| {
        p.len() >= 2
            && p[0].is_ascii_alphabetic()
            && (p[1] == b':' || p[1] == b'|')
            && (p.len() == 2 || p[2] == b'/' || p[2] == b'\\')
    };
    let with_drive = |p: &[u8]| {
        // `C|` is the old spelling of `C:` in file URIs.
        let mut out = vec![p[0], b':'];
        out.extend(p[2..].iter().map(sep));
        if out.len() == 2 {
            out.push(b'\\');
        }
        out
    };
    // file://C:/x/: a drive letter where the host belongs, as some tools write it (also the
    // whole path percent-encoded into the host: file://C%3A%5Cx%5C).
    if !local && drive(host) {
        let mut p = host.to_vec();
        p.extend_from_slice(path);
        return Ok(with_drive(&p));
    }
    if !local {
        // file://server/share/x/ names \\server\share\x\.
        if path.iter().all(|&b| b == b'/') {
            return Err(format!(
                "host \"{}\" without a share: a UNC location is file://server/share/path/",
                String::from_utf8_lossy(host)
            ));
        }
        let mut out = b"\\\\".to_vec();
        out.extend_from_slice(host);
        out.extend(path.iter().map(sep));
        return Ok(out);
    }
    match path {
        // file:C:/x/ (no slashes at all).
        p if drive(p) => Ok(with_drive(p)),
        // file:///C:/x/, file:/C:/x/, file://localhost/C:/x/.
        [b'/', p @ ..] if drive(p) => Ok(with_drive(p)),
        // file:////server/share/x/: a UNC share after an empty authority.
        [b'/', b'/', p @ ..] if p.first().is_some_and(|&b| b != b'/') => {
            let mut out = b"\\\\".to_vec();
            out.extend(p.iter().map(sep));
            Ok(out)
        }
        // file:///x/: the root of the current drive.
        [b'/', ..] => Ok(path.iter().map(sep).collect()),
        _ => Err(
            "must name an absolute path (file:///C:/path/to/resources/ or file:///path/to/resources/)"
                .into(),
        ),
    }
}

fn percent_decode(s: &str) -> Result<Vec<u8>, String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = b
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("bad percent-escape at byte {i}: must be %XX"))?;
            if hex == 0 {
                return Err("%00 is not allowed in a path".into());
            }
            out.push(hex);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    Ok(out)
}

#[cfg(unix)]
fn bytes_to_path(b: Vec<u8>) -> Result<PathBuf, String> {
    use std::os::unix::ffi::OsStringExt;
    Ok(PathBuf::from(std::ffi::OsString::from_vec(b)))
}

/// Windows paths are UTF-16: the decoded bytes must be UTF-8.
#[cfg(not(unix))]
fn bytes_to_path(b: Vec<u8>) -> Result<PathBuf, String> {
    String::from_utf8(b)
        .map(PathBuf::from)
        .map_err(|_| "the decoded path is not UTF-8".to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unix(uri: &str) -> String {
        String::from_utf8(resource_path(uri, Os::Unix).unwrap()).unwrap()
    }

    fn windows(uri: &str) -> String {
        String::from_utf8(resource_path(uri, Os::Windows).unwrap()).unwrap()
    }

    #[test]
    fn every_local_unix_spelling_names_the_same_folder() {
        for uri in [
            "file:///tmp/fmu/resources/",
            "file:/tmp/fmu/resources/",
            "file://localhost/tmp/fmu/resources/",
            "FILE://LOCALHOST/tmp/fmu/resources/",
            "file:////tmp/fmu/resources/",
            "file:///tmp/f%6Du/resources/",
            "file:///tmp/fmu/resources/?query#fragment",
        ] {
            assert_eq!(unix(uri), "/tmp/fmu/resources/", "{uri}");
        }
        for uri in [
            "file:///tmp/fmu/resources",
            "file:/tmp/fmu/resources",
            "file:////tmp/fmu/resources",
        ] {
            assert_eq!(unix(uri), "/tmp/fmu/resources", "{uri}");
        }
        assert_eq!(unix("file:///tmp/a%20b/"), "/tmp/a b/");
        // On Unix a colon is an ordinary character of a file name.
        assert_eq!(unix("file:///C:/x/"), "/C:/x/");
    }

    #[test]
    fn every_windows_spelling_names_the_same_folder() {
        for uri in [
            // fmpy on Windows: pathlib.Path.as_uri().
            "file:///C:/Users/u/AppData/Local/Temp/fmu/resources/",
            "file:/C:/Users/u/AppData/Local/Temp/fmu/resources/",
            "file://localhost/C:/Users/u/AppData/Local/Temp/fmu/resources/",
            "file:///C|/Users/u/AppData/Local/Temp/fmu/resources/",
            "file:C:/Users/u/AppData/Local/Temp/fmu/resources/",
            "file://C:/Users/u/AppData/Local/Temp/fmu/resources/",
            "file:///C%3A/Users/u/AppData/Local/Temp/fmu/resources/",
            "file:///C%3a%2FUsers/u/AppData/Local/Temp/fmu/resources/",
            "file:///C:%5CUsers%5Cu/AppData/Local/Temp/fmu/resources/",
            "file://C%3A%5CUsers%5Cu%5CAppData%5CLocal%5CTemp%5Cfmu%5Cresources/",
            "file:///C:/Users/u/AppData/Local/Temp/fmu/resources/#f",
        ] {
            assert_eq!(
                windows(uri),
                r"C:\Users\u\AppData\Local\Temp\fmu\resources\",
                "{uri}"
            );
        }
        assert_eq!(windows("file:///d:/a%20b"), r"d:\a b");
        assert_eq!(windows("file:///Z:/"), r"Z:\");
        assert_eq!(windows("file:///Z:"), r"Z:\");
        // UNC shares: a host, or four slashes.
        for (uri, want) in [
            (
                "file://server/share/fmu/resources/",
                r"\\server\share\fmu\resources\",
            ),
            (
                "file:////server/share/fmu/resources/",
                r"\\server\share\fmu\resources\",
            ),
            ("file://SERVER%2Dx/share/fmu", r"\\SERVER-x\share\fmu"),
        ] {
            assert_eq!(windows(uri), want, "{uri}");
        }
        // No drive: the root of the current drive (how Windows reads "\x").
        assert_eq!(
            windows("file:///tmp/fmu/resources/"),
            r"\tmp\fmu\resources\"
        );
        assert_eq!(windows("file://localhost/tmp/x"), r"\tmp\x");
    }

    #[test]
    fn foreign_or_malformed_locations_are_refused_with_the_reason() {
        let both = [Os::Unix, Os::Windows];
        for (uri, why, oses) in [
            ("http://x/resources/", "file: URI", &both[..]),
            ("/tmp/fmu/resources/", "file: URI", &both),
            (r"C:\fmu\resources", "file: URI", &both),
            ("file://server/share/", "host \"server\"", &[Os::Unix]),
            ("file://server", "without a share", &[Os::Windows]),
            ("file://server/", "without a share", &[Os::Windows]),
            ("file:relative/path", "absolute path", &both),
            ("file:///tmp/%zz/", "percent-escape", &both),
            ("file:///tmp/%4/", "percent-escape", &both),
            ("file:///tmp/%00/", "%00", &both),
            ("file://se%zzrver/x/", "percent-escape", &both),
            ("", "file: URI", &both),
            // A multi-byte character across byte 5 (this panicked: a slice inside it).
            ("fileé///x/", "file: URI", &both),
            ("filé:///x/", "file: URI", &both),
            ("é", "file: URI", &both),
        ] {
            for &os in oses {
                let e = resource_path(uri, os).unwrap_err();
                assert!(e.contains(why), "{uri} ({os:?}): {e}");
                assert!(e.starts_with("fmuResourceLocation = "), "{e}");
            }
        }
    }

    #[test]
    fn this_platforms_rules_make_the_path() {
        let (uri, want) = if cfg!(windows) {
            ("file:///C:/fmu/a%20b/resources/", r"C:\fmu\a b\resources\")
        } else {
            (
                "file:///tmp/fmu/a%20b/resources/",
                "/tmp/fmu/a b/resources/",
            )
        };
        assert_eq!(resource_dir(uri).unwrap(), PathBuf::from(want));
    }

    #[test]
    fn long_values_are_cut_in_messages() {
        let long = format!("http://{}", "x".repeat(10_000_000));
        let e = resource_dir(&long).unwrap_err();
        assert!(e.len() < 400, "{} bytes", e.len());
        assert!(e.contains("… (10000007 bytes)"), "{e}");
        assert_eq!(shown("éé"), "éé");
    }
}
