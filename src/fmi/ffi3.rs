//! The FMI 3.0 co-simulation C interface, over the same instance as FMI 2.0
//! (`ffi`): each function is checked against fmi-sys's function type at
//! compile time (the `const _` lines). The FMI 2.0 functions do the work
//! where the two standards agree (FMU states, string variables, modes);
//! here are what FMI 3.0 changes: arrays (a pair's per-node outputs are one
//! variable, `fmi3::variables3`), the independent variable `time`, the
//! instantiation and its logger, `fmi3DoStep`'s out-arguments. Model
//! exchange, scheduled execution, event mode, clocks, configuration mode,
//! output derivatives and adjoint derivatives are not offered: those calls
//! return fmi3Error with a log line. Like FMI 2.0, no panic leaves a call.

#![allow(non_snake_case)]

use super::boundary::{
    Component, Value, Variables3, error, null, panic_text, resource_path, slice, slice_mut, string,
    unsupported, with, with_solving,
};
use super::ffi;
use super::fmi3::TIME_VR;
use super::instance::{Instance, LogFn, Status};
use super::variables::Type;
use fmi_sys::fmi3::*;
use std::ffi::{CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// The FMI 2.0 call names in the instance's messages, as an FMI 3.0 master
/// knows them.
fn fmi3_names(msg: &str) -> String {
    const NAMES: [(&str, &str); 14] = [
        ("fmi2GetReal", "fmi3GetFloat64"),
        ("fmi2SetReal", "fmi3SetFloat64"),
        ("fmi2GetInteger", "fmi3GetInt32"),
        ("fmi2SetInteger", "fmi3SetInt32"),
        ("fmi2SetupExperiment", "fmi3EnterInitializationMode"),
        ("fmi2GetFMUstate", "fmi3GetFMUState"),
        ("fmi2SetFMUstate", "fmi3SetFMUState"),
        ("fmi2FreeFMUstate", "fmi3FreeFMUState"),
        ("fmi2SerializedFMUstateSize", "fmi3SerializedFMUStateSize"),
        ("fmi2SerializeFMUstate", "fmi3SerializeFMUState"),
        ("fmi2DeSerializeFMUstate", "fmi3DeserializeFMUState"),
        ("vUnknown_ref", "unknowns"),
        ("vKnown_ref", "knowns"),
        ("dvKnown", "seed"),
    ];
    let mut out = msg.to_string();
    for (from, to) in NAMES {
        out = out.replace(from, to);
    }
    out.replace("fmi2", "fmi3")
}

/// The master's logger (FMI 3.0: not variadic).
struct Logger {
    callback: fmi3LogMessageCallback,
    env: fmi3InstanceEnvironment,
}

// The master guarantees the environment pointer for the instance's life and
// that one instance is not called from two threads at once.
unsafe impl Send for Logger {}

impl Logger {
    fn call(&self, status: Status, category: &str, message: &str) {
        let Some(callback) = self.callback else {
            return;
        };
        let status = match status {
            Status::Ok => fmi3Status_fmi3OK,
            Status::Warning => fmi3Status_fmi3Warning,
            Status::Discard => fmi3Status_fmi3Discard,
            Status::Error => fmi3Status_fmi3Error,
        };
        let clean = |s: &str| CString::new(s.replace('\0', " ")).unwrap_or_default();
        let (category, message) = (clean(category), clean(&fmi3_names(message)));
        unsafe { callback(self.env, status, category.as_ptr(), message.as_ptr()) };
    }
}

const _: fmi3GetVersionTYPE = Some(fmi3GetVersion);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

const _: fmi3SetDebugLoggingTYPE = Some(fmi3SetDebugLogging);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3SetDebugLogging(
    instance: fmi3Instance,
    loggingOn: fmi3Boolean,
    nCategories: usize,
    categories: *const fmi3String,
) -> fmi3Status {
    ffi::fmi2SetDebugLogging(instance, loggingOn.into(), nCategories, categories)
}

const _: fmi3InstantiateCoSimulationTYPE = Some(fmi3InstantiateCoSimulation);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3InstantiateCoSimulation(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    _earlyReturnAllowed: fmi3Boolean,
    _requiredIntermediateVariables: *const fmi3ValueReference,
    nRequiredIntermediateVariables: usize,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    _intermediateUpdate: fmi3IntermediateUpdateCallback,
) -> fmi3Instance {
    let logger = || Logger {
        callback: logMessage,
        env: instanceEnvironment,
    };
    let fail = |msg: String| {
        logger().call(
            Status::Error,
            "logStatusError",
            &format!("fmi3InstantiateCoSimulation: {msg}"),
        );
        std::ptr::null_mut()
    };
    let made = catch_unwind(AssertUnwindSafe(|| {
        let Some(name) = (unsafe { string(instanceName) }) else {
            return fail("instanceName is NULL".into());
        };
        if eventModeUsed {
            return fail(
                "eventModeUsed is true, but this FMU has no event mode (hasEventMode=\"false\")"
                    .into(),
            );
        }
        if nRequiredIntermediateVariables > 0 {
            return fail("intermediate variables were requested, but this FMU provides no intermediate update (providesIntermediateUpdate=\"false\")".into());
        }
        let Some(token) = (unsafe { string(instantiationToken) }) else {
            return fail("instantiationToken is NULL".into());
        };
        let Some(location) = (unsafe { string(resourcePath) }) else {
            return fail("resourcePath is NULL: the scene is in the FMU's resources".into());
        };
        let scene = resource_path(&location).join(super::SCENE_FILE);
        let instance_logger = logger();
        let log: LogFn = Box::new(move |s, cat, msg| instance_logger.call(s, cat, msg));
        match Instance::new(&name, &scene, &token, loggingOn, log) {
            Ok(instance) => {
                let vars = Variables3::of(&instance);
                Component::boxed(instance, Some(vars)) as fmi3Instance
            }
            Err(msg) => fail(msg),
        }
    }));
    made.unwrap_or_else(|p| {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            fail(format!("internal error: {}", panic_text(&*p)))
        }));
        std::ptr::null_mut()
    })
}

