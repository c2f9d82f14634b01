//! `vibrofric export`: reads every scene first (one bad scene exports nothing), builds the
//! libraries of the requested platforms, and writes each scene's FMI 2.0 and FMI 3.0 FMU with its
//! model description and documentation page (and, for ARM Linux, which FMI 2.0 names no folder
//! for, an FMI 2.0 FMU of its own in `<out>/aarch64-linux/`: `platforms.rs`); optionally the
//! checked-in model descriptions and the self-checks.

use std::path::{Path, PathBuf};

use vibrofric::description::variables::Causality;
use vibrofric::description::{xml, xml3, xml_string, Scene};
use vibrofric::table::Role;
use vibrofric_docs::docs;

use crate::package::write_fmu;
use crate::platforms::{self, Request, Shipped};
use crate::self_check::{
    self_check, self_check_fmi3, self_check_model_exchange, self_check_string,
};
use crate::{standard_scenes, SCENES_DIR};

pub fn export(
    scene_files: &[PathBuf],
    out: &Path,
    descriptions: Option<&Path>,
    library: Option<&Path>,
    check: bool,
    platforms: &Request,
) -> Result<(), String> {
    let files = if scene_files.is_empty() {
        standard_scenes(Path::new(SCENES_DIR))?
    } else {
        scene_files.to_vec()
    };
    // Read every scene before writing anything: one bad scene exports nothing.
    let mut scenes: Vec<(PathBuf, Scene)> = vec![];
    for f in &files {
        let s = Scene::load(f).map_err(|e| e.to_string())?;
        if let Some((other, _)) = scenes
            .iter()
            .find(|(_, o)| o.model_identifier == s.model_identifier)
        {
            return Err(format!(
                "{}: model_identifier = \"{}\": already used by {}; each FMU needs its own",
                f.display(),
                s.model_identifier,
                other.display()
            ));
        }
        scenes.push((f.clone(), s));
    }
    let (shipped, skipped) = platforms::build(platforms, library)?;
    for s in &shipped {
        println!("{}", s.line);
    }
    for line in &skipped {
        println!("{line}");
    }
    // The platforms of the standard FMI 2.0 FMUs, and those with FMI 2.0 FMUs of their own.
    let (own2, main2): (Vec<&Shipped>, Vec<&Shipped>) =
        shipped.iter().partition(|s| s.platform.own_fmi2_edition());
    let names = |list: &[&Shipped]| -> String {
        list.iter()
            .map(|s| s.platform.name())
            .collect::<Vec<_>>()
            .join(", ")
    };
    println!(
        "platforms in each FMU: FMI 3.0 {}; FMI 2.0 {}",
        names(&shipped.iter().collect::<Vec<_>>()),
        names(&main2)
    );
    for s in &own2 {
        println!(
            "{}: FMI 2.0 names no folder for it: its FMI 2.0 FMUs are in {}, with the library in binaries/{}/",
            s.platform.name(),
            out.join(s.platform.name()).display(),
            s.platform.fmi2_folder()
        );
    }
    let doc2: Vec<docs::Binary> = main2.iter().map(|s| s.doc2.clone()).collect();
    let doc3: Vec<docs::Binary> = shipped.iter().map(|s| s.doc3.clone()).collect();

    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    if let Some(d) = descriptions {
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    let out3 = out.join("fmi3");
    std::fs::create_dir_all(&out3).map_err(|e| format!("{}: {e}", out3.display()))?;
    for s in &own2 {
        let d = out.join(s.platform.name());
        std::fs::create_dir_all(&d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    for (file, scene) in &scenes {
        let fmu = out.join(format!("{}.fmu", scene.model_identifier));
        let description = xml::model_description(scene);
        let id = &scene.model_identifier;
        let doc = docs::index_html_for(scene, &doc2);
        write_fmu(&fmu, scene, &description, &fmi2_binaries(&main2, id), &doc)?;
        // FMI 2.0 FMUs of a platform FMI 2.0 names no folder for: its library alone.
        for s in &own2 {
            let p = out.join(s.platform.name()).join(format!("{id}.fmu"));
            let doc = docs::index_html_for(scene, std::slice::from_ref(&s.doc2));
            write_fmu(&p, scene, &description, &fmi2_binaries(&[s], id), &doc)?;
        }
        // The FMI 3.0 edition: the same libraries and scene, FMI 3.0's description and layout.
        let fmu3 = out3.join(format!("{id}.fmu"));
        let bins3: Vec<(String, &[u8])> = shipped
            .iter()
            .flat_map(|s| {
                let ext = s.platform.extension();
                s.fmi3.iter().map(move |(folder, lib)| {
                    (format!("binaries/{folder}/{id}.{ext}"), &lib.bytes[..])
                })
            })
            .collect();
        let doc3 = docs::index_html_fmi3(scene, &doc3);
        write_fmu(&fmu3, scene, &xml3::model_description(scene), &bins3, &doc3)?;
        let (n_vars, n_out) = match &scene.string {
            // FMI 2.0's scalars.
            Some(_) => {
                let rows = xml_string::rows(scene, xml_string::Edition::Fmi2);
                let outputs = rows.iter().filter(|r| r.role == Role::Output).count();
                (rows.len(), outputs)
            }
            None => (
                scene.variables().count(),
                scene
                    .variables()
                    .filter(|v| v.causality(&scene.config) == Causality::Output)
                    .count(),
            ),
        };
        let size = std::fs::metadata(&fmu).map(|m| m.len()).unwrap_or(0);
        println!(
            "{} -> {} and {} ({n_vars} variables, {n_out} outputs, {:.1} MB, GUID {})",
            file.display(),
            fmu.display(),
            fmu3.display(),
            size as f64 / 1e6,
            xml::guid(scene)
        );
        if let Some(d) = descriptions {
            let p = d.join(format!("{}.xml", scene.model_identifier));
            std::fs::write(&p, &description).map_err(|e| format!("{}: {e}", p.display()))?;
            println!("  wrote {}", p.display());
        }
        if check && scene.string.is_some() {
            match self_check_string(&fmu, &fmu3, scene) {
                Ok(line) => println!("  self-check: {line}"),
                Err(e) => return Err(format!("{}: self-check failed: {e}", fmu.display())),
            }
        } else if check {
            match self_check(&fmu, scene) {
                Ok(line) => println!("  self-check: {line}"),
                Err(e) => return Err(format!("{}: self-check failed: {e}", fmu.display())),
            }
            match self_check_fmi3(&fmu3, &fmu) {
                Ok(line) => println!("  self-check FMI 3.0: {line}"),
                Err(e) => return Err(format!("{}: self-check failed: {e}", fmu3.display())),
            }
            match self_check_model_exchange(&fmu, scene) {
                Ok(line) => println!("  self-check Model Exchange: {line}"),
                Err(e) => return Err(format!("{}: self-check failed: {e}", fmu.display())),
            }
        }
    }
    Ok(())
}

/// The FMI 2.0 archive entries of these platforms' libraries: `binaries/<folder>/<id>.<ext>`.
fn fmi2_binaries<'a>(list: &[&'a Shipped], id: &str) -> Vec<(String, &'a [u8])> {
    list.iter()
        .map(|s| {
            let (folder, ext) = (s.platform.fmi2_folder(), s.platform.extension());
            (format!("binaries/{folder}/{id}.{ext}"), &s.fmi2.bytes[..])
        })
        .collect()
}
