//! The exported FMI 3.0 functions on variables: getters and setters, the FMU state, the
//! derivatives.
#![allow(non_snake_case, clippy::missing_safety_doc, clippy::too_many_arguments)]

use super::{call, unsupported, NO_CLOCKS};
use crate::fmi::c_boundary::{
    array, array_mut, deserialize_state, free_state, get_state, serialize_state, set_state,
    state_size,
};
use crate::fmi::fmi3::types::*;
use crate::fmi::fmi3::Function;
use crate::fmi::{Answer, Refusal};

// ---- getters and setters --------------------------------------------------------------------

/// Checks that a scalar call's `nValues` equals `nValueReferences` (every variable is a
/// scalar).
fn scalar_count(nvr: usize, n_values: usize) -> Answer<()> {
    if nvr != n_values {
        return Err(Refusal::error(format!("nValues = {n_values} with nValueReferences = {nvr}: every variable of this FMU is a scalar, so they must be equal")));
    }
    Ok(())
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *mut fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    const F: Function = Function::GetFloat64;
    call(instance, F, |inst, call| {
        // A string's arrays: their value references hold all their elements (checked there).
        if !inst.has_arrays() {
            scalar_count(nValueReferences, nValues)?;
        }
        let Some(vrs) = array(valueReferences, nValueReferences) else {
            return Err(Refusal::null("valueReferences", nValueReferences));
        };
        let Some(values) = array_mut(values, nValues) else {
            return Err(Refusal::null("values", nValues));
        };
        inst.get_values(call, vrs, values)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    const F: Function = Function::SetFloat64;
    call(instance, F, |inst, call| {
        // A string's arrays: their value references hold all their elements (checked there).
        if !inst.has_arrays() {
            scalar_count(nValueReferences, nValues)?;
        }
        let Some(vrs) = array(valueReferences, nValueReferences) else {
            return Err(Refusal::null("valueReferences", nValueReferences));
        };
        let Some(values) = array(values, nValues) else {
            return Err(Refusal::null("values", nValues));
        };
        inst.set_values(call, vrs, values)
    })
}

/// The getters and setters of the types this FMU has no variables of: nothing to do for no
/// value reference, an error naming the variable's type otherwise.
unsafe fn no_variables(
    instance: fmi3Instance,
    f: Function,
    type_name: &str,
    vrs: *const fmi3ValueReference,
    nvr: usize,
) -> fmi3Status {
    call(instance, f, |inst, _| {
        let Some(vrs) = array(vrs, nvr) else {
            return Err(Refusal::null("valueReferences", nvr));
        };
        inst.no_variables_of_type(type_name, vrs)
    })
}

macro_rules! other_types {
    ($($get:ident, $set:ident, $t:ty, $name:literal;)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $get(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            _values: *mut $t,
            _nValues: usize,
        ) -> fmi3Status {
            let f = Function::GetOther(stringify!($get));
            no_variables(instance, f, $name, valueReferences, nValueReferences)
        }

        #[no_mangle]
        pub unsafe extern "C" fn $set(
            instance: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            _values: *const $t,
            _nValues: usize,
        ) -> fmi3Status {
            let f = Function::SetOther(stringify!($set));
            no_variables(instance, f, $name, valueReferences, nValueReferences)
        }
    )*};
}

other_types! {
    fmi3GetFloat32, fmi3SetFloat32, fmi3Float32, "Float32";
    fmi3GetInt8, fmi3SetInt8, fmi3Int8, "Int8";
    fmi3GetUInt8, fmi3SetUInt8, fmi3UInt8, "UInt8";
    fmi3GetInt16, fmi3SetInt16, fmi3Int16, "Int16";
    fmi3GetUInt16, fmi3SetUInt16, fmi3UInt16, "UInt16";
    fmi3GetInt32, fmi3SetInt32, fmi3Int32, "Int32";
    fmi3GetUInt32, fmi3SetUInt32, fmi3UInt32, "UInt32";
    fmi3GetInt64, fmi3SetInt64, fmi3Int64, "Int64";
    fmi3GetUInt64, fmi3SetUInt64, fmi3UInt64, "UInt64";
    fmi3GetBoolean, fmi3SetBoolean, fmi3Boolean, "Boolean";
    fmi3GetString, fmi3SetString, fmi3String, "String";
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _valueSizes: *mut usize,
    _values: *mut fmi3Binary,
    _nValues: usize,
) -> fmi3Status {
    let f = Function::GetOther("fmi3GetBinary");
    no_variables(instance, f, "Binary", valueReferences, nValueReferences)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetBinary(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    _valueSizes: *const usize,
    _values: *const fmi3Binary,
    _nValues: usize,
) -> fmi3Status {
    let f = Function::SetOther("fmi3SetBinary");
    no_variables(instance, f, "Binary", valueReferences, nValueReferences)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetClock(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _values: *mut fmi3Clock,
) -> fmi3Status {
    unsupported(instance, "fmi3GetClock", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetClock(
    instance: fmi3Instance,
    _valueReferences: *const fmi3ValueReference,
    _nValueReferences: usize,
    _values: *const fmi3Clock,
) -> fmi3Status {
    unsupported(instance, "fmi3SetClock", NO_CLOCKS)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(
    instance: fmi3Instance,
    _valueReference: fmi3ValueReference,
    _nDependencies: *mut usize,
) -> fmi3Status {
    unsupported(
        instance,
        "fmi3GetNumberOfVariableDependencies",
        "the dependencies are in modelDescription.xml (ModelStructure)",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetVariableDependencies(
    instance: fmi3Instance,
    _dependent: fmi3ValueReference,
    _elementIndicesOfDependent: *mut usize,
    _independents: *mut fmi3ValueReference,
    _elementIndicesOfIndependents: *mut usize,
    _dependencyKinds: *mut fmi3DependencyKind,
    _nDependencies: usize,
) -> fmi3Status {
    unsupported(
        instance,
        "fmi3GetVariableDependencies",
        "the dependencies are in modelDescription.xml (ModelStructure)",
    )
}

// ---- FMU state ------------------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    call(instance, Function::GetFMUState, |i, call| {
        get_state(i, call, FMUState)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
) -> fmi3Status {
    call(instance, Function::SetFMUState, |i, call| {
        set_state(i, call, FMUState)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    call(instance, Function::FreeFMUState, |_, call| {
        free_state(call, FMUState)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    call(instance, Function::SerializedFMUStateSize, |i, call| {
        state_size(i, call, FMUState, size)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: usize,
) -> fmi3Status {
    call(instance, Function::SerializeFMUState, |i, call| {
        serialize_state(i, call, FMUState, serializedState, size)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: usize,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    call(instance, Function::DeserializeFMUState, |i, call| {
        deserialize_state(i, call, serializedState, size, FMUState)
    })
}

// ---- derivatives ----------------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
    instance: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    nUnknowns: usize,
    knowns: *const fmi3ValueReference,
    nKnowns: usize,
    seed: *const fmi3Float64,
    nSeed: usize,
    sensitivity: *mut fmi3Float64,
    nSensitivity: usize,
) -> fmi3Status {
    const F: Function = Function::GetDirectionalDerivative;
    call(instance, F, |inst, call| {
        // One seed per element of the knowns, one sensitivity per element of the unknowns
        // (checked by the instance: every variable of a single contact is a scalar).
        let Some(unknowns) = array(unknowns, nUnknowns) else {
            return Err(Refusal::null("unknowns", nUnknowns));
        };
        let Some(knowns) = array(knowns, nKnowns) else {
            return Err(Refusal::null("knowns", nKnowns));
        };
        let Some(seed) = array(seed, nSeed) else {
            return Err(Refusal::null("seed", nSeed));
        };
        let Some(sensitivity) = array_mut(sensitivity, nSensitivity) else {
            return Err(Refusal::null("sensitivity", nSensitivity));
        };
        inst.get_directional_derivative(call, unknowns, knowns, seed, sensitivity)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetAdjointDerivative(
    instance: fmi3Instance,
    _unknowns: *const fmi3ValueReference,
    _nUnknowns: usize,
    _knowns: *const fmi3ValueReference,
    _nKnowns: usize,
    _seed: *const fmi3Float64,
    _nSeed: usize,
    _sensitivity: *mut fmi3Float64,
    _nSensitivity: usize,
) -> fmi3Status {
    unsupported(
        instance,
        "fmi3GetAdjointDerivative",
        "this FMU provides no adjoint derivatives (providesAdjointDerivatives = false)",
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetOutputDerivatives(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    orders: *const fmi3Int32,
    values: *mut fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    const F: Function = Function::GetOutputDerivatives;
    call(instance, F, |inst, call| {
        scalar_count(nValueReferences, nValues)?;
        let Some(vrs) = array(valueReferences, nValueReferences) else {
            return Err(Refusal::null("valueReferences", nValueReferences));
        };
        let Some(orders) = array(orders, nValueReferences) else {
            return Err(Refusal::null("orders", nValueReferences));
        };
        let Some(values) = array_mut(values, nValues) else {
            return Err(Refusal::null("values", nValues));
        };
        inst.get_output_derivatives(call, vrs, orders, values)
    })
}