/// An instantiation this FMU does not offer: NULL, said to the logger.
fn no_instance(
    call: &str,
    env: fmi3InstanceEnvironment,
    log: fmi3LogMessageCallback,
    why: &str,
) -> fmi3Instance {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        Logger { callback: log, env }.call(
            Status::Error,
            "logStatusError",
            &format!("{call}: {why}"),
        );
    }));
    std::ptr::null_mut()
}

const _: fmi3InstantiateModelExchangeTYPE = Some(fmi3InstantiateModelExchange);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3InstantiateModelExchange(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
) -> fmi3Instance {
    no_instance(
        "fmi3InstantiateModelExchange",
        instanceEnvironment,
        logMessage,
        "this FMU is co-simulation only",
    )
}

const _: fmi3InstantiateScheduledExecutionTYPE = Some(fmi3InstantiateScheduledExecution);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3InstantiateScheduledExecution(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    _clockUpdate: fmi3ClockUpdateCallback,
    _lockPreemption: fmi3LockPreemptionCallback,
    _unlockPreemption: fmi3UnlockPreemptionCallback,
) -> fmi3Instance {
    no_instance(
        "fmi3InstantiateScheduledExecution",
        instanceEnvironment,
        logMessage,
        "this FMU is co-simulation only",
    )
}

const _: fmi3FreeInstanceTYPE = Some(fmi3FreeInstance);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
    ffi::fmi2FreeInstance(instance)
}

const _: fmi3EnterInitializationModeTYPE = Some(fmi3EnterInitializationMode);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3EnterInitializationMode(
    instance: fmi3Instance,
    _toleranceDefined: fmi3Boolean,
    _tolerance: fmi3Float64,
    startTime: fmi3Float64,
    _stopTimeDefined: fmi3Boolean,
    _stopTime: fmi3Float64,
) -> fmi3Status {
    with(
        instance,
        "fmi3EnterInitializationMode",
        |inst, _| match inst.setup_experiment(startTime) {
            Status::Ok => inst.enter_initialization(),
            s => s,
        },
    )
}

const _: fmi3ExitInitializationModeTYPE = Some(fmi3ExitInitializationMode);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3ExitInitializationMode(instance: fmi3Instance) -> fmi3Status {
    ffi::fmi2ExitInitializationMode(instance)
}

