//! A small FMI 2.0 and 3.0 importer: loads an FMU (an unpacked folder or a `.fmu` archive)
//! with `libloading`, binds every common, Co-Simulation and (FMI 2.0) Model Exchange function,
//! and drives instances through a safe API; [`Importer`] and [`CoSimulation`] are what both
//! editions' Co-Simulation have in common, for code written once for both. The tests use it
//! as an importer would, and the exporter's self-check runs every FMU it writes through it.
//!
//! `unsafe` is confined to loading the library, calling its functions with pointers that this
//! module owns, and the logger callback below; each block says why it is sound.
//!
//! # The logger callback
//!
//! The FMI logger is a C variadic function, which stable Rust cannot define. The callback here is
//! an ordinary `extern "C"` function with one pointer parameter after `message`, cast to the
//! variadic type. On the x86-64 System V and AArch64 Linux calling conventions, variadic
//! arguments are passed exactly like named ones, so the first variadic argument arrives in that
//! parameter. The FMU of this crate always logs with the format `"%s"` and the message as that
//! first argument; the callback reads it only when the format is exactly `"%s"`, and otherwise
//! records the format string itself, unformatted. (On ABIs that pass variadic arguments
//! differently, e.g. Apple's AArch64, only the format string would be reliable.)

use std::ffi::{CStr, CString};
use std::fmt;
use std::os::raw::{c_char, c_void};
use std::path::{Path, PathBuf};
use std::ptr;
use std::sync::Mutex;

use libloading::Library;

mod cosim;
pub mod fmi3;
mod instance;

pub use cosim::{CoSimulation, Importer};
pub use instance::{Instance, State};

use vibrofric::fmi::fmi2::types::*;
pub use vibrofric::fmi::Status;

/// One message of the FMU's logger.
#[derive(Clone, Debug, PartialEq)]
pub struct LogRecord {
    pub instance: String,
    pub status: Status,
    pub category: String,
    /// The format string the FMU passed (this crate's FMU always passes `"%s"`).
    pub format: String,
    /// The message: the first variadic argument when the format is `"%s"`, else the format.
    pub message: String,
}

impl fmt::Display for LogRecord {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "[{}] {} {}: {}",
            self.category,
            self.instance,
            vibrofric::fmi::fmi2::status_name(self.status),
            self.message
        )
    }
}

/// Why an FMU could not be loaded or run.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportError(pub String);

impl fmt::Display for ImportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ImportError {}

pub(crate) fn err<T>(msg: impl Into<String>) -> Result<T, ImportError> {
    Err(ImportError(msg.into()))
}

/// The status an FMU returned; codes outside the standard's map to `Fatal`.
pub fn status(code: fmi2Status) -> Status {
    match code {
        0 => Status::Ok,
        1 => Status::Warning,
        2 => Status::Discard,
        3 => Status::Error,
        5 => Status::Pending,
        _ => Status::Fatal,
    }
}

