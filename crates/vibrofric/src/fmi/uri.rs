//! `fmuResourceLocation`: the `file:` URI of the unpacked FMU's `resources/` folder.
//!
//! The standard asks for an RFC 3986 URI, `file:///path/to/resources/`. Importers differ, so
//! every spelling of a local file URI seen in the wild is accepted:
//! `file:///p/`, `file:/p/`, `file://localhost/p/`, `file:////p/` (an empty authority followed by
//! an absolute path with a doubled slash, as some masters write it), each with or without the
//! trailing slash, with percent-encoding (`%20`) decoded. A URI with another scheme, a remote
//! host, a relative path or a bad escape is refused with the reason.

use std::path::PathBuf;

use crate::description::scene::shown;

/// The local folder a `file:` URI names.
pub fn resource_dir(uri: &str) -> Result<PathBuf, String> {
    // `get` and not an index: a multi-byte character may straddle byte 5.
    let Some(rest) = uri
        .get(..5)
        .filter(|s| s.eq_ignore_ascii_case("file:"))
        .and_then(|_| uri.get(5..))
    else {
        return Err(format!(
            "fmuResourceLocation = \"{}\": must be a file: URI such as file:///path/to/resources/",
            shown(uri)
        ));
    };
    let path = match rest.strip_prefix("//") {
        // file:///p, file:////p: empty authority.
        Some(p) if p.starts_with('/') => p,
        Some(p) => {
            let (host, path) = p.split_at(p.find('/').unwrap_or(p.len()));
            if !host.eq_ignore_ascii_case("localhost") {
                return Err(format!(
                    "fmuResourceLocation = \"{}\": host \"{}\" is not supported, only local files (file:///path/ or file://localhost/path/)",
                    shown(uri),
                    shown(host)
                ));
            }
            path
        }
        None => rest,
    };
    if !path.starts_with('/') {
        return Err(format!(
            "fmuResourceLocation = \"{}\": must name an absolute path (file:///path/to/resources/)",
            shown(uri)
        ));
    }
    // Query and fragment have no meaning for a folder.
    let path = path.split(['?', '#']).next().unwrap_or(path);
    let bytes = percent_decode(path)
        .map_err(|e| format!("fmuResourceLocation = \"{}\": {e}", shown(uri)))?;
    // Collapse the leading slashes of file:////p to one.
    let start = bytes.iter().position(|&b| b != b'/').unwrap_or(bytes.len());
    let mut norm = vec![b'/'];
    norm.extend_from_slice(&bytes[start..]);
    Ok(bytes_to_path(norm))
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
fn bytes_to_path(b: Vec<u8>) -> PathBuf {
    use std::os::unix::ffi::OsStringExt;
    PathBuf::from(std::ffi::OsString::from_vec(b))
}

#[cfg(not(unix))]
fn bytes_to_path(b: Vec<u8>) -> PathBuf {
    PathBuf::from(String::from_utf8_lossy(&b).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_local_spelling_names_the_same_folder() {
        for uri in [
            "file:///tmp/fmu/resources/",
            "file:///tmp/fmu/resources",
            "file:/tmp/fmu/resources/",
            "file:/tmp/fmu/resources",
            "file://localhost/tmp/fmu/resources/",
            "FILE://LOCALHOST/tmp/fmu/resources",
            "file:////tmp/fmu/resources/",
            "file:////tmp/fmu/resources",
            "file:///tmp/f%6Du/resources/",
        ] {
            let p = resource_dir(uri).unwrap();
            assert_eq!(
                p.components().collect::<Vec<_>>(),
                PathBuf::from("/tmp/fmu/resources")
                    .components()
                    .collect::<Vec<_>>(),
                "{uri}"
            );
        }
        assert_eq!(
            resource_dir("file:///tmp/a%20b/").unwrap(),
            PathBuf::from("/tmp/a b/")
        );
    }

    #[test]
    fn foreign_or_malformed_locations_are_refused_with_the_reason() {
        for (uri, why) in [
            ("http://x/resources/", "file: URI"),
            ("/tmp/fmu/resources/", "file: URI"),
            ("file://server/share/", "host \"server\""),
            ("file:relative/path", "absolute path"),
            ("file:///tmp/%zz/", "percent-escape"),
            ("file:///tmp/%00/", "%00"),
            ("", "file: URI"),
            // A multi-byte character across byte 5 (this panicked: a slice inside it).
            ("fileé///x/", "file: URI"),
            ("filé:///x/", "file: URI"),
            ("é", "file: URI"),
        ] {
            let e = resource_dir(uri).unwrap_err();
            assert!(e.contains(why), "{uri}: {e}");
        }
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
