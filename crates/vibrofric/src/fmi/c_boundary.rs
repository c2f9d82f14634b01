//! What every FMI version's C layer shares: the boxes behind instance and state pointers (with a
//! magic number, so that a pointer of the wrong kind is refused rather than used), running a
//! call on an instance with panics caught, turning C arrays and strings into Rust ones, and the
//! bodies of the FMU-state and Model Exchange vector functions.
#![allow(clippy::missing_safety_doc)]

use std::ffi::CStr;
use std::os::raw::{c_char, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};

use super::{Call, FmuState, Instance, Status};

pub(crate) const COMPONENT_MAGIC: u64 = 0x7669_6272_6f66_7269; // "vibrofri"
pub(crate) const STATE_MAGIC: u64 = 0x7669_6272_6f73_7461; // "vibrosta"

pub(crate) struct Component {
    pub magic: u64,
    pub inst: Instance,
}

pub(crate) struct StateBox {
    pub magic: u64,
    pub state: FmuState,
}

pub(crate) fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        format!("panic: {s}")
    } else if let Some(s) = p.downcast_ref::<String>() {
        format!("panic: {s}")
    } else {
        "panic".to_string()
    }
}

/// The instance behind a component pointer, or `None` for NULL or a foreign pointer.
pub(crate) unsafe fn component<'a>(c: *mut c_void) -> Option<&'a mut Component> {
    let comp = (c as *mut Component).as_mut()?;
    (comp.magic == COMPONENT_MAGIC).then_some(comp)
}

/// Runs `body` on the instance behind `c` with the call's name and allowed states, catching
/// panics (a caught panic becomes an error of the instance). `None` for a NULL or foreign
/// pointer.
pub(crate) unsafe fn run(
    c: *mut c_void,
    call: Call,
    body: impl FnOnce(&mut Instance, Call) -> Status,
) -> Option<Status> {
    let comp = component(c)?;
    Some(
        match catch_unwind(AssertUnwindSafe(|| body(&mut comp.inst, call))) {
            Ok(s) => s,
            Err(p) => {
                let what = panic_text(p.as_ref());
                let _ = catch_unwind(AssertUnwindSafe(|| comp.inst.internal_error(call, &what)));
                Status::Error
            }
        },
    )
}

/// An input array: empty when `n` is 0, `None` when NULL with `n` > 0.
pub(crate) unsafe fn array<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if p.is_null() {
        None
    } else {
        Some(std::slice::from_raw_parts(p, n))
    }
}

/// An output array: empty when `n` is 0, `None` when NULL with `n` > 0.
pub(crate) unsafe fn array_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if p.is_null() {
        None
    } else {
        Some(std::slice::from_raw_parts_mut(p, n))
    }
}

pub(crate) fn null(inst: &mut Instance, f: &str, arg: &str, n: usize) -> Status {
    inst.invalid_argument(
        f,
        format!("{arg} = NULL with nvr = {n}: must point to {n} elements"),
    )
}

/// A Model Exchange getter that fills the importer's vector `out` of `n` reals (argument `arg`):
/// the pointer checked, then `get` on the slice.
pub(crate) unsafe fn fill(
    inst: &mut Instance,
    call: Call,
    arg: &str,
    out: *mut f64,
    n: usize,
    get: fn(&mut Instance, Call, &mut [f64]) -> Status,
) -> Status {
    match array_mut(out, n) {
        Some(out) => get(inst, call, out),
        None => null(inst, call.name, arg, n),
    }
}

/// `fmi2SetContinuousStates`, `fmi3SetContinuousStates`: the importer's `n` states `x`
/// (argument `arg`).
pub(crate) unsafe fn set_states(
    inst: &mut Instance,
    call: Call,
    arg: &str,
    x: *const f64,
    n: usize,
) -> Status {
    match array(x, n) {
        Some(x) => inst.set_continuous_states(call, x),
        None => null(inst, call.name, arg, n),
    }
}

pub(crate) unsafe fn string(s: *const c_char) -> Option<String> {
    (!s.is_null()).then(|| CStr::from_ptr(s).to_string_lossy().into_owned())
}

pub(crate) unsafe fn state_ref<'a>(s: *mut c_void) -> Option<&'a mut StateBox> {
    let b = (s as *mut StateBox).as_mut()?;
    (b.magic == STATE_MAGIC).then_some(b)
}

/// Stores `state` in `*slot`: into the box already there (the standard lets the importer hand a
/// previous state back for reuse), or a new one.
pub(crate) unsafe fn store(slot: &mut *mut c_void, state: FmuState) -> bool {
    if slot.is_null() {
        *slot = Box::into_raw(Box::new(StateBox {
            magic: STATE_MAGIC,
            state,
        })) as *mut c_void;
        true
    } else if let Some(b) = state_ref(*slot) {
        b.state = state;
        true
    } else {
        false
    }
}

// ---- FMU states: the bodies of the six state functions, the same in every version ----------

