//! What every FMI version's C layer shares: the boxes behind instance and state pointers (with a
//! magic number, so that a pointer of the wrong kind is refused rather than used), running a
//! call on an instance with panics caught, turning C arrays and strings into Rust ones, and the
//! bodies of the FMU-state and Model Exchange vector functions.
#![allow(clippy::missing_safety_doc)]

use std::ffi::CStr;
use std::os::raw::{c_char, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};

use super::{Answer, Call, FmuState, Instance, Refusal, Status};

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

/// Runs `body` on the instance behind `c` through [`Instance::answer`] (the call's allowed
/// states checked once, a refusal turned into log, state and status), catching panics (a
/// caught panic becomes an internal error of the instance). `None` for a NULL or foreign
/// pointer.
pub(crate) unsafe fn run(
    c: *mut c_void,
    call: Call,
    body: impl FnOnce(&mut Instance, Call) -> Answer,
) -> Option<Status> {
    let comp = component(c)?;
    Some(
        match catch_unwind(AssertUnwindSafe(|| {
            comp.inst.answer(call, |inst| body(inst, call))
        })) {
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

/// A Model Exchange getter that fills the importer's vector `out` of `n` reals (argument `arg`):
/// the pointer checked, then `get` on the slice.
pub(crate) unsafe fn fill(
    inst: &mut Instance,
    call: Call,
    arg: &str,
    out: *mut f64,
    n: usize,
    get: fn(&mut Instance, Call, &mut [f64]) -> Answer,
) -> Answer {
    get(
        inst,
        call,
        array_mut(out, n).ok_or_else(|| Refusal::null(arg, n))?,
    )
}

/// `fmi2SetContinuousStates`, `fmi3SetContinuousStates`: the importer's `n` states `x`
/// (argument `arg`).
pub(crate) unsafe fn set_states(inst: &mut Instance, arg: &str, x: *const f64, n: usize) -> Answer {
    inst.set_continuous_states(array(x, n).ok_or_else(|| Refusal::null(arg, n))?)
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
pub(crate) unsafe fn get_state(inst: &mut Instance, call: Call, slot: *mut *mut c_void) -> Answer {
    let w = call.words;
    let Some(slot) = slot.as_mut() else {
        return Err(Refusal::error(format!(
            "{} = NULL: must point to an {}",
            w.state_arg, w.state_type
        )));
    };
    if store(slot, inst.save_state(call)) {
        Ok(Status::Ok)
    } else {
        Err(Refusal::error(format!(
            "*{} is neither NULL nor a state returned by this FMU",
            w.state_arg
        )))
    }
}

/// Set state.
pub(crate) unsafe fn set_state(inst: &mut Instance, call: Call, state: *mut c_void) -> Answer {
    let w = call.words;
    match state_ref(state) {
        Some(b) => inst.restore_state(call, &b.state),
        None => Err(Refusal::error(format!(
            "{} is NULL or not a state returned by {}/{}",
            w.state_arg, w.get_state, w.deserialize_state
        ))),
    }
}

/// Free state: frees `*slot` and sets it to NULL (nothing to do for NULL).
pub(crate) unsafe fn free_state(call: Call, slot: *mut *mut c_void) -> Answer {
    let w = call.words;
    let Some(slot) = slot.as_mut() else {
        return Err(Refusal::error(format!(
            "{} = NULL: must point to an {}",
            w.state_arg, w.state_type
        )));
    };
    if slot.is_null() {
        return Ok(Status::Ok);
    }
    match state_ref(*slot) {
        Some(b) => {
            b.magic = 0;
            drop(Box::from_raw(b as *mut StateBox));
            *slot = std::ptr::null_mut();
            Ok(Status::Ok)
        }
        None => Err(Refusal::error(format!(
            "*{} is not a state returned by this FMU",
            w.state_arg
        ))),
    }
}

/// The state behind a state pointer, or why there is none.
unsafe fn saved<'a>(call: Call, state: *mut c_void) -> Answer<&'a FmuState> {
    match state_ref(state) {
        Some(b) => Ok(&b.state),
        None => Err(Refusal::error(format!(
            "{} is NULL or not a state of this FMU",
            call.words.state_arg
        ))),
    }
}

/// Serialized state size.
pub(crate) unsafe fn state_size(
    inst: &mut Instance,
    call: Call,
    state: *mut c_void,
    size: *mut usize,
) -> Answer {
    let state = saved(call, state)?;
    let size = size.as_mut().ok_or_else(|| Refusal::error("size = NULL"))?;
    *size = inst.serialize_state(state).len();
    Ok(Status::Ok)
}

/// Serialize state into `size` bytes at `out` (zero-filled past the state).
pub(crate) unsafe fn serialize_state(
    inst: &mut Instance,
    call: Call,
    state: *mut c_void,
    out: *mut u8,
    size: usize,
) -> Answer {
    let bytes = inst.serialize_state(saved(call, state)?);
    if size < bytes.len() {
        return Err(Refusal::error(format!(
            "size = {size}: the state needs {} bytes ({})",
            bytes.len(),
            call.words.state_size
        )));
    }
    let Some(out) = array_mut(out, size) else {
        return Err(Refusal::error(format!(
            "serializedState = NULL with size = {size}"
        )));
    };
    out[..bytes.len()].copy_from_slice(&bytes);
    out[bytes.len()..].fill(0);
    Ok(Status::Ok)
}

/// Deserialize state: a new state in `*slot` from `size` bytes at `bytes`.
pub(crate) unsafe fn deserialize_state(
    inst: &mut Instance,
    call: Call,
    bytes: *const u8,
    size: usize,
    slot: *mut *mut c_void,
) -> Answer {
    let w = call.words;
    let Some(bytes) = array(bytes, size) else {
        return Err(Refusal::error(format!(
            "serializedState = NULL with size = {size}"
        )));
    };
    let Some(slot) = slot.as_mut() else {
        return Err(Refusal::error(format!(
            "{} = NULL: must point to an {}",
            w.state_arg, w.state_type
        )));
    };
    let state = inst.deserialize_state(call, bytes)?;
    if store(slot, state) {
        Ok(Status::Ok)
    } else {
        Err(Refusal::error(format!(
            "*{} is neither NULL nor a state returned by this FMU",
            w.state_arg
        )))
    }
}