const _: fmi3TerminateTYPE = Some(fmi3Terminate);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3Terminate(instance: fmi3Instance) -> fmi3Status {
    ffi::fmi2Terminate(instance)
}

const _: fmi3ResetTYPE = Some(fmi3Reset);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3Reset(instance: fmi3Instance) -> fmi3Status {
    ffi::fmi2Reset(instance)
}

/// The FMI 3.0 variables of an instance (made by FMI 3.0 or not).
fn table<'a>(
    inst: &mut Instance,
    comp: &'a Component,
    call: &str,
) -> Result<&'a Variables3, Status> {
    comp.fmi3.as_ref().ok_or_else(|| {
        error(
            inst,
            format!(
                "{call}: the instance was made by fmi2Instantiate, not fmi3InstantiateCoSimulation"
            ),
        )
    })
}

/// fmi3GetFloat64 and fmi3GetInt32: element by element through the FMI 2.0
/// getter; `time` is the end of the last converged step.
fn get<T: Value>(
    instance: fmi3Instance,
    call: &str,
    vrs: *const fmi3ValueReference,
    nvr: usize,
    values: *mut T,
    n_values: usize,
) -> fmi3Status {
    with(instance, call, |inst, comp| {
        let (Some(vrs), Some(out)) = (unsafe { (slice(vrs, nvr), slice_mut(values, n_values)) })
        else {
            return null(inst, call, "valueReferences or values");
        };
        let elements = match table(inst, comp, call)
            .and_then(|t| t.expand(inst, call, vrs, T::TYPE, n_values))
        {
            Ok(e) => e,
            Err(s) => return s,
        };
        let members: Vec<u32> = elements.iter().flatten().copied().collect();
        let mut got = vec![T::default(); members.len()];
        let status = T::get(inst, &members, &mut got);
        if status != Status::Ok {
            return status;
        }
        let mut next = got.into_iter();
        for (o, e) in out.iter_mut().zip(&elements) {
            *o = match e {
                Some(_) => next.next().unwrap_or_default(),
                None => T::time(inst.last_successful_time()),
            };
        }
        Status::Ok
    })
}

/// fmi3SetFloat64 and fmi3SetInt32: element by element through the FMI 2.0
/// setter (which accepts only parameters and inputs, all scalars).
fn set<T: Value>(
    instance: fmi3Instance,
    call: &str,
    vrs: *const fmi3ValueReference,
    nvr: usize,
    values: *const T,
    n_values: usize,
) -> fmi3Status {
    with(instance, call, |inst, comp| {
        let (Some(vrs), Some(v)) = (unsafe { (slice(vrs, nvr), slice(values, n_values)) }) else {
            return null(inst, call, "valueReferences or values");
        };
        let elements = match table(inst, comp, call)
            .and_then(|t| t.expand(inst, call, vrs, T::TYPE, n_values))
        {
            Ok(e) => e,
            Err(s) => return s,
        };
        if elements.iter().any(Option::is_none) {
            return error(
                inst,
                format!(
                    "{call}: `time` (valueReference {TIME_VR}) is the independent variable; it follows the steps and cannot be set"
                ),
            );
        }
        let members: Vec<u32> = elements.into_iter().flatten().collect();
        T::set(inst, &members, v)
    })
}

const _: fmi3GetFloat64TYPE = Some(fmi3GetFloat64);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *mut fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    get(
        instance,
        "fmi3GetFloat64",
        valueReferences,
        nValueReferences,
        values,
        nValues,
    )
}

const _: fmi3GetInt32TYPE = Some(fmi3GetInt32);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetInt32(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *mut fmi3Int32,
    nValues: usize,
) -> fmi3Status {
    get(
        instance,
        "fmi3GetInt32",
        valueReferences,
        nValueReferences,
        values,
        nValues,
    )
}

const _: fmi3SetFloat64TYPE = Some(fmi3SetFloat64);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3SetFloat64(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3Float64,
    nValues: usize,
) -> fmi3Status {
    set(
        instance,
        "fmi3SetFloat64",
        valueReferences,
        nValueReferences,
        values,
        nValues,
    )
}

