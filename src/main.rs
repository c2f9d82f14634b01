//! `vibrofric`: exports scenes (`scenes/*.toml`, described in `docs/scenes.md`) as FMI 2.0 and
//! FMI 3.0 FMUs, each for Co-Simulation and Model Exchange.
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
//! `=0` ships the host build), ARM Linux (cargo-zigbuild, glibc 2.17; FMI 3.0's `aarch64-linux`,
//! and FMI 2.0 FMUs of its own in `DIR/aarch64-linux/`), Windows (mingw-w64) and macOS
//! (cargo-zigbuild, universal). By default every platform whose toolchain is installed; the
//! output names the others and how to add them.

//!
//! The command line is here; `export.rs` writes the FMUs, `package.rs` their archives,
//! `self_check.rs` runs each exported FMU against the core, `platforms.rs` (with `binary.rs` and
//! `elf.rs`) builds and inspects the libraries, `simulate.rs` runs a scene on the core.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod binary;
mod elf;
mod export;
mod package;
mod platforms;
mod self_check;
mod simulate;

use export::export;
use platforms::Request;

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
        /// installed; the others are named), `all` (linux64, aarch64-linux, win64, darwin64, or
        /// fail), or a list such as `linux64,win64`. ARM Linux (`aarch64-linux`) goes into the
        /// FMI 3.0 FMUs and into FMI 2.0 FMUs of its own in OUT/aarch64-linux/.
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
