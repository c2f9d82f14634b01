//! The platforms an FMU carries, and how each one's library is built on this Linux machine.
//!
//! | platform | FMI 2.0 folder | FMI 3.0 folders | built by | library |
//! |---|---|---|---|---|
//! | Linux | `linux64` | `x86_64-linux` | `cargo zigbuild`, target `x86_64-unknown-linux-gnu.2.17` (glibc 2.17), else the host build | `.so` |
//! | ARM Linux | `linux64` of a separate FMI 2.0 FMU (`<out>/aarch64-linux/`) | `aarch64-linux` | `cargo zigbuild`, target `aarch64-unknown-linux-gnu.2.17` (glibc 2.17) | `.so` |
//! | Windows | `win64` | `x86_64-windows` | `cargo build`, target `x86_64-pc-windows-gnu`, linked by mingw-w64 | `.dll` |
//! | macOS | `darwin64` (universal) | `x86_64-darwin`, `aarch64-darwin` (each slice) | `cargo zigbuild`, target `universal2-apple-darwin`, macOS 11 | `.dylib` |
//!
//! FMI 2.0 names no ARM folder. fmpy, the FMI Library and rust-fmi all load `binaries/linux64/`
//! on 64-bit ARM Linux, where the x86-64 library already is: an FMI 2.0 FMU can hold only one of
//! the two, so the aarch64 library goes into an FMI 2.0 FMU of its own, whose `linux64` holds it.
//!
//! The exporter installs nothing: where a toolchain is missing it says which and how to get it
//! (`bash tests/cross/setup.sh` installs them all), ships the platforms it could build, and fails
//! only when asked for a platform it cannot build (`--platforms all`, or a list).

use std::path::{Path, PathBuf};
use std::process::Command;

use vibrofric_docs::docs;

use crate::{binary, elf};

/// A desktop platform of the FMI standard.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Platform {
    Linux64,
    /// 64-bit ARM Linux (FMI 3.0's `aarch64-linux`).
    LinuxAarch64,
    Win64,
    Darwin64,
}

impl Platform {
    pub const ALL: [Platform; 4] = [
        Platform::Linux64,
        Platform::LinuxAarch64,
        Platform::Win64,
        Platform::Darwin64,
    ];

    /// The name on the command line: the FMI 2.0 folder of the desktop platforms, FMI 3.0's
    /// platform tuple for ARM Linux, which FMI 2.0 does not name.
    pub fn name(self) -> &'static str {
        match self {
            Platform::Linux64 => "linux64",
            Platform::LinuxAarch64 => "aarch64-linux",
            Platform::Win64 => "win64",
            Platform::Darwin64 => "darwin64",
        }
    }

    /// The folder of `binaries/` that holds this platform's library in an FMI 2.0 FMU.
    pub fn fmi2_folder(self) -> &'static str {
        match self {
            Platform::LinuxAarch64 => "linux64",
            p => p.name(),
        }
    }

    /// Whether this platform's FMI 2.0 library goes into FMI 2.0 FMUs of its own, in
    /// `<out>/<name>/`: its [`Platform::fmi2_folder`] is another platform's in the standard FMUs.
    pub fn own_fmi2_edition(self) -> bool {
        self == Platform::LinuxAarch64
    }

    pub fn extension(self) -> &'static str {
        match self {
            Platform::Linux64 | Platform::LinuxAarch64 => "so",
            Platform::Win64 => "dll",
            Platform::Darwin64 => "dylib",
        }
    }

    fn os(self) -> &'static str {
        match self {
            Platform::Linux64 => "x86-64 Linux",
            Platform::LinuxAarch64 => "64-bit ARM Linux (aarch64)",
            Platform::Win64 => "64-bit Windows (x86-64)",
            Platform::Darwin64 => "macOS on Intel and Apple silicon",
        }
    }

    /// How the user gets the toolchain this platform's build needs.
    fn toolchain_hint(self) -> &'static str {
        match self {
            Platform::Linux64 => "build on x86-64 Linux",
            Platform::LinuxAarch64 => {
                "`rustup target add aarch64-unknown-linux-gnu`, and zig with cargo-zigbuild \
                 (`pip install ziglang cargo-zigbuild`, into .venv)"
            }
            Platform::Win64 => {
                "`rustup target add x86_64-pc-windows-gnu` and mingw-w64's gcc \
                 (Debian: `apt-get install gcc-mingw-w64-x86-64`)"
            }
            Platform::Darwin64 => {
                "`rustup target add x86_64-apple-darwin aarch64-apple-darwin`, and zig with \
                 cargo-zigbuild (`pip install ziglang cargo-zigbuild`, into .venv)"
            }
        }
    }
}

