//! The exported FMI 3.0 functions of Model Exchange, and those of configuration, clocks and event
//! mode, which this FMU does not offer.
#![allow(non_snake_case, clippy::missing_safety_doc, clippy::too_many_arguments)]

use super::{call, unsupported, NO_CLOCKS, NO_EVENTS};
use crate::fmi::c_boundary::{fill, set_states};
use crate::fmi::fmi3::types::*;
use crate::fmi::fmi3::Function;
use crate::fmi::{Instance, Refusal, Status};

// ---- configuration, clocks and event mode: not offered ---------------------------------------

macro_rules! not_offered {
    ($($name:ident ( $($arg:ident : $t:ty),* ) => $why:expr;)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $name(instance: fmi3Instance, $($arg: $t),*) -> fmi3Status {
            $(let _ = $arg;)*
            unsupported(instance, stringify!($name), $why)
        }
    )*};
}

not_offered! {
    fmi3EnterConfigurationMode() => "this FMU has no structural parameters";
    fmi3ExitConfigurationMode() => "this FMU has no structural parameters";
    fmi3GetIntervalDecimal(_vr: *const fmi3ValueReference, _n: usize, _intervals: *mut fmi3Float64, _qualifiers: *mut fmi3IntervalQualifier) => NO_CLOCKS;
    fmi3GetIntervalFraction(_vr: *const fmi3ValueReference, _n: usize, _counters: *mut fmi3UInt64, _resolutions: *mut fmi3UInt64, _qualifiers: *mut fmi3IntervalQualifier) => NO_CLOCKS;
    fmi3GetShiftDecimal(_vr: *const fmi3ValueReference, _n: usize, _shifts: *mut fmi3Float64) => NO_CLOCKS;
    fmi3GetShiftFraction(_vr: *const fmi3ValueReference, _n: usize, _counters: *mut fmi3UInt64, _resolutions: *mut fmi3UInt64) => NO_CLOCKS;
    fmi3SetIntervalDecimal(_vr: *const fmi3ValueReference, _n: usize, _intervals: *const fmi3Float64) => NO_CLOCKS;
    fmi3SetIntervalFraction(_vr: *const fmi3ValueReference, _n: usize, _counters: *const fmi3UInt64, _resolutions: *const fmi3UInt64) => NO_CLOCKS;
    fmi3SetShiftDecimal(_vr: *const fmi3ValueReference, _n: usize, _shifts: *const fmi3Float64) => NO_CLOCKS;
    fmi3SetShiftFraction(_vr: *const fmi3ValueReference, _n: usize, _counters: *const fmi3UInt64, _resolutions: *const fmi3UInt64) => NO_CLOCKS;
    fmi3EvaluateDiscreteStates() => NO_EVENTS;
    fmi3EnterStepMode() => NO_EVENTS;
    fmi3ActivateModelPartition(_clock: fmi3ValueReference, _time: fmi3Float64) => "this FMU has no Scheduled Execution (no clocks)";
}

// ---- Model Exchange -------------------------------------------------------------------------