macro_rules! functions {
    ($(#[$doc:meta])* $table:ident; $($name:ident : fn($($arg:ty),*) $(-> $ret:ty)?;)*) => {
        $(#[$doc])*
        #[derive(Clone, Copy)]
        #[allow(non_snake_case)]
        pub struct $table {
            $(pub $name: unsafe extern "C" fn($($arg),*) $(-> $ret)?,)*
        }

        impl $table {
            /// Names of the functions of this table.
            pub const NAMES: &'static [&'static str] = &[$(stringify!($name)),*];

            fn load(lib: &Library) -> Result<$table, ImportError> {
                Ok($table {
                    $($name: {
                        let name = concat!(stringify!($name), "\0");
                        // SAFETY: the symbol is declared with the signature of the FMI 2.0
                        // standard; the pointer is copied out and used only while `lib` lives
                        // (both are owned by the same `Fmu`).
                        let sym = unsafe {
                            lib.get::<unsafe extern "C" fn($($arg),*) $(-> $ret)?>(name.as_bytes())
                        };
                        match sym {
                            Ok(s) => *s,
                            Err(e) => return err(format!(
                                "the FMU does not export {}: {e}", stringify!($name))),
                        }
                    },)*
                })
            }
        }
    };
}

functions! {
    /// Every FMI 2.0 common and Co-Simulation function of a loaded FMU, for callers that need
    /// the raw C interface (the tests pass NULL pointers through it). The pointers are valid
    /// while the [`Fmu`] they came from is alive.
    Functions;
    fmi2GetTypesPlatform: fn() -> *const c_char;
    fmi2GetVersion: fn() -> *const c_char;
    fmi2SetDebugLogging: fn(fmi2Component, fmi2Boolean, usize, *const fmi2String) -> fmi2Status;
    fmi2Instantiate: fn(fmi2String, fmi2Type, fmi2String, fmi2String,
        *const fmi2CallbackFunctions, fmi2Boolean, fmi2Boolean) -> fmi2Component;
    fmi2FreeInstance: fn(fmi2Component);
    fmi2SetupExperiment: fn(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real, fmi2Boolean,
        fmi2Real) -> fmi2Status;
    fmi2EnterInitializationMode: fn(fmi2Component) -> fmi2Status;
    fmi2ExitInitializationMode: fn(fmi2Component) -> fmi2Status;
    fmi2Terminate: fn(fmi2Component) -> fmi2Status;
    fmi2Reset: fn(fmi2Component) -> fmi2Status;
    fmi2GetReal: fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Real) -> fmi2Status;
    fmi2GetInteger: fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Integer)
        -> fmi2Status;
    fmi2GetBoolean: fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Boolean)
        -> fmi2Status;
    fmi2GetString: fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2String)
        -> fmi2Status;
    fmi2SetReal: fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Real)
        -> fmi2Status;
    fmi2SetInteger: fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Integer)
        -> fmi2Status;
    fmi2SetBoolean: fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Boolean)
        -> fmi2Status;
    fmi2SetString: fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2String)
        -> fmi2Status;
    fmi2GetFMUstate: fn(fmi2Component, *mut fmi2FMUstate) -> fmi2Status;
    fmi2SetFMUstate: fn(fmi2Component, fmi2FMUstate) -> fmi2Status;
    fmi2FreeFMUstate: fn(fmi2Component, *mut fmi2FMUstate) -> fmi2Status;
    fmi2SerializedFMUstateSize: fn(fmi2Component, fmi2FMUstate, *mut usize) -> fmi2Status;
    fmi2SerializeFMUstate: fn(fmi2Component, fmi2FMUstate, *mut fmi2Byte, usize) -> fmi2Status;
    fmi2DeSerializeFMUstate: fn(fmi2Component, *const fmi2Byte, usize, *mut fmi2FMUstate)
        -> fmi2Status;
    fmi2GetDirectionalDerivative: fn(fmi2Component, *const fmi2ValueReference, usize,
        *const fmi2ValueReference, usize, *const fmi2Real, *mut fmi2Real) -> fmi2Status;
    fmi2SetRealInputDerivatives: fn(fmi2Component, *const fmi2ValueReference, usize,
        *const fmi2Integer, *const fmi2Real) -> fmi2Status;
    fmi2GetRealOutputDerivatives: fn(fmi2Component, *const fmi2ValueReference, usize,
        *const fmi2Integer, *mut fmi2Real) -> fmi2Status;
    fmi2DoStep: fn(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean) -> fmi2Status;
    fmi2CancelStep: fn(fmi2Component) -> fmi2Status;
    fmi2GetStatus: fn(fmi2Component, fmi2StatusKind, *mut fmi2Status) -> fmi2Status;
    fmi2GetRealStatus: fn(fmi2Component, fmi2StatusKind, *mut fmi2Real) -> fmi2Status;
    fmi2GetIntegerStatus: fn(fmi2Component, fmi2StatusKind, *mut fmi2Integer) -> fmi2Status;
    fmi2GetBooleanStatus: fn(fmi2Component, fmi2StatusKind, *mut fmi2Boolean) -> fmi2Status;
    fmi2GetStringStatus: fn(fmi2Component, fmi2StatusKind, *mut fmi2String) -> fmi2Status;
}