/// Get state: a new state in `*slot`, or the box already there reused.
pub(crate) unsafe fn get_state(inst: &mut Instance, call: Call, slot: *mut *mut c_void) -> Status {
    let w = call.words;
    let Some(slot) = slot.as_mut() else {
        let msg = format!("{} = NULL: must point to an {}", w.state_arg, w.state_type);
        return inst.invalid_argument(call.name, msg);
    };
    let state = match inst.get_fmu_state(call) {
        Ok(s) => s,
        Err(s) => return s,
    };
    if store(slot, state) {
        Status::Ok
    } else {
        let msg = format!(
            "*{} is neither NULL nor a state returned by this FMU",
            w.state_arg
        );
        inst.invalid_argument(call.name, msg)
    }
}

/// Set state.
pub(crate) unsafe fn set_state(inst: &mut Instance, call: Call, state: *mut c_void) -> Status {
    let w = call.words;
    match state_ref(state) {
        Some(b) => inst.set_fmu_state(call, &b.state),
        None => inst.invalid_argument(
            call.name,
            format!(
                "{} is NULL or not a state returned by {}/{}",
                w.state_arg, w.get_state, w.deserialize_state
            ),
        ),
    }
}

/// Free state: frees `*slot` and sets it to NULL (nothing to do for NULL).
pub(crate) unsafe fn free_state(inst: &mut Instance, call: Call, slot: *mut *mut c_void) -> Status {
    let w = call.words;
    let Some(slot) = slot.as_mut() else {
        let msg = format!("{} = NULL: must point to an {}", w.state_arg, w.state_type);
        return inst.invalid_argument(call.name, msg);
    };
    let s = inst.allow_call(call);
    if s != Status::Ok {
        return s;
    }
    if slot.is_null() {
        return Status::Ok;
    }
    match state_ref(*slot) {
        Some(b) => {
            b.magic = 0;
            drop(Box::from_raw(b as *mut StateBox));
            *slot = std::ptr::null_mut();
            Status::Ok
        }
        None => {
            let msg = format!("*{} is not a state returned by this FMU", w.state_arg);
            inst.invalid_argument(call.name, msg)
        }
    }
}

/// Serialized state size.
pub(crate) unsafe fn state_size(
    inst: &mut Instance,
    call: Call,
    state: *mut c_void,
    size: *mut usize,
) -> Status {
    let Some(b) = state_ref(state) else {
        let msg = format!(
            "{} is NULL or not a state of this FMU",
            call.words.state_arg
        );
        return inst.invalid_argument(call.name, msg);
    };
    let Some(size) = size.as_mut() else {
        return inst.invalid_argument(call.name, "size = NULL");
    };
    match inst.serialize_fmu_state(call, &b.state) {
        Ok(bytes) => {
            *size = bytes.len();
            Status::Ok
        }
        Err(s) => s,
    }
}

/// Serialize state into `size` bytes at `out` (zero-filled past the state).
pub(crate) unsafe fn serialize_state(
    inst: &mut Instance,
    call: Call,
    state: *mut c_void,
    out: *mut u8,
    size: usize,
) -> Status {
    let Some(b) = state_ref(state) else {
        let msg = format!(
            "{} is NULL or not a state of this FMU",
            call.words.state_arg
        );
        return inst.invalid_argument(call.name, msg);
    };
    let bytes = match inst.serialize_fmu_state(call, &b.state) {
        Ok(b) => b,
        Err(s) => return s,
    };
    if size < bytes.len() {
        let msg = format!(
            "size = {size}: the state needs {} bytes ({})",
            bytes.len(),
            call.words.state_size
        );
        return inst.invalid_argument(call.name, msg);
    }
    let Some(out) = array_mut(out, size) else {
        return inst.invalid_argument(
            call.name,
            format!("serializedState = NULL with size = {size}"),
        );
    };
    out[..bytes.len()].copy_from_slice(&bytes);
    out[bytes.len()..].fill(0);
    Status::Ok
}

/// Deserialize state: a new state in `*slot` from `size` bytes at `bytes`.
pub(crate) unsafe fn deserialize_state(
    inst: &mut Instance,
    call: Call,
    bytes: *const u8,
    size: usize,
    slot: *mut *mut c_void,
) -> Status {
    let w = call.words;
    let Some(bytes) = array(bytes, size) else {
        return inst.invalid_argument(
            call.name,
            format!("serializedState = NULL with size = {size}"),
        );
    };
    let Some(slot) = slot.as_mut() else {
        let msg = format!("{} = NULL: must point to an {}", w.state_arg, w.state_type);
        return inst.invalid_argument(call.name, msg);
    };
    let state = match inst.deserialize_fmu_state(call, bytes) {
        Ok(s) => s,
        Err(s) => return s,
    };
    if store(slot, state) {
        Status::Ok
    } else {
        let msg = format!(
            "*{} is neither NULL nor a state returned by this FMU",
            w.state_arg
        );
        inst.invalid_argument(call.name, msg)
    }
}
