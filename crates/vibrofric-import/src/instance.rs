//! One FMI 2.0 instance of a loaded [`Fmu`]: the safe calls of its life (setup, modes,
//! Co-Simulation's step, Model Exchange's states and events), its values, states and
//! directional derivatives, and the messages its logger collected. `unsafe` only calls the
//! FMU's functions with pointers this module owns; each block says why it is sound.

use std::ffi::CString;
use std::os::raw::c_int;
use std::ptr;

use vibrofric::fmi::fmi2::types::*;

use super::{status, Fmu, Functions, LogRecord, MeFunctions, Sink, Status};

/// A saved FMU state (`fmi2FMUstate`), to be freed with [`Instance::free_state`].
#[derive(Debug)]
pub struct State(fmi2FMUstate);

impl State {
    /// The raw pointer, for tests of the C interface.
    pub fn raw(&self) -> fmi2FMUstate {
        self.0
    }
}

/// One FMU instance; `fmi2FreeInstance` is called on drop.
pub struct Instance<'a> {
    pub(crate) fmu: &'a Fmu,
    pub(crate) c: fmi2Component,
    pub(crate) sink: Box<Sink>,
    pub(crate) _callbacks: Box<fmi2CallbackFunctions>,
}

// SAFETY: FMI 2.0 lets an instance be called from any thread, one call at a time, which `&mut`
// and `Send` (without `Sync`) enforce; the sink is behind a mutex.
unsafe impl Send for Instance<'_> {}

impl Drop for Instance<'_> {
    fn drop(&mut self) {
        // SAFETY: `c` came from fmi2Instantiate of this FMU and is freed once.
        unsafe { (self.fmu.functions.fmi2FreeInstance)(self.c) }
    }
}

