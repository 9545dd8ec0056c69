//! The FMI 2.0 co-simulation C interface: all 34 functions, over the C types
//! of `fmi-sys`, each checked against fmi-sys's function type at compile
//! time (the `const _` lines). Every entry point checks its pointers, catches
//! panics (a panic marks the instance failed and returns fmi2Error) and
//! never unwinds into the host.

#![allow(non_snake_case)]

use super::boundary::{
    Component, Value, null, panic_text, resource_path, slice, slice_mut, status as fmi_status,
    string, thread_token, unsupported, with, with_solving,
};
use super::instance::{Instance, LogFn, Snapshot, Status};
use crate::results::LogCategory;
use fmi_sys::fmi2::*;
use std::ffi::{CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::TryLockError;
use std::sync::atomic::Ordering;

/// The master's logger; the environment pointer is the master's and stays
/// valid for the instance's life (FMI 2.0, 2.1.5).
struct Logger {
    logger: fmi2CallbackLogger,
    env: fmi2ComponentEnvironment,
    name: CString,
}

// The master guarantees the environment pointer for the instance's life and
// that one instance is not called from two threads at once.
unsafe impl Send for Logger {}

impl Logger {
    /// The logger of a callback struct, which may be NULL or hold no logger.
    fn new(functions: *const fmi2CallbackFunctions, name: &str) -> Logger {
        let callbacks = (!functions.is_null()).then(|| unsafe { *functions });
        Logger {
            logger: callbacks.and_then(|f| f.logger),
            env: callbacks.map_or(std::ptr::null_mut(), |f| f.componentEnvironment),
            name: CString::new(name.replace('\0', " ")).unwrap_or_default(),
        }
    }

    fn call(&self, status: Status, category: &str, message: &str) {
        let Some(logger) = self.logger else {
            return;
        };
        let status = fmi_status(status);
        let clean = |s: &str| CString::new(s.replace('\0', " ")).unwrap_or_default();
        let (category, message) = (clean(category), clean(message));
        // printf-style: the message goes in as an argument of "%s".
        unsafe {
            logger(
                self.env,
                self.name.as_ptr(),
                status,
                category.as_ptr(),
                c"%s".as_ptr(),
                message.as_ptr(),
            )
        };
    }
}

// ---------------------------------------------------------------------------
// Common functions.

const _: fmi2GetTypesPlatformTYPE = Some(fmi2GetTypesPlatform);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

const _: fmi2GetVersionTYPE = Some(fmi2GetVersion);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

const _: fmi2SetDebugLoggingTYPE = Some(fmi2SetDebugLogging);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    with(c, "fmi2SetDebugLogging", |inst, _| {
        let Some(list) = (unsafe { slice(categories, nCategories) }) else {
            return null(inst, "fmi2SetDebugLogging", "categories");
        };
        let mut names = Vec::with_capacity(list.len());
        for &p in list {
            match unsafe { string(p) } {
                Some(s) => names.push(s),
                None => return null(inst, "fmi2SetDebugLogging", "a category"),
            }
        }
        inst.set_debug_logging(loggingOn != 0, &names)
    })
}

const _: fmi2InstantiateTYPE = Some(fmi2Instantiate);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: fmi2Type,
    fmuGUID: fmi2String,
    fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    let made = catch_unwind(AssertUnwindSafe(|| {
        let name = unsafe { string(instanceName) };
        let logger = Logger::new(functions, name.as_deref().unwrap_or(""));
        let fail = |msg: String| {
            logger.call(
                Status::Error,
                "logStatusError",
                &format!("fmi2Instantiate: {msg}"),
            );
            std::ptr::null_mut()
        };
        let Some(name) = name else {
            return fail("instanceName is NULL".into());
        };
        if fmuType != fmi2Type_fmi2CoSimulation {
            return fail(format!(
                "fmuType {fmuType} requested; this FMU is co-simulation only"
            ));
        }
        let Some(guid) = (unsafe { string(fmuGUID) }) else {
            return fail("fmuGUID is NULL".into());
        };
        let Some(location) = (unsafe { string(fmuResourceLocation) }) else {
            return fail("fmuResourceLocation is NULL".into());
        };
        let scene = resource_path(&location).join(super::SCENE_FILE);
        let instance_logger = Logger::new(functions, &name);
        let log: LogFn = Box::new(move |s, cat, msg| instance_logger.call(s, cat, msg));
        match Instance::new(&name, &scene, &guid, loggingOn != 0, log) {
            Ok(instance) => Component::boxed(instance, None) as fmi2Component,
            Err(msg) => fail(msg),
        }
    }));
    made.unwrap_or_else(|p| {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            let name = unsafe { string(instanceName) };
            report_instantiate_panic(functions, name.as_deref().unwrap_or(""), &*p);
        }));
        std::ptr::null_mut()
    })
}