functions! {
    /// The FMI 2.0 Model Exchange functions of a loaded FMU (valid while the [`Fmu`] lives).
    MeFunctions;
    fmi2EnterEventMode: fn(fmi2Component) -> fmi2Status;
    fmi2NewDiscreteStates: fn(fmi2Component, *mut fmi2EventInfo) -> fmi2Status;
    fmi2EnterContinuousTimeMode: fn(fmi2Component) -> fmi2Status;
    fmi2CompletedIntegratorStep: fn(fmi2Component, fmi2Boolean, *mut fmi2Boolean,
        *mut fmi2Boolean) -> fmi2Status;
    fmi2SetTime: fn(fmi2Component, fmi2Real) -> fmi2Status;
    fmi2SetContinuousStates: fn(fmi2Component, *const fmi2Real, usize) -> fmi2Status;
    fmi2GetDerivatives: fn(fmi2Component, *mut fmi2Real, usize) -> fmi2Status;
    fmi2GetEventIndicators: fn(fmi2Component, *mut fmi2Real, usize) -> fmi2Status;
    fmi2GetContinuousStates: fn(fmi2Component, *mut fmi2Real, usize) -> fmi2Status;
    fmi2GetNominalsOfContinuousStates: fn(fmi2Component, *mut fmi2Real, usize) -> fmi2Status;
}

/// The platform folder of `binaries/` and the shared library suffix (FMI 2.0 names). FMI 2.0 has
/// no name for ARM: on 64-bit ARM Linux this is `linux64`, as fmpy, the FMI Library and rust-fmi
/// choose there.
pub fn platform() -> (&'static str, &'static str) {
    if cfg!(target_os = "windows") {
        (
            if cfg!(target_pointer_width = "64") {
                "win64"
            } else {
                "win32"
            },
            "dll",
        )
    } else if cfg!(target_os = "macos") {
        ("darwin64", "dylib")
    } else if cfg!(target_pointer_width = "64") {
        ("linux64", "so")
    } else {
        ("linux32", "so")
    }
}

/// What the importer reads from `modelDescription.xml`.
#[derive(Clone, Debug, PartialEq)]
pub struct Description {
    pub fmi_version: String,
    pub model_name: String,
    pub guid: String,
    /// `modelIdentifier` of the `CoSimulation` element.
    pub model_identifier: String,
    /// Every `ScalarVariable` (FMI 2.0) or `Float64` (FMI 3.0), in file order.
    pub variables: Vec<Variable>,
}

/// A variable of the model description, as the importer reads it.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    pub name: String,
    pub vr: u32,
    /// The `causality` attribute: `parameter`, `input`, `output`, `local`, ... (`local` where
    /// it is absent, the default of both editions).
    pub causality: String,
    /// How many values it holds: 1, or for an FMI 3.0 array the product of its `Dimension`
    /// elements' `start` (this FMU's arrays have fixed sizes).
    pub size: usize,
}

