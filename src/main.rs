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
//! An FMU holds `modelDescription.xml`, `binaries/<platform>/<model_identifier>.<ext>` for each
//! platform it carries (the one `libvibrofric` cdylib built per platform, which reads the scene
//! from `resources/` at instantiation), `documentation/index.html` and `resources/scene.toml`.
//!
//! `--platforms` chooses the platforms (`platforms.rs`): Linux (glibc 2.17 by cargo-zigbuild
//! where installed, else the host build; `VIBROFRIC_PORTABLE=1` requires the glibc 2.17 build,
//! `=0` ships the host build), Windows (mingw-w64) and macOS (cargo-zigbuild, universal). By
//! default every platform whose toolchain is installed; the output names the others and how to
//! add them.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod binary;
mod elf;
mod platforms;
mod simulate;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

use platforms::{Request, Shipped};
use vibrofric::description::variables::{Causality, VarKind};
use vibrofric::description::{docs, xml, xml3, Scene};
use vibrofric::model::{self, StateId};
use vibrofric_import::fmi3::Fmu3;
use vibrofric_import::{Fmu, Importer};

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
        /// Platforms to put into each FMU: `available` (every platform whose toolchain is
        /// installed; the others are named), `all` (linux64, win64, darwin64, or fail), or a
        /// list such as `linux64,win64`.
        #[arg(long, value_name = "LIST", default_value = "available", value_parser = Request::parse)]
        platforms: Request,
    },
    /// Run a scene with the core directly (no FMU) and print its outputs as CSV, one row per
    /// communication point, as fmpy's co-simulation loop places them.
    Simulate(simulate::Options),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => export(
            &[],
            Path::new(DIST_DIR),
            None,
            None,
            true,
            &Request::Available,
        ),
        Some(Command::Export {
            scenes,
            out,
            write_descriptions,
            library,
            check,
            platforms,
        }) => export(
            &scenes,
            &out,
            write_descriptions.as_deref(),
            library.as_deref(),
            check,
            &platforms,
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

fn export(
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
    let names: Vec<&str> = shipped.iter().map(|s| s.platform.name()).collect();
    println!("platforms in each FMU: {}", names.join(", "));
    let files = read_binaries(&shipped)?;
    let doc2: Vec<docs::Binary> = shipped.iter().map(|s| s.doc2.clone()).collect();
    let doc3: Vec<docs::Binary> = shipped.iter().map(|s| s.doc3.clone()).collect();

    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    if let Some(d) = descriptions {
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    let out3 = out.join("fmi3");
    std::fs::create_dir_all(&out3).map_err(|e| format!("{}: {e}", out3.display()))?;
    for (file, scene) in &scenes {
        let fmu = out.join(format!("{}.fmu", scene.model_identifier));
        let description = xml::model_description(scene);
        let id = &scene.model_identifier;
        let bins2: Vec<(String, &[u8])> = shipped
            .iter()
            .zip(&files)
            .map(|(s, (lib2, _))| {
                let ext = s.platform.extension();
                (
                    format!("binaries/{}/{id}.{ext}", s.platform.name()),
                    &lib2[..],
                )
            })
            .collect();
        let doc = docs::index_html_for(scene, &doc2);
        write_fmu(&fmu, scene, &description, &bins2, &doc)?;
        // The FMI 3.0 edition: the same libraries and scene, FMI 3.0's description and layout.
        let fmu3 = out3.join(format!("{id}.fmu"));
        let bins3: Vec<(String, &[u8])> = shipped
            .iter()
            .zip(&files)
            .flat_map(|(s, (_, libs3))| {
                let ext = s.platform.extension();
                s.fmi3.iter().zip(libs3).map(move |((folder, _), lib)| {
                    (format!("binaries/{folder}/{id}.{ext}"), &lib[..])
                })
            })
            .collect();
        let doc3 = docs::index_html_fmi3(scene, &doc3);
        write_fmu(&fmu3, scene, &xml3::model_description(scene), &bins3, &doc3)?;
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

/// The bytes of each shipped library: the FMI 2.0 file and the FMI 3.0 files, per platform.
type Binaries = Vec<(Vec<u8>, Vec<Vec<u8>>)>;

fn read_binaries(shipped: &[Shipped]) -> Result<Binaries, String> {
    let read =
        |p: &Path| std::fs::read(p).map_err(|e| format!("{}: cannot read: {e}", p.display()));
    shipped
        .iter()
        .map(|s| {
            let libs3 = s
                .fmi3
                .iter()
                .map(|(_, f)| read(f))
                .collect::<Result<_, _>>()?;
            Ok((read(&s.fmi2)?, libs3))
        })
        .collect()
}

/// Writes the FMU archive (to a temporary name first, so that a failed export leaves no
/// half-written FMU behind).
fn write_fmu(
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

/// The core for a scene as the FMU starts it in its default experiment: its start values and
/// inputs, at `t0`, tolerance `tol`.
fn core_at(scene: &Scene, t0: f64, tol: f64) -> Result<Box<dyn model::Simulator>, String> {
    model::Setup::new(scene.config, scene.start)
        .inputs(scene.inputs)
        .start(t0)
        .tolerance(tol)
        .build()
        .map_err(|e| e.to_string())
}

/// Model Exchange through the exported FMU: the core steps the scene (its start values, the
/// default tolerance) to a time inside a later window; an instance for Model Exchange, set to
/// the same time and states, must give the core's derivatives and the Jacobian column of each
/// state bit for bit (the same code behind the C interface).
fn self_check_model_exchange(fmu_path: &Path, scene: &Scene) -> Result<String, String> {
    let (t0, _, tol, _) = xml::DEFAULT_EXPERIMENT;
    let t = t0 + 0.0123;
    let mut sim = core_at(scene, t0, tol)?;
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
    // `reduction` is an output of velocity-driven scenes only.
    let mut outputs = vec![vr("F_mean")?];
    outputs.extend(fmu.description.vr("reduction"));
    let rows = fmu
        .simulate(t1 - t0, step, &[], &outputs)
        .map_err(|e| e.to_string())?;
    let elapsed = clock.elapsed().as_secs_f64();
    let last = rows.last().ok_or("the simulation returned no rows")?;
    let (f_mean, reduction) = (last[1], last.get(2).copied());
    if !(f_mean.is_finite() && reduction.is_none_or(f64::is_finite)) {
        return Err(format!(
            "non-finite result: F_mean = {f_mean}, reduction = {reduction:?}"
        ));
    }
    let reduction = reduction.map_or(String::new(), |r| format!(", reduction = {r:.4}"));

    // The same communication points through the core (as `Importer::simulate` steps them).
    let mut sim = core_at(scene, t0, tol)?;
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
        "F_mean = {f_mean:.4} N{reduction} at t = {t1} s ({n} steps of {step} s through the FMU in {:.0} ms; {agreement})",
        elapsed * 1e3
    ))
}