/// A panic while reading the scene or building an instance: its text to the
/// master's logger (the process's panic hook may have printed it to stderr,
/// which the master need not show).
fn report_instantiate_panic(
    functions: *const fmi2CallbackFunctions,
    name: &str,
    payload: &(dyn std::any::Any + Send),
) {
    Logger::new(functions, name).call(
        Status::Error,
        "logStatusError",
        &format!("fmi2Instantiate: internal error: {}", panic_text(payload)),
    );
}

const _: fmi2FreeInstanceTYPE = Some(fmi2FreeInstance);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    if c.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // In use (freed from inside the logger during a call on it, or,
        // against FMI, from another thread during a call): freeing it under
        // that call would leave the call on freed memory; that call frees
        // it when it returns (`boundary::with`).
        let comp = unsafe { &*(c as *const Component) };
        if comp.owner.load(Ordering::SeqCst) == thread_token()
            || matches!(comp.instance.try_lock(), Err(TryLockError::WouldBlock))
        {
            comp.defer(
                LogCategory::Warning,
                "fmi2FreeInstance: the instance is in a call; it is freed when that call returns"
                    .into(),
            );
            comp.free_when_done.store(true, Ordering::SeqCst);
            return;
        }
        drop(unsafe { Box::from_raw(c as *mut Component) });
    }));
}

const _: fmi2SetupExperimentTYPE = Some(fmi2SetupExperiment);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _toleranceDefined: fmi2Boolean,
    _tolerance: fmi2Real,
    startTime: fmi2Real,
    _stopTimeDefined: fmi2Boolean,
    _stopTime: fmi2Real,
) -> fmi2Status {
    // The master's tolerance is for its integrators; Newton has
    // solver.tolerance.
    with(c, "fmi2SetupExperiment", |inst, _| {
        inst.setup_experiment(startTime)
    })
}

const _: fmi2EnterInitializationModeTYPE = Some(fmi2EnterInitializationMode);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    with(c, "fmi2EnterInitializationMode", |inst, _| {
        inst.enter_initialization()
    })
}

const _: fmi2ExitInitializationModeTYPE = Some(fmi2ExitInitializationMode);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    with_solving(c, "fmi2ExitInitializationMode", |inst, _| {
        inst.exit_initialization()
    })
}

const _: fmi2TerminateTYPE = Some(fmi2Terminate);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    with(c, "fmi2Terminate", |inst, _| inst.terminate())
}

const _: fmi2ResetTYPE = Some(fmi2Reset);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    with(c, "fmi2Reset", |inst, _| inst.reset())
}

/// fmi2Get/SetReal and fmi2Get/SetInteger: the value references, then
/// `values` reads the values' array and calls the instance's getter or
/// setter of that type (`Value`); a NULL array is the error naming
/// "vr or value".
fn transfer(
    c: fmi2Component,
    call: &str,
    vr: *const fmi2ValueReference,
    nvr: usize,
    values: impl FnOnce(&mut Instance, &[u32]) -> Option<Status>,
) -> fmi2Status {
    with(c, call, |inst, _| {
        match unsafe { slice(vr, nvr) }.and_then(|vr| values(inst, vr)) {
            Some(status) => status,
            None => null(inst, call, "vr or value"),
        }
    })
}

const _: fmi2GetRealTYPE = Some(fmi2GetReal);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    transfer(c, "fmi2GetReal", vr, nvr, |inst, vr| {
        unsafe { slice_mut(value, nvr) }.map(|out| Value::get(inst, vr, out))
    })
}

const _: fmi2GetIntegerTYPE = Some(fmi2GetInteger);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    transfer(c, "fmi2GetInteger", vr, nvr, |inst, vr| {
        unsafe { slice_mut(value, nvr) }.map(|out| Value::get(inst, vr, out))
    })
}

const _: fmi2GetBooleanTYPE = Some(fmi2GetBoolean);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *mut fmi2Boolean,
) -> fmi2Status {
    with(c, "fmi2GetBoolean", |inst, _| {
        no_booleans(inst, "fmi2GetBoolean", nvr)
    })
}