impl Description {
    /// Parses the attributes the importer needs.
    pub fn parse(xml: &str) -> Result<Description, ImportError> {
        use quick_xml::events::Event;
        let mut reader = quick_xml::Reader::from_str(xml);
        let mut d = Description {
            fmi_version: String::new(),
            model_name: String::new(),
            guid: String::new(),
            model_identifier: String::new(),
            variables: vec![],
        };
        let mut cs = false;
        loop {
            let ev = reader
                .read_event()
                .map_err(|e| ImportError(format!("modelDescription.xml: {e}")))?;
            let e = match &ev {
                Event::Start(e) | Event::Empty(e) => e,
                Event::Eof => break,
                _ => continue,
            };
            let attr = |name: &str| -> Result<Option<String>, ImportError> {
                for a in e.attributes() {
                    let a = a.map_err(|e| ImportError(format!("modelDescription.xml: {e}")))?;
                    if a.key.as_ref() == name {
                        let v = a
                            .normalized_value(quick_xml::XmlVersion::default())
                            .map_err(|e| ImportError(format!("modelDescription.xml: {e}")))?;
                        return Ok(Some(v.into_owned()));
                    }
                }
                Ok(None)
            };
            match e.name().as_ref() {
                "fmiModelDescription" => {
                    d.fmi_version = attr("fmiVersion")?.unwrap_or_default();
                    d.model_name = attr("modelName")?.unwrap_or_default();
                    // FMI 3.0 calls the GUID the instantiation token.
                    d.guid = attr("guid")?
                        .or(attr("instantiationToken")?)
                        .unwrap_or_default();
                }
                "CoSimulation" => {
                    cs = true;
                    d.model_identifier = attr("modelIdentifier")?.unwrap_or_default();
                }
                // FMI 2.0's ScalarVariable, FMI 3.0's Float64 (the only type this FMU has).
                "ScalarVariable" | "Float64" => {
                    let name = attr("name")?.unwrap_or_default();
                    let vr = attr("valueReference")?
                        .and_then(|v| v.parse().ok())
                        .ok_or_else(|| {
                            ImportError(format!("variable {name}: bad valueReference"))
                        })?;
                    let causality = attr("causality")?.unwrap_or_else(|| "local".into());
                    d.variables.push(Variable {
                        name,
                        vr,
                        causality,
                        size: 1,
                    });
                }
                "Dimension" => {
                    let start: Option<usize> = attr("start")?.and_then(|v| v.parse().ok());
                    match (d.variables.last_mut(), start) {
                        (Some(v), Some(n)) => v.size *= n,
                        _ => {
                            return err(
                                "modelDescription.xml: a Dimension without a fixed start (sizes \
                                 from structural parameters are not read)",
                            )
                        }
                    }
                }
                _ => {}
            }
        }
        if d.fmi_version != "2.0" && d.fmi_version != "3.0" {
            return err(format!(
                "modelDescription.xml: fmiVersion = \"{}\", this importer reads FMI 2.0 and 3.0",
                d.fmi_version
            ));
        }
        if !cs || d.model_identifier.is_empty() {
            return err("modelDescription.xml: no CoSimulation element with a modelIdentifier");
        }
        Ok(d)
    }

    /// The value reference of a variable.
    pub fn vr(&self, name: &str) -> Option<u32> {
        self.variables.iter().find(|v| v.name == name).map(|v| v.vr)
    }
}

/// An FMU's folder (unpacked into a temporary folder, kept while the result lives, when `path`
/// is an archive) and its model description.
pub(crate) fn unpack(
    path: &Path,
) -> Result<(PathBuf, Option<tempfile::TempDir>, Description), ImportError> {
    let (dir, tmp) = if path.is_dir() {
        (path.to_path_buf(), None)
    } else {
        let file = std::fs::File::open(path)
            .map_err(|e| ImportError(format!("cannot open {}: {e}", path.display())))?;
        let mut zip = zip::ZipArchive::new(file)
            .map_err(|e| ImportError(format!("{} is not a zip archive: {e}", path.display())))?;
        let tmp = tempfile::Builder::new()
            .prefix("vibrofric-fmu-")
            .tempdir()
            .map_err(|e| ImportError(format!("cannot create a temporary folder: {e}")))?;
        zip.extract(tmp.path())
            .map_err(|e| ImportError(format!("cannot unpack {}: {e}", path.display())))?;
        (tmp.path().to_path_buf(), Some(tmp))
    };
    let md = dir.join("modelDescription.xml");
    let xml = std::fs::read_to_string(&md)
        .map_err(|e| ImportError(format!("cannot read {}: {e}", md.display())))?;
    let description = Description::parse(&xml)?;
    Ok((dir, tmp, description))
}

/// A loaded FMU: its unpacked folder, model description and C functions.
pub struct Fmu {
    /// The unpacked FMU (the folder holding `modelDescription.xml`).
    pub dir: PathBuf,
    pub description: Description,
    /// The raw C functions; valid while this `Fmu` lives.
    pub functions: Functions,
    /// The Model Exchange functions, where the FMU exports them.
    pub model_exchange: Option<MeFunctions>,
    _lib: Library,
    _tmp: Option<tempfile::TempDir>,
}

