//! The FMU harness: builds an unpacked FMU folder around the cdylib that cargo built for this
//! test run, and drives it through `vibrofric_import` as an importer would.

use std::path::{Path, PathBuf};

use vibrofric::description::xml;
use vibrofric::description::Scene;

use super::scenes::scene_text;
use vibrofric_import::{Fmu, Instance, Status};

/// Value references, from the variable table (stable across scenes).
pub mod vr {
    use vibrofric::table::{InputId, OutputId, ParamId};
    pub const M: u32 = ParamId::M.vr();
    pub const F_N: u32 = ParamId::FN.vr();
    pub const MU: u32 = ParamId::Mu.vr();
    pub const K_T: u32 = ParamId::KT.vr();
    pub const KAPPA: u32 = ParamId::Kappa.vr();
    pub const R_BA: u32 = ParamId::RBa.vr();
    pub const U0: u32 = ParamId::U0.vr();
    pub const F: u32 = ParamId::F.vr();
    pub const ANGLE: u32 = ParamId::Angle.vr();
    pub const F_D: u32 = InputId::FD.vr();
    pub const V_D: u32 = InputId::VD.vr();
    pub const V_SX: u32 = InputId::VSx.vr();
    pub const V_SY: u32 = InputId::VSy.vr();
    pub const F_FX: u32 = OutputId::FFx.vr();
    pub const X: u32 = OutputId::X.vr();
    pub const V_X: u32 = OutputId::Vx.vr();
    pub const S_X: u32 = OutputId::Sx.vr();
    pub const F_MEAN: u32 = OutputId::FMean.vr();
    pub const REDUCTION: u32 = OutputId::Reduction.vr();
}

/// The cdylib of this build: `target/<profile>/libvibrofric.so`, found from the test
/// executable in `target/<profile>/deps/`.
pub fn library() -> PathBuf {
    let exe = std::env::current_exe().expect("current_exe");
    let name = format!(
        "{}vibrofric.{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_EXTENSION
    );
    for dir in exe.ancestors().skip(1) {
        let p = dir.join(&name);
        if p.is_file() {
            return p;
        }
    }
    panic!("{name} not found above {}", exe.display());
}

