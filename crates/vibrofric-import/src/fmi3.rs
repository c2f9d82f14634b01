//! FMI 3.0 Co-Simulation: load an FMU, instantiate it (no event mode) and drive it through a
//! safe API (initialization, `Float64` get/set, steps, FMU states), as [`crate::Fmu`] does for
//! FMI 2.0. The exporter's self-check and the fuzz tests run every FMI 3.0 FMU through it.

use std::ffi::{c_void, CStr, CString};
use std::os::raw::c_char;
use std::path::{Path, PathBuf};
use std::ptr;
use std::sync::Mutex;

use libloading::Library;

use crate::{err, status, unpack, Description, ImportError, Status};

/// The FMI 3.0 C types, from one place: the platform types as the exporter declares them
/// (`vibrofric::fmi::fmi3::types`, `fmi3PlatformTypes.h`) and the function types of
/// `fmi3FunctionTypes.h` this importer and the tests of the C interface call through.
#[allow(non_camel_case_types)]
pub mod types {
    pub use vibrofric::fmi::fmi3::types::*;

    pub type fmi3InstantiateCoSimulationTYPE = unsafe extern "C" fn(
        fmi3String,
        fmi3String,
        fmi3String,
        fmi3Boolean,
        fmi3Boolean,
        fmi3Boolean,
        fmi3Boolean,
        *const fmi3ValueReference,
        usize,
        fmi3InstanceEnvironment,
        fmi3LogMessageCallback,
        fmi3IntermediateUpdateCallback,
    ) -> fmi3Instance;
    pub type fmi3FreeInstanceTYPE = unsafe extern "C" fn(fmi3Instance);
    pub type fmi3EnterInitializationModeTYPE = unsafe extern "C" fn(
        fmi3Instance,
        fmi3Boolean,
        fmi3Float64,
        fmi3Float64,
        fmi3Boolean,
        fmi3Float64,
    ) -> fmi3Status;
    /// `fmi3ExitInitializationMode`, `fmi3EnterEventMode`, `fmi3Terminate`, `fmi3Reset`.
    pub type fmi3InstanceOnlyTYPE = unsafe extern "C" fn(fmi3Instance) -> fmi3Status;
    pub type fmi3GetFloat64TYPE = unsafe extern "C" fn(
        fmi3Instance,
        *const fmi3ValueReference,
        usize,
        *mut fmi3Float64,
        usize,
    ) -> fmi3Status;
    pub type fmi3SetFloat64TYPE = unsafe extern "C" fn(
        fmi3Instance,
        *const fmi3ValueReference,
        usize,
        *const fmi3Float64,
        usize,
    ) -> fmi3Status;
    pub type fmi3GetInt32TYPE = unsafe extern "C" fn(
        fmi3Instance,
        *const fmi3ValueReference,
        usize,
        *mut fmi3Int32,
        usize,
    ) -> fmi3Status;
    pub type fmi3DoStepTYPE = unsafe extern "C" fn(
        fmi3Instance,
        fmi3Float64,
        fmi3Float64,
        fmi3Boolean,
        *mut fmi3Boolean,
        *mut fmi3Boolean,
        *mut fmi3Boolean,
        *mut fmi3Float64,
    ) -> fmi3Status;
    /// `fmi3GetFMUState`, `fmi3FreeFMUState`.
    pub type fmi3GetFMUStateTYPE =
        unsafe extern "C" fn(fmi3Instance, *mut fmi3FMUState) -> fmi3Status;
    pub type fmi3FreeFMUStateTYPE = fmi3GetFMUStateTYPE;
    pub type fmi3SetFMUStateTYPE = unsafe extern "C" fn(fmi3Instance, fmi3FMUState) -> fmi3Status;
    pub type fmi3SerializedFMUStateSizeTYPE =
        unsafe extern "C" fn(fmi3Instance, fmi3FMUState, *mut usize) -> fmi3Status;
    pub type fmi3SerializeFMUStateTYPE =
        unsafe extern "C" fn(fmi3Instance, fmi3FMUState, *mut fmi3Byte, usize) -> fmi3Status;
    pub type fmi3DeserializeFMUStateTYPE =
        unsafe extern "C" fn(fmi3Instance, *const fmi3Byte, usize, *mut fmi3FMUState) -> fmi3Status;
}