impl Instance<'_> {
    /// The raw component, for tests of the C interface.
    pub fn raw(&self) -> fmi2Component {
        self.c
    }

    pub fn functions(&self) -> &Functions {
        &self.fmu.functions
    }

    /// Messages logged since the last call (and takes them).
    pub fn take_messages(&self) -> Vec<LogRecord> {
        self.sink.take()
    }

    /// The text of the last message logged (kept), or "" when none.
    pub fn last_message(&self) -> String {
        let r = self.sink.records.lock().unwrap_or_else(|e| e.into_inner());
        r.last().map(|r| r.message.clone()).unwrap_or_default()
    }

    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> Status {
        let cs: Vec<CString> = categories
            .iter()
            .map(|c| CString::new(*c).unwrap_or_default())
            .collect();
        let ps: Vec<fmi2String> = cs.iter().map(|c| c.as_ptr()).collect();
        // SAFETY: `ps` holds `ps.len()` valid C strings for the duration of the call.
        status(unsafe {
            (self.fmu.functions.fmi2SetDebugLogging)(
                self.c,
                on as fmi2Boolean,
                ps.len(),
                ps.as_ptr(),
            )
        })
    }

    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Status {
        // SAFETY: plain values.
        status(unsafe {
            (self.fmu.functions.fmi2SetupExperiment)(
                self.c,
                tolerance.is_some() as fmi2Boolean,
                tolerance.unwrap_or(0.0),
                start,
                stop.is_some() as fmi2Boolean,
                stop.unwrap_or(0.0),
            )
        })
    }

    pub fn enter_initialization_mode(&mut self) -> Status {
        // SAFETY: valid component.
        status(unsafe { (self.fmu.functions.fmi2EnterInitializationMode)(self.c) })
    }

    pub fn exit_initialization_mode(&mut self) -> Status {
        // SAFETY: valid component.
        status(unsafe { (self.fmu.functions.fmi2ExitInitializationMode)(self.c) })
    }

    pub fn terminate(&mut self) -> Status {
        // SAFETY: valid component.
        status(unsafe { (self.fmu.functions.fmi2Terminate)(self.c) })
    }

    pub fn reset(&mut self) -> Status {
        // SAFETY: valid component.
        status(unsafe { (self.fmu.functions.fmi2Reset)(self.c) })
    }

    /// `fmi2SetReal`; `vrs` and `values` must have the same length.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Status {
        assert_eq!(vrs.len(), values.len(), "set_real: one value per reference");
        // SAFETY: both arrays hold `vrs.len()` elements.
        status(unsafe {
            (self.fmu.functions.fmi2SetReal)(self.c, vrs.as_ptr(), vrs.len(), values.as_ptr())
        })
    }

    /// `fmi2GetReal`.
    pub fn get_real(&mut self, vrs: &[u32]) -> Result<Vec<f64>, Status> {
        let mut out = vec![0.0; vrs.len()];
        // SAFETY: both arrays hold `vrs.len()` elements.
        let s = status(unsafe {
            (self.fmu.functions.fmi2GetReal)(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr())
        });
        if s <= Status::Warning {
            Ok(out)
        } else {
            Err(s)
        }
    }

    /// `fmi2SetRealInputDerivatives`.
    pub fn set_real_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Status {
        assert!(vrs.len() == orders.len() && vrs.len() == values.len());
        // SAFETY: the three arrays hold `vrs.len()` elements.
        status(unsafe {
            (self.fmu.functions.fmi2SetRealInputDerivatives)(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                orders.as_ptr() as *const c_int,
                values.as_ptr(),
            )
        })
    }

    /// `fmi2DoStep` (with `noSetFMUStatePriorToCurrentPoint` false).
    pub fn do_step(&mut self, current: f64, step: f64) -> Status {
        // SAFETY: plain values.
        status(unsafe { (self.fmu.functions.fmi2DoStep)(self.c, current, step, fmi2False) })
    }

    fn me(&self) -> &MeFunctions {
        // An instance for Model Exchange exists only when the table loaded.
        self.fmu
            .model_exchange
            .as_ref()
            .expect("Model Exchange functions of an instance made for Model Exchange")
    }

    /// `fmi2NewDiscreteStates`: the status and the event information.
    pub fn new_discrete_states(&mut self) -> (Status, fmi2EventInfo) {
        let mut info = fmi2EventInfo {
            newDiscreteStatesNeeded: fmi2False,
            terminateSimulation: fmi2False,
            nominalsOfContinuousStatesChanged: fmi2False,
            valuesOfContinuousStatesChanged: fmi2False,
            nextEventTimeDefined: fmi2False,
            nextEventTime: 0.0,
        };
        // SAFETY: `info` is a valid out-pointer.
        let s = status(unsafe { (self.me().fmi2NewDiscreteStates)(self.c, &mut info) });
        (s, info)
    }

    /// `fmi2EnterEventMode`.
    pub fn enter_event_mode(&mut self) -> Status {
        // SAFETY: plain values.
        status(unsafe { (self.me().fmi2EnterEventMode)(self.c) })
    }

    /// `fmi2CompletedIntegratorStep` (with `noSetFMUStatePriorToCurrentPoint` true); the status
    /// only (this FMU never asks for an event or to terminate there).
    pub fn completed_integrator_step(&mut self) -> Status {
        let (mut event, mut terminate) = (fmi2False, fmi2False);
        // SAFETY: both are valid out-pointers.
        status(unsafe {
            (self.me().fmi2CompletedIntegratorStep)(self.c, fmi2True, &mut event, &mut terminate)
        })
    }

    /// `fmi2GetEventIndicators` of `ni` indicators.
    pub fn get_event_indicators(&mut self, ni: usize) -> Result<Vec<f64>, Status> {
        let mut z = vec![0.0; ni];
        // SAFETY: `z` holds `ni` values.
        let s = status(unsafe { (self.me().fmi2GetEventIndicators)(self.c, z.as_mut_ptr(), ni) });
        if s == Status::Ok {
            Ok(z)
        } else {
            Err(s)
        }
    }

    /// `fmi2EnterContinuousTimeMode`.
    pub fn enter_continuous_time_mode(&mut self) -> Status {
        // SAFETY: plain values.
        status(unsafe { (self.me().fmi2EnterContinuousTimeMode)(self.c) })
    }

    /// `fmi2SetTime`.
    pub fn set_time(&mut self, t: f64) -> Status {
        // SAFETY: plain values.
        status(unsafe { (self.me().fmi2SetTime)(self.c, t) })
    }

    /// `fmi2SetContinuousStates`.
    pub fn set_continuous_states(&mut self, x: &[f64]) -> Status {
        // SAFETY: the slice is valid for its length.
        status(unsafe { (self.me().fmi2SetContinuousStates)(self.c, x.as_ptr(), x.len()) })
    }

    /// `fmi2GetDerivatives` of `nx` states.
    pub fn get_derivatives(&mut self, nx: usize) -> Result<Vec<f64>, Status> {
        let mut dx = vec![0.0; nx];
        // SAFETY: `dx` holds `nx` values.
        let s = status(unsafe { (self.me().fmi2GetDerivatives)(self.c, dx.as_mut_ptr(), nx) });
        if s == Status::Ok {
            Ok(dx)
        } else {
            Err(s)
        }
    }

    /// `fmi2GetDirectionalDerivative`.
    pub fn get_directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
    ) -> Result<Vec<f64>, Status> {
        assert_eq!(knowns.len(), seed.len(), "one seed per known");
        let mut out = vec![0.0; unknowns.len()];
        // SAFETY: every slice is valid for the length passed with it.
        let s = status(unsafe {
            (self.fmu.functions.fmi2GetDirectionalDerivative)(
                self.c,
                unknowns.as_ptr(),
                unknowns.len(),
                knowns.as_ptr(),
                knowns.len(),
                seed.as_ptr(),
                out.as_mut_ptr(),
            )
        });
        if s == Status::Ok {
            Ok(out)
        } else {
            Err(s)
        }
    }

    /// `fmi2GetRealStatus`.
    pub fn get_real_status(&mut self, kind: i32) -> (Status, f64) {
        let mut v = 0.0;
        // SAFETY: `v` is a valid out-pointer.
        let s = status(unsafe { (self.fmu.functions.fmi2GetRealStatus)(self.c, kind, &mut v) });
        (s, v)
    }

    /// `fmi2GetBooleanStatus`.
    pub fn get_boolean_status(&mut self, kind: i32) -> (Status, bool) {
        let mut v = 0;
        // SAFETY: `v` is a valid out-pointer.
        let s = status(unsafe { (self.fmu.functions.fmi2GetBooleanStatus)(self.c, kind, &mut v) });
        (s, v != 0)
    }

    /// `fmi2GetFMUstate` into a new state.
    pub fn get_state(&mut self) -> Result<State, Status> {
        let mut p: fmi2FMUstate = ptr::null_mut();
        // SAFETY: `p` is a valid out-pointer holding NULL (a new state).
        let s = status(unsafe { (self.fmu.functions.fmi2GetFMUstate)(self.c, &mut p) });
        if s <= Status::Warning && !p.is_null() {
            Ok(State(p))
        } else {
            Err(s.max(Status::Error))
        }
    }

    /// `fmi2GetFMUstate` into an existing state (the FMU may reuse its memory).
    pub fn update_state(&mut self, state: &mut State) -> Status {
        // SAFETY: `state.0` is a state this FMU returned.
        status(unsafe { (self.fmu.functions.fmi2GetFMUstate)(self.c, &mut state.0) })
    }

    /// `fmi2SetFMUstate`.
    pub fn set_state(&mut self, state: &State) -> Status {
        // SAFETY: `state.0` is a state this FMU returned.
        status(unsafe { (self.fmu.functions.fmi2SetFMUstate)(self.c, state.0) })
    }

    /// `fmi2FreeFMUstate`.
    pub fn free_state(&mut self, mut state: State) -> Status {
        // SAFETY: `state.0` is a state this FMU returned, freed once (it is consumed).
        status(unsafe { (self.fmu.functions.fmi2FreeFMUstate)(self.c, &mut state.0) })
    }

    /// `fmi2SerializedFMUstateSize` and `fmi2SerializeFMUstate`.
    pub fn serialize_state(&mut self, state: &State) -> Result<Vec<u8>, Status> {
        let mut n = 0usize;
        // SAFETY: `n` is a valid out-pointer; `state.0` a state of this FMU.
        let s = status(unsafe {
            (self.fmu.functions.fmi2SerializedFMUstateSize)(self.c, state.0, &mut n)
        });
        if s > Status::Warning {
            return Err(s);
        }
        let mut buf = vec![0u8; n];
        // SAFETY: `buf` holds `n` bytes.
        let s = status(unsafe {
            (self.fmu.functions.fmi2SerializeFMUstate)(
                self.c,
                state.0,
                buf.as_mut_ptr() as *mut fmi2Byte,
                n,
            )
        });
        if s > Status::Warning {
            return Err(s);
        }
        Ok(buf)
    }

    /// `fmi2DeSerializeFMUstate` into a new state.
    pub fn deserialize_state(&mut self, bytes: &[u8]) -> Result<State, Status> {
        let mut p: fmi2FMUstate = ptr::null_mut();
        // SAFETY: `bytes` holds `bytes.len()` bytes; `p` is a valid out-pointer.
        let s = status(unsafe {
            (self.fmu.functions.fmi2DeSerializeFMUstate)(
                self.c,
                bytes.as_ptr() as *const fmi2Byte,
                bytes.len(),
                &mut p,
            )
        });
        if s <= Status::Warning && !p.is_null() {
            Ok(State(p))
        } else {
            Err(s.max(Status::Error))
        }
    }
}