const _: fmi3SetInt32TYPE = Some(fmi3SetInt32);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3SetInt32(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3Int32,
    nValues: usize,
) -> fmi3Status {
    set(
        instance,
        "fmi3SetInt32",
        valueReferences,
        nValueReferences,
        values,
        nValues,
    )
}

/// String variables are scalars (the output folder): one value each.
fn scalar_strings(
    instance: fmi3Instance,
    call: &str,
    nvr: usize,
    n_values: usize,
) -> Option<fmi3Status> {
    (nvr != n_values).then(|| {
        with(instance, call, |inst, _| {
            error(
                inst,
                format!("{call}: nValues = {n_values}, but the {nvr} String variables are scalars"),
            )
        })
    })
}

const _: fmi3GetStringTYPE = Some(fmi3GetString);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetString(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *mut fmi3String,
    nValues: usize,
) -> fmi3Status {
    scalar_strings(instance, "fmi3GetString", nValueReferences, nValues)
        .unwrap_or_else(|| ffi::fmi2GetString(instance, valueReferences, nValueReferences, values))
}

const _: fmi3SetStringTYPE = Some(fmi3SetString);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3SetString(
    instance: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3String,
    nValues: usize,
) -> fmi3Status {
    scalar_strings(instance, "fmi3SetString", nValueReferences, nValues)
        .unwrap_or_else(|| ffi::fmi2SetString(instance, valueReferences, nValueReferences, values))
}

/// A getter or setter of a type this FMU has no variables of: fine for no
/// value references, an error naming the type otherwise.
fn no_variables(instance: fmi3Instance, call: &str, nvr: usize) -> fmi3Status {
    with(instance, call, |inst, _| {
        if nvr == 0 {
            Status::Ok
        } else {
            error(
                inst,
                format!(
                    "{call}: this FMU has no variables of this type (only Float64, Int32 and String)"
                ),
            )
        }
    })
}

/// Getters and setters of the types this FMU has no variables of (the
/// arguments after the value references differ by type).
macro_rules! no_variables_of_type {
    ($($name:ident, $check:ident, ($($arg:ident: $ty:ty),*);)*) => {$(
        const _: $check = Some($name);
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(
            instance: fmi3Instance,
            _valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            $($arg: $ty),*
        ) -> fmi3Status {
            $(let _ = $arg;)*
            no_variables(instance, stringify!($name), nValueReferences)
        }
    )*};
}

no_variables_of_type! {
    fmi3GetFloat32, fmi3GetFloat32TYPE, (values: *mut fmi3Float32, n_values: usize);
    fmi3GetInt8, fmi3GetInt8TYPE, (values: *mut fmi3Int8, n_values: usize);
    fmi3GetUInt8, fmi3GetUInt8TYPE, (values: *mut fmi3UInt8, n_values: usize);
    fmi3GetInt16, fmi3GetInt16TYPE, (values: *mut fmi3Int16, n_values: usize);
    fmi3GetUInt16, fmi3GetUInt16TYPE, (values: *mut fmi3UInt16, n_values: usize);
    fmi3GetUInt32, fmi3GetUInt32TYPE, (values: *mut fmi3UInt32, n_values: usize);
    fmi3GetInt64, fmi3GetInt64TYPE, (values: *mut fmi3Int64, n_values: usize);
    fmi3GetUInt64, fmi3GetUInt64TYPE, (values: *mut fmi3UInt64, n_values: usize);
    fmi3GetBoolean, fmi3GetBooleanTYPE, (values: *mut fmi3Boolean, n_values: usize);
    fmi3SetFloat32, fmi3SetFloat32TYPE, (values: *const fmi3Float32, n_values: usize);
    fmi3SetInt8, fmi3SetInt8TYPE, (values: *const fmi3Int8, n_values: usize);
    fmi3SetUInt8, fmi3SetUInt8TYPE, (values: *const fmi3UInt8, n_values: usize);
    fmi3SetInt16, fmi3SetInt16TYPE, (values: *const fmi3Int16, n_values: usize);
    fmi3SetUInt16, fmi3SetUInt16TYPE, (values: *const fmi3UInt16, n_values: usize);
    fmi3SetUInt32, fmi3SetUInt32TYPE, (values: *const fmi3UInt32, n_values: usize);
    fmi3SetInt64, fmi3SetInt64TYPE, (values: *const fmi3Int64, n_values: usize);
    fmi3SetUInt64, fmi3SetUInt64TYPE, (values: *const fmi3UInt64, n_values: usize);
    fmi3SetBoolean, fmi3SetBooleanTYPE, (values: *const fmi3Boolean, n_values: usize);
    fmi3GetBinary, fmi3GetBinaryTYPE, (value_sizes: *mut usize, values: *mut fmi3Binary, n_values: usize);
    fmi3SetBinary, fmi3SetBinaryTYPE, (value_sizes: *const usize, values: *const fmi3Binary, n_values: usize);
    fmi3GetClock, fmi3GetClockTYPE, (values: *mut fmi3Clock);
    fmi3SetClock, fmi3SetClockTYPE, (values: *const fmi3Clock);
}