#[no_mangle]
pub unsafe extern "C" fn fmi3UpdateDiscreteStates(
    instance: fmi3Instance,
    discreteStatesNeedUpdate: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
    valuesOfContinuousStatesChanged: *mut fmi3Boolean,
    nextEventTimeDefined: *mut fmi3Boolean,
    nextEventTime: *mut fmi3Float64,
) -> fmi3Status {
    const F: Function = Function::UpdateDiscreteStates;
    call(instance, F, |inst, call| {
        let (Some(need), Some(terminate), Some(nominals), Some(values), Some(defined), Some(next)) = (
            discreteStatesNeedUpdate.as_mut(),
            terminateSimulation.as_mut(),
            nominalsOfContinuousStatesChanged.as_mut(),
            valuesOfContinuousStatesChanged.as_mut(),
            nextEventTimeDefined.as_mut(),
            nextEventTime.as_mut(),
        ) else {
            return Err(Refusal::error("an output argument is NULL"));
        };
        let info = inst.update_events(call)?;
        (*need, *terminate, *nominals) = (false, false, false);
        *values = info.values_of_continuous_states_changed;
        *defined = info.next_event_time.is_some();
        *next = info.next_event_time.unwrap_or(0.0);
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterContinuousTimeMode(instance: fmi3Instance) -> fmi3Status {
    call(instance, Function::EnterContinuousTimeMode, |i, _| {
        i.enter_continuous_time_mode()
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3CompletedIntegratorStep(
    instance: fmi3Instance,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    enterEventMode: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
) -> fmi3Status {
    const F: Function = Function::CompletedIntegratorStep;
    call(instance, F, |_, _| {
        let (Some(event), Some(terminate)) =
            (enterEventMode.as_mut(), terminateSimulation.as_mut())
        else {
            return Err(Refusal::error(
                "enterEventMode or terminateSimulation = NULL",
            ));
        };
        // Nothing to do (no step events); never asks for an event or to terminate.
        (*event, *terminate) = (false, false);
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetTime(instance: fmi3Instance, time: fmi3Float64) -> fmi3Status {
    call(instance, Function::SetTime, |i, _| i.set_time(time))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetContinuousStates(
    instance: fmi3Instance,
    continuousStates: *const fmi3Float64,
    nContinuousStates: usize,
) -> fmi3Status {
    call(instance, Function::SetContinuousStates, |i, _| {
        set_states(i, "continuousStates", continuousStates, nContinuousStates)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetContinuousStateDerivatives(
    instance: fmi3Instance,
    derivatives: *mut fmi3Float64,
    nContinuousStates: usize,
) -> fmi3Status {
    call(
        instance,
        Function::GetContinuousStateDerivatives,
        |i, call| {
            fill(
                i,
                call,
                "derivatives",
                derivatives,
                nContinuousStates,
                Instance::get_derivatives,
            )
        },
    )
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetEventIndicators(
    instance: fmi3Instance,
    eventIndicators: *mut fmi3Float64,
    nEventIndicators: usize,
) -> fmi3Status {
    call(instance, Function::GetEventIndicators, |i, call| {
        fill(
            i,
            call,
            "eventIndicators",
            eventIndicators,
            nEventIndicators,
            Instance::get_event_indicators,
        )
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetContinuousStates(
    instance: fmi3Instance,
    continuousStates: *mut fmi3Float64,
    nContinuousStates: usize,
) -> fmi3Status {
    call(instance, Function::GetContinuousStates, |i, call| {
        fill(
            i,
            call,
            "continuousStates",
            continuousStates,
            nContinuousStates,
            Instance::get_continuous_states,
        )
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNominalsOfContinuousStates(
    instance: fmi3Instance,
    nominals: *mut fmi3Float64,
    nContinuousStates: usize,
) -> fmi3Status {
    call(
        instance,
        Function::GetNominalsOfContinuousStates,
        |i, call| {
            fill(
                i,
                call,
                "nominals",
                nominals,
                nContinuousStates,
                Instance::get_nominals,
            )
        },
    )
}

/// `fmi3GetNumberOf...`: a count written to `n`.
unsafe fn get_count(
    instance: fmi3Instance,
    f: Function,
    n: *mut usize,
    count: impl FnOnce(&Instance) -> usize,
) -> fmi3Status {
    call(instance, f, |inst, _| {
        let out = n
            .as_mut()
            .ok_or_else(|| Refusal::error("the count's pointer is NULL"))?;
        *out = count(inst);
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfEventIndicators(
    instance: fmi3Instance,
    nEventIndicators: *mut usize,
) -> fmi3Status {
    let f = Function::GetNumberOfEventIndicators;
    get_count(instance, f, nEventIndicators, |i| {
        i.number_of_event_indicators()
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfContinuousStates(
    instance: fmi3Instance,
    nContinuousStates: *mut usize,
) -> fmi3Status {
    let f = Function::GetNumberOfContinuousStates;
    get_count(instance, f, nContinuousStates, |i| i.number_of_states())
}