fn no_booleans(inst: &mut Instance, call: &str, nvr: usize) -> Status {
    if nvr == 0 {
        return Status::Ok;
    }
    inst.log(
        crate::results::LogCategory::Error,
        &format!("{call}: this FMU has no Boolean variables"),
    );
    Status::Error
}

const _: fmi2GetStringTYPE = Some(fmi2GetString);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    with(c, "fmi2GetString", |inst, comp| {
        let (Some(vr), Some(out)) = (unsafe { (slice(vr, nvr), slice_mut(value, nvr)) }) else {
            return null(inst, "fmi2GetString", "vr or value");
        };
        let values = match inst.get_string(vr) {
            Ok(v) => v,
            Err(s) => return s,
        };
        let mut strings = comp
            .strings
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        *strings = values
            .iter()
            .map(|s| CString::new(s.replace('\0', " ")).unwrap_or_default())
            .collect();
        for (o, s) in out.iter_mut().zip(strings.iter()) {
            *o = s.as_ptr();
        }
        Status::Ok
    })
}

const _: fmi2SetRealTYPE = Some(fmi2SetReal);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    transfer(c, "fmi2SetReal", vr, nvr, |inst, vr| {
        unsafe { slice(value, nvr) }.map(|v| Value::set(inst, vr, v))
    })
}

const _: fmi2SetIntegerTYPE = Some(fmi2SetInteger);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    transfer(c, "fmi2SetInteger", vr, nvr, |inst, vr| {
        unsafe { slice(value, nvr) }.map(|v| Value::set(inst, vr, v))
    })
}

const _: fmi2SetBooleanTYPE = Some(fmi2SetBoolean);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *const fmi2Boolean,
) -> fmi2Status {
    with(c, "fmi2SetBoolean", |inst, _| {
        no_booleans(inst, "fmi2SetBoolean", nvr)
    })
}

const _: fmi2SetStringTYPE = Some(fmi2SetString);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2String,
) -> fmi2Status {
    with(c, "fmi2SetString", |inst, _| {
        let (Some(vr), Some(v)) = (unsafe { (slice(vr, nvr), slice(value, nvr)) }) else {
            return null(inst, "fmi2SetString", "vr or value");
        };
        let mut values = Vec::with_capacity(v.len());
        for &p in v {
            match unsafe { string(p) } {
                Some(s) => values.push(s),
                None => return null(inst, "fmi2SetString", "a value"),
            }
        }
        inst.set_string(vr, &values)
    })
}

const _: fmi2GetFMUstateTYPE = Some(fmi2GetFMUstate);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetFMUstate(c: fmi2Component, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
    with(c, "fmi2GetFMUstate", |inst, _| {
        if FMUstate.is_null() {
            return null(inst, "fmi2GetFMUstate", "FMUstate");
        }
        let snap = match inst.get_state() {
            Ok(s) => s,
            Err(s) => return s,
        };
        unsafe {
            let old = *FMUstate;
            if old.is_null() {
                *FMUstate = Box::into_raw(Box::new(snap)) as fmi2FMUstate;
            } else {
                // A state given back to be overwritten.
                *(old as *mut Snapshot) = snap;
            }
        }
        Status::Ok
    })
}

const _: fmi2SetFMUstateTYPE = Some(fmi2SetFMUstate);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    with(c, "fmi2SetFMUstate", |inst, _| {
        if FMUstate.is_null() {
            return null(inst, "fmi2SetFMUstate", "FMUstate");
        }
        let snap = unsafe { &*(FMUstate as *const Snapshot) };
        inst.set_state(snap)
    })
}

const _: fmi2FreeFMUstateTYPE = Some(fmi2FreeFMUstate);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2FreeFMUstate(c: fmi2Component, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
    with(c, "fmi2FreeFMUstate", |inst, _| {
        if FMUstate.is_null() {
            return null(inst, "fmi2FreeFMUstate", "FMUstate");
        }
        unsafe {
            let p = *FMUstate;
            if !p.is_null() {
                drop(Box::from_raw(p as *mut Snapshot));
            }
            *FMUstate = std::ptr::null_mut();
        }
        Status::Ok
    })
}

const _: fmi2SerializedFMUstateSizeTYPE = Some(fmi2SerializedFMUstateSize);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    with(c, "fmi2SerializedFMUstateSize", |inst, _| {
        if FMUstate.is_null() || size.is_null() {
            return null(inst, "fmi2SerializedFMUstateSize", "FMUstate or size");
        }
        let snap = unsafe { &*(FMUstate as *const Snapshot) };
        unsafe { *size = snap.to_bytes().len() };
        Status::Ok
    })
}