use types::*;

/// The log lines of one instance, reached through its environment pointer.
pub type Log = Mutex<Vec<String>>;

/// An `fmi3LogMessageCallback` whose instance environment is a [`Log`]: records the message.
///
/// # Safety
/// `env` must point to a live [`Log`] and `message` to a NUL-terminated string.
pub unsafe extern "C" fn log_message(
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

    /// A Co-Simulation instance (no event mode) with the FMU's token and resources.
    pub fn instantiate(&self, name: &str) -> Result<Instance3<'_>, ImportError> {
        let f = Functions {
            instantiate: self.function("fmi3InstantiateCoSimulation")?,
            free: self.function("fmi3FreeInstance")?,
            enter: self.function("fmi3EnterInitializationMode")?,
            exit: self.function("fmi3ExitInitializationMode")?,
            terminate: self.function("fmi3Terminate")?,
            reset: self.function("fmi3Reset")?,
            set: self.function("fmi3SetFloat64")?,
            get: self.function("fmi3GetFloat64")?,
            do_step: self.function("fmi3DoStep")?,
            get_state: self.function("fmi3GetFMUState")?,
            set_state: self.function("fmi3SetFMUState")?,
            free_state: self.function("fmi3FreeFMUState")?,
            state_size: self.function("fmi3SerializedFMUStateSize")?,
            serialize: self.function("fmi3SerializeFMUState")?,
            deserialize: self.function("fmi3DeserializeFMUState")?,
        };
        let text = |s: &str| CString::new(s).map_err(|_| ImportError(format!("{s:?}: NUL")));
        let (name, token) = (text(name)?, text(&self.description.guid)?);
        let resources = text(&format!("{}/", self.dir.join("resources").display()))?;
        let log: Box<Log> = Box::default();
        // SAFETY: the strings live until the call returns; the log lives in the instance, which
        // frees the FMU's instance before dropping it.
        let raw = unsafe {
            (f.instantiate)(
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
                None,
            )
        };
        if raw.is_null() {
            let msg = log.lock().ok().and_then(|l| l.last().cloned());
            return err(format!(
                "fmi3InstantiateCoSimulation returned NULL: {}",
                msg.unwrap_or_default()
            ));
        }
        Ok(Instance3 {
            f,
            raw,
            log,
            _fmu: std::marker::PhantomData,
        })
    }
}

/// The FMI 3.0 functions an instance calls.
struct Functions {
    instantiate: fmi3InstantiateCoSimulationTYPE,
    free: fmi3FreeInstanceTYPE,
    enter: fmi3EnterInitializationModeTYPE,
    exit: fmi3InstanceOnlyTYPE,
    terminate: fmi3InstanceOnlyTYPE,
    reset: fmi3InstanceOnlyTYPE,
    set: fmi3SetFloat64TYPE,
    get: fmi3GetFloat64TYPE,
    do_step: fmi3DoStepTYPE,
    get_state: fmi3GetFMUStateTYPE,
    set_state: fmi3SetFMUStateTYPE,
    free_state: fmi3FreeFMUStateTYPE,
    state_size: fmi3SerializedFMUStateSizeTYPE,
    serialize: fmi3SerializeFMUStateTYPE,
    deserialize: fmi3DeserializeFMUStateTYPE,
}

/// An FMI 3.0 Co-Simulation instance; freed when dropped.
pub struct Instance3<'a> {
    f: Functions,
    raw: *mut c_void,
    log: Box<Log>,
    _fmu: std::marker::PhantomData<&'a Fmu3>,
}

/// An FMU state of an [`Instance3`].
pub struct State3(*mut c_void);

