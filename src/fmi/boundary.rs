//! What the FMI 2.0 (`ffi`) and FMI 3.0 (`ffi3`) C interfaces share: the
//! component a C handle points to, the one guarded entry (`with`: NULL
//! check, lock, panic catch, status mapping), the C-array and C-string
//! readers, an instance's FMI 3.0 variable table, and the typed values a
//! getter or setter moves (`Value`). Both interfaces import this; neither
//! imports the other's helpers.

use super::fmi3::{TIME_VR, variables3};
use super::instance::{Instance, Status};
use super::variables::Type;
use crate::results::LogCategory;
use fmi_sys::fmi2::*;
use std::collections::HashMap;
use std::ffi::{CStr, CString};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;
use std::sync::{Mutex, TryLockError};

/// What `fmi2Component` (and `fmi3Instance`) points to.
pub(super) struct Component {
    pub(super) instance: Mutex<Instance>,
    /// Strings handed out by fmi2GetString live until the next call.
    pub(super) strings: Mutex<Vec<CString>>,
    /// The FMI 3.0 variables (arrays of FMI 2.0 ones) of an instance made
    /// by fmi3InstantiateCoSimulation; None for FMI 2.0.
    pub(super) fmi3: Option<Variables3>,
}

pub(super) fn status(s: Status) -> fmi2Status {
    match s {
        Status::Ok => fmi2Status_fmi2OK,
        Status::Warning => fmi2Status_fmi2Warning,
        Status::Discard => fmi2Status_fmi2Discard,
        Status::Error => fmi2Status_fmi2Error,
    }
}

pub(super) fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// Runs `f` on the instance behind `c`: a NULL component is refused, a
/// panic is caught and marks the instance failed.
pub(super) fn with(
    c: fmi2Component,
    call: &str,
    f: impl FnOnce(&mut Instance, &Component) -> Status,
) -> fmi2Status {
    if c.is_null() {
        return fmi2Status_fmi2Error;
    }
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let comp = unsafe { &*(c as *const Component) };
        // Held already: a call from inside the master's logger while this
        // instance is logging (or a second thread on one instance, which
        // FMI forbids). Waiting would deadlock: refuse the call.
        let mut guard = match comp.instance.try_lock() {
            Ok(guard) => guard,
            Err(TryLockError::Poisoned(poisoned)) => poisoned.into_inner(),
            Err(TryLockError::WouldBlock) => return fmi2Status_fmi2Error,
        };
        let result = catch_unwind(AssertUnwindSafe(|| f(&mut guard, comp)));
        match result {
            Ok(s) => status(s),
            Err(p) => {
                guard.fail(&format!(
                    "{call}: internal error: {}; the instance is failed (reset it or restore a saved state)",
                    panic_text(&*p)
                ));
                fmi2Status_fmi2Error
            }
        }
    }));
    outcome.unwrap_or(fmi2Status_fmi2Error)
}

/// A slice from a C array; NULL with n > 0 is an error, n = 0 is empty.
pub(super) unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if p.is_null() {
        None
    } else {
        Some(unsafe { std::slice::from_raw_parts(p, n) })
    }
}

pub(super) unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if p.is_null() {
        None
    } else {
        Some(unsafe { std::slice::from_raw_parts_mut(p, n) })
    }
}

pub(super) fn null(inst: &mut Instance, call: &str, what: &str) -> Status {
    inst.log(
        crate::results::LogCategory::Error,
        &format!("{call}: {what} is NULL"),
    );
    Status::Error
}

