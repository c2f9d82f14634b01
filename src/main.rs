//! `vibrofric`: exports scenes (`scenes/*.toml`, described in `docs/scenes.md`) as FMI 2.0 and
//! FMI 3.0 Co-Simulation FMUs.
//!
//! - `vibrofric` with no arguments exports every `scenes/*.toml` into `dist/` and runs a one-line
//!   self-check simulation of each.
//! - `vibrofric export SCENE.toml... --out DIR` writes `DIR/<model_identifier>.fmu` (FMI 2.0) and
//!   `DIR/fmi3/<model_identifier>.fmu` (FMI 3.0).
//! - `vibrofric export --write-descriptions modelDescription/` also refreshes the checked-in
//!   model descriptions.
//!
//! An FMU holds `modelDescription.xml`, `binaries/<platform>/<model_identifier>.<ext>` (a copy of
//! the one `libvibrofric` cdylib, which reads the scene from `resources/` at instantiation),
//! `documentation/index.html` and `resources/scene.toml`.
//!
//! On x86-64 Linux the shipped library is built for glibc 2.17 by `cargo zigbuild` when
//! cargo-zigbuild is installed (in `.venv/bin`, where `bash tests/all.sh` puts it, or on `PATH`),
//! else it is the host build, which needs the host's glibc; the output says which glibc the
//! FMUs need. `VIBROFRIC_PORTABLE=1` requires the glibc 2.17 build, `=0` ships the host build.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod elf;
mod simulate;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

use vibrofric::description::variables::{Causality, VarKind};
use vibrofric::description::{docs, xml, xml3, Scene};
use vibrofric::model::{self, InputId, StateId};
use vibrofric_import::fmi3::Fmu3;
use vibrofric_import::Fmu;

/// FMI 2.0 platform directory of this build (`linux64`, `win64`, `darwin64`).
fn platform() -> &'static str {
    vibrofric_import::platform().0
}

/// FMI 3.0 platform tuple of this build (`x86_64-linux`, `x86_64-windows`, `aarch64-darwin`).
fn platform3() -> String {
    let os = match std::env::consts::OS {
        "macos" => "darwin",
        os => os,
    };
    format!("{}-{os}", std::env::consts::ARCH)
}

/// File name of the FMU library cargo builds beside the binary (`libvibrofric.so` on Linux).
fn lib_file() -> String {
    use std::env::consts::{DLL_EXTENSION, DLL_PREFIX};
    format!("{DLL_PREFIX}vibrofric.{DLL_EXTENSION}")
}

/// Scene directory and FMU directory of the no-argument run.
const SCENES_DIR: &str = "scenes";
const DIST_DIR: &str = "dist";

#[derive(Parser)]
#[command(
    name = "vibrofric",
    version,
    about = "Exports friction-contact scenes as FMI 2.0 and FMI 3.0 FMUs for Co-Simulation and Model Exchange.",
    long_about = "Exports friction-contact scenes as FMI 2.0 and FMI 3.0 FMUs, each offering \
        Co-Simulation (the FMU's own solver) and Model Exchange (the importer's integrator).\n\n\
        Without arguments: export every scenes/*.toml into dist/ (FMI 3.0 editions in dist/fmi3/) \
        and run a short self-check simulation of each."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Write DIR/<model_identifier>.fmu (FMI 2.0) and DIR/fmi3/<model_identifier>.fmu (FMI 3.0) for each scene.
    Export {
        /// Scene files (default: every scenes/*.toml).
        scenes: Vec<PathBuf>,
        /// Directory for the FMUs.
        #[arg(long, value_name = "DIR", default_value = DIST_DIR)]
        out: PathBuf,
        /// Also write DIR/<model_identifier>.xml (refreshes the checked-in modelDescription/).
        #[arg(long, value_name = "DIR")]
        write_descriptions: Option<PathBuf>,
        /// The FMU's shared library (default: the libvibrofric cdylib next to this executable).
        #[arg(long, value_name = "FILE")]
        library: Option<PathBuf>,
        /// Run a short self-check simulation of each exported FMU.
        #[arg(long)]
        check: bool,
    },
    /// Run a scene with the core directly (no FMU) and print its outputs as CSV, one row per
    /// communication point, as fmpy's co-simulation loop places them.
    Simulate(simulate::Options),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => export(&[], Path::new(DIST_DIR), None, None, true),
        Some(Command::Export {
            scenes,
            out,
            write_descriptions,
            library,
            check,
        }) => export(
            &scenes,
            &out,
            write_descriptions.as_deref(),
            library.as_deref(),
            check,
        ),
        Some(Command::Simulate(o)) => simulate::run(&o).map(|csv| print!("{csv}")),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("vibrofric: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Every `*.toml` in `dir`, sorted.
fn standard_scenes(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let entries = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: cannot list scenes: {e}", dir.display()))?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(format!("{}: no *.toml scene files", dir.display()));
    }
    Ok(files)
}