impl Instance3<'_> {
    /// The last message the instance logged.
    pub fn last_message(&self) -> String {
        self.log
            .lock()
            .ok()
            .and_then(|l| l.last().cloned())
            .unwrap_or_default()
    }

    // SAFETY (every method below): `raw` is a live instance of the library the functions come
    // from, and every array passed has the length passed with it.

    pub fn enter_initialization_mode(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Status {
        let (tol, stop_time) = (tolerance.unwrap_or(0.0), stop.unwrap_or(0.0));
        status(unsafe {
            (self.f.enter)(
                self.raw,
                tolerance.is_some(),
                tol,
                start,
                stop.is_some(),
                stop_time,
            )
        })
    }

    pub fn exit_initialization_mode(&mut self) -> Status {
        status(unsafe { (self.f.exit)(self.raw) })
    }

    pub fn terminate(&mut self) -> Status {
        status(unsafe { (self.f.terminate)(self.raw) })
    }

    pub fn reset(&mut self) -> Status {
        status(unsafe { (self.f.reset)(self.raw) })
    }

    pub fn set_f64(&mut self, vrs: &[u32], values: &[f64]) -> Status {
        let n = vrs.len().min(values.len());
        status(unsafe { (self.f.set)(self.raw, vrs.as_ptr(), n, values.as_ptr(), n) })
    }

    pub fn get_f64(&mut self, vrs: &[u32]) -> Result<Vec<f64>, Status> {
        self.get_f64_values(vrs, vrs.len())
    }

    /// The `n` values of the variables `vrs` (arrays hold several each).
    pub fn get_f64_values(&mut self, vrs: &[u32], n: usize) -> Result<Vec<f64>, Status> {
        let mut v = vec![0.0; n];
        match status(unsafe {
            (self.f.get)(self.raw, vrs.as_ptr(), vrs.len(), v.as_mut_ptr(), v.len())
        }) {
            Status::Ok | Status::Warning => Ok(v),
            s => Err(s),
        }
    }

    /// A step; the status and `lastSuccessfulTime`.
    pub fn do_step(&mut self, current: f64, step: f64) -> (Status, f64) {
        let (mut a, mut b, mut c, mut last) = (false, false, false, f64::NAN);
        let s = unsafe {
            (self.f.do_step)(
                self.raw, current, step, false, &mut a, &mut b, &mut c, &mut last,
            )
        };
        (status(s), last)
    }

    pub fn get_state(&mut self) -> Result<State3, Status> {
        let mut s = ptr::null_mut();
        match status(unsafe { (self.f.get_state)(self.raw, &mut s) }) {
            Status::Ok => Ok(State3(s)),
            st => Err(st),
        }
    }

    pub fn set_state(&mut self, state: &State3) -> Status {
        status(unsafe { (self.f.set_state)(self.raw, state.0) })
    }

    pub fn free_state(&mut self, mut state: State3) -> Status {
        status(unsafe { (self.f.free_state)(self.raw, &mut state.0) })
    }

    pub fn serialize_state(&mut self, state: &State3) -> Result<Vec<u8>, Status> {
        let mut size = 0;
        let s = status(unsafe { (self.f.state_size)(self.raw, state.0, &mut size) });
        if s != Status::Ok {
            return Err(s);
        }
        let mut bytes = vec![0u8; size];
        match status(unsafe { (self.f.serialize)(self.raw, state.0, bytes.as_mut_ptr(), size) }) {
            Status::Ok => Ok(bytes),
            s => Err(s),
        }
    }

    pub fn deserialize_state(&mut self, bytes: &[u8]) -> Result<State3, Status> {
        let mut s = ptr::null_mut();
        match status(unsafe { (self.f.deserialize)(self.raw, bytes.as_ptr(), bytes.len(), &mut s) })
        {
            Status::Ok => Ok(State3(s)),
            st => Err(st),
        }
    }
}

impl Drop for Instance3<'_> {
    fn drop(&mut self) {
        // SAFETY: the instance is live and freed once; the log it writes to outlives the call.
        unsafe { (self.f.free)(self.raw) }
    }
}