pub(super) unsafe fn string(p: fmi2String) -> Option<String> {
    (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}

/// `file:///a/b%20c/resources` (or a plain path) to a path.
pub(super) fn resource_path(uri: &str) -> PathBuf {
    let rest = uri
        .strip_prefix("file://localhost")
        .or_else(|| uri.strip_prefix("file://"))
        .or_else(|| uri.strip_prefix("file:"))
        .unwrap_or(uri);
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        if bytes[i] == b'%'
            && i + 2 < bytes.len()
            && let (Some(h), Some(l)) = (hex(bytes[i + 1]), hex(bytes[i + 2]))
        {
            out.push((h * 16 + l) as u8);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    PathBuf::from(String::from_utf8_lossy(&out).into_owned())
}

pub(super) fn unsupported(c: fmi2Component, call: &str, why: &str) -> fmi2Status {
    with(c, call, |inst, _| {
        inst.log(
            crate::results::LogCategory::Error,
            &format!("{call} is not supported: {why}"),
        );
        Status::Error
    })
}

/// An instance's FMI 3.0 variables: per value reference, its type and the
/// FMI 2.0 value references of its elements (`time` has none).
pub(crate) struct Variables3 {
    pub(super) by_vr: HashMap<u32, (Type, Vec<u32>)>,
}

impl Variables3 {
    pub(super) fn of(inst: &Instance) -> Variables3 {
        let vars = inst.variables();
        let by_vr = variables3(vars)
            .into_iter()
            .map(|v| {
                let ty = v.members.first().map_or(Type::Real, |&i| vars[i].ty);
                let members = v.members.iter().map(|&i| vars[i].vr).collect();
                (v.vr, (ty, members))
            })
            .collect();
        Variables3 { by_vr }
    }

    /// The FMI 2.0 value references of `vrs`, in order, element by
    /// element (None for `time`), checked against `ty` and `n_values`.
    pub(super) fn expand(
        &self,
        inst: &mut Instance,
        call: &str,
        vrs: &[u32],
        ty: Type,
        n_values: usize,
    ) -> Result<Vec<Option<u32>>, Status> {
        let mut out = Vec::with_capacity(n_values);
        for &vr in vrs {
            match self.by_vr.get(&vr) {
                Some((t, _)) if *t != ty => {
                    return Err(error(
                        inst,
                        format!("{call}: valueReference {vr} is a {t:?} variable, not {ty:?}"),
                    ));
                }
                Some(_) if vr == TIME_VR => out.push(None),
                Some((_, members)) => out.extend(members.iter().map(|&m| Some(m))),
                None => {
                    return Err(error(
                        inst,
                        format!("{call}: no variable has valueReference {vr}"),
                    ));
                }
            }
        }
        if out.len() != n_values {
            return Err(error(
                inst,
                format!(
                    "{call}: nValues = {n_values}, but the {} value references hold {} values (an array counts its elements)",
                    vrs.len(),
                    out.len()
                ),
            ));
        }
        Ok(out)
    }
}

pub(super) fn error(inst: &mut Instance, msg: String) -> Status {
    inst.log(LogCategory::Error, &msg);
    Status::Error
}

/// A value type the getters and setters move (FMI 2.0 Real and Integer,
/// FMI 3.0 Float64 and Int32): its variables' type, the instance's getter
/// and setter for it, and its reading of `time` (FMI 3.0).
pub(super) trait Value: Copy + Default {
    const TYPE: Type;
    fn get(inst: &mut Instance, vrs: &[u32], out: &mut [Self]) -> Status;
    fn set(inst: &mut Instance, vrs: &[u32], values: &[Self]) -> Status;
    fn time(t: f64) -> Self;
}

/// `Value` for a type whose variables are `$ty`, moved by the instance's
/// `$get` and `$set`, reading `time` as `$time`.
macro_rules! value {
    ($t:ty, $ty:expr, $get:ident, $set:ident, $time:expr) => {
        impl Value for $t {
            const TYPE: Type = $ty;
            fn get(inst: &mut Instance, vrs: &[u32], out: &mut [$t]) -> Status {
                inst.$get(vrs, out)
            }
            fn set(inst: &mut Instance, vrs: &[u32], values: &[$t]) -> Status {
                inst.$set(vrs, values)
            }
            fn time(t: f64) -> $t {
                $time(t)
            }
        }
    };
}

value!(f64, Type::Real, get_real, set_real, |t| t);
value!(i32, Type::Integer, get_integer, set_integer, |_| 0);
