//! What the FMI 2.0 (`ffi`) and FMI 3.0 (`ffi3`) C interfaces share: the
//! component a C handle points to, the one guarded entry (`with`: NULL
//! check, lock, panic catch, status mapping), the C-array and C-string
//! readers, an instance's FMI 3.0 variable table, and the typed values a
//! getter or setter moves (`Value`). Both interfaces import this; neither
//! imports the other's helpers.

use super::fmi3::{TIME_VR, variables3};
use super::instance::{Instance, Status};
use super::variables::Type;
use super::worker::Worker;
use crate::results::LogCategory;
use fmi_sys::fmi2::*;
use std::collections::HashMap;
use std::ffi::{CStr, CString};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

/// What `fmi2Component` (and `fmi3Instance`) points to.
pub(super) struct Component {
    pub(super) instance: Mutex<Instance>,
    /// The thread inside a call on the instance (`thread_token`), 0 when
    /// none: a call from that thread's logger must not wait for itself.
    pub(super) owner: AtomicUsize,
    /// Strings handed out by fmi2GetString live until the next call.
    pub(super) strings: Mutex<Vec<CString>>,
    /// The FMI 3.0 variables (arrays of FMI 2.0 ones) of an instance made
    /// by fmi3InstantiateCoSimulation; None for FMI 2.0.
    pub(super) fmi3: Option<Variables3>,
    /// The thread the calls that solve run on (`with_solving`), started at
    /// the first; it ends when the component is dropped.
    worker: Mutex<Option<Worker>>,
    /// Lines for the logger that arose where logging could recurse (a call
    /// refused from inside the logger, a free of an instance in use): the
    /// call in progress logs them when its own work is done (`with`).
    deferred: Mutex<Vec<(LogCategory, String)>>,
    /// fmi2FreeInstance came while a call was in progress: that call frees
    /// the component when it returns.
    pub(super) free_when_done: AtomicBool,
}

impl Component {
    /// A new instance's component, to be handed out as its C handle.
    pub(super) fn boxed(instance: Instance, fmi3: Option<Variables3>) -> *mut Component {
        Box::into_raw(Box::new(Component {
            instance: Mutex::new(instance),
            owner: AtomicUsize::new(0),
            strings: Mutex::new(Vec::new()),
            fmi3,
            worker: Mutex::new(None),
            deferred: Mutex::new(Vec::new()),
            free_when_done: AtomicBool::new(false),
        }))
    }

    /// A line for the logger of the call in progress, logged when its work
    /// is done.
    pub(super) fn defer(&self, category: LogCategory, msg: String) {
        let mut lines = self.deferred.lock().unwrap_or_else(PoisonError::into_inner);
        lines.push((category, msg));
    }

    /// Logs the deferred lines. A line deferred while these are logged (the
    /// logger calling back in) waits for the next call's end: this never
    /// recurses.
    fn flush(&self, inst: &mut Instance) {
        let lines =
            std::mem::take(&mut *self.deferred.lock().unwrap_or_else(PoisonError::into_inner));
        for (category, msg) in lines {
            inst.log(category, &msg);
        }
    }
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
/// call from another thread waits until the call in progress ends (each
/// instance has one lock), a call back into the instance from inside the
/// logger of a call on the same thread is refused (waiting would deadlock;
/// its refusal is logged when the call in progress has done its work, as
/// logging it at once would call that logger again), a panic is caught and
/// marks the instance failed. A free that came during the call frees the
/// component when it returns.
pub(super) fn with(
    c: fmi2Component,
    call: &str,
    f: impl FnOnce(&mut Instance, &Component) -> Status,
) -> fmi2Status {
    if c.is_null() {
        return fmi2Status_fmi2Error;
    }
    let mut ran = false;
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let comp = unsafe { &*(c as *const Component) };
        let me = thread_token();
        if comp.owner.load(Ordering::SeqCst) == me {
            comp.defer(
                LogCategory::Error,
                format!(
                    "{call}: refused: called from inside the logger during another call on this instance (it would wait for itself)"
                ),
            );
            return fmi2Status_fmi2Error;
        }
        let mut guard = match comp.instance.lock() {
            Ok(guard) => guard,
            Err(poisoned) => return recover(comp, poisoned.into_inner(), call),
        };
        ran = true;
        comp.owner.store(me, Ordering::SeqCst);
        let result = catch_unwind(AssertUnwindSafe(|| f(&mut guard, comp)));
        let status = match result {
            Ok(s) => status(s),
            Err(p) => {
                guard.fail(&format!(
                    "{call}: internal error: {}; the instance is failed (reset it or restore a saved state)",
                    panic_text(&*p)
                ));
                fmi2Status_fmi2Error
            }
        };
        let _ = catch_unwind(AssertUnwindSafe(|| comp.flush(&mut guard)));
        comp.owner.store(0, Ordering::SeqCst);
        status
    }));
    // Only the call that held the instance frees it: a refused re-entry
    // returns to the call that does.
    let comp = unsafe { &*(c as *const Component) };
    if ran && comp.free_when_done.swap(false, Ordering::SeqCst) {
        drop(unsafe { Box::from_raw(c as *mut Component) });
    }
    outcome.unwrap_or(fmi2Status_fmi2Error)
}