/// Which platforms `--platforms` asks for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Request {
    /// Every platform whose toolchain is installed (the default); the others are named.
    Available,
    /// These, or fail saying what is missing (`all` is every platform).
    Required(Vec<Platform>),
}

impl Request {
    /// `available`, `all`, or a comma-separated list such as `linux64,win64`.
    pub fn parse(s: &str) -> Result<Request, String> {
        match s {
            "available" => return Ok(Request::Available),
            "all" => return Ok(Request::Required(Platform::ALL.to_vec())),
            _ => {}
        }
        let mut list = vec![];
        for name in s.split(',').map(str::trim) {
            let p = Platform::ALL
                .into_iter()
                .find(|p| p.name() == name)
                .ok_or_else(|| {
                    format!(
                        "--platforms {s:?}: unknown platform {name:?}; valid: available, all, or a list of linux64, aarch64-linux, win64, darwin64"
                    )
                })?;
            if !list.contains(&p) {
                list.push(p);
            }
        }
        Ok(Request::Required(list))
    }
}

/// One platform's library as it goes into both editions of an FMU.
pub struct Shipped {
    pub platform: Platform,
    /// The library for the FMI 2.0 folder (`binaries/<fmi2_folder>/`).
    pub fmi2: Library,
    /// The FMI 3.0 folders (`binaries/<arch>-<os>/`) and the library each gets.
    pub fmi3: Vec<(&'static str, Library)>,
    /// What the exporter prints: where the library comes from and what it needs.
    pub line: String,
    /// What the FMU's documentation page says of it (the FMI 2.0 edition's folders).
    pub doc2: docs::Binary,
    /// The same for the FMI 3.0 edition.
    pub doc3: docs::Binary,
}

/// A built library, read once: its checks, the export check and the FMU archives all use
/// these bytes.
#[derive(Clone)]
pub struct Library {
    pub path: PathBuf,
    pub bytes: Vec<u8>,
}

impl Library {
    fn read(path: PathBuf) -> Result<Library, String> {
        let bytes =
            std::fs::read(&path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        Ok(Library { path, bytes })
    }
}

/// Where this executable's cargo put its builds, and how to run cargo there.
struct Cargo {
    cargo: std::ffi::OsString,
    manifest: PathBuf,
    target_dir: PathBuf,
    /// `PATH` with `.venv/bin` first, and `cargo-zigbuild` where found.
    path: std::ffi::OsString,
    zigbuild: Option<PathBuf>,
}

impl Cargo {
    fn new() -> Result<Cargo, String> {
        let exe =
            std::env::current_exe().map_err(|e| format!("cannot locate this executable: {e}"))?;
        // <target>/release/vibrofric: the target directory is two levels up.
        let target_dir = exe
            .parent()
            .filter(|d| d.file_name().is_some_and(|n| n == "release"))
            .and_then(Path::parent)
            .ok_or_else(|| {
                format!(
                    "{} is not in a cargo target directory's release/: build with `cargo run --release`",
                    exe.display()
                )
            })?
            .to_path_buf();
        let (path, zigbuild) = zigbuild_path();
        Ok(Cargo {
            cargo: std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()),
            manifest: Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml"),
            target_dir,
            path,
            zigbuild,
        })
    }