/// The cdylib cargo built beside this executable: `libvibrofric` in the executable's directory
/// or its parent (for executables cargo places in `deps/`).
fn host_library() -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate this executable: {e}"))?;
    let dir = exe.parent().unwrap_or(Path::new("."));
    let candidates = [Some(dir), dir.parent()];
    for d in candidates.into_iter().flatten() {
        let p = d.join(lib_file());
        if p.is_file() {
            return Ok(p);
        }
    }
    Err(format!(
        "cannot find {} next to {}: build it with `cargo build --release` (cargo builds \
         the cdylib beside the binary) or pass --library FILE",
        lib_file(),
        exe.display()
    ))
}

/// The Rust target of the portable Linux build: x86-64, glibc 2.17 symbol versions (RHEL 7,
/// Ubuntu 18.04 and everything newer), linked by zig through cargo-zigbuild.
const PORTABLE_TARGET: &str = "x86_64-unknown-linux-gnu.2.17";
/// The oldest glibc the portable build targets.
const PORTABLE_GLIBC: &str = "2.17";

/// How the portable build is asked for: `VIBROFRIC_PORTABLE` = `1` (required: fail without
/// it), `0` (never), unset (when cargo-zigbuild is found).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Portable {
    Auto,
    Required,
    Off,
}

fn portable_mode() -> Result<Portable, String> {
    match std::env::var("VIBROFRIC_PORTABLE").as_deref() {
        Err(_) | Ok("") => Ok(Portable::Auto),
        Ok("1") => Ok(Portable::Required),
        Ok("0") => Ok(Portable::Off),
        Ok(other) => Err(format!(
            "VIBROFRIC_PORTABLE = {other:?}: must be 1 (require the glibc {PORTABLE_GLIBC} build), \
             0 (ship the host build) or unset (the glibc {PORTABLE_GLIBC} build when cargo-zigbuild is found)"
        )),
    }
}

/// `PATH` with the project's `.venv/bin` first (where `bash tests/all.sh` installs cargo-zigbuild
/// and zig), and the directory of `cargo-zigbuild` when found on it.
fn zigbuild_path() -> (std::ffi::OsString, Option<PathBuf>) {
    let venv_bin = std::env::current_dir()
        .map(|d| d.join(".venv").join("bin"))
        .unwrap_or_else(|_| PathBuf::from(".venv/bin"));
    let mut dirs = vec![venv_bin];
    if let Some(p) = std::env::var_os("PATH") {
        dirs.extend(std::env::split_paths(&p));
    }
    let found = dirs
        .iter()
        .map(|d| d.join("cargo-zigbuild"))
        .find(|p| p.is_file());
    let path = std::env::join_paths(&dirs).unwrap_or_default();
    (path, found)
}

