//! An FMU archive: the libraries' bytes and the zip with the model description, the libraries,
//! the documentation page and the scene.

use std::fs::File;
use std::io::Write;
use std::path::Path;

use vibrofric::description::Scene;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

/// Writes the FMU archive (to a temporary name first, so that a failed export leaves no
/// half-written FMU behind).
pub fn write_fmu(
    path: &Path,
    scene: &Scene,
    description: &str,
    binaries: &[(String, &[u8])],
    doc: &str,
) -> Result<(), String> {
    let tmp = path.with_extension("fmu.partial");
    let io = |e: std::io::Error| format!("{}: {e}", tmp.display());
    let zerr = |e: zip::result::ZipError| format!("{}: {e}", tmp.display());
    let file = File::create(&tmp).map_err(io)?;
    let mut zip = ZipWriter::new(file);
    // A fixed time stamp keeps the archive a function of its content.
    let opts = SimpleFileOptions::default()
        .compression_method(CompressionMethod::Deflated)
        .last_modified_time(DateTime::default())
        .unix_permissions(0o644);
    let mut entries: Vec<(String, &[u8], u32)> =
        vec![("modelDescription.xml".into(), description.as_bytes(), 0o644)];
    entries.extend(
        binaries
            .iter()
            .map(|(name, lib)| (name.clone(), *lib, 0o755)),
    );
    entries.push(("documentation/index.html".into(), doc.as_bytes(), 0o644));
    entries.push((
        "resources/scene.toml".into(),
        scene.source.as_bytes(),
        0o644,
    ));
    for (name, bytes, mode) in entries {
        zip.start_file(name, opts.unix_permissions(mode))
            .map_err(zerr)?;
        zip.write_all(bytes).map_err(io)?;
    }
    zip.finish().map_err(zerr)?;
    std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(())
}