    /// `cargo build` (or `zigbuild`) of the FMU library for `target`, with its progress shown.
    fn build(&self, zig: bool, target: &str, env: &[(&str, &str)]) -> Result<(), String> {
        let sub = if zig { "zigbuild" } else { "build" };
        let mut cmd = Command::new(&self.cargo);
        cmd.env("PATH", &self.path)
            .args([sub, "--release", "--package", "vibrofric", "--lib"])
            .args(["--target", target])
            .arg("--manifest-path")
            .arg(&self.manifest)
            .arg("--target-dir")
            .arg(&self.target_dir);
        for (k, v) in env {
            cmd.env(k, v);
        }
        let status = cmd
            .status()
            .map_err(|e| format!("cannot run {}: {e}", self.cargo.to_string_lossy()))?;
        if status.success() {
            Ok(())
        } else {
            Err(format!(
                "`cargo {sub} --release --package vibrofric --lib --target {target}` failed ({status})"
            ))
        }
    }

    /// The library cargo wrote for a target (`<target dir>/<triple>/release/<file>`).
    fn output(&self, triple: &str, file: &str) -> Result<PathBuf, String> {
        let p = self.target_dir.join(triple).join("release").join(file);
        if p.is_file() {
            Ok(p)
        } else {
            Err(format!("the build did not write {}", p.display()))
        }
    }
}

/// `PATH` with the project's `.venv/bin` first (where `bash tests/all.sh` and
/// `tests/cross/setup.sh` install cargo-zigbuild and zig), and `cargo-zigbuild` when found on it.
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

/// Whether rustup installed the standard library of `triple`.
fn has_rust_target(triple: &str) -> bool {
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    Command::new(rustc)
        .args(["--print", "sysroot"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| {
            let sysroot = String::from_utf8_lossy(&o.stdout).trim().to_string();
            Path::new(&sysroot)
                .join("lib/rustlib")
                .join(triple)
                .join("lib")
                .is_dir()
        })
        .unwrap_or(false)
}

fn on_path(path: &std::ffi::OsStr, program: &str) -> bool {
    std::env::split_paths(path).any(|d| d.join(program).is_file())
}

/// The Rust target of the portable Linux build: x86-64, glibc 2.17 symbol versions (RHEL 7,
/// Ubuntu 18.04 and everything newer), linked by zig through cargo-zigbuild.
const PORTABLE_TARGET: &str = "x86_64-unknown-linux-gnu.2.17";
/// The oldest glibc the portable build targets.
pub const PORTABLE_GLIBC: &str = "2.17";
const WINDOWS_TARGET: &str = "x86_64-pc-windows-gnu";
const MACOS_TARGETS: [&str; 2] = ["x86_64-apple-darwin", "aarch64-apple-darwin"];
/// The Rust target of the ARM Linux build, glibc 2.17 as the x86-64 one.
const ARM_LINUX_TARGET: &str = "aarch64-unknown-linux-gnu";

/// How the glibc 2.17 build is asked for: `VIBROFRIC_PORTABLE` = `1` (required: fail without
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

/// File name of the FMU library cargo builds for a platform (`libvibrofric.so`, `vibrofric.dll`).
fn lib_file(p: Platform) -> String {
    match p {
        Platform::Win64 => "vibrofric.dll".into(),
        _ => format!("libvibrofric.{}", p.extension()),
    }
}

/// The platform this executable runs on, when it is one of the FMI desktop platforms built here.
fn host() -> Option<Platform> {
    match (std::env::consts::OS, std::env::consts::ARCH) {
        ("linux", "x86_64") => Some(Platform::Linux64),
        ("windows", "x86_64") => Some(Platform::Win64),
        ("macos", _) => Some(Platform::Darwin64),
        _ => None,
    }
}

/// The cdylib cargo built beside this executable (`libvibrofric` in the executable's directory or
/// its parent, for executables cargo places in `deps/`).
fn host_library() -> Result<PathBuf, String> {
    let file = format!(
        "{}vibrofric.{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_EXTENSION
    );
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate this executable: {e}"))?;
    let dir = exe.parent().unwrap_or(Path::new("."));
    for d in [Some(dir), dir.parent()].into_iter().flatten() {
        let p = d.join(&file);
        if p.is_file() {
            return Ok(p);
        }
    }
    Err(format!(
        "cannot find {file} next to {}: build it with `cargo build --release` (cargo builds \
         the cdylib beside the binary) or pass --library FILE",
        exe.display()
    ))
}

/// Builds (or finds) the library of every platform asked for. Returns the shipped ones, in
/// [`Platform::ALL`]'s order, and a line for each platform left out saying why.
pub fn build(
    request: &Request,
    library: Option<&Path>,
) -> Result<(Vec<Shipped>, Vec<String>), String> {
    let wanted: Vec<Platform> = match request {
        Request::Available => Platform::ALL.to_vec(),
        Request::Required(list) => list.clone(),
    };
    let required = matches!(request, Request::Required(_));
    let cargo = Cargo::new();
    let mut shipped = vec![];
    let mut skipped = vec![];
    for p in Platform::ALL.into_iter().filter(|p| wanted.contains(p)) {
        let result = match p {
            Platform::Linux64 => linux(library, cargo.as_ref()),
            Platform::LinuxAarch64 => cargo
                .as_ref()
                .map_err(|e| e.clone().into())
                .and_then(linux_aarch64),
            Platform::Win64 => cargo
                .as_ref()
                .map_err(|e| e.clone().into())
                .and_then(windows),
            Platform::Darwin64 => cargo.as_ref().map_err(|e| e.clone().into()).and_then(macos),
        };
        match result {
            Ok(s) => shipped.push(s),
            Err(Missing::Toolchain(why)) if !required => skipped.push(format!(
                "{}: not in the FMUs: {why}; to add it: {} (`bash tests/cross/setup.sh` installs every cross toolchain), then export again",
                p.name(),
                p.toolchain_hint()
            )),
            Err(Missing::Toolchain(why)) => {
                return Err(format!(
                    "{}: cannot build: {why}; install {} (`bash tests/cross/setup.sh` installs every cross toolchain)",
                    p.name(),
                    p.toolchain_hint()
                ))
            }
            Err(Missing::Failed(e)) => return Err(format!("{}: {e}", p.name())),
        }
    }
    if shipped.is_empty() {
        return Err(format!(
            "no platform could be built: {}",
            skipped.join("; ")
        ));
    }
    check_exports(&shipped)?;
    Ok((shipped, skipped))
}

/// Why a platform is not shipped: its toolchain is missing (named), or its build failed.
enum Missing {
    Toolchain(String),
    Failed(String),
}

impl From<String> for Missing {
    fn from(e: String) -> Missing {
        Missing::Failed(e)
    }
}

/// The Linux library: `--library`, else the glibc 2.17 build when cargo-zigbuild is found, else
/// the host build.
fn linux(library: Option<&Path>, cargo: Result<&Cargo, &String>) -> Result<Shipped, Missing> {
    let (lib, source) = if let Some(p) = library {
        if !p.is_file() {
            return Err(Missing::Failed(format!(
                "--library {}: no such file",
                p.display()
            )));
        }
        (p.to_path_buf(), "--library")
    } else {
        let mode = portable_mode()?;
        let zig = cargo.ok().filter(|c| c.zigbuild.is_some());
        match (mode, zig) {
            (Portable::Off, _) | (Portable::Auto, None) => {
                if host() != Some(Platform::Linux64) {
                    return Err(Missing::Toolchain(
                        "the Linux library is built on x86-64 Linux".into(),
                    ));
                }
                (host_library()?, "host toolchain")
            }
            (Portable::Required, None) => {
                return Err(Missing::Failed(
                    "VIBROFRIC_PORTABLE=1 but cargo-zigbuild was found neither in .venv/bin nor on \
                     PATH: `bash tests/all.sh` or `bash tests/cross/setup.sh` installs it (with zig) \
                     into .venv, or `pip install ziglang cargo-zigbuild`"
                        .into(),
                ))
            }
            (_, Some(c)) => {
                println!(
                    "linux64: building the FMU library for glibc >= {PORTABLE_GLIBC} with cargo-zigbuild (target {PORTABLE_TARGET})"
                );
                c.build(true, PORTABLE_TARGET, &[])?;
                (
                    c.output("x86_64-unknown-linux-gnu", &lib_file(Platform::Linux64))?,
                    "cargo-zigbuild",
                )
            }
        }
    };
    elf_shipped(Platform::Linux64, Library::read(lib)?, source)
}

/// The ARM Linux library: `cargo zigbuild --target aarch64-unknown-linux-gnu.2.17`, linked by zig
/// against glibc 2.17's symbol versions as the x86-64 one.
fn linux_aarch64(cargo: &Cargo) -> Result<Shipped, Missing> {
    let mut missing = vec![];
    if !has_rust_target(ARM_LINUX_TARGET) {
        missing.push(format!("the Rust target {ARM_LINUX_TARGET}"));
    }
    if cargo.zigbuild.is_none() {
        missing.push("cargo-zigbuild (with zig)".into());
    }
    toolchain(missing)?;
    let target = format!("{ARM_LINUX_TARGET}.{PORTABLE_GLIBC}");
    println!(
        "aarch64-linux: building the FMU library for glibc >= {PORTABLE_GLIBC} with cargo-zigbuild (target {target})"
    );
    cargo.build(true, &target, &[])?;
    let lib = cargo.output(ARM_LINUX_TARGET, &lib_file(Platform::LinuxAarch64))?;
    elf_shipped(
        Platform::LinuxAarch64,
        Library::read(lib)?,
        "cargo-zigbuild",
    )
}

/// A Linux library as the ELF file says: refused when its code is for another processor than
/// the platform's; the highest glibc symbol version it imports and the libraries it links go
/// into the exporter's line and the documentation page.
fn elf_shipped(platform: Platform, lib: Library, source: &str) -> Result<Shipped, Missing> {
    let at = lib.path.display().to_string();
    let needs = elf::needs(&lib.bytes).map_err(|e| format!("{at}: {e}"))?;
    let (arch, fmi3_folder) = match platform {
        Platform::LinuxAarch64 => ("aarch64", "aarch64-linux"),
        _ => ("x86_64", "x86_64-linux"),
    };
    if needs.machine != arch {
        return Err(Missing::Failed(format!(
            "{at}: its code is for {}, not {arch}: not a {} library",
            needs.machine,
            platform.name()
        )));
    }
    let glibc = needs.max_glibc().map(|v| v.to_string());
    let need = glibc
        .as_deref()
        .map_or("no versioned glibc symbol".to_string(), |v| {
            format!("needs glibc >= {v}")
        });
    let mut line = format!("{}: {at} ({source}): {need}", platform.name());
    if source == "cargo-zigbuild" {
        line.push_str(&format!(
            " (built for glibc {PORTABLE_GLIBC}: RHEL 7/8, Ubuntu 18.04/20.04 and newer)"
        ));
    }
    if source == "host toolchain" {
        line.push_str(&format!(
            "; for glibc >= {PORTABLE_GLIBC} (RHEL 7/8, Ubuntu 18.04/20.04) install cargo-zigbuild \
             (`bash tests/cross/setup.sh` puts it, with zig, into .venv) and export again"
        ));
    }
    let requirement = match &glibc {
        Some(v) => format!(
            "glibc {v} or newer (the highest <code>GLIBC_</code> symbol version the library imports; glibc 2.17 is RHEL 7, 2.27 Ubuntu 18.04, 2.28 RHEL 8, 2.31 Ubuntu 20.04)"
        ),
        None => "no versioned glibc symbol".into(),
    };
    let doc = |folder| docs::Binary {
        folders: vec![folder],
        file_ext: "so",
        os: platform.os(),
        requirement: requirement.clone(),
        libraries: needs.libraries.clone(),
    };
    Ok(Shipped {
        platform,
        fmi3: vec![(fmi3_folder, lib.clone())],
        fmi2: lib,
        line,
        doc2: doc(platform.fmi2_folder()),
        doc3: doc(fmi3_folder),
    })
}

/// A platform whose toolchain misses something: which (none: ready to build).
fn toolchain(missing: Vec<String>) -> Result<(), Missing> {
    if missing.is_empty() {
        Ok(())
    } else {
        Err(Missing::Toolchain(format!(
            "missing {}",
            missing.join(" and ")
        )))
    }
}

/// The Windows DLL: `cargo build --target x86_64-pc-windows-gnu`, linked by mingw-w64's gcc.
fn windows(cargo: &Cargo) -> Result<Shipped, Missing> {
    let mut missing = vec![];
    if !has_rust_target(WINDOWS_TARGET) {
        missing.push(format!("the Rust target {WINDOWS_TARGET}"));
    }
    let linker = std::env::var("CARGO_TARGET_X86_64_PC_WINDOWS_GNU_LINKER")
        .unwrap_or_else(|_| "x86_64-w64-mingw32-gcc".into());
    if !Path::new(&linker).is_file() && !on_path(&cargo.path, &linker) {
        missing.push(format!("the linker {linker} (mingw-w64)"));
    }
    toolchain(missing)?;
    println!("win64: building the FMU library with mingw-w64 (target {WINDOWS_TARGET})");
    cargo.build(false, WINDOWS_TARGET, &[])?;
    let lib = Library::read(cargo.output(WINDOWS_TARGET, &lib_file(Platform::Win64))?)?;
    let facts = checked(&lib)?;
    let doc = |folder| docs::Binary {
        folders: vec![folder],
        file_ext: "dll",
        os: Platform::Win64.os(),
        requirement: "Windows 10 or later (Windows Server 2016 or later)".into(),
        libraries: facts.slices[0].libraries.clone(),
    };
    Ok(Shipped {
        platform: Platform::Win64,
        fmi3: vec![("x86_64-windows", lib.clone())],
        line: format!(
            "win64: {} (mingw-w64): {}",
            lib.path.display(),
            facts.summary()
        ),
        fmi2: lib,
        doc2: doc("win64"),
        doc3: doc("x86_64-windows"),
    })
}

/// The macOS dylibs: a universal one (x86_64 + arm64) for FMI 2.0's `darwin64`, and each slice
/// for FMI 3.0's `x86_64-darwin` and `aarch64-darwin`, built for macOS 11 by cargo-zigbuild.
fn macos(cargo: &Cargo) -> Result<Shipped, Missing> {
    let mut missing: Vec<String> = MACOS_TARGETS
        .iter()
        .filter(|t| !has_rust_target(t))
        .map(|t| format!("the Rust target {t}"))
        .collect();
    if cargo.zigbuild.is_none() {
        missing.push("cargo-zigbuild (with zig)".into());
    }
    toolchain(missing)?;
    let (major, minor) = binary::MACOS_MIN;
    let deployment = format!("{major}.{minor}");
    println!(
        "darwin64: building the universal FMU library (x86_64 + arm64, macOS {deployment}) with cargo-zigbuild"
    );
    cargo.build(
        true,
        "universal2-apple-darwin",
        &[("MACOSX_DEPLOYMENT_TARGET", &deployment)],
    )?;
    let file = lib_file(Platform::Darwin64);
    let universal = Library::read(cargo.output("universal2-apple-darwin", &file)?)?;
    let x86 = Library::read(cargo.output(MACOS_TARGETS[0], &file)?)?;
    let arm = Library::read(cargo.output(MACOS_TARGETS[1], &file)?)?;
    let facts = checked(&universal)?;
    for thin in [&x86, &arm] {
        checked(thin)?;
    }
    let libraries = facts
        .slices
        .iter()
        .flat_map(|s| s.libraries.iter().cloned())
        .fold(vec![], |mut v: Vec<String>, l| {
            if !v.contains(&l) {
                v.push(l);
            }
            v
        });
    let doc = |folders, layout: &str| docs::Binary {
        folders,
        file_ext: "dylib",
        os: Platform::Darwin64.os(),
        requirement: format!(
            "macOS {deployment} or later; {layout}; the arm64 code carries an ad-hoc signature"
        ),
        libraries: libraries.clone(),
    };
    Ok(Shipped {
        platform: Platform::Darwin64,
        fmi3: vec![("x86_64-darwin", x86), ("aarch64-darwin", arm)],
        line: format!(
            "darwin64: {} (cargo-zigbuild): {}",
            universal.path.display(),
            facts.summary()
        ),
        fmi2: universal,
        doc2: doc(
            vec!["darwin64"],
            "one universal library (x86_64 and arm64 slices), which Intel and Apple-silicon Macs both load",
        ),
        doc3: doc(
            vec!["x86_64-darwin", "aarch64-darwin"],
            "one library per processor (Intel: x86_64-darwin, Apple silicon: aarch64-darwin)",
        ),
    })
}

/// The facts of a PE or Mach-O library, refusing one an importer could not load (the FMI
/// functions are checked against the other libraries' in [`check_exports`]).
fn checked(lib: &Library) -> Result<binary::Facts, String> {
    let at = lib.path.display();
    let facts = binary::read(&lib.bytes).map_err(|e| format!("{at}: {e}"))?;
    let problems = facts.problems();
    if !problems.is_empty() {
        return Err(format!("{at}: {}", problems.join("; ")));
    }
    Ok(facts)
}

/// Every shipped library exports the FMI functions of every other: the reference is the first
/// library's `fmi2*`/`fmi3*` exports (read with the same reader), at least the 44 + 75 the
/// FMI layers define.
fn check_exports(shipped: &[Shipped]) -> Result<(), String> {
    let mut sets = vec![];
    for s in shipped {
        for lib in std::iter::once(&s.fmi2).chain(s.fmi3.iter().map(|(_, l)| l)) {
            let names = binary::fmi_exports(&lib.bytes)
                .map_err(|e| format!("{}: {e}", lib.path.display()))?;
            sets.push((&lib.path, names));
        }
    }
    let all: std::collections::BTreeSet<&String> = sets.iter().flat_map(|(_, n)| n).collect();
    if all.len() < binary::FMI_FUNCTIONS {
        return Err(format!(
            "the libraries export {} FMI functions, fewer than the {} of FMI 2.0 and 3.0",
            all.len(),
            binary::FMI_FUNCTIONS
        ));
    }
    for (file, names) in &sets {
        if let Some(f) = all.iter().find(|f| !names.contains(**f)) {
            return Err(format!(
                "{}: does not export {f}, which the other platforms' libraries do",
                file.display()
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn platform_lists_are_read_with_their_errors() {
        assert_eq!(Request::parse("available"), Ok(Request::Available));
        assert_eq!(
            Request::parse("all"),
            Ok(Request::Required(Platform::ALL.to_vec()))
        );
        assert_eq!(
            Request::parse("win64, linux64,win64"),
            Ok(Request::Required(vec![Platform::Win64, Platform::Linux64]))
        );
        let e = Request::parse("linux64,macos").unwrap_err();
        assert!(e.contains("unknown platform \"macos\""), "{e}");
        assert!(e.contains("linux64, aarch64-linux, win64, darwin64"), "{e}");
        assert_eq!(
            Request::parse("aarch64-linux"),
            Ok(Request::Required(vec![Platform::LinuxAarch64]))
        );
    }
}