/// A fresh, empty temporary folder (removed at the start of the next run with the same tag).
pub fn temp(tag: &str) -> PathBuf {
    let p = std::env::temp_dir().join(format!("vibrofric-test-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    std::fs::create_dir_all(&p).unwrap();
    p
}

/// Lays out an unpacked FMU for the scene text in `dir`: `modelDescription.xml`,
/// `binaries/<platform>/<id>.so` (a link to this build's cdylib) and `resources/scene.toml`.
pub fn unpack(dir: &Path, text: &str) -> Scene {
    let scene = Scene::parse(text, "scene.toml").unwrap();
    let (platform, ext) = vibrofric_import::platform();
    let bin = dir.join("binaries").join(platform);
    std::fs::create_dir_all(&bin).unwrap();
    let so = bin.join(format!("{}.{ext}", scene.model_identifier));
    let _ = std::fs::remove_file(&so);
    #[cfg(unix)]
    std::os::unix::fs::symlink(library(), &so).unwrap();
    #[cfg(not(unix))]
    std::fs::copy(library(), &so).unwrap();
    std::fs::create_dir_all(dir.join("resources")).unwrap();
    std::fs::write(dir.join("resources").join("scene.toml"), text).unwrap();
    std::fs::write(
        dir.join("modelDescription.xml"),
        xml::model_description(&scene),
    )
    .unwrap();
    scene
}

/// Loads the FMI 3.0 edition of a standard scene's FMU, unpacked in a temporary folder
/// (`binaries/<arch>-<os>/<id>.so` a link to this build's cdylib).
pub fn load3(file: &str, tag: &str) -> vibrofric_import::fmi3::Fmu3 {
    let dir = temp(tag);
    let text = scene_text(file);
    let scene = unpack(&dir, &text);
    std::fs::write(
        dir.join("modelDescription.xml"),
        vibrofric::description::xml3::model_description(&scene),
    )
    .unwrap();
    let os = match std::env::consts::OS {
        "macos" => "darwin",
        os => os,
    };
    let bin = dir
        .join("binaries")
        .join(format!("{}-{os}", std::env::consts::ARCH));
    std::fs::create_dir_all(&bin).unwrap();
    let so = bin.join(format!(
        "{}.{}",
        scene.model_identifier,
        std::env::consts::DLL_EXTENSION
    ));
    let _ = std::fs::remove_file(&so);
    #[cfg(unix)]
    std::os::unix::fs::symlink(library(), &so).unwrap();
    #[cfg(not(unix))]
    std::fs::copy(library(), &so).unwrap();
    vibrofric_import::fmi3::Fmu3::load(&dir).unwrap()
}

/// Loads the FMU of a standard scene (`scenes/<file>`), unpacked in a temporary folder.
pub fn load(file: &str, tag: &str) -> Fmu {
    let dir = temp(tag);
    unpack(&dir, &scene_text(file));
    Fmu::load(&dir).unwrap()
}

/// Asserts that a call on an instance returned `OK`, showing the last log line otherwise:
/// `ok!(inst, inst.do_step(t, h))`.
macro_rules! ok {
    ($i:expr, $call:expr) => {{
        let s = $call;
        $crate::support::fmu::ok(&$i, s)
    }};
}

/// Asserts `OK`.
#[track_caller]
pub fn ok(inst: &Instance, s: Status) {
    assert_eq!(s, Status::Ok, "{}", inst.last_message());
}

/// Instantiates, sets up (tolerance 1e-6, start 0), enters initialization, sets `init`, leaves
/// initialization.
pub fn started<'a>(fmu: &'a Fmu, name: &str, init: &[(u32, f64)]) -> Instance<'a> {
    let mut i = fmu.instantiate(name).unwrap();
    let s = i.setup_experiment(Some(1e-6), 0.0, None);
    ok(&i, s);
    let s = i.enter_initialization_mode();
    ok(&i, s);
    let (vrs, vals): (Vec<u32>, Vec<f64>) = init.iter().copied().unzip();
    let s = i.set_real(&vrs, &vals);
    ok(&i, s);
    let s = i.exit_initialization_mode();
    ok(&i, s);
    i
}

/// The scene's value references, in table order.
pub fn all_vrs(scene: &Scene) -> Vec<u32> {
    scene.variables().map(|v| v.vr).collect()
}

/// Bit patterns, so that NaN compares and -0.0 differs from 0.0.
pub fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The driving force of step `k` of the standard runs: varies so that inputs matter.
pub fn drive(k: usize) -> f64 {
    2.0 + 8.0 * ((k as f64) * 0.7).sin()
}

/// One step of the standard run: sets `F_d`, steps by `h` from `t`, returns the new time.
pub fn step(i: &mut Instance, k: usize, t: f64, h: f64) -> f64 {
    let s = i.set_real(&[vr::F_D], &[drive(k)]);
    ok(i, s);
    let s = i.do_step(t, h);
    ok(i, s);
    t + h
}

/// Steps `k0..k1` from `t` and returns every variable after each step.
pub fn run(
    i: &mut Instance,
    vrs: &[u32],
    k0: usize,
    k1: usize,
    mut t: f64,
    h: f64,
) -> Vec<Vec<u64>> {
    let mut rows = Vec::new();
    for k in k0..k1 {
        t = step(i, k, t, h);
        rows.push(bits(&i.get_real(vrs).unwrap()));
    }
    rows
}

/// Runs `f` on its own thread and fails (instead of hanging the test run) when it has not
/// finished after `secs` seconds; a stuck thread ends with the test process.
pub fn within<T: Send + 'static>(
    secs: u64,
    what: &str,
    f: impl FnOnce() -> T + Send + 'static,
) -> T {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)));
    });
    match rx.recv_timeout(std::time::Duration::from_secs(secs)) {
        Ok(Ok(v)) => v,
        Ok(Err(p)) => std::panic::resume_unwind(p),
        Err(_) => panic!("{what}: not finished after {secs} s (the integrator stalls?)"),
    }
}