/// `with` for a call that may solve: `f` runs on the instance's own thread
/// (`worker`), so that the solver's thread-locals never live on the
/// master's thread; on the calling thread should that thread not start.
pub(super) fn with_solving(
    c: fmi2Component,
    call: &str,
    f: impl FnOnce(&mut Instance, &Component) -> Status,
) -> fmi2Status {
    with(c, call, |inst, comp| {
        let mut worker = comp.worker.lock().unwrap_or_else(PoisonError::into_inner);
        // A forked child inherits the instance but not its thread.
        if !worker.as_ref().is_some_and(Worker::here) {
            *worker = Worker::start();
            if worker.is_none() {
                inst.log(
                    LogCategory::Warning,
                    &format!(
                        "{call}: no thread of the instance's own could start; the call runs on the calling thread (the library may then stay loaded after it is unloaded, for as long as that thread lives)"
                    ),
                );
            }
        }
        match worker.as_ref() {
            Some(worker) => worker.run(inst, |inst| f(inst, comp)),
            None => f(inst, comp),
        }
    })
}

/// A lock left poisoned by a panic that escaped a call while it held the
/// instance: the instance is marked failed with a logged error (as after
/// a caught panic), the lock cleared, and this call refused.
fn recover(comp: &Component, mut guard: MutexGuard<Instance>, call: &str) -> fmi2Status {
    comp.owner.store(0, Ordering::SeqCst);
    guard.fail(&format!(
        "{call}: refused: an earlier call on this instance ended in an internal error; the instance is failed (reset it or restore a saved state)"
    ));
    drop(guard);
    comp.instance.clear_poison();
    fmi2Status_fmi2Error
}

/// A number that tells the live threads apart (the address of a
/// thread-local), never 0: `Component::owner`'s value when no call holds
/// the instance.
pub(super) fn thread_token() -> usize {
    thread_local!(static TOKEN: u8 = const { 0 });
    TOKEN.with(|t| t as *const u8 as usize)
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

#[cfg(test)]
mod tests {
    use super::super::description::guid;
    use super::super::instance::Mode;
    use super::*;
    use std::sync::Arc;

    /// A lock poisoned by a panic that escaped a call (none is known to:
    /// `with` catches them, so the poison is made here) gives a logged
    /// error and a failed instance, never a panic; the calls after it are
    /// answered as after a caught panic.
    #[test]
    fn a_poisoned_lock_is_a_logged_error() {
        let scene =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/hertz_plane_strain.toml");
        let id = guid(&crate::scene::load(&scene).unwrap());
        let seen = Arc::new(Mutex::new(Vec::new()));
        let sink = Arc::clone(&seen);
        let log: super::super::instance::LogFn =
            Box::new(move |s, _, msg| sink.lock().unwrap().push((s, msg.to_string())));
        let inst = Instance::new("poisoned", &scene, &id, false, log).unwrap();
        let c = Component::boxed(inst, None);
        let comp = unsafe { &*c };
        let poisoner = std::thread::scope(|s| {
            s.spawn(|| {
                let _guard = comp.instance.lock().unwrap();
                panic!("a panic while holding the instance");
            })
            .join()
        });
        assert!(poisoner.is_err() && comp.instance.is_poisoned());
        let handle = c as fmi2Component;
        let called = with(handle, "fmi2GetReal", |_, _| Status::Ok);
        assert_eq!(called, fmi2Status_fmi2Error);
        {
            let seen = seen.lock().unwrap();
            assert_eq!(seen.len(), 1, "{seen:?}");
            assert_eq!(seen[0].0, Status::Error);
            assert!(seen[0].1.starts_with("fmi2GetReal: refused"), "{seen:?}");
        }
        let mode = std::cell::Cell::new(None);
        let called = with(handle, "fmi2GetReal", |inst, _| {
            mode.set(Some(inst.mode()));
            Status::Ok
        });
        assert_eq!(called, fmi2Status_fmi2OK);
        assert_eq!(mode.get(), Some(Mode::Error));
        drop(unsafe { Box::from_raw(c) });
    }
}
