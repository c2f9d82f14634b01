//! FMI 3.0 Co-Simulation, enough to run an FMU through the same steps as
//! [`Fmu::simulate`](crate::Fmu::simulate): load, instantiate (no event mode), initialize, set
//! `Float64` inputs, step, read `Float64` outputs. The exporter's self-check runs every FMI 3.0
//! FMU it writes through it.

use std::ffi::{c_void, CStr, CString};
use std::os::raw::c_char;
use std::path::{Path, PathBuf};
use std::ptr;
use std::sync::Mutex;

use libloading::Library;

use crate::{err, unpack, Description, ImportError};

type LogCallback = unsafe extern "C" fn(*mut c_void, i32, *const c_char, *const c_char);
type Instantiate = unsafe extern "C" fn(
    *const c_char,
    *const c_char,
    *const c_char,
    bool,
    bool,
    bool,
    bool,
    *const u32,
    usize,
    *mut c_void,
    Option<LogCallback>,
    *mut c_void,
) -> *mut c_void;
type EnterInit = unsafe extern "C" fn(*mut c_void, bool, f64, f64, bool, f64) -> i32;
type Unary = unsafe extern "C" fn(*mut c_void) -> i32;
type Free = unsafe extern "C" fn(*mut c_void);
type GetF64 = unsafe extern "C" fn(*mut c_void, *const u32, usize, *mut f64, usize) -> i32;
type SetF64 = unsafe extern "C" fn(*mut c_void, *const u32, usize, *const f64, usize) -> i32;
type DoStep = unsafe extern "C" fn(
    *mut c_void,
    f64,
    f64,
    bool,
    *mut bool,
    *mut bool,
    *mut bool,
    *mut f64,
) -> i32;

/// The log lines of one instance, reached through its environment pointer.
type Log = Mutex<Vec<String>>;

/// The instance's `fmi3LogMessageCallback`: records the message.
unsafe extern "C" fn log_message(
    env: *mut c_void,
    _status: i32,
    _category: *const c_char,
    message: *const c_char,
) {
    // SAFETY: `env` is the `Log` this module passed at instantiation, alive while the instance
    // is; `message` is a NUL-terminated string for the duration of the call.
    let (log, text) = unsafe { (&*(env as *const Log), CStr::from_ptr(message)) };
    if let Ok(mut log) = log.lock() {
        log.push(text.to_string_lossy().into_owned());
    }
}

/// A loaded FMI 3.0 FMU.
pub struct Fmu3 {
    pub dir: PathBuf,
    pub description: Description,
    lib: Library,
    _tmp: Option<tempfile::TempDir>,
}

impl Fmu3 {
    /// Loads an FMI 3.0 FMU (an unpacked folder or a `.fmu` archive).
    pub fn load(path: &Path) -> Result<Fmu3, ImportError> {
        let (dir, tmp, description) = unpack(path)?;
        if description.fmi_version != "3.0" {
            return err(format!(
                "{}: fmiVersion = \"{}\", not an FMI 3.0 FMU",
                path.display(),
                description.fmi_version
            ));
        }
        let os = match std::env::consts::OS {
            "macos" => "darwin",
            os => os,
        };
        let lib_path = dir
            .join("binaries")
            .join(format!("{}-{os}", std::env::consts::ARCH))
            .join(format!(
                "{}.{}",
                description.model_identifier,
                std::env::consts::DLL_EXTENSION
            ));
        // SAFETY: loading a shared library runs its initialisers; an FMU's binary is trusted
        // as any importer trusts it.
        let lib = unsafe { Library::new(&lib_path) }
            .map_err(|e| ImportError(format!("cannot load {}: {e}", lib_path.display())))?;
        Ok(Fmu3 {
            dir,
            description,
            lib,
            _tmp: tmp,
        })
    }