/// Builds the cdylib for glibc 2.17 with `cargo zigbuild` into the same target directory as this
/// executable, and returns it. `Ok(None)` when cargo-zigbuild is not installed (the caller ships
/// the host build and says which glibc it needs).
fn portable_library() -> Result<Option<PathBuf>, String> {
    if !(cfg!(target_os = "linux") && cfg!(target_arch = "x86_64")) {
        return Ok(None);
    }
    let (path, zigbuild) = zigbuild_path();
    if zigbuild.is_none() {
        return Ok(None);
    }
    // <target>/release/vibrofric: the target directory is two levels up.
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate this executable: {e}"))?;
    let target_dir = exe
        .parent()
        .filter(|d| d.file_name().is_some_and(|n| n == "release"))
        .and_then(Path::parent)
        .ok_or_else(|| {
            format!(
                "{} is not in a cargo target directory's release/: build with `cargo run --release`",
                exe.display()
            )
        })?;
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    println!(
        "building the FMU binary for glibc >= {PORTABLE_GLIBC} with cargo-zigbuild \
         (target {PORTABLE_TARGET}; the first build takes about as long as `cargo build --release`)"
    );
    let status = std::process::Command::new(&cargo)
        .env("PATH", &path)
        .args([
            "zigbuild",
            "--release",
            "--package",
            "vibrofric",
            "--lib",
            "--target",
            PORTABLE_TARGET,
        ])
        .arg("--manifest-path")
        .arg(&manifest)
        .arg("--target-dir")
        .arg(target_dir)
        .status()
        .map_err(|e| format!("cannot run {}: {e}", cargo.to_string_lossy()))?;
    if !status.success() {
        return Err(format!(
            "`cargo zigbuild --release --package vibrofric --lib --target {PORTABLE_TARGET}` failed ({status})"
        ));
    }
    let lib = target_dir
        .join("x86_64-unknown-linux-gnu")
        .join("release")
        .join(lib_file());
    if !lib.is_file() {
        return Err(format!("cargo zigbuild did not write {}", lib.display()));
    }
    Ok(Some(lib))
}

/// The cdylib to ship, and a line saying where it comes from: `--library`, else the glibc 2.17
/// build when cargo-zigbuild is available (see [`Portable`]), else the host build.
fn find_library(explicit: Option<&Path>) -> Result<(PathBuf, &'static str), String> {
    if let Some(p) = explicit {
        return if p.is_file() {
            Ok((p.to_path_buf(), "--library"))
        } else {
            Err(format!("--library {}: no such file", p.display()))
        };
    }
    let mode = portable_mode()?;
    if mode != Portable::Off {
        match portable_library() {
            Ok(Some(lib)) => return Ok((lib, "cargo-zigbuild")),
            Ok(None) if mode == Portable::Required => return Err(
                "VIBROFRIC_PORTABLE=1 but cargo-zigbuild was found neither in .venv/bin nor on \
                     PATH: `bash tests/all.sh` installs it (with zig) into .venv, or \
                     `pip install ziglang cargo-zigbuild`"
                    .to_string(),
            ),
            Ok(None) => {}
            Err(e) if mode == Portable::Required => return Err(e),
            Err(e) => println!("warning: {e}; shipping the host build instead"),
        }
    }
    Ok((host_library()?, "host toolchain"))
}

/// One line on which C library the shipped binary needs.
fn platform_line(lib: &Path, source: &str) -> Result<(String, docs::Binary), String> {
    if !cfg!(target_os = "linux") {
        return Ok((
            format!("binaries/{}: {} ({source})", platform(), lib.display()),
            docs::Binary {
                platform: platform(),
                glibc: None,
                libraries: vec![],
            },
        ));
    }
    let needs = elf::file_needs(lib)?;
    let glibc = needs.max_glibc().map(|v| v.to_string());
    let need = glibc
        .as_deref()
        .map_or("no versioned glibc symbol".to_string(), |v| {
            format!("needs glibc >= {v}")
        });
    let mut line = format!(
        "binaries/{}: {} ({source}): {need}",
        platform(),
        lib.display()
    );
    if source == "cargo-zigbuild" {
        line.push_str(&format!(
            " (built for glibc {PORTABLE_GLIBC}: RHEL 7/8, Ubuntu 18.04/20.04 and newer)"
        ));
    }
    if source == "host toolchain" {
        line.push_str(&format!(
            "; for glibc >= {PORTABLE_GLIBC} (RHEL 7/8, Ubuntu 18.04/20.04) install cargo-zigbuild \
             (`bash tests/all.sh` puts it, with zig, into .venv) and export again"
        ));
    }
    Ok((
        line,
        docs::Binary {
            platform: platform(),
            glibc,
            libraries: needs.libraries,
        },
    ))
}