const _: fmi2SerializeFMUstateTYPE = Some(fmi2SerializeFMUstate);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    with(c, "fmi2SerializeFMUstate", |inst, _| {
        if FMUstate.is_null() {
            return null(inst, "fmi2SerializeFMUstate", "FMUstate");
        }
        let bytes = unsafe { &*(FMUstate as *const Snapshot) }.to_bytes();
        if size < bytes.len() {
            inst.log(
                crate::results::LogCategory::Error,
                &format!(
                    "fmi2SerializeFMUstate: size = {size}, the state needs {} bytes (fmi2SerializedFMUstateSize)",
                    bytes.len()
                ),
            );
            return Status::Error;
        }
        let Some(out) = (unsafe { slice_mut(serializedState as *mut u8, bytes.len()) }) else {
            return null(inst, "fmi2SerializeFMUstate", "serializedState");
        };
        out.copy_from_slice(&bytes);
        Status::Ok
    })
}

const _: fmi2DeSerializeFMUstateTYPE = Some(fmi2DeSerializeFMUstate);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: usize,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    with(c, "fmi2DeSerializeFMUstate", |inst, _| {
        if FMUstate.is_null() {
            return null(inst, "fmi2DeSerializeFMUstate", "FMUstate");
        }
        let Some(bytes) = (unsafe { slice(serializedState as *const u8, size) }) else {
            return null(inst, "fmi2DeSerializeFMUstate", "serializedState");
        };
        let snap = match Snapshot::from_bytes(bytes) {
            Ok(s) => s,
            Err(msg) => {
                inst.log(crate::results::LogCategory::Error, &msg);
                return Status::Error;
            }
        };
        if snap.guid() != inst.guid() {
            inst.log(
                crate::results::LogCategory::Error,
                &format!(
                    "fmi2DeSerializeFMUstate: the state belongs to an FMU with GUID {}, this one is {}",
                    snap.guid(),
                    inst.guid()
                ),
            );
            return Status::Error;
        }
        unsafe {
            let old = *FMUstate;
            if old.is_null() {
                *FMUstate = Box::into_raw(Box::new(snap)) as fmi2FMUstate;
            } else {
                *(old as *mut Snapshot) = snap;
            }
        }
        Status::Ok
    })
}

const _: fmi2GetDirectionalDerivativeTYPE = Some(fmi2GetDirectionalDerivative);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    vUnknown_ref: *const fmi2ValueReference,
    nUnknown: usize,
    vKnown_ref: *const fmi2ValueReference,
    nKnown: usize,
    dvKnown: *const fmi2Real,
    dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    const CALL: &str = "fmi2GetDirectionalDerivative";
    with_solving(c, CALL, |inst, _| {
        let arrays = unsafe {
            (
                slice(vUnknown_ref, nUnknown),
                slice(vKnown_ref, nKnown),
                slice(dvKnown, nKnown),
                slice_mut(dvUnknown, nUnknown),
            )
        };
        match arrays {
            (Some(unknown), Some(known), Some(seed), Some(out)) => {
                inst.directional_derivative(unknown, known, seed, out)
            }
            _ => null(inst, CALL, "vUnknown_ref, vKnown_ref, dvKnown or dvUnknown"),
        }
    })
}

// ---------------------------------------------------------------------------
// Co-simulation functions.

const _: fmi2SetRealInputDerivativesTYPE = Some(fmi2SetRealInputDerivatives);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    order: *const fmi2Integer,
    value: *const fmi2Real,
) -> fmi2Status {
    with(c, "fmi2SetRealInputDerivatives", |inst, _| {
        match unsafe { (slice(vr, nvr), slice(order, nvr), slice(value, nvr)) } {
            (Some(vr), Some(o), Some(v)) => inst.set_real_input_derivatives(vr, o, v),
            _ => null(inst, "fmi2SetRealInputDerivatives", "vr, order or value"),
        }
    })
}

const _: fmi2GetRealOutputDerivativesTYPE = Some(fmi2GetRealOutputDerivatives);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    unsupported(
        c,
        "fmi2GetRealOutputDerivatives",
        "maxOutputDerivativeOrder is 0",
    )
}

const _: fmi2DoStepTYPE = Some(fmi2DoStep);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    with_solving(c, "fmi2DoStep", |inst, _| {
        inst.do_step(currentCommunicationPoint, communicationStepSize)
    })
}