const _: fmi3GetNumberOfVariableDependenciesTYPE = Some(fmi3GetNumberOfVariableDependencies);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetNumberOfVariableDependencies(
    instance: fmi3Instance,
    valueReference: fmi3ValueReference,
    nDependencies: *mut usize,
) -> fmi3Status {
    const CALL: &str = "fmi3GetNumberOfVariableDependencies";
    with(instance, CALL, |inst, comp| {
        if nDependencies.is_null() {
            return null(inst, CALL, "nDependencies");
        }
        if let Err(s) = table(inst, comp, CALL).and_then(|t| {
            t.by_vr.get(&valueReference).map(|_| ()).ok_or_else(|| {
                error(
                    inst,
                    format!("{CALL}: no variable has valueReference {valueReference}"),
                )
            })
        }) {
            return s;
        }
        // No direct feedthrough: no output depends on an input at the
        // same instant (the model structure's dependencies="").
        unsafe { *nDependencies = 0 };
        Status::Ok
    })
}

const _: fmi3GetVariableDependenciesTYPE = Some(fmi3GetVariableDependencies);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetVariableDependencies(
    instance: fmi3Instance,
    dependent: fmi3ValueReference,
    _elementIndicesOfDependent: *mut usize,
    _independents: *mut fmi3ValueReference,
    _elementIndicesOfIndependents: *mut usize,
    _dependencyKinds: *mut fmi3DependencyKind,
    nDependencies: usize,
) -> fmi3Status {
    const CALL: &str = "fmi3GetVariableDependencies";
    with(instance, CALL, |inst, _| {
        if nDependencies == 0 {
            Status::Ok
        } else {
            error(
                inst,
                format!(
                    "{CALL}: valueReference {dependent} has no dependencies (fmi3GetNumberOfVariableDependencies gives 0), nDependencies = {nDependencies}"
                ),
            )
        }
    })
}

const _: fmi3GetFMUStateTYPE = Some(fmi3GetFMUState);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    ffi::fmi2GetFMUstate(instance, FMUState)
}

const _: fmi3SetFMUStateTYPE = Some(fmi3SetFMUState);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3SetFMUState(instance: fmi3Instance, FMUState: fmi3FMUState) -> fmi3Status {
    ffi::fmi2SetFMUstate(instance, FMUState)
}

const _: fmi3FreeFMUStateTYPE = Some(fmi3FreeFMUState);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3FreeFMUState(
    instance: fmi3Instance,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    ffi::fmi2FreeFMUstate(instance, FMUState)
}

const _: fmi3SerializedFMUStateSizeTYPE = Some(fmi3SerializedFMUStateSize);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3SerializedFMUStateSize(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    ffi::fmi2SerializedFMUstateSize(instance, FMUState, size)
}

const _: fmi3SerializeFMUStateTYPE = Some(fmi3SerializeFMUState);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3SerializeFMUState(
    instance: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: usize,
) -> fmi3Status {
    ffi::fmi2SerializeFMUstate(instance, FMUState, serializedState as *mut c_char, size)
}

const _: fmi3DeserializeFMUStateTYPE = Some(fmi3DeserializeFMUState);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3DeserializeFMUState(
    instance: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: usize,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    ffi::fmi2DeSerializeFMUstate(instance, serializedState as *const c_char, size, FMUState)
}