    fn function<T: Copy>(&self, name: &str) -> Result<T, ImportError> {
        // SAFETY: `T` is the function type the FMI 3.0 header gives `name`.
        unsafe { self.lib.get::<T>(name.as_bytes()) }
            .map(|f| *f)
            .map_err(|e| ImportError(format!("{name}: {e}")))
    }

    /// Runs from 0 to `stop` in steps of `step` (the last one shortened to end on `stop`) with
    /// `inputs` set before initialization; returns `[t, outputs...]` at the start and after
    /// every step.
    pub fn simulate(
        &self,
        stop: f64,
        step: f64,
        inputs: &[(u32, f64)],
        outputs: &[u32],
    ) -> Result<Vec<Vec<f64>>, ImportError> {
        let instantiate: Instantiate = self.function("fmi3InstantiateCoSimulation")?;
        let enter: EnterInit = self.function("fmi3EnterInitializationMode")?;
        let exit: Unary = self.function("fmi3ExitInitializationMode")?;
        let set: SetF64 = self.function("fmi3SetFloat64")?;
        let get: GetF64 = self.function("fmi3GetFloat64")?;
        let do_step: DoStep = self.function("fmi3DoStep")?;
        let free: Free = self.function("fmi3FreeInstance")?;
        let log: Box<Log> = Box::default();
        let text = |s: &str| CString::new(s).map_err(|_| ImportError(format!("{s:?}: NUL")));
        let name = text("simulate")?;
        let token = text(&self.description.guid)?;
        let resources = text(&format!("{}/", self.dir.join("resources").display()))?;
        let last = |what: &str, s: i32| -> Result<(), ImportError> {
            if s <= 1 {
                return Ok(());
            }
            let msg = log.lock().ok().and_then(|l| l.last().cloned());
            err(format!(
                "{what} returned status {s}: {}",
                msg.unwrap_or_default()
            ))
        };
        // SAFETY: every pointer passed lives until the call returns (the log until the
        // instance is freed below); the arrays have the lengths passed with them.
        unsafe {
            let inst = instantiate(
                name.as_ptr(),
                token.as_ptr(),
                resources.as_ptr(),
                false,
                false,
                false,
                false,
                ptr::null(),
                0,
                &*log as *const Log as *mut c_void,
                Some(log_message),
                ptr::null_mut(),
            );
            if inst.is_null() {
                last("fmi3InstantiateCoSimulation", 3)?;
                return err("fmi3InstantiateCoSimulation returned NULL");
            }
            let run = || -> Result<Vec<Vec<f64>>, ImportError> {
                last(
                    "fmi3EnterInitializationMode",
                    enter(inst, false, 0.0, 0.0, true, stop),
                )?;
                let (vrs, vals): (Vec<u32>, Vec<f64>) = inputs.iter().copied().unzip();
                last(
                    "fmi3SetFloat64",
                    set(inst, vrs.as_ptr(), vrs.len(), vals.as_ptr(), vals.len()),
                )?;
                last("fmi3ExitInitializationMode", exit(inst))?;
                // The points and steps of `Fmu::simulate`, so that both editions compare.
                let n = (stop / step).round().max(1.0) as u64;
                let mut rows = vec![];
                let mut t = 0.0;
                for k in 0..=n {
                    let mut row = vec![0.0; outputs.len()];
                    last(
                        "fmi3GetFloat64",
                        get(
                            inst,
                            outputs.as_ptr(),
                            outputs.len(),
                            row.as_mut_ptr(),
                            row.len(),
                        ),
                    )?;
                    row.insert(0, t);
                    rows.push(row);
                    if k == n {
                        break;
                    }
                    let h = if k + 1 == n { stop - t } else { step };
                    let (mut a, mut b, mut c, mut at) = (false, false, false, 0.0);
                    last(
                        "fmi3DoStep",
                        do_step(inst, t, h, false, &mut a, &mut b, &mut c, &mut at),
                    )?;
                    t = if k + 1 == n { stop } else { t + h };
                }
                Ok(rows)
            };
            let result = run();
            free(inst);
            result
        }
    }
}