const _: fmi2CancelStepTYPE = Some(fmi2CancelStep);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    unsupported(
        c,
        "fmi2CancelStep",
        "canRunAsynchronuously is false: fmi2DoStep returns when the step is done",
    )
}

/// A status kind that this FMU does not provide: fmi2Discard (FMI 2.0,
/// 4.2.3).
fn not_available(c: fmi2Component, call: &str, kind: fmi2StatusKind) -> fmi2Status {
    with(c, call, |inst, _| {
        inst.log(
            crate::results::LogCategory::Warning,
            &format!(
                "{call}: status kind {kind} is not available (fmi2DoStep never returns fmi2Pending)"
            ),
        );
        Status::Discard
    })
}

const _: fmi2GetStatusTYPE = Some(fmi2GetStatus);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    _value: *mut fmi2Status,
) -> fmi2Status {
    not_available(c, "fmi2GetStatus", s)
}

const _: fmi2GetRealStatusTYPE = Some(fmi2GetRealStatus);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    if s != fmi2StatusKind_fmi2LastSuccessfulTime {
        return not_available(c, "fmi2GetRealStatus", s);
    }
    with(c, "fmi2GetRealStatus", |inst, _| {
        if value.is_null() {
            return null(inst, "fmi2GetRealStatus", "value");
        }
        unsafe { *value = inst.last_successful_time() };
        Status::Ok
    })
}

const _: fmi2GetIntegerStatusTYPE = Some(fmi2GetIntegerStatus);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    _value: *mut fmi2Integer,
) -> fmi2Status {
    not_available(c, "fmi2GetIntegerStatus", s)
}

const _: fmi2GetBooleanStatusTYPE = Some(fmi2GetBooleanStatus);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    if s != fmi2StatusKind_fmi2Terminated {
        return not_available(c, "fmi2GetBooleanStatus", s);
    }
    with(c, "fmi2GetBooleanStatus", |inst, _| {
        if value.is_null() {
            return null(inst, "fmi2GetBooleanStatus", "value");
        }
        // The slave never asks to end the simulation.
        unsafe { *value = fmi2False as fmi2Boolean };
        Status::Ok
    })
}

const _: fmi2GetStringStatusTYPE = Some(fmi2GetStringStatus);
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    _value: *mut fmi2String,
) -> fmi2Status {
    not_available(c, "fmi2GetStringStatus", s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::{CStr, c_void};
    use std::sync::Mutex;

    type Seen = Mutex<Vec<(fmi2Status, String)>>;

    unsafe extern "C" fn collect(
        env: fmi2ComponentEnvironment,
        _name: fmi2String,
        status: fmi2Status,
        _category: fmi2String,
        _format: fmi2String,
        message: *const c_char,
    ) {
        let seen = unsafe { &*(env as *const Seen) };
        let text = unsafe { CStr::from_ptr(message) }
            .to_string_lossy()
            .into_owned();
        seen.lock().unwrap().push((status, text));
    }

    /// The text of a panic in fmi2Instantiate reaches the master's logger
    /// (issue 13, defect 2: it went to stderr only). No input is known to
    /// panic there any more, so the report is tested on a panic of its own.
    #[test]
    fn an_instantiate_panic_reaches_the_logger() {
        let seen: Seen = Mutex::new(Vec::new());
        let functions = fmi2CallbackFunctions {
            logger: Some(unsafe {
                std::mem::transmute::<
                    unsafe extern "C" fn(
                        fmi2ComponentEnvironment,
                        fmi2String,
                        fmi2Status,
                        fmi2String,
                        fmi2String,
                        *const c_char,
                    ),
                    unsafe extern "C" fn(
                        fmi2ComponentEnvironment,
                        fmi2String,
                        fmi2Status,
                        fmi2String,
                        fmi2String,
                        ...
                    ),
                >(collect)
            }),
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: &seen as *const Seen as *mut c_void,
        };
        let payload = catch_unwind(|| {
            let v: Vec<u64> = Vec::with_capacity(usize::MAX);
            v.len()
        })
        .unwrap_err();
        report_instantiate_panic(&functions, "x", &*payload);
        let seen = seen.lock().unwrap();
        assert_eq!(seen.len(), 1);
        assert_eq!(seen[0].0, fmi2Status_fmi2Error);
        assert_eq!(
            seen[0].1,
            "fmi2Instantiate: internal error: capacity overflow"
        );
        // No logger given: nothing to call, no crash.
        report_instantiate_panic(std::ptr::null(), "x", &*payload);
    }
}