const _: fmi3GetDirectionalDerivativeTYPE = Some(fmi3GetDirectionalDerivative);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetDirectionalDerivative(
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
    const CALL: &str = "fmi3GetDirectionalDerivative";
    with_solving(instance, CALL, |inst, comp| {
        let arrays = unsafe {
            (
                slice(unknowns, nUnknowns),
                slice(knowns, nKnowns),
                slice(seed, nSeed),
                slice_mut(sensitivity, nSensitivity),
            )
        };
        let (Some(unknowns), Some(knowns), Some(seed), Some(out)) = arrays else {
            return null(inst, CALL, "unknowns, knowns, seed or sensitivity");
        };
        let vars = match table(inst, comp, CALL) {
            Ok(t) => t,
            Err(s) => return s,
        };
        let mut members = Vec::with_capacity(2);
        for (list, n) in [(unknowns, nSensitivity), (knowns, nSeed)] {
            match vars.expand(inst, CALL, list, Type::Real, n) {
                Ok(e) if e.iter().any(Option::is_none) => {
                    return error(
                        inst,
                        format!(
                            "{CALL}: `time` (valueReference {TIME_VR}) has no directional derivative here; the knowns are the Float64 inputs"
                        ),
                    );
                }
                Ok(e) => members.push(e.into_iter().flatten().collect::<Vec<u32>>()),
                Err(s) => return s,
            }
        }
        inst.directional_derivative(&members[0], &members[1], seed, out)
    })
}

const _: fmi3DoStepTYPE = Some(fmi3DoStep);
#[unsafe(no_mangle)]
pub extern "C" fn fmi3DoStep(
    instance: fmi3Instance,
    currentCommunicationPoint: fmi3Float64,
    communicationStepSize: fmi3Float64,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    eventHandlingNeeded: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    earlyReturn: *mut fmi3Boolean,
    lastSuccessfulTime: *mut fmi3Float64,
) -> fmi3Status {
    const CALL: &str = "fmi3DoStep";
    with_solving(instance, CALL, |inst, _| {
        if eventHandlingNeeded.is_null()
            || terminateSimulation.is_null()
            || earlyReturn.is_null()
            || lastSuccessfulTime.is_null()
        {
            return null(
                inst,
                CALL,
                "eventHandlingNeeded, terminateSimulation, earlyReturn or lastSuccessfulTime",
            );
        }
        let status = inst.do_step(currentCommunicationPoint, communicationStepSize);
        // No events, no early return, never a request to stop: a step that
        // cannot converge is fmi3Discard, and the time it reached is the
        // last converged one.
        unsafe {
            *eventHandlingNeeded = false;
            *terminateSimulation = false;
            *earlyReturn = false;
            *lastSuccessfulTime = inst.last_successful_time();
        }
        status
    })
}

/// A call for a capability this FMU does not declare: fmi3Error, said to
/// the logger.
macro_rules! not_offered {
    ($($name:ident, $check:ident, $why:expr, ($($arg:ident: $ty:ty),*);)*) => {$(
        const _: $check = Some($name);
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(instance: fmi3Instance, $($arg: $ty),*) -> fmi3Status {
            $(let _ = $arg;)*
            unsupported(instance, stringify!($name), $why)
        }
    )*};
}

const NO_EVENTS: &str = "this FMU has no event mode (hasEventMode=\"false\")";
const NO_ME: &str = "this FMU is co-simulation only";
const NO_CLOCKS: &str = "this FMU has no clocks";