impl fmt::Debug for Fmu {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Fmu")
            .field("dir", &self.dir)
            .field("description", &self.description)
            .finish()
    }
}

/// The `*.fmu` files directly in `dir`, sorted by name (the FMI 3.0 editions the exporter
/// writes are in `dir/fmi3/`, under the same names).
pub fn fmus_in(dir: &Path) -> Result<Vec<std::path::PathBuf>, String> {
    let mut v: Vec<std::path::PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "fmu"))
        .collect();
    v.sort();
    Ok(v)
}

/// The `file:` URI of a local folder as RFC 8089 and fmpy (`pathlib.Path.as_uri()`) write it:
/// `file:///home/u/x` on Unix, `file:///C:/Users/u/x` on Windows (`\\server\share\x` as
/// `file://server/share/x`), every byte but the unreserved ones, `/` and a drive's `:`
/// percent-encoded.
pub fn file_uri(path: &Path) -> String {
    file_uri_of(&path.to_string_lossy(), cfg!(windows))
}

fn file_uri_of(path: &str, windows: bool) -> String {
    let mut s = String::from("file://");
    let mut rest = path.to_string();
    if windows {
        rest = rest.replace('\\', "/");
        // Verbatim paths (from canonicalize): //?/C:/x and //?/UNC/server/share/x.
        if let Some(p) = rest.strip_prefix("//?/UNC/") {
            rest = format!("//{p}");
        } else if let Some(p) = rest.strip_prefix("//?/") {
            rest = p.to_string();
        }
        match rest.strip_prefix("//") {
            // A UNC share: the server is the URI's host.
            Some(unc) => rest = unc.to_string(),
            // A drive-letter path: an empty host, then /C:/...
            None if !rest.starts_with('/') => s.push('/'),
            None => {}
        }
    }
    for (i, b) in rest.bytes().enumerate() {
        let drive_colon = windows && i == 1 && b == b':';
        if b.is_ascii_alphanumeric() || b"/-._~".contains(&b) || drive_colon {
            s.push(b as char);
        } else {
            s.push_str(&format!("%{b:02X}"));
        }
    }
    s
}

impl Fmu {
    /// Loads an unpacked FMU folder, or a `.fmu` archive (unpacked into a temporary folder that
    /// is removed when the `Fmu` is dropped).
    pub fn load(path: &Path) -> Result<Fmu, ImportError> {
        let (dir, tmp, description) = unpack(path)?;
        if description.fmi_version != "2.0" {
            return err(format!(
                "{}: an FMI {} FMU; load it with fmi3::Fmu3",
                path.display(),
                description.fmi_version
            ));
        }
        let (platform, ext) = platform();
        let lib_path = dir
            .join("binaries")
            .join(platform)
            .join(format!("{}.{ext}", description.model_identifier));
        // SAFETY: loading a shared library runs its initialisers; an FMU's binary is trusted
        // as any importer trusts it.
        let lib = unsafe { Library::new(&lib_path) }
            .map_err(|e| ImportError(format!("cannot load {}: {e}", lib_path.display())))?;
        let functions = Functions::load(&lib)?;
        let model_exchange = MeFunctions::load(&lib).ok();
        Ok(Fmu {
            dir,
            description,
            functions,
            model_exchange,
            _lib: lib,
            _tmp: tmp,
        })
    }

    /// The `file:` URI of the FMU's `resources/` folder, with a trailing slash.
    pub fn resource_uri(&self) -> String {
        let mut u = file_uri(&self.dir.join("resources"));
        u.push('/');
        u
    }

    /// `fmi2GetVersion`.
    pub fn version(&self) -> String {
        // SAFETY: returns a static C string.
        unsafe { cstr((self.functions.fmi2GetVersion)()) }
    }

    /// `fmi2GetTypesPlatform`.
    pub fn types_platform(&self) -> String {
        // SAFETY: returns a static C string.
        unsafe { cstr((self.functions.fmi2GetTypesPlatform)()) }
    }