fn export(
    scene_files: &[PathBuf],
    out: &Path,
    descriptions: Option<&Path>,
    library: Option<&Path>,
    check: bool,
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
    let (lib_path, source) = find_library(library)?;
    let lib = std::fs::read(&lib_path)
        .map_err(|e| format!("{}: cannot read: {e}", lib_path.display()))?;
    let (line, binary) = platform_line(&lib_path, source)?;
    println!("{line}");

    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    if let Some(d) = descriptions {
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    let out3 = out.join("fmi3");
    std::fs::create_dir_all(&out3).map_err(|e| format!("{}: {e}", out3.display()))?;
    for (file, scene) in &scenes {
        let fmu = out.join(format!("{}.fmu", scene.model_identifier));
        let description = xml::model_description(scene);
        let bin = format!(
            "binaries/{}/{}.{}",
            platform(),
            scene.model_identifier,
            std::env::consts::DLL_EXTENSION
        );
        let doc = docs::index_html_for(scene, &binary);
        write_fmu(&fmu, scene, &description, &bin, &lib, &doc)?;
        // The FMI 3.0 edition: the same library and scene, FMI 3.0's description and layout.
        let fmu3 = out3.join(format!("{}.fmu", scene.model_identifier));
        let bin3 = format!(
            "binaries/{}/{}.{}",
            platform3(),
            scene.model_identifier,
            std::env::consts::DLL_EXTENSION
        );
        let doc3 = docs::index_html_fmi3(scene, &binary);
        write_fmu(
            &fmu3,
            scene,
            &xml3::model_description(scene),
            &bin3,
            &lib,
            &doc3,
        )?;
        let n_vars = scene.variables().count();
        let n_out = scene
            .variables()
            .filter(|v| v.causality(&scene.config) == Causality::Output)
            .count();
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
        if check {
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

/// Writes the FMU archive (to a temporary name first, so that a failed export leaves no
/// half-written FMU behind).
fn write_fmu(
    path: &Path,
    scene: &Scene,
    description: &str,
    binary_name: &str,
    lib: &[u8],
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
    let entries: [(String, &[u8], u32); 4] = [
        ("modelDescription.xml".into(), description.as_bytes(), 0o644),
        (binary_name.into(), lib, 0o755),
        ("documentation/index.html".into(), doc.as_bytes(), 0o644),
        (
            "resources/scene.toml".into(),
            scene.source.as_bytes(),
            0o644,
        ),
    ];
    for (name, bytes, mode) in entries {
        zip.start_file(name, opts.unix_permissions(mode))
            .map_err(zerr)?;
        zip.write_all(bytes).map_err(io)?;
    }
    zip.finish().map_err(zerr)?;
    std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(())
}

/// The FMI 3.0 edition through the importer's FMI 3.0 loader, on the steps of [`self_check`]:
/// its `F_mean` and `reduction` must equal the FMI 2.0 edition's bit for bit.
fn self_check_fmi3(fmu3_path: &Path, fmu2_path: &Path) -> Result<String, String> {
    let (t0, t1, _, step) = xml::DEFAULT_EXPERIMENT;
    let fmu2 = Fmu::load(fmu2_path).map_err(|e| e.to_string())?;
    let fmu3 = Fmu3::load(fmu3_path).map_err(|e| e.to_string())?;
    if fmu3.description.guid != fmu2.description.guid {
        return Err(format!(
            "instantiationToken {} is not the FMI 2.0 GUID {}",
            fmu3.description.guid, fmu2.description.guid
        ));
    }
    let outputs = ["F_mean", "reduction"].map(|n| fmu2.description.vr(n));
    let outputs: Vec<u32> = outputs.into_iter().flatten().collect();
    let rows2 = fmu2
        .simulate(t1 - t0, step, &[], &outputs)
        .map_err(|e| e.to_string())?;
    let rows3 = fmu3
        .simulate(t1 - t0, step, &[], &outputs)
        .map_err(|e| e.to_string())?;
    let same = rows2.len() == rows3.len()
        && rows2
            .iter()
            .flatten()
            .zip(rows3.iter().flatten())
            .all(|(a, b)| a.to_bits() == b.to_bits());
    if !same {
        return Err("F_mean or reduction differ from the FMI 2.0 edition's".into());
    }
    Ok(format!(
        "F_mean and reduction at all {} points equal to the FMI 2.0 edition's, bit for bit",
        rows3.len()
    ))
}

/// Model Exchange through the exported FMU: the core steps the scene (its start values, the
/// default tolerance) to a time inside a later window; an instance for Model Exchange, set to
/// the same time and states, must give the core's derivatives and the Jacobian column of each
/// state bit for bit (the same code behind the C interface).
fn self_check_model_exchange(fmu_path: &Path, scene: &Scene) -> Result<String, String> {
    let (t0, _, tol, _) = xml::DEFAULT_EXPERIMENT;
    let t = t0 + 0.0123;
    let mut sim = model::build(scene.config, scene.start, t0, tol).map_err(|e| e.to_string())?;
    for i in InputId::ALL {
        if i.present(&scene.config) {
            sim.set_input(i, i.get(&scene.inputs))
                .map_err(|e| e.to_string())?;
        }
    }
    sim.step_to(t).map_err(|e| e.to_string())?;
    let states: Vec<StateId> = scene
        .variables()
        .filter_map(|v| match v.kind {
            VarKind::State(x) => Some(x),
            _ => None,
        })
        .collect();
    let (x, dx) = (sim.states(), sim.derivatives());
    let fmu = Fmu::load(fmu_path).map_err(|e| e.to_string())?;
    let mut inst = fmu
        .instantiate_model_exchange("self-check")
        .map_err(|e| e.to_string())?;
    let ok = |s: vibrofric_import::Status, what: &str, inst: &vibrofric_import::Instance| {
        if s == vibrofric_import::Status::Ok {
            Ok(())
        } else {
            Err(format!("{what}: {s:?} ({})", inst.last_message()))
        }
    };
    ok(inst.setup_experiment(Some(tol), t0, None), "setup", &inst)?;
    ok(inst.enter_initialization_mode(), "initialization", &inst)?;
    ok(inst.exit_initialization_mode(), "initialization", &inst)?;
    ok(inst.new_discrete_states().0, "event update", &inst)?;
    ok(inst.enter_continuous_time_mode(), "continuous time", &inst)?;
    ok(inst.set_time(t), "time", &inst)?;
    let values: Vec<f64> = states.iter().map(|s| x[s.index()]).collect();
    ok(inst.set_continuous_states(&values), "states", &inst)?;
    let got = inst
        .get_derivatives(states.len())
        .map_err(|s| format!("derivatives: {s:?} ({})", inst.last_message()))?;
    for (s, d) in states.iter().zip(&got) {
        if d.to_bits() != dx[s.index()].to_bits() {
            return Err(format!(
                "{} = {d} through the FMU but {} through the core",
                s.derivative_name(),
                dx[s.index()]
            ));
        }
    }
    let unknowns: Vec<u32> = states.iter().map(|s| s.derivative_vr()).collect();
    for known in &states {
        let mut dir = [0.0; StateId::COUNT];
        dir[known.index()] = 1.0;
        let (core, _) = sim.tangent(&dir, &model::Inputs::default());
        let column = inst
            .get_directional_derivative(&unknowns, &[known.vr()], &[1.0])
            .map_err(|s| format!("directional derivative: {s:?} ({})", inst.last_message()))?;
        for (s, d) in states.iter().zip(&column) {
            if d.to_bits() != core[s.index()].to_bits() {
                return Err(format!(
                    "d {} / d {} = {d} through the FMU but {} through the core",
                    s.derivative_name(),
                    known.name(),
                    core[s.index()]
                ));
            }
        }
    }
    Ok(format!(
        "the derivatives of its {} states and their Jacobian at t = {t} s equal to the core's, bit for bit",
        states.len()
    ))
}

/// A short simulation through the exported FMU: load the archive with the crate's importer
/// (unpacks it, loads `binaries/<platform>/<model_identifier>.so`, instantiates with the GUID of
/// its model description and its `resources/`), run the default experiment (0.1 s, communication
/// step 1e-3 s) with the scene's start values, and compare `F_mean` and `reduction` with the same
/// steps taken by the core library directly. Returns the line to print.
fn self_check(fmu_path: &Path, scene: &Scene) -> Result<String, String> {
    let (t0, t1, tol, step) = xml::DEFAULT_EXPERIMENT;
    let clock = std::time::Instant::now();
    let fmu = Fmu::load(fmu_path).map_err(|e| e.to_string())?;
    if fmu.description.guid != xml::guid(scene) {
        return Err(format!(
            "the archive's GUID {} is not the scene's {}",
            fmu.description.guid,
            xml::guid(scene)
        ));
    }
    let vr = |name: &str| {
        fmu.description
            .vr(name)
            .ok_or_else(|| format!("the FMU has no variable {name}"))
    };
    let outputs = [vr("F_mean")?, vr("reduction")?];
    let rows = fmu
        .simulate(t1 - t0, step, &[], &outputs)
        .map_err(|e| e.to_string())?;
    let elapsed = clock.elapsed().as_secs_f64();
    let last = rows.last().ok_or("the simulation returned no rows")?;
    let (f_mean, reduction) = (last[1], last[2]);
    if !(f_mean.is_finite() && reduction.is_finite()) {
        return Err(format!(
            "non-finite result: F_mean = {f_mean}, reduction = {reduction}"
        ));
    }

    // The same communication points through the core (as `Fmu::simulate` steps them).
    let mut sim = model::build(scene.config, scene.start, t0, tol).map_err(|e| e.to_string())?;
    for i in InputId::ALL {
        if i.present(&scene.config) {
            sim.set_input(i, i.get(&scene.inputs))
                .map_err(|e| e.to_string())?;
        }
    }
    let n = ((t1 - t0) / step).round().max(1.0) as u64;
    let mut t = t0;
    for k in 0..n {
        t = if k + 1 == n { t1 } else { t + step };
        sim.step_to(t).map_err(|e| e.to_string())?;
    }
    let core = sim.outputs();
    let diff = (f_mean - core.f_mean).abs();
    // Both run the same code with the same tolerance: anything beyond rounding is a fault.
    let scale = scene.start.f_c().max(f_mean.abs()).max(1e-12);
    if diff > 1e-9 * scale {
        return Err(format!(
            "F_mean = {f_mean} N through the FMU but {} N through the core",
            core.f_mean
        ));
    }
    let agreement = if diff == 0.0 {
        "identical to the core".to_string()
    } else {
        format!("core differs by {diff:.1e} N")
    };
    Ok(format!(
        "F_mean = {f_mean:.4} N, reduction = {reduction:.4} at t = {t1} s ({n} steps of {step} s through the FMU in {:.0} ms; {agreement})",
        elapsed * 1e3
    ))
}