not_offered! {
    fmi3EnterEventMode, fmi3EnterEventModeTYPE, NO_EVENTS, ();
    fmi3EnterStepMode, fmi3EnterStepModeTYPE, "without event mode the instance is in step mode from fmi3ExitInitializationMode on", ();
    fmi3UpdateDiscreteStates, fmi3UpdateDiscreteStatesTYPE, NO_EVENTS, (a: *mut fmi3Boolean, b: *mut fmi3Boolean, c: *mut fmi3Boolean, d: *mut fmi3Boolean, e: *mut fmi3Boolean, f: *mut fmi3Float64);
    fmi3EvaluateDiscreteStates, fmi3EvaluateDiscreteStatesTYPE, NO_EVENTS, ();
    fmi3GetAdjointDerivative, fmi3GetAdjointDerivativeTYPE, "providesAdjointDerivatives is false; fmi3GetDirectionalDerivative gives the same derivatives", (a: *const fmi3ValueReference, b: usize, c: *const fmi3ValueReference, d: usize, e: *const fmi3Float64, f: usize, g: *mut fmi3Float64, h: usize);
    fmi3GetOutputDerivatives, fmi3GetOutputDerivativesTYPE, "maxOutputDerivativeOrder is 0", (a: *const fmi3ValueReference, b: usize, c: *const fmi3Int32, d: *mut fmi3Float64, e: usize);
    fmi3EnterConfigurationMode, fmi3EnterConfigurationModeTYPE, "this FMU has no structural parameters", ();
    fmi3ExitConfigurationMode, fmi3ExitConfigurationModeTYPE, "this FMU has no structural parameters", ();
    fmi3GetIntervalDecimal, fmi3GetIntervalDecimalTYPE, NO_CLOCKS, (a: *const fmi3ValueReference, b: usize, c: *mut fmi3Float64, d: *mut fmi3IntervalQualifier);
    fmi3GetIntervalFraction, fmi3GetIntervalFractionTYPE, NO_CLOCKS, (a: *const fmi3ValueReference, b: usize, c: *mut fmi3UInt64, d: *mut fmi3UInt64, e: *mut fmi3IntervalQualifier);
    fmi3GetShiftDecimal, fmi3GetShiftDecimalTYPE, NO_CLOCKS, (a: *const fmi3ValueReference, b: usize, c: *mut fmi3Float64);
    fmi3GetShiftFraction, fmi3GetShiftFractionTYPE, NO_CLOCKS, (a: *const fmi3ValueReference, b: usize, c: *mut fmi3UInt64, d: *mut fmi3UInt64);
    fmi3SetIntervalDecimal, fmi3SetIntervalDecimalTYPE, NO_CLOCKS, (a: *const fmi3ValueReference, b: usize, c: *const fmi3Float64);
    fmi3SetIntervalFraction, fmi3SetIntervalFractionTYPE, NO_CLOCKS, (a: *const fmi3ValueReference, b: usize, c: *const fmi3UInt64, d: *const fmi3UInt64);
    fmi3SetShiftDecimal, fmi3SetShiftDecimalTYPE, NO_CLOCKS, (a: *const fmi3ValueReference, b: usize, c: *const fmi3Float64);
    fmi3SetShiftFraction, fmi3SetShiftFractionTYPE, NO_CLOCKS, (a: *const fmi3ValueReference, b: usize, c: *const fmi3UInt64, d: *const fmi3UInt64);
    fmi3ActivateModelPartition, fmi3ActivateModelPartitionTYPE, NO_CLOCKS, (a: fmi3ValueReference, b: fmi3Float64);
    fmi3EnterContinuousTimeMode, fmi3EnterContinuousTimeModeTYPE, NO_ME, ();
    fmi3CompletedIntegratorStep, fmi3CompletedIntegratorStepTYPE, NO_ME, (a: fmi3Boolean, b: *mut fmi3Boolean, c: *mut fmi3Boolean);
    fmi3SetTime, fmi3SetTimeTYPE, NO_ME, (a: fmi3Float64);
    fmi3SetContinuousStates, fmi3SetContinuousStatesTYPE, NO_ME, (a: *const fmi3Float64, b: usize);
    fmi3GetContinuousStateDerivatives, fmi3GetContinuousStateDerivativesTYPE, NO_ME, (a: *mut fmi3Float64, b: usize);
    fmi3GetEventIndicators, fmi3GetEventIndicatorsTYPE, NO_ME, (a: *mut fmi3Float64, b: usize);
    fmi3GetContinuousStates, fmi3GetContinuousStatesTYPE, NO_ME, (a: *mut fmi3Float64, b: usize);
    fmi3GetNominalsOfContinuousStates, fmi3GetNominalsOfContinuousStatesTYPE, NO_ME, (a: *mut fmi3Float64, b: usize);
    fmi3GetNumberOfEventIndicators, fmi3GetNumberOfEventIndicatorsTYPE, NO_ME, (a: *mut usize);
    fmi3GetNumberOfContinuousStates, fmi3GetNumberOfContinuousStatesTYPE, NO_ME, (a: *mut usize);
}