    /// Instantiates as Co-Simulation slave with the model description's GUID and the FMU's
    /// resources, debug logging off (errors are logged anyway).
    pub fn instantiate(&self, name: &str) -> Result<Instance<'_>, ImportError> {
        let guid = self.description.guid.clone();
        let uri = self.resource_uri();
        let (inst, log) =
            self.instantiate_with(name, fmi2CoSimulation, Some(&guid), Some(&uri), false);
        inst.ok_or_else(|| {
            let msgs: Vec<String> = log.iter().map(|r| r.message.clone()).collect();
            ImportError(format!("fmi2Instantiate failed: {}", msgs.join("; ")))
        })
    }

    /// Instantiates for Model Exchange, with the model description's GUID and the FMU's
    /// resources.
    pub fn instantiate_model_exchange(&self, name: &str) -> Result<Instance<'_>, ImportError> {
        if self.model_exchange.is_none() {
            return err("the FMU does not export the Model Exchange functions".to_string());
        }
        let guid = self.description.guid.clone();
        let uri = self.resource_uri();
        let (inst, log) =
            self.instantiate_with(name, fmi2ModelExchange, Some(&guid), Some(&uri), false);
        inst.ok_or_else(|| {
            let msgs: Vec<String> = log.iter().map(|r| r.message.clone()).collect();
            ImportError(format!("fmi2Instantiate failed: {}", msgs.join("; ")))
        })
    }

    /// `fmi2Instantiate` with every argument chosen by the caller (`None` passes NULL). Returns
    /// the instance, if any, and the messages logged during the call.
    pub fn instantiate_with(
        &self,
        name: &str,
        fmu_type: i32,
        guid: Option<&str>,
        resource_location: Option<&str>,
        logging_on: bool,
    ) -> (Option<Instance<'_>>, Vec<LogRecord>) {
        let sink = Box::new(Sink {
            records: Mutex::new(Vec::new()),
        });
        let callbacks = Box::new(fmi2CallbackFunctions {
            logger: Some(logger_fn()),
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: &*sink as *const Sink as *mut c_void,
        });
        let name_c = CString::new(name).unwrap_or_default();
        let guid_c = guid.map(|g| CString::new(g).unwrap_or_default());
        let res_c = resource_location.map(|r| CString::new(r).unwrap_or_default());
        let opt = |s: &Option<CString>| s.as_ref().map_or(ptr::null(), |s| s.as_ptr());
        // SAFETY: every pointer is valid for the call; `callbacks` and `sink` are boxed and
        // live as long as the instance (they move into it).
        let c = unsafe {
            (self.functions.fmi2Instantiate)(
                name_c.as_ptr(),
                fmu_type,
                opt(&guid_c),
                opt(&res_c),
                &*callbacks,
                fmi2False,
                logging_on as fmi2Boolean,
            )
        };
        if c.is_null() {
            let log = sink.take();
            return (None, log);
        }
        let log = sink.take();
        (
            Some(Instance {
                fmu: self,
                c,
                sink,
                _callbacks: callbacks,
            }),
            log,
        )
    }
}

unsafe fn cstr(p: *const c_char) -> String {
    if p.is_null() {
        String::new()
    } else {
        CStr::from_ptr(p).to_string_lossy().into_owned()
    }
}

/// Where the logger callback collects messages: the `componentEnvironment`.
struct Sink {
    records: Mutex<Vec<LogRecord>>,
}

impl Sink {
    fn take(&self) -> Vec<LogRecord> {
        std::mem::take(&mut *self.records.lock().unwrap_or_else(|e| e.into_inner()))
    }
}

/// The logger, declared with the first variadic argument as a named parameter (see the module
/// documentation).
unsafe extern "C" fn collect(
    env: fmi2ComponentEnvironment,
    instance: fmi2String,
    status_code: fmi2Status,
    category: fmi2String,
    format: fmi2String,
    arg: *const c_char,
) {
    let Some(sink) = (env as *const Sink).as_ref() else {
        return;
    };
    let format = cstr(format);
    let message = if format == "%s" {
        cstr(arg)
    } else {
        format.clone()
    };
    let rec = LogRecord {
        instance: cstr(instance),
        status: status(status_code),
        category: cstr(category),
        format,
        message,
    };
    if let Ok(mut r) = sink.records.lock() {
        r.push(rec);
    }
}

fn logger_fn() -> fmi2CallbackLogger {
    let f: unsafe extern "C" fn(
        fmi2ComponentEnvironment,
        fmi2String,
        fmi2Status,
        fmi2String,
        fmi2String,
        *const c_char,
    ) = collect;
    // SAFETY: on the supported ABIs (x86-64 System V, AArch64 Linux) a call through the
    // variadic type passes the first variadic argument where `collect` expects `arg`; the
    // other parameters are identical.
    unsafe { std::mem::transmute::<_, fmi2CallbackLogger>(f) }
}

#[cfg(test)]
mod tests {
    use super::{file_uri_of, Description};

    #[test]
    fn description_keeps_each_variables_causality() {
        let xml = r#"<fmiModelDescription fmiVersion="2.0" modelName="m" guid="{g}">
            <CoSimulation modelIdentifier="M"/>
            <ModelVariables>
              <ScalarVariable name="k_t" valueReference="3" causality="parameter"/>
              <ScalarVariable name="F_d" valueReference="101" causality="input"/>
              <ScalarVariable name="F_Fx" valueReference="201" causality="output"/>
              <ScalarVariable name="s_x" valueReference="301"/>
            </ModelVariables></fmiModelDescription>"#;
        let d = Description::parse(xml).unwrap();
        let got: Vec<(&str, u32, &str)> = d
            .variables
            .iter()
            .map(|v| (v.name.as_str(), v.vr, v.causality.as_str()))
            .collect();
        assert_eq!(
            got,
            [
                ("k_t", 3, "parameter"),
                ("F_d", 101, "input"),
                ("F_Fx", 201, "output"),
                ("s_x", 301, "local"),
            ]
        );
        assert_eq!(d.vr("F_Fx"), Some(201));
        assert!(d.variables.iter().all(|v| v.size == 1));
    }

    /// FMI 3.0 arrays: a variable's size is the product of its dimensions.
    #[test]
    fn description_reads_array_sizes() {
        let xml = r#"<fmiModelDescription fmiVersion="3.0" modelName="m" instantiationToken="{g}">
            <CoSimulation modelIdentifier="M"/>
            <ModelVariables>
              <Float64 name="time" valueReference="0" causality="independent"/>
              <Float64 name="m" valueReference="1000000" causality="parameter" start="1 2 3">
                <Dimension start="3"/>
              </Float64>
              <Float64 name="a" valueReference="7" causality="parameter">
                <Dimension start="2"/><Dimension start="5"/>
              </Float64>
              <Float64 name="F_top" valueReference="201" causality="output"/>
            </ModelVariables></fmiModelDescription>"#;
        let d = Description::parse(xml).unwrap();
        let sizes: Vec<(&str, usize)> = d
            .variables
            .iter()
            .map(|v| (v.name.as_str(), v.size))
            .collect();
        assert_eq!(sizes, [("time", 1), ("m", 3), ("a", 10), ("F_top", 1)]);
    }

    #[test]
    fn file_uris_are_written_as_rfc_8089_and_fmpy_write_them() {
        for (path, windows, want) in [
            (
                "/home/u/fmu/resources",
                false,
                "file:///home/u/fmu/resources",
            ),
            ("/tmp/a b/ä", false, "file:///tmp/a%20b/%C3%A4"),
            ("/tmp/C:x", false, "file:///tmp/C%3Ax"),
            (
                r"C:\Users\u\fmu\resources",
                true,
                "file:///C:/Users/u/fmu/resources",
            ),
            (r"\\?\C:\Users\u\a b", true, "file:///C:/Users/u/a%20b"),
            (r"\\server\share\fmu", true, "file://server/share/fmu"),
            (r"\\?\UNC\server\share\fmu", true, "file://server/share/fmu"),
            (r"\fmu\resources", true, "file:///fmu/resources"),
        ] {
            assert_eq!(file_uri_of(path, windows), want, "{path}");
        }
    }
}
