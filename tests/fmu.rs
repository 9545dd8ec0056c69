//! The FMU's C interface, driven through the built shared library as a
//! master would load it (fmi-sys's libloading binding): instantiate,
//! initialize, step, get/set/serialize state, reset, free; the wrong GUID,
//! NULL and zero-length arguments, rejected inputs and parameters, a
//! discarded step and its retry, and instances on two threads.

mod common;

use contact2d::fmi::description::{guid, model_description};
use contact2d::fmi::variables::variables;
use contact2d::newton::Solver;
use fmi_sys::fmi2::*;
use std::collections::HashMap;
use std::ffi::{CStr, CString, c_char, c_void};
use std::path::{Path, PathBuf};
use std::ptr::{null, null_mut};
use std::sync::{Mutex, OnceLock};

const OK: fmi2Status = fmi2Status_fmi2OK;
const DISCARD: fmi2Status = fmi2Status_fmi2Discard;
const ERROR: fmi2Status = fmi2Status_fmi2Error;

/// The sliding block's `[steps]` line (scenes/verification/sliding_block.toml),
/// which the force-input tests replace.
const TIMES_LINE: &str = "times = [0.5, 1.0, 1.02, 1.04, 1.06, 1.08, 1.1, 1.12, 1.14, 1.16, 1.18, 1.2, 1.22, 1.24, 1.26, 1.28, 1.3, 1.5, 1.75, 2.0, 2.5, 3.0, 3.01, 3.02, 3.03, 3.04, 3.05, 3.06, 3.07, 3.08, 3.09, 3.1, 3.11, 3.12, 3.13, 3.14, 3.15, 3.16, 3.17, 3.18, 3.19, 3.2, 3.25, 3.5, 3.75, 4.0]";

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn library_path() -> PathBuf {
    contact2d::fmi::export::find_library(Path::new(env!("CARGO_BIN_EXE_contact2d")))
        .expect("libcontact2d.so built beside the binary or under deps/")
}

/// The library, loaded once per test process (as a master shares it
/// between its instances).
fn lib() -> &'static Fmi2Binding {
    static LIB: OnceLock<Fmi2Binding> = OnceLock::new();
    LIB.get_or_init(|| unsafe { Fmi2Binding::new(library_path()) }.expect("load libcontact2d.so"))
}

/// Messages the logger received, per instance (the environment pointer).
type Log = Mutex<Vec<(fmi2Status, String, String)>>;

/// The logger is variadic in C; the FMU always calls it with the format
/// "%s" and one string, so this receives that string as the sixth argument
/// (the x86-64 and AArch64 C conventions pass it in the same register).
unsafe extern "C" fn logger(
    env: fmi2ComponentEnvironment,
    _name: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    format: fmi2String,
    message: *const c_char,
) {
    let log = unsafe { &*(env as *const Log) };
    assert_eq!(unsafe { CStr::from_ptr(format) }, c"%s");
    let text = |p: *const c_char| unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned();
    log.lock()
        .unwrap()
        .push((status, text(category), text(message)));
}

/// A master's logger as Rust writes it (no variadic arguments: the FMU
/// passes its message as one `%s` argument).
type PlainLogger = unsafe extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    *const c_char,
);

/// Callbacks with `logger` as the FMI logger and `env` as its environment.
fn callbacks(logger: PlainLogger, env: *mut c_void) -> Box<fmi2CallbackFunctions> {
    Box::new(fmi2CallbackFunctions {
        logger: Some(unsafe {
            std::mem::transmute::<
                PlainLogger,
                unsafe extern "C" fn(
                    fmi2ComponentEnvironment,
                    fmi2String,
                    fmi2Status,
                    fmi2String,
                    fmi2String,
                    ...
                ),
            >(logger)
        }),
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: env,
    })
}

/// An FMU unpacked by hand: `resources/scene.toml` and the variables.
struct Unpacked {
    resources: CString,
    guid: CString,
    vr: HashMap<String, u32>,
    _dir: PathBuf,
}

fn unpack(scene: &Path, tag: &str) -> Unpacked {
    static COUNT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = COUNT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("contact2d-fmu-{}-{tag}-{n}", std::process::id()));
    let resources = dir.join("resources");
    std::fs::create_dir_all(&resources).unwrap();
    std::fs::copy(scene, resources.join("scene.toml")).unwrap();
    let problem = contact2d::scene::load(scene).unwrap();
    let vr = variables(&problem)
        .into_iter()
        .map(|v| (v.name, v.vr))
        .collect();
    Unpacked {
        resources: CString::new(format!("file://{}", resources.display())).unwrap(),
        guid: CString::new(guid(&problem)).unwrap(),
        vr,
        _dir: dir,
    }
}

/// One instance with its logger.
struct Inst {
    c: fmi2Component,
    log: Box<Log>,
    vr: HashMap<String, u32>,
    _callbacks: Box<fmi2CallbackFunctions>,
}

unsafe impl Send for Inst {}

impl Inst {
    fn new(u: &Unpacked, name: &str) -> Inst {
        Self::with_guid(u, name, &u.guid).expect("instantiate")
    }

    /// Instantiation that must fail: the logger's messages.
    fn new_or_messages(u: &Unpacked, name: &str) -> Vec<String> {
        match Self::with_guid(u, name, &u.guid) {
            Ok(_) => panic!("{name}: instantiated"),
            Err(messages) => messages,
        }
    }

    fn with_guid(u: &Unpacked, name: &str, guid: &CStr) -> Result<Inst, Vec<String>> {
        let log: Box<Log> = Box::default();
        let callbacks = callbacks(logger, &*log as *const Log as *mut c_void);
        let name = CString::new(name).unwrap();
        let c = unsafe {
            (lib().fmi2Instantiate.as_ref().unwrap())(
                name.as_ptr(),
                fmi2Type_fmi2CoSimulation,
                guid.as_ptr(),
                u.resources.as_ptr(),
                &*callbacks,
                0,
                0,
            )
        };
        if c.is_null() {
            return Err(log.lock().unwrap().iter().map(|m| m.2.clone()).collect());
        }
        Ok(Inst {
            c,
            log,
            vr: u.vr.clone(),
            _callbacks: callbacks,
        })
    }

    fn vr(&self, name: &str) -> u32 {
        *self
            .vr
            .get(name)
            .unwrap_or_else(|| panic!("no variable {name}"))
    }

    /// Setup and enter initialisation (both must succeed); the status of
    /// fmi2ExitInitializationMode.
    fn init_status(&self) -> fmi2Status {
        let l = lib();
        unsafe {
            assert_eq!(
                (l.fmi2SetupExperiment.as_ref().unwrap())(self.c, 0, 0.0, 0.0, 0, 0.0),
                OK
            );
            assert_eq!(
                (l.fmi2EnterInitializationMode.as_ref().unwrap())(self.c),
                OK
            );
            (l.fmi2ExitInitializationMode.as_ref().unwrap())(self.c)
        }
    }

    fn init(&self) {
        assert_eq!(self.init_status(), OK, "{:?}", self.messages());
    }

    fn set_real(&self, name: &str, v: f64) -> fmi2Status {
        let vr = [self.vr(name)];
        unsafe { (lib().fmi2SetReal.as_ref().unwrap())(self.c, vr.as_ptr(), 1, &v) }
    }

    fn set_int(&self, name: &str, v: i32) -> fmi2Status {
        let vr = [self.vr(name)];
        unsafe { (lib().fmi2SetInteger.as_ref().unwrap())(self.c, vr.as_ptr(), 1, &v) }
    }

    fn real(&self, name: &str) -> f64 {
        let vr = [self.vr(name)];
        let mut v = f64::NAN;
        let s = unsafe { (lib().fmi2GetReal.as_ref().unwrap())(self.c, vr.as_ptr(), 1, &mut v) };
        assert_eq!(s, OK, "get {name}");
        v
    }

    fn int(&self, name: &str) -> i32 {
        let vr = [self.vr(name)];
        let mut v = -1;
        let s = unsafe { (lib().fmi2GetInteger.as_ref().unwrap())(self.c, vr.as_ptr(), 1, &mut v) };
        assert_eq!(s, OK, "get {name}");
        v
    }

    fn step(&self, t: f64, h: f64) -> fmi2Status {
        unsafe { (lib().fmi2DoStep.as_ref().unwrap())(self.c, t, h, 1) }
    }

    /// Every output, as f64 (Integer outputs converted), in name order.
    fn outputs(&self) -> Vec<(String, f64)> {
        let mut names: Vec<&String> = self.vr.keys().collect();
        names.sort();
        let is_output = |n: &str| {
            [
                ".Rx",
                ".Ry",
                ".Mz",
                ".Fx",
                ".Fy",
                ".Fn",
                ".Ft",
                "n_stick",
                "n_slip",
                "n_open",
                "_length",
                "state[",
                ".tn[",
                ".tt[",
                ".x[",
                ".y[",
                ".gap[",
                ".slip[",
                "solver.iterations",
                "solver.substeps",
                "solver.residual",
            ]
            .iter()
            .any(|k| n.contains(k))
        };
        names
            .into_iter()
            .filter(|n| is_output(n))
            .map(|n| {
                let integer = n.contains("state[")
                    || n.contains("n_")
                    || n == "solver.iterations"
                    || n == "solver.substeps";
                let v = if integer {
                    f64::from(self.int(n))
                } else {
                    self.real(n)
                };
                (n.clone(), v)
            })
            .collect()
    }

    fn messages(&self) -> Vec<String> {
        self.log
            .lock()
            .unwrap()
            .iter()
            .map(|m| m.2.clone())
            .collect()
    }

    fn last_message(&self) -> String {
        self.messages().last().cloned().unwrap_or_default()
    }
}

impl Drop for Inst {
    fn drop(&mut self) {
        unsafe { (lib().fmi2FreeInstance.as_ref().unwrap())(self.c) };
    }
}

/// Every shipped scene file, sorted.
fn shipped_scenes() -> Vec<PathBuf> {
    let mut scenes = Vec::new();
    for dir in ["scenes", "scenes/verification"] {
        for e in std::fs::read_dir(repo().join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "toml") {
                scenes.push(p);
            }
        }
    }
    scenes.sort();
    scenes
}

fn hertz() -> Unpacked {
    unpack(&repo().join("scenes/hertz_plane_strain.toml"), "hertz")
}

/// Steps Hertz as its scene does: press.uy = -0.07 t, t = 0.25 ... 1.
fn step_hertz(inst: &Inst, from: usize, to: usize) {
    for k in from..to {
        let t = 0.25 * k as f64;
        assert_eq!(inst.set_real("press.uy", -0.07 * (t + 0.25)), OK);
        assert_eq!(inst.step(t, 0.25), OK, "{:?}", inst.messages());
    }
}

#[test]
fn exports_all_34_functions() {
    let library = unsafe { libloading::Library::new(library_path()) }.unwrap();
    let names = [
        "fmi2GetTypesPlatform",
        "fmi2GetVersion",
        "fmi2SetDebugLogging",
        "fmi2Instantiate",
        "fmi2FreeInstance",
        "fmi2SetupExperiment",
        "fmi2EnterInitializationMode",
        "fmi2ExitInitializationMode",
        "fmi2Terminate",
        "fmi2Reset",
        "fmi2GetReal",
        "fmi2GetInteger",
        "fmi2GetBoolean",
        "fmi2GetString",
        "fmi2SetReal",
        "fmi2SetInteger",
        "fmi2SetBoolean",
        "fmi2SetString",
        "fmi2GetFMUstate",
        "fmi2SetFMUstate",
        "fmi2FreeFMUstate",
        "fmi2SerializedFMUstateSize",
        "fmi2SerializeFMUstate",
        "fmi2DeSerializeFMUstate",
        "fmi2GetDirectionalDerivative",
        "fmi2SetRealInputDerivatives",
        "fmi2GetRealOutputDerivatives",
        "fmi2DoStep",
        "fmi2CancelStep",
        "fmi2GetStatus",
        "fmi2GetRealStatus",
        "fmi2GetIntegerStatus",
        "fmi2GetBooleanStatus",
        "fmi2GetStringStatus",
    ];
    assert_eq!(names.len(), 34);
    for n in names {
        let sym = unsafe { library.get::<*const c_void>(n.as_bytes()) };
        assert!(sym.is_ok(), "{n} not exported");
    }
    let platform = unsafe { CStr::from_ptr((lib().fmi2GetTypesPlatform.as_ref().unwrap())()) };
    assert_eq!(platform, c"default");
    let version = unsafe { CStr::from_ptr((lib().fmi2GetVersion.as_ref().unwrap())()) };
    assert_eq!(version, c"2.0");
}

/// The FMU's outputs after each step equal the solver's own run of the same
/// load path (the scene's ramp) to round-off: the FMU only maps variables.
#[test]
fn steps_match_the_solver() {
    let u = hertz();
    let inst = Inst::new(&u, "hertz");
    inst.init();
    // Before the first step: at rest, every node open at its position.
    assert_eq!(inst.real("contact.Fn"), 0.0);
    assert_eq!(
        inst.int("contact.n_open"),
        inst.vr
            .keys()
            .filter(|k| k.starts_with("contact.x["))
            .count() as i32
    );

    let mut solver = Solver::new(
        contact2d::scene::load(&repo().join("scenes/hertz_plane_strain.toml")).unwrap(),
    )
    .unwrap();
    for k in 0..4 {
        step_hertz(&inst, k, k + 1);
        let t = 0.25 * (k + 1) as f64;
        let step = solver.advance(t, &mut |_, _| {}).unwrap();
        let pair = &step.pairs[0].1;
        let press = &step.drivers[1].1;
        let close = |a: f64, b: f64, what: &str| {
            // The FMU reaches the input linearly from the converged value;
            // the scene's ramp gives the same numbers up to the last bits.
            assert!(
                (a - b).abs() <= 1e-9 * b.abs().max(1.0),
                "{what}: FMU {a} vs solver {b}"
            );
        };
        close(inst.real("contact.Fn"), pair.fn_, "Fn");
        close(inst.real("contact.Fx"), pair.fx, "Fx");
        close(inst.real("contact.Fy"), pair.fy, "Fy");
        close(inst.real("press.Ry"), press.ry, "press.Ry");
        close(inst.real("flat.Ry"), step.drivers[2].1.ry, "flat.Ry");
        assert_eq!(inst.int("contact.n_slip") as usize, pair.n_slip);
        assert_eq!(inst.int("contact.n_open") as usize, pair.n_open);
        // Frictionless: the zone in contact slides; a quarter model shows
        // half of Hertz's 2a.
        close(
            inst.real("contact.slip_length"),
            pair.slip_length,
            "slip_length",
        );
        assert_eq!(inst.real("contact.stick_length"), 0.0);
        assert!(pair.slip_length > 0.0);
        for (i, (&tn, &x)) in pair.nodes.tn.iter().zip(&pair.nodes.x).enumerate() {
            close(inst.real(&format!("contact.tn[{}]", i + 1)), tn, "tn");
            close(inst.real(&format!("contact.x[{}]", i + 1)), x, "x");
            // Gap and slip: lengths of the order of the displacements.
            let gap = inst.real(&format!("contact.gap[{}]", i + 1));
            assert!((gap - pair.nodes.gap[i]).abs() <= 1e-12, "gap {gap}");
            let slip = inst.real(&format!("contact.slip[{}]", i + 1));
            assert!((slip - pair.nodes.slip[i]).abs() <= 1e-12, "slip {slip}");
            // In contact: on the target; open: clear of it.
            if pair.nodes.state[i] == contact2d::results::NodeState::Open {
                assert!(gap > 0.0, "open node {i} with gap {gap}");
            } else {
                assert!(gap.abs() < 1e-9, "node {i} in contact with gap {gap}");
            }
            assert_eq!(
                inst.int(&format!("contact.state[{}]", i + 1)),
                i32::from(pair.nodes.state[i])
            );
        }
        assert_eq!(inst.int("solver.iterations") as usize, step.iterations);
    }
    // The quarter model carries P/2; the scene is set to reach P of about
    // 6600 (the paper's maximum) within 2 %.
    let half = inst.real("contact.Fn");
    assert!((half - 3300.0).abs() < 0.02 * 3300.0, "P/2 = {half}");
    let mut t = f64::NAN;
    let s = unsafe {
        (lib().fmi2GetRealStatus.as_ref().unwrap())(
            inst.c,
            fmi2StatusKind_fmi2LastSuccessfulTime,
            &mut t,
        )
    };
    assert_eq!((s, t), (OK, 1.0));
    unsafe { assert_eq!((lib().fmi2Terminate.as_ref().unwrap())(inst.c), OK) };
}

/// Get a state, step, set it back, step again: identical outputs, bit for
/// bit; the same through serialization into a second instance.
#[test]
fn saved_state_continues_bit_for_bit() {
    let u = hertz();
    let l = lib();
    let a = Inst::new(&u, "a");
    a.init();
    step_hertz(&a, 0, 2);
    let mut state: fmi2FMUstate = null_mut();
    unsafe { assert_eq!((l.fmi2GetFMUstate.as_ref().unwrap())(a.c, &mut state), OK) };
    step_hertz(&a, 2, 4);
    let first = a.outputs();
    unsafe { assert_eq!((l.fmi2SetFMUstate.as_ref().unwrap())(a.c, state), OK) };
    assert_eq!(a.real("press.Ry"), {
        // Outputs are those of the saved time again.
        let b = Inst::new(&u, "check");
        b.init();
        step_hertz(&b, 0, 2);
        b.real("press.Ry")
    });
    step_hertz(&a, 2, 4);
    let again = a.outputs();
    assert_eq!(first.len(), again.len());
    for ((n, x), (_, y)) in first.iter().zip(&again) {
        assert_eq!(x.to_bits(), y.to_bits(), "{n}: {x} then {y}");
    }

    // Serialize, deserialize into a fresh instance, continue there.
    let mut size = 0usize;
    unsafe {
        assert_eq!(
            (l.fmi2SerializedFMUstateSize.as_ref().unwrap())(a.c, state, &mut size),
            OK
        )
    };
    let mut bytes = vec![0 as c_char; size];
    unsafe {
        assert_eq!(
            (l.fmi2SerializeFMUstate.as_ref().unwrap())(a.c, state, bytes.as_mut_ptr(), size),
            OK
        );
        // Too small a buffer is refused.
        assert_eq!(
            (l.fmi2SerializeFMUstate.as_ref().unwrap())(a.c, state, bytes.as_mut_ptr(), size - 1),
            ERROR
        );
    }
    let b = Inst::new(&u, "b");
    b.init();
    let mut restored: fmi2FMUstate = null_mut();
    unsafe {
        assert_eq!(
            (l.fmi2DeSerializeFMUstate.as_ref().unwrap())(b.c, bytes.as_ptr(), size, &mut restored),
            OK
        );
        assert_eq!((l.fmi2SetFMUstate.as_ref().unwrap())(b.c, restored), OK);
    }
    step_hertz(&b, 2, 4);
    for ((n, x), (_, y)) in first.iter().zip(&b.outputs()) {
        assert_eq!(
            x.to_bits(),
            y.to_bits(),
            "{n} after deserialization: {x} vs {y}"
        );
    }
    // Damaged bytes are refused with a message.
    let mut bad: fmi2FMUstate = null_mut();
    unsafe {
        assert_eq!(
            (l.fmi2DeSerializeFMUstate.as_ref().unwrap())(b.c, bytes.as_ptr(), size / 2, &mut bad),
            ERROR
        );
    }
    assert!(b.last_message().contains("damaged"), "{}", b.last_message());
    unsafe {
        assert_eq!((l.fmi2FreeFMUstate.as_ref().unwrap())(a.c, &mut state), OK);
        assert_eq!(
            (l.fmi2FreeFMUstate.as_ref().unwrap())(b.c, &mut restored),
            OK
        );
    }
    assert!(state.is_null() && restored.is_null());
}

/// A step that cannot converge without bisection returns Discard, keeps the
/// last converged state, and the same jump in four steps then succeeds.
#[test]
fn discarded_step_keeps_the_state_and_a_retry_succeeds() {
    let u = unpack(&repo().join("tests/data/scenes/tl_shear.toml"), "tl");
    let l = lib();
    let inst = Inst::new(&u, "tl");
    unsafe {
        assert_eq!(
            (l.fmi2EnterInitializationMode.as_ref().unwrap())(inst.c),
            OK
        );
    }
    assert_eq!(inst.set_int("solver.max_substeps", 0), OK);
    unsafe {
        assert_eq!((l.fmi2ExitInitializationMode.as_ref().unwrap())(inst.c), OK);
    }
    let mut saved: fmi2FMUstate = null_mut();
    unsafe {
        assert_eq!(
            (l.fmi2GetFMUstate.as_ref().unwrap())(inst.c, &mut saved),
            OK
        )
    };
    assert_eq!(inst.set_real("top.ux", 0.5), OK);
    assert_eq!(inst.set_real("top.uy", -0.3), OK);
    assert_eq!(inst.step(0.0, 1.0), DISCARD);
    assert!(
        inst.messages().iter().any(|m| m.contains("discarded")),
        "{:?}",
        inst.messages()
    );
    let mut t = f64::NAN;
    unsafe {
        (l.fmi2GetRealStatus.as_ref().unwrap())(
            inst.c,
            fmi2StatusKind_fmi2LastSuccessfulTime,
            &mut t,
        )
    };
    assert_eq!(t, 0.0);
    assert_eq!(
        inst.real("top.Rx"),
        0.0,
        "outputs stay at the last converged time"
    );
    // Roll back (a master's usual move) and retry in four steps.
    unsafe { assert_eq!((l.fmi2SetFMUstate.as_ref().unwrap())(inst.c, saved), OK) };
    for k in 0..4 {
        let s = (k + 1) as f64 / 4.0;
        inst.set_real("top.ux", 0.5 * s);
        inst.set_real("top.uy", -0.3 * s);
        assert_eq!(
            inst.step(k as f64 * 0.25, 0.25),
            OK,
            "{:?}",
            inst.messages()
        );
        assert!(inst.int("solver.iterations") <= 6);
    }
    // The same end state as the solver's own four increments.
    let mut problem =
        contact2d::scene::load(&repo().join("tests/data/scenes/tl_shear.toml")).unwrap();
    problem.solver.max_bisections = 0;
    let mut solver = Solver::new(problem).unwrap();
    let mut last = None;
    for k in 1..=4 {
        last = Some(solver.advance(k as f64 * 0.25, &mut |_, _| {}).unwrap());
    }
    let top = &last.unwrap().drivers[1].1;
    for (name, want) in [("top.Rx", top.rx), ("top.Ry", top.ry)] {
        let got = inst.real(name);
        assert!(
            (got - want).abs() <= 1e-9 * want.abs(),
            "{name}: FMU {got} vs solver {want}"
        );
    }
    unsafe { (l.fmi2FreeFMUstate.as_ref().unwrap())(inst.c, &mut saved) };
}

#[test]
fn bad_inputs_and_parameters_are_rejected_by_name() {
    let u = hertz();
    let l = lib();
    let inst = Inst::new(&u, "bad");
    unsafe {
        assert_eq!(
            (l.fmi2EnterInitializationMode.as_ref().unwrap())(inst.c),
            OK
        )
    };
    for (name, value, expect) in [
        ("steel.E", -1.0, "steel.E = -1.0 rejected: Young's modulus"),
        ("steel.E", 0.0, "steel.E = 0.0 rejected"),
        (
            "steel.nu",
            0.5,
            "steel.nu = 0.5 rejected: Poisson's ratio must satisfy -1 < nu < 0.5 in plane strain",
        ),
        (
            "steel.nu",
            f64::NAN,
            "steel.nu = NaN rejected: not a finite number",
        ),
        ("contact.mu_s", -0.1, "contact.mu_s = -0.1 rejected"),
        ("solver.tolerance", 2.0, "solver.tolerance = 2.0 rejected"),
    ] {
        assert_eq!(inst.set_real(name, value), ERROR, "{name} = {value}");
        assert!(
            inst.last_message().contains(expect),
            "{}",
            inst.last_message()
        );
    }
    assert_eq!(inst.set_int("solver.max_iterations", 0), ERROR);
    assert!(inst.last_message().contains("solver.max_iterations = 0"));
    // mu_d > mu_s is a relation: checked when initialization ends.
    assert_eq!(inst.set_real("contact.mu_d", 0.2), OK);
    unsafe {
        assert_eq!(
            (l.fmi2ExitInitializationMode.as_ref().unwrap())(inst.c),
            ERROR
        )
    };
    assert!(
        inst.last_message()
            .contains("contact.mu_d = 0.2: mu_d must not exceed mu_s = 0.0"),
        "{}",
        inst.last_message()
    );
    assert_eq!(inst.set_real("contact.mu_d", 0.0), OK);
    unsafe { assert_eq!((l.fmi2ExitInitializationMode.as_ref().unwrap())(inst.c), OK) };
    // Fixed parameters are refused after initialization; inputs must be
    // finite; outputs cannot be set.
    assert_eq!(inst.set_real("steel.E", 1.0), ERROR);
    assert!(
        inst.last_message()
            .contains("cannot be set in mode StepComplete")
    );
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(inst.set_real("press.uy", bad), ERROR);
        assert!(
            inst.last_message().contains("press.uy"),
            "{}",
            inst.last_message()
        );
    }
    assert_eq!(inst.set_real("contact.Fn", 1.0), ERROR);
    // A type mismatch and an unknown reference.
    let vr = [inst.vr("contact.n_slip")];
    let mut x = 0.0;
    unsafe {
        assert_eq!(
            (l.fmi2GetReal.as_ref().unwrap())(inst.c, vr.as_ptr(), 1, &mut x),
            ERROR
        );
        assert_eq!(
            (l.fmi2GetReal.as_ref().unwrap())(inst.c, [99_999].as_ptr(), 1, &mut x),
            ERROR
        );
    }
    assert!(inst.last_message().contains("99999"));
    // The instance still works.
    step_hertz(&inst, 0, 1);
    assert!(inst.real("contact.Fn") > 0.0);
    // Wrong state: a step before the current time, initialization again.
    assert_eq!(inst.step(0.0, 0.25), ERROR);
    assert!(inst.last_message().contains("but the FMU is at t = 0.25"));
    unsafe {
        assert_eq!(
            (l.fmi2EnterInitializationMode.as_ref().unwrap())(inst.c),
            ERROR
        )
    };
    assert!(
        inst.last_message()
            .contains("not allowed in mode StepComplete")
    );
}

/// An input that makes an output non-finite (issue 35, item 4): the rubber
/// sheet's wall moved to y = DBL_MAX converged with 41 gaps of +inf and
/// fmi2OK. The step is discarded with a message naming the input, the
/// state and outputs stay at the last converged step, and a sensible input
/// steps on from there. A non-finite value is refused when it is set.
#[test]
fn an_input_that_makes_an_output_non_finite_discards_the_step() {
    let u = unpack(&repo().join("scenes/rubber_sheet.toml"), "rubber");
    let inst = Inst::new(&u, "rubber");
    inst.init();
    let before = inst.outputs();
    assert!(before.iter().all(|(_, v)| v.is_finite()));
    for bad in [f64::INFINITY, f64::NAN] {
        assert_eq!(inst.set_real("wall.uy", bad), ERROR);
        assert!(
            inst.last_message().contains("wall.uy"),
            "{}",
            inst.last_message()
        );
    }
    assert_eq!(inst.set_real("wall.uy", f64::MAX), OK);
    assert_eq!(inst.step(0.0, 0.5), DISCARD, "{:?}", inst.messages());
    let msg = inst.last_message();
    assert!(
        msg.contains("not finite") && msg.contains("wall.uy = 1.7976931348623157e308"),
        "{msg}"
    );
    let mut t = f64::NAN;
    unsafe {
        (lib().fmi2GetRealStatus.as_ref().unwrap())(
            inst.c,
            fmi2StatusKind_fmi2LastSuccessfulTime,
            &mut t,
        )
    };
    assert_eq!(t, 0.0);
    assert_eq!(
        inst.outputs(),
        before,
        "outputs stay at the last converged step"
    );
    assert_eq!(inst.set_real("wall.uy", 0.0), OK);
    assert_eq!(inst.set_real("push.ux", -50.0 * 0.5 / 16.0), OK);
    assert_eq!(inst.step(0.0, 0.5), OK, "{:?}", inst.messages());
    assert!(inst.outputs().iter().all(|(_, v)| v.is_finite()));
    assert!(inst.real("channel.Fn") > 0.0);
}

/// Absurd solver settings (issue 35, item 5): `solver.tolerance = 5e-324`
/// was taken and the step then Discarded after 14 s. Values outside the
/// ranges (`contact2d::problem::SolverSettings`) are refused by the setter,
/// at initialization and between steps, with the value and the range; the
/// ends of each range are accepted.
#[test]
fn absurd_solver_settings_are_refused_with_their_range() {
    let u = hertz();
    let l = lib();
    let inst = Inst::new(&u, "settings");
    let tolerance = "must lie in [1e-14, 0.1]";
    let refuse_real = |value: f64| {
        assert_eq!(inst.set_real("solver.tolerance", value), ERROR, "{value:?}");
        let msg = inst.last_message();
        assert!(
            msg.contains(&format!("solver.tolerance = {value:?} rejected"))
                && msg.contains(tolerance),
            "{msg}"
        );
    };
    let refuse_int = |name: &str, value: i32, range: &str| {
        assert_eq!(inst.set_int(name, value), ERROR, "{name} = {value}");
        let msg = inst.last_message();
        assert!(
            msg.contains(&format!("{name} = {value} rejected: must lie in {range}")),
            "{msg}"
        );
    };
    let refuse_all = || {
        for value in [5e-324, 0.0, -1e-8, 1e-15, 0.5, 1e300] {
            refuse_real(value);
        }
        assert_eq!(inst.set_real("solver.tolerance", f64::NAN), ERROR);
        for value in [0, -1, 1001, i32::MAX] {
            refuse_int("solver.max_iterations", value, "[1, 1000]");
        }
        for value in [-1, 65, i32::MAX] {
            refuse_int("solver.max_substeps", value, "[0, 64]");
        }
    };
    refuse_all();
    unsafe {
        assert_eq!(
            (l.fmi2EnterInitializationMode.as_ref().unwrap())(inst.c),
            OK
        );
    }
    for value in [1e-14, 0.1] {
        assert_eq!(inst.set_real("solver.tolerance", value), OK, "{value}");
    }
    assert_eq!(inst.set_int("solver.max_iterations", 1000), OK);
    assert_eq!(inst.set_int("solver.max_substeps", 64), OK);
    assert_eq!(inst.set_real("solver.tolerance", 1e-8), OK);
    unsafe {
        assert_eq!((l.fmi2ExitInitializationMode.as_ref().unwrap())(inst.c), OK);
    }
    // Tunable between steps: the same ranges, the settings kept.
    refuse_all();
    step_hertz(&inst, 0, 1);
    assert!(inst.real("contact.Fn") > 0.0);
}

/// fmi2GetReal of an Integer variable (cofmpy reads every output as Real;
/// issue 35, item 10) is refused with a message naming the variable, its
/// value reference and its type, also within a list of Real ones, and the
/// values of the call are left as they were after the refused one.
#[test]
fn get_real_of_an_integer_variable_names_it_and_its_type() {
    let u = hertz();
    let inst = Inst::new(&u, "types");
    inst.init();
    step_hertz(&inst, 0, 1);
    for name in [
        "contact.n_stick",
        "contact.state[1]",
        "solver.max_iterations",
    ] {
        let vr = [inst.vr("contact.Fn"), inst.vr(name)];
        let mut out = [f64::NAN; 2];
        let status = unsafe {
            (lib().fmi2GetReal.as_ref().unwrap())(inst.c, vr.as_ptr(), 2, out.as_mut_ptr())
        };
        assert_eq!(status, ERROR, "{name}");
        assert_eq!(
            inst.last_message(),
            format!(
                "fmi2GetReal: variable '{name}' (valueReference {}) is Integer, not Real",
                vr[1]
            )
        );
        assert!(out[1].is_nan(), "{name}: {out:?}");
    }
    // fmi2GetInteger reads them: Hertz after its first step has nodes in
    // (frictionless, sliding) contact.
    assert!(inst.int("contact.n_stick") + inst.int("contact.n_slip") > 0);
}

#[test]
fn null_and_zero_length_arguments() {
    let u = hertz();
    let l = lib();
    unsafe {
        // A NULL component is refused by every function.
        assert_eq!(
            (l.fmi2DoStep.as_ref().unwrap())(null_mut(), 0.0, 1.0, 0),
            ERROR
        );
        assert_eq!((l.fmi2Reset.as_ref().unwrap())(null_mut()), ERROR);
        assert_eq!(
            (l.fmi2GetReal.as_ref().unwrap())(null_mut(), null(), 0, null_mut()),
            ERROR
        );
        (l.fmi2FreeInstance.as_ref().unwrap())(null_mut());
    }
    let inst = Inst::new(&u, "null");
    inst.init();
    unsafe {
        // Zero-length arrays may be NULL.
        assert_eq!(
            (l.fmi2GetReal.as_ref().unwrap())(inst.c, null(), 0, null_mut()),
            OK
        );
        assert_eq!(
            (l.fmi2SetReal.as_ref().unwrap())(inst.c, null(), 0, null()),
            OK
        );
        assert_eq!(
            (l.fmi2GetBoolean.as_ref().unwrap())(inst.c, null(), 0, null_mut()),
            OK
        );
        // NULL arrays with a length are not.
        assert_eq!(
            (l.fmi2GetReal.as_ref().unwrap())(inst.c, null(), 3, null_mut()),
            ERROR
        );
        assert!(inst.last_message().contains("NULL"));
        assert_eq!(
            (l.fmi2SetString.as_ref().unwrap())(inst.c, null(), 1, null()),
            ERROR
        );
        let mut s: fmi2FMUstate = null_mut();
        assert_eq!(
            (l.fmi2GetFMUstate.as_ref().unwrap())(inst.c, null_mut()),
            ERROR
        );
        assert_eq!((l.fmi2SetFMUstate.as_ref().unwrap())(inst.c, s), ERROR);
        assert_eq!((l.fmi2FreeFMUstate.as_ref().unwrap())(inst.c, &mut s), OK);
        // Unsupported functions say so.
        assert_eq!((l.fmi2CancelStep.as_ref().unwrap())(inst.c), ERROR);
        assert!(inst.last_message().contains("not supported"));
        let mut st = OK;
        assert_eq!(
            (l.fmi2GetStatus.as_ref().unwrap())(inst.c, fmi2StatusKind_fmi2DoStepStatus, &mut st),
            DISCARD
        );
    }
    // Instantiation failures return NULL and say why.
    let wrong = Inst::with_guid(&u, "wrong", c"{00000000-0000-0000-0000-000000000000}");
    let msgs = wrong.err().expect("wrong GUID refused");
    assert!(
        msgs.iter().any(|m| m.contains("does not match")),
        "{msgs:?}"
    );
    let missing = Unpacked {
        resources: c"file:///nonexistent/resources".into(),
        guid: u.guid.clone(),
        vr: HashMap::new(),
        _dir: PathBuf::new(),
    };
    let msgs = Inst::with_guid(&missing, "missing", &u.guid)
        .err()
        .expect("no scene");
    assert!(
        msgs.iter()
            .any(|m| m.contains("/nonexistent/resources/scene.toml") && m.contains("cannot read")),
        "{msgs:?}"
    );
    let c = unsafe {
        (lib().fmi2Instantiate.as_ref().unwrap())(
            null(),
            fmi2Type_fmi2CoSimulation,
            u.guid.as_ptr(),
            u.resources.as_ptr(),
            null(),
            0,
            0,
        )
    };
    assert!(
        c.is_null(),
        "a NULL instance name (and no callbacks) is refused"
    );
    let c = unsafe {
        (lib().fmi2Instantiate.as_ref().unwrap())(
            c"me".as_ptr(),
            fmi2Type_fmi2ModelExchange,
            u.guid.as_ptr(),
            u.resources.as_ptr(),
            null(),
            0,
            0,
        )
    };
    assert!(c.is_null(), "model exchange is refused");
}

/// Reset returns to the start values; the same steps give the same outputs.
#[test]
fn reset_starts_again() {
    let u = hertz();
    let inst = Inst::new(&u, "reset");
    inst.init();
    step_hertz(&inst, 0, 2);
    let first = inst.outputs();
    unsafe { assert_eq!((lib().fmi2Reset.as_ref().unwrap())(inst.c), OK) };
    assert_eq!(inst.real("press.uy"), 0.0);
    assert_eq!(inst.real("contact.Fn"), 0.0);
    inst.init();
    step_hertz(&inst, 0, 2);
    for ((n, x), (_, y)) in first.iter().zip(&inst.outputs()) {
        assert_eq!(x.to_bits(), y.to_bits(), "{n}");
    }
}

/// Instances on two threads at once, each its own state, the results those
/// of one instance alone.
#[test]
fn instances_on_two_threads() {
    let u = hertz();
    let alone = Inst::new(&u, "alone");
    alone.init();
    step_hertz(&alone, 0, 4);
    let expect = alone.outputs();
    let runs: Vec<Vec<(String, f64)>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..2)
            .map(|i| {
                let u = &u;
                s.spawn(move || {
                    let inst = Inst::new(u, &format!("thread{i}"));
                    inst.init();
                    step_hertz(&inst, 0, 4);
                    inst.outputs()
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for run in runs {
        assert_eq!(run, expect);
    }
}

/// Two threads on one instance (issue 35, item 1): while one thread steps
/// Hertz, another reads outputs of the same instance; each read waits its
/// turn and returns fmi2OK with finite values (it was refused at once, with
/// no log line, while a step held the instance).
#[test]
fn a_second_thread_on_one_instance_waits_its_turn() {
    let u = hertz();
    let inst = Inst::new(&u, "shared");
    inst.init();
    let vrs = [
        inst.vr("contact.Fn"),
        inst.vr("press.Ry"),
        inst.vr("contact.gap[1]"),
    ];
    let addr = inst.c as usize;
    let stepping = std::sync::atomic::AtomicBool::new(true);
    let reads: Vec<(fmi2Status, [f64; 3])> = std::thread::scope(|s| {
        let reader = s.spawn(|| {
            let c = addr as fmi2Component;
            let mut reads = Vec::new();
            while stepping.load(std::sync::atomic::Ordering::SeqCst) {
                let mut v = [f64::NAN; 3];
                let status = unsafe {
                    (lib().fmi2GetReal.as_ref().unwrap())(c, vrs.as_ptr(), 3, v.as_mut_ptr())
                };
                reads.push((status, v));
            }
            reads
        });
        // A failed step must still stop the reader (or the scope waits).
        let stepped =
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| step_hertz(&inst, 0, 4)));
        stepping.store(false, std::sync::atomic::Ordering::SeqCst);
        let reads = reader.join().unwrap();
        if let Err(p) = stepped {
            std::panic::resume_unwind(p);
        }
        reads
    });
    assert!(!reads.is_empty());
    let refused = reads.iter().filter(|r| r.0 != OK).count();
    assert_eq!(refused, 0, "{refused} of {} reads refused", reads.len());
    assert!(
        reads.iter().all(|r| r.1.iter().all(|v| v.is_finite())),
        "a read gave a value that is not finite"
    );
    assert!(inst.messages().is_empty(), "{:?}", inst.messages());
}

/// Newton and contact lines reach the logger only when their category is on.
#[test]
fn log_categories() {
    let u = hertz();
    let l = lib();
    let inst = Inst::new(&u, "log");
    inst.init();
    step_hertz(&inst, 0, 1);
    assert!(inst.log.lock().unwrap().is_empty(), "logging off: nothing");
    let cats = [c"logNewton".as_ptr()];
    unsafe {
        assert_eq!(
            (l.fmi2SetDebugLogging.as_ref().unwrap())(inst.c, 1, 1, cats.as_ptr()),
            OK
        )
    };
    step_hertz(&inst, 1, 2);
    let log = inst.log.lock().unwrap().clone();
    assert!(
        log.iter()
            .any(|m| m.1 == "logNewton" && m.2.contains("|r|/F"))
    );
    assert!(log.iter().all(|m| m.1 != "logContact"));
    let unknown = [c"logEverything".as_ptr()];
    unsafe {
        assert_eq!(
            (l.fmi2SetDebugLogging.as_ref().unwrap())(inst.c, 1, 1, unknown.as_ptr()),
            ERROR
        )
    };
    assert!(inst.last_message().contains("logEverything"));
}

/// `modelDescription/` holds what `export` writes for each shipped scene.
#[test]
fn committed_model_descriptions_are_current() {
    let scenes = shipped_scenes();
    let bless = std::env::var_os("CONTACT2D_BLESS").is_some();
    let mut stale = Vec::new();
    for scene in &scenes {
        let stem = scene.file_stem().unwrap().to_string_lossy().into_owned();
        let xml = model_description(&contact2d::scene::load(scene).unwrap());
        let path = repo().join("modelDescription").join(format!("{stem}.xml"));
        if bless {
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(&path, &xml).unwrap();
        } else if std::fs::read_to_string(&path).ok().as_deref() != Some(xml.as_str()) {
            stale.push(path.display().to_string());
        }
    }
    assert!(
        stale.is_empty(),
        "out of date (regenerate with CONTACT2D_BLESS=1 cargo test --release --test fmu committed): {stale:?}"
    );
}

/// `<DefaultExperiment stepSize>` is the increment a scene takes most often
/// (issue 35, item 10), not its first: the sliding block's first increment
/// is 0.5, then it steps by 0.02 and 0.01 (0.01 twenty times); the
/// Cattaneo-Mindlin scene's 0.25 four times, then 0.125 eight times; the
/// inclined block's 0.0002 twenty-five times; Hertz's dt = 0.25 throughout.
#[test]
fn default_experiment_step_is_the_usual_increment() {
    for (scene, stop, step) in [
        ("scenes/verification/sliding_block.toml", "4.0", "0.01"),
        ("scenes/verification/cattaneo_mindlin.toml", "2.0", "0.125"),
        ("scenes/verification/cgs4_inclined.toml", "1.415", "0.0002"),
        ("scenes/hertz_plane_strain.toml", "1.0", "0.25"),
    ] {
        let xml = model_description(&contact2d::scene::load(&repo().join(scene)).unwrap());
        let experiment =
            format!(r#"<DefaultExperiment startTime="0.0" stopTime="{stop}" stepSize="{step}"/>"#);
        assert!(
            xml.contains(&experiment),
            "{scene}: {:?}",
            xml.lines().find(|l| l.contains("DefaultExperiment"))
        );
    }
}

/// A name of FMI 2.0's structured naming convention as the descriptions
/// use it: identifiers (a letter or '_', then letters, digits or '_')
/// joined by '.', each optionally indexed by `[n]`, n >= 1.
fn structured_name(name: &str) -> bool {
    name.split('.').all(|part| {
        let (id, index) = match part.split_once('[') {
            Some((id, rest)) => (id, Some(rest)),
            None => (part, None),
        };
        let mut chars = id.chars();
        let id_ok = chars
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && chars.all(|c| c.is_ascii_alphanumeric() || c == '_');
        let index_ok = index.is_none_or(|r| {
            r.strip_suffix(']')
                .and_then(|n| n.parse::<u32>().ok())
                .is_some_and(|n| n >= 1)
        });
        id_ok && index_ok
    })
}

/// Every shipped scene's variables have structured names, unique; every
/// output is in <Outputs> depending on every input ("dependent": an input's
/// value is its value at the end of the step, and the outputs there are
/// functions of it); providesDirectionalDerivative is true where every pair
/// decides nodally.
#[test]
fn model_structure_and_names() {
    use contact2d::fmi::variables::Causality;
    assert!(structured_name("press.Rx") && structured_name("contact.tn[12]"));
    for bad in ["press-1.Rx", "2a.b", "a..b", "a.tn[0]", "a.tn[x]", "a b"] {
        assert!(!structured_name(bad), "{bad}");
    }
    for scene in shipped_scenes() {
        let problem = contact2d::scene::load(&scene).unwrap();
        let vars = variables(&problem);
        let mut names: Vec<&str> = vars.iter().map(|v| v.name.as_str()).collect();
        for n in &names {
            assert!(structured_name(n), "{}: {n}", scene.display());
        }
        names.sort();
        names.dedup();
        assert_eq!(names.len(), vars.len(), "{}: names unique", scene.display());
        let xml = model_description(&problem);
        let outputs = xml
            .split("<Outputs>")
            .nth(1)
            .and_then(|rest| rest.split("</Outputs>").next())
            .unwrap();
        let indices = |c: Causality| {
            (vars.iter().enumerate())
                .filter(|(_, v)| v.causality == c)
                .map(|(i, _)| (i + 1).to_string())
                .collect::<Vec<_>>()
        };
        let (inputs, listed) = (indices(Causality::Input), indices(Causality::Output));
        assert!(!inputs.is_empty(), "{}", scene.display());
        // No direct feedthrough: every output with no dependency.
        let expected: String = listed
            .iter()
            .map(|i| format!("\n      <Unknown index=\"{i}\" dependencies=\"\"/>"))
            .collect();
        assert_eq!(outputs, format!("{expected}\n    "), "{}", scene.display());
        let nodal =
            (problem.contacts.iter()).all(|c| c.decisions == contact2d::problem::Decisions::Nodal);
        assert!(xml.contains(&format!("providesDirectionalDerivative=\"{nodal}\"")));
        assert_eq!(
            nodal,
            !scene.ends_with("cattaneo_mindlin.toml"),
            "{}",
            scene.display()
        );
    }
}

/// `contact2d export` writes the committed description, the library and
/// the scene. (It names the native library: the default, the portable
/// one, is tested in tests/python/test_portable_library.py, and building
/// it here would put a zig build inside `cargo test`.)
#[test]
fn export_writes_the_fmu() {
    let out = std::env::temp_dir().join(format!("contact2d-export-{}.fmu", std::process::id()));
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_contact2d"))
        .args(["export", "scenes/hertz_plane_strain.toml", "-o"])
        .arg(&out)
        .arg("--library")
        .arg(library_path())
        .current_dir(repo())
        .status()
        .unwrap();
    assert!(status.success());
    let mut zip = zip::ZipArchive::new(std::fs::File::open(&out).unwrap()).unwrap();
    let mut names: Vec<String> = zip.file_names().map(|n| n.unwrap().into_owned()).collect();
    names.sort();
    assert_eq!(
        names,
        [
            "binaries/linux64/contact2d.so",
            "modelDescription.xml",
            "resources/scene.toml"
        ]
    );
    let mut xml = String::new();
    std::io::Read::read_to_string(&mut zip.by_name("modelDescription.xml").unwrap(), &mut xml)
        .unwrap();
    let committed =
        std::fs::read_to_string(repo().join("modelDescription/hertz_plane_strain.xml")).unwrap();
    assert_eq!(xml, committed);
    let _ = std::fs::remove_file(&out);

    // A scene that does not load is refused with its file:line (without
    // --library: export's default).
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_contact2d"))
        .args(["export", "tests/data/scenes/syntax.toml", "-o"])
        .arg(&out)
        .current_dir(repo())
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    let said = String::from_utf8_lossy(&bad.stderr);
    assert!(said.contains("syntax.toml:"), "{said}");
    // Refused before export would build a library for it.
    assert!(!said.contains("building the portable library"), "{said}");
}

/// Value references are unique across types; the GUID follows the interface
/// (names, references, types, causality, units), not the start values.
#[test]
fn guid_follows_the_interface() {
    let text = std::fs::read_to_string(repo().join("scenes/hertz_plane_strain.toml")).unwrap();
    let load = |t: &str| contact2d::scene::parse(t, &repo().join("scenes/x.toml")).unwrap();
    let base = load(&text);
    let vars = variables(&base);
    let mut vrs: Vec<u32> = vars.iter().map(|v| v.vr).collect();
    vrs.sort();
    vrs.dedup();
    assert_eq!(vrs.len(), vars.len(), "value references unique");
    let g = guid(&base);
    // Another E: same interface, same GUID.
    let stiffer = load(&text.replace("E = 200000.0", "E = 210000.0"));
    assert_eq!(guid(&stiffer), g);
    // A renamed driver, other units, a finer mesh (more contactor nodes):
    // another interface, another GUID.
    for (from, to) in [
        ("name = \"press\"", "name = \"push\""),
        ("length = \"mm\"", "length = \"m\""),
        ("divisions = 60", "divisions = 62"),
    ] {
        assert!(text.contains(from), "{from}");
        assert_ne!(guid(&load(&text.replace(from, to))), g, "{from} -> {to}");
    }
}

/// `output_dir` set: per step the solid, the pair's contactor surface and
/// the rigid target, named after the instance, and the `.pvd` of the
/// steps so far (after a restored state, of the steps taken from there).
#[test]
fn output_dir_gets_one_vtk_file_per_step() {
    let u = hertz();
    let l = lib();
    let inst = Inst::new(&u, "vtk out");
    let dir = std::env::temp_dir().join(format!("contact2d-vtk-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let value = CString::new(dir.to_string_lossy().as_bytes()).unwrap();
    let vr = [inst.vr("output_dir")];
    unsafe {
        assert_eq!(
            (l.fmi2EnterInitializationMode.as_ref().unwrap())(inst.c),
            OK
        );
        assert_eq!(
            (l.fmi2SetString.as_ref().unwrap())(inst.c, vr.as_ptr(), 1, &value.as_ptr()),
            OK
        );
        assert_eq!((l.fmi2ExitInitializationMode.as_ref().unwrap())(inst.c), OK);
        let mut back: fmi2String = null();
        assert_eq!(
            (l.fmi2GetString.as_ref().unwrap())(inst.c, vr.as_ptr(), 1, &mut back),
            OK
        );
        assert_eq!(CStr::from_ptr(back), value.as_c_str());
    }
    step_hertz(&inst, 0, 1);
    let saved = inst.save();
    step_hertz(&inst, 1, 2);
    // Taken back and stepped again: the step's files and its .pvd entries
    // are replaced, not added.
    inst.restore(saved);
    step_hertz(&inst, 1, 2);
    inst.free_state(saved);
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(
        files,
        [
            "vtk_out.pvd",
            "vtk_out_0001.vtu",
            "vtk_out_0002.vtu",
            "vtk_out_contact_contact_0001.vtu",
            "vtk_out_contact_contact_0002.vtu",
            "vtk_out_rigid_flat_0001.vtu",
            "vtk_out_rigid_flat_0002.vtu",
        ]
    );
    // Binary appended data after the XML: look for the arrays' names.
    let has = |file: &str, name: &[u8]| {
        let bytes = std::fs::read(dir.join(file)).unwrap();
        bytes.windows(name.len()).any(|w| w == name)
    };
    assert!(has("vtk_out_0002.vtu", b"\"displacement\""));
    for array in [&b"\"state\""[..], b"\"tn\"", b"\"slip\"", b"\"gap\""] {
        assert!(has("vtk_out_contact_contact_0002.vtu", array));
    }
    let pvd = std::fs::read_to_string(dir.join("vtk_out.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 6, "{pvd}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every shipped scene through the FMU layer along its own load history
/// (inputs set to the scene's driver values at the end of each step) gives
/// the solver's own results: the FMU adds no physics and loses nothing.
#[test]
fn every_shipped_scene_steps_as_the_solver() {
    use contact2d::fmi::instance::{Instance, Status};
    use contact2d::fmi::variables::Causality;
    let scenes = shipped_scenes();
    for scene in &scenes {
        let problem = contact2d::scene::load(scene).unwrap();
        let vars = variables(&problem);
        let times = problem.times.clone();
        let mut inst =
            Instance::new("all", scene, &guid(&problem), false, Box::new(|_, _, _| {})).unwrap();
        assert_eq!(inst.enter_initialization(), Status::Ok);
        assert_eq!(inst.exit_initialization(), Status::Ok);
        let mut solver = Solver::new(problem.clone()).unwrap();
        let mut t = 0.0;
        // Once a step has been bisected, the FMU's midpoints (inputs
        // reached linearly from the converged state) differ from the
        // scene's functions there in their last bits, and friction carries
        // that in the history: later steps agree to Newton's tolerance and
        // may take an iteration more or less (the running capstan: 4e-7 of
        // its largest traction at a node by the entry, over 500 steps).
        let mut bisected = false;
        for &t1 in &times {
            for v in &vars {
                let Some(value) = contact2d::fmi::variables::input(&v.binding, &problem, t1) else {
                    continue;
                };
                assert_eq!(inst.set_real(&[v.vr], &[value]), Status::Ok);
            }
            let name = scene.display();
            let Ok(step) = solver.advance(t1, &mut |_, _| {}) else {
                // A scene that runs past its limit (CGS-4 past slip onset):
                // the FMU discards the same step.
                assert_eq!(
                    inst.do_step(t, t1 - t),
                    Status::Discard,
                    "{name} to t = {t1}"
                );
                break;
            };
            assert_eq!(inst.do_step(t, t1 - t), Status::Ok, "{name} to t = {t1}");
            let outputs: Vec<_> = (vars.iter())
                .filter(|v| v.causality == Causality::Output)
                .map(|v| {
                    (
                        v,
                        contact2d::fmi::variables::output(&v.binding, &step).unwrap(),
                    )
                })
                .collect();
            // The largest output of each quantity: Newton's tolerance is
            // relative to the problem's forces, so a component near zero
            // (a drum's Rx under end forces of 20-36 N) agrees to that.
            let mut largest_of: Vec<(contact2d::fmi::variables::Quantity, f64)> = Vec::new();
            for (v, w) in &outputs {
                match largest_of.iter_mut().find(|(q, _)| *q == v.quantity) {
                    Some((_, m)) => *m = m.max(w.abs()),
                    None => largest_of.push((v.quantity, w.abs())),
                }
            }
            let largest = |q| {
                largest_of
                    .iter()
                    .find(|(p, _)| *p == q)
                    .map_or(0.0, |e| e.1)
            };
            let tolerance = if bisected { 1e-6 } else { 1e-7 };
            for &(v, want) in &outputs {
                if bisected && v.name.starts_with("solver.") {
                    continue;
                }
                let mut got = [f64::NAN];
                let mut got_i = [0];
                if v.ty == contact2d::fmi::variables::Type::Real {
                    assert_eq!(inst.get_real(&[v.vr], &mut got), Status::Ok);
                } else {
                    assert_eq!(inst.get_integer(&[v.vr], &mut got_i), Status::Ok);
                    got[0] = f64::from(got_i[0]);
                }
                // Inputs reached linearly from the converged state against
                // the scene's piecewise linear functions: equal up to the
                // last bits of the prescribed values, and Newton's tolerance.
                let scale = want.abs().max(1.0).max(largest(v.quantity));
                assert!(
                    (got[0] - want).abs() <= tolerance * scale,
                    "{name} t = {t1}: {} FMU {} solver {want}",
                    v.name,
                    got[0]
                );
            }
            t = t1;
            bisected |= step.substeps > 0;
        }
    }
}

/// The friction coefficients and the solver settings are tunable: set
/// between steps they act from the next step on, as the same change made
/// on a solver does; a combination that breaks a rule (mu_d > mu_s) is
/// refused and the values kept; fixed parameters stay refused; a saved
/// state carries the values it was saved with.
#[test]
fn tunable_parameters_between_steps() {
    let scene = repo().join("scenes/verification/sliding_block.toml");
    let problem = contact2d::scene::load(&scene).unwrap();
    let xml = model_description(&problem);
    for (name, variability) in [
        ("base.mu_s", "tunable"),
        ("base.mu_d", "tunable"),
        ("solver.tolerance", "tunable"),
        ("solver.max_iterations", "tunable"),
        ("rubberish.E", "fixed"),
    ] {
        let line = xml
            .lines()
            .find(|l| l.contains(&format!("name=\"{name}\"")))
            .unwrap();
        assert!(
            line.contains(&format!("variability=\"{variability}\"")),
            "{line}"
        );
    }

    let u = unpack(&scene, "tunable");
    let inst = Inst::new(&u, "tunable");
    inst.init();
    let mut solver = Solver::new(problem.clone()).unwrap();
    // The drag: top.ux = 0.2 drag(t), top.uy = -0.01 press(t).
    let drag = |t: f64| {
        if t <= 1.0 {
            0.0
        } else if t <= 3.0 {
            (t - 1.0) / 2.0
        } else {
            1.0 - 0.5 * (t - 3.0)
        }
    };
    let l = lib();
    let mut saved: fmi2FMUstate = null_mut();
    let mut t0 = 0.0;
    for (k, &t) in problem.times.iter().enumerate().take(20) {
        if k == 12 {
            unsafe {
                assert_eq!(
                    (l.fmi2GetFMUstate.as_ref().unwrap())(inst.c, &mut saved),
                    OK
                )
            };
            // While the block slides (t = 1.22): friction 0.3 / 0.2 to
            // 0.5 / 0.4, a tighter tolerance.
            assert_eq!(inst.set_real("base.mu_s", 0.5), OK);
            assert_eq!(inst.set_real("base.mu_d", 0.4), OK);
            assert_eq!(inst.set_real("solver.tolerance", 1e-10), OK);
            let mut tuned = solver.problem().clone();
            tuned.contacts[0].mu_s = 0.5;
            tuned.contacts[0].mu_d = 0.4;
            tuned.solver.force_tolerance = 1e-10;
            tuned.solver.displacement_tolerance = 1e-10;
            solver.set_tunables(&tuned);
            // Refused together, nothing changed: mu_d above mu_s.
            assert_eq!(inst.set_real("base.mu_d", 0.6), ERROR);
            assert!(
                inst.last_message().contains("mu_d must not exceed mu_s"),
                "{}",
                inst.last_message()
            );
            assert_eq!(inst.real("base.mu_d"), 0.4);
            // Fixed: refused between steps.
            assert_eq!(inst.set_real("rubberish.E", 2000.0), ERROR);
        }
        assert_eq!(inst.set_real("top.ux", 0.2 * drag(t)), OK);
        assert_eq!(inst.set_real("top.uy", -0.01 * t.min(1.0)), OK);
        assert_eq!(inst.step(t0, t - t0), OK, "t = {t}");
        let step = solver.advance(t, &mut |_, _| {}).unwrap();
        let pair = &step.pairs[0].1;
        let scale = pair.fn_.abs().max(1e-12);
        for (name, value) in [("base.Fn", pair.fn_), ("base.Ft", pair.ft)] {
            assert!(
                (inst.real(name) - value).abs() <= 1e-9 * scale,
                "t = {t}: {name} FMU {} solver {value}",
                inst.real(name)
            );
        }
        // Sliding at both ends of the change: |Ft| = mu_d Fn.
        if k == 11 || k == 19 {
            let mu_d = if k == 11 { 0.2 } else { 0.4 };
            assert_eq!(pair.n_stick, 0, "t = {t}: the block slides");
            assert!(
                ((pair.ft.abs() / pair.fn_) - mu_d).abs() <= 1e-6,
                "t = {t}: |Ft|/Fn = {}",
                pair.ft.abs() / pair.fn_
            );
        }
        t0 = t;
    }
    // Back to t = 1.22, saved before the change: mu_d 0.2 again, and the
    // next step slides with it.
    unsafe { assert_eq!((l.fmi2SetFMUstate.as_ref().unwrap())(inst.c, saved), OK) };
    assert_eq!(inst.real("base.mu_d"), 0.2);
    let (t0, t) = (problem.times[11], problem.times[12]);
    assert_eq!(inst.set_real("top.ux", 0.2 * drag(t)), OK);
    assert_eq!(inst.step(t0, t - t0), OK);
    let ratio = inst.real("base.Ft").abs() / inst.real("base.Fn");
    assert!((ratio - 0.2).abs() <= 1e-6, "|Ft|/Fn = {ratio}");
    unsafe {
        assert_eq!(
            (l.fmi2FreeFMUstate.as_ref().unwrap())(inst.c, &mut saved),
            OK
        )
    };
}

/// Input derivatives: a step reaches value + h * derivative, as the scene's
/// own ramp does, and the input then holds that value; the derivative acts
/// for one step; a Discarded step keeps both; bad calls are refused and
/// change nothing.
#[test]
fn input_derivatives_extrapolate_over_the_step() {
    let u = hertz();
    let inst = Inst::new(&u, "derivatives");
    inst.init();
    let l = lib();
    let set_der = |names: &[&str], orders: &[i32], values: &[f64]| -> fmi2Status {
        let vrs: Vec<u32> = names.iter().map(|n| inst.vr(n)).collect();
        unsafe {
            (l.fmi2SetRealInputDerivatives.as_ref().unwrap())(
                inst.c,
                vrs.as_ptr(),
                vrs.len(),
                orders.as_ptr(),
                values.as_ptr(),
            )
        }
    };
    let problem = contact2d::scene::load(&repo().join("scenes/hertz_plane_strain.toml")).unwrap();
    let mut solver = Solver::new(problem).unwrap();
    // press.uy = -0.07 t: at each communication point t the master sets
    // the value at t and the slope; the step reaches the scene's value at
    // t + h.
    for k in 0..4 {
        let t = 0.25 * k as f64;
        assert_eq!(inst.set_real("press.uy", -0.07 * t), OK);
        assert_eq!(set_der(&["press.uy"], &[1], &[-0.07]), OK);
        assert_eq!(inst.step(t, 0.25), OK);
        let step = solver.advance(t + 0.25, &mut |_, _| {}).unwrap();
        let fn_ = step.pairs[0].1.fn_;
        assert!(
            (inst.real("contact.Fn") - fn_).abs() <= 1e-9 * fn_,
            "t = {}: FMU {} solver {fn_}",
            t + 0.25,
            inst.real("contact.Fn")
        );
        // The input holds the value it reached.
        assert!((inst.real("press.uy") + 0.07 * (t + 0.25)).abs() <= 1e-15);
    }
    // The derivative acted for one step only: a step with none holds the
    // input, the state is in equilibrium (no iteration).
    assert_eq!(inst.step(1.0, 0.25), OK);
    assert_eq!(inst.int("solver.iterations"), 0);

    // Refused, nothing changed: an output, order 2, a non-finite value.
    assert_eq!(set_der(&["contact.Fn"], &[1], &[1.0]), ERROR);
    assert!(inst.last_message().contains("not an input"));
    assert_eq!(set_der(&["press.uy"], &[2], &[1.0]), ERROR);
    assert!(inst.last_message().contains("order 2"));
    assert_eq!(
        set_der(&["press.uy", "press.uy"], &[1, 1], &[1.0, f64::NAN]),
        ERROR
    );
    assert!(inst.last_message().contains("not a finite number"));
    assert_eq!(inst.step(1.25, 0.25), OK);
    assert_eq!(inst.int("solver.iterations"), 0, "no derivative was taken");

    // A step that cannot converge (the press driven 1000 times the model
    // into the flat in one step, no bisection) is Discarded: the input and
    // its derivative stay, and a master retrying with a smaller h
    // extrapolates over that h.
    assert_eq!(inst.set_int("solver.max_substeps", 0), OK);
    assert_eq!(inst.set_int("solver.max_iterations", 2), OK);
    assert_eq!(set_der(&["press.uy"], &[1], &[-1.0e4]), OK);
    assert_eq!(inst.step(1.5, 0.25), DISCARD);
    assert!((inst.real("press.uy") + 0.07).abs() <= 1e-15);
    assert_eq!(inst.set_int("solver.max_iterations", 25), OK);
    assert_eq!(inst.step(1.5, 1e-7), OK);
    assert!((inst.real("press.uy") + 0.07 + 1e-3).abs() <= 1e-12);
}

/// A frictionless pair made frictional between steps, and frictionless
/// again: the FMU follows a solver tuned the same way; lowering mu_s below
/// mu_d alone is refused, both in one call are taken.
#[test]
fn friction_switched_on_and_off_between_steps() {
    let u = hertz();
    let inst = Inst::new(&u, "friction on off");
    inst.init();
    let l = lib();
    let set_mu = |mu_s: f64, mu_d: f64| -> fmi2Status {
        let vrs = [inst.vr("contact.mu_s"), inst.vr("contact.mu_d")];
        let values = [mu_s, mu_d];
        unsafe { (l.fmi2SetReal.as_ref().unwrap())(inst.c, vrs.as_ptr(), 2, values.as_ptr()) }
    };
    let problem = contact2d::scene::load(&repo().join("scenes/hertz_plane_strain.toml")).unwrap();
    let mut solver = Solver::new(problem).unwrap();
    let tune = |solver: &mut Solver, mu: f64| {
        let mut p = solver.problem().clone();
        (p.contacts[0].mu_s, p.contacts[0].mu_d) = (mu, mu);
        solver.set_tunables(&p);
    };
    for k in 0..4 {
        if k == 2 {
            assert_eq!(set_mu(0.3, 0.3), OK);
            tune(&mut solver, 0.3);
        }
        step_hertz(&inst, k, k + 1);
        let step = solver
            .advance(0.25 * (k + 1) as f64, &mut |_, _| {})
            .unwrap();
        let pair = &step.pairs[0].1;
        assert!((inst.real("contact.Ft") - pair.ft).abs() <= 1e-9 * pair.fn_);
        assert_eq!(inst.int("contact.n_stick") as usize, pair.n_stick);
        if k >= 2 {
            // Pressed on with friction: the contact zone's new part sticks.
            assert!(
                pair.n_stick > 0 && pair.ft.abs() > 1e-3 * pair.fn_,
                "{pair:?}"
            );
        }
    }
    assert_eq!(inst.set_real("contact.mu_s", 0.0), ERROR);
    assert!(inst.last_message().contains("mu_d must not exceed mu_s"));
    assert_eq!(set_mu(0.0, 0.0), OK);
    tune(&mut solver, 0.0);
    // The flat moved sideways: frictionless, it carries no tangential force.
    assert_eq!(inst.set_real("flat.ux", 0.01), OK);
    assert_eq!(inst.step(1.0, 0.25), OK);
    solver.set_rigid_input(0, 0, Some(0.01));
    let step = solver.advance(1.25, &mut |_, _| {}).unwrap();
    let pair = &step.pairs[0].1;
    assert_eq!(pair.n_stick, 0);
    assert!(pair.ft.abs() <= 1e-9 * pair.fn_, "{}", pair.ft);
    assert!((inst.real("contact.Fn") - pair.fn_).abs() <= 1e-9 * pair.fn_);
}

/// A force input (`<driver>.Fy`, a driver that prescribes a force): the
/// cantilever's tip load set to its full value reaches equilibrium in one
/// doStep, with the displacement it produced as the output `<driver>.uy`;
/// the same as the scene's four increments (elastic, so path-independent
/// to the Newton tolerance), and a held force converges at once.
#[test]
fn force_input_reaches_equilibrium_in_one_step() {
    let text = std::fs::read_to_string(repo().join("scenes/verification/cantilever_tip_load.toml"))
        .unwrap()
        .replace(
            "[[force]]\nset = \"beam.tip\"\nfy = { function = \"ramp\", scale = -80.0 }",
            "[[driver]]\nname = \"tip\"\nset = \"beam.tip\"\nfy = { function = \"ramp\", scale = -80.0 }",
        );
    assert!(text.contains("name = \"tip\""));
    let dir = std::env::temp_dir().join(format!("contact2d-force-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("cantilever_force.toml");
    std::fs::write(&scene, &text).unwrap();
    let problem = contact2d::scene::load(&scene).unwrap();
    let names: Vec<String> = variables(&problem).into_iter().map(|v| v.name).collect();
    assert!(names.contains(&"tip.Fy".into()) && names.contains(&"tip.uy".into()));
    assert!(!names.contains(&"tip.Fx".into()) && !names.contains(&"tip.ux".into()));

    let mut solver = Solver::new(problem.clone()).unwrap();
    for &t in &problem.times {
        solver.advance(t, &mut |_, _| {}).unwrap();
    }
    let node = problem.mesh.node_sets["beam.tip"][0];
    let uy = solver.state().u[2 * node + 1];

    let u = unpack(&scene, "force");
    let inst = Inst::new(&u, "force");
    inst.init();
    assert_eq!(inst.real("tip.Fy"), 0.0);
    assert_eq!(inst.set_real("tip.Fy", -80.0), OK);
    assert_eq!(inst.step(0.0, 1.0), OK);
    assert_eq!(inst.real("tip.Ry"), -80.0);
    let fmu_uy = inst.real("tip.uy");
    assert!(
        (fmu_uy - uy).abs() <= 1e-6 * uy.abs(),
        "FMU {fmu_uy}, scene {uy}"
    );
    // Mattiasson (1981), k = 1: v/L = 0.30172 (tests/scenes.rs, 0.2 %).
    assert!((-fmu_uy / 10.0 / 0.30172 - 1.0).abs() < 2e-3, "{fmu_uy}");
    // Held: no iteration.
    assert_eq!(inst.step(1.0, 0.5), OK);
    assert_eq!(inst.int("solver.iterations"), 0);
    assert_eq!(inst.real("tip.uy"), fmu_uy);
    // A non-finite force is refused by name.
    assert_eq!(inst.set_real("tip.Fy", f64::NAN), ERROR);
    assert!(
        inst.last_message().contains("tip.Fy"),
        "{}",
        inst.last_message()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A force input checked against the displacement-driven run of the same
/// scene, through the FMU: the sliding block pressed onto its plane and
/// pulled sideways by `drag.Fx` on its top (a set that moves as one), in
/// one doStep each (a pull in partial slip, then a larger one); then the
/// scene with the top moved by the `drag.ux` the FMU reported, stepped the
/// same way, needs that force back as its reaction, with the same contact
/// resultants and states. Tolerance: each run stops at the force tolerance,
/// 1e-8 of the force scale; 1e-6 of the pull leaves room for both.
#[test]
fn force_input_matches_the_displacement_driven_scene() {
    let dir = std::env::temp_dir().join(format!("contact2d-twin-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, top: &str| {
        let text = edited(
            "verification/sliding_block.toml",
            &[
                (
                    "ux = { function = \"drag\", scale = 0.2 }\nuy = { function = \"press\", scale = -0.01 }",
                    &format!(
                        "uy = -0.01\n\n[[driver]]\nname = \"drag\"\nset = \"block.top\"\n{top}"
                    ),
                ),
                // Held sideways by a force alone: it starts in touch.
                (
                    "points = [[10.0, 0.0], [-10.0, 0.0]]",
                    "points = [[10.0, 1e-8], [-10.0, 1e-8]]",
                ),
                (TIMES_LINE, "times = [1.0, 2.0]"),
            ],
        );
        let scene = dir.join(name);
        std::fs::write(&scene, text).unwrap();
        unpack(&scene, name)
    };
    let names: Vec<String> = (1..=9).map(|k| format!("base.state[{k}]")).collect();
    let forced = write("forced.toml", "fx = 0.0\ndistribution = \"rigid\"");
    let inst = Inst::new(&forced, "forced");
    inst.init();
    let pulls = [1.2, 2.3];
    let mut seen = Vec::new();
    for (k, &fx) in pulls.iter().enumerate() {
        assert_eq!(inst.set_real("drag.Fx", fx), OK);
        assert_eq!(inst.step(k as f64, 1.0), OK, "{}", inst.last_message());
        let out = ["drag.ux", "base.Fn", "base.Ft"].map(|n| inst.real(n));
        seen.push((out, inst.contact_states(&names)));
    }
    let slide = |s: &[i32]| s.iter().filter(|&&x| x == 2).count();
    for (_, states) in &seen {
        assert!(
            slide(states) > 0 && slide(states) < 9,
            "partial slip: {states:?}"
        );
    }

    let moved = write("moved.toml", "ux = 0.0");
    let twin = Inst::new(&moved, "moved");
    twin.init();
    for (k, (&fx, (out, states))) in pulls.iter().zip(&seen).enumerate() {
        assert_eq!(twin.set_real("drag.ux", out[0]), OK);
        assert_eq!(twin.step(k as f64, 1.0), OK, "{}", twin.last_message());
        let rx = twin.real("drag.Rx");
        assert!((rx - fx).abs() <= 1e-6 * fx, "step {k}: Rx {rx} vs {fx}");
        for (i, n) in ["base.Fn", "base.Ft"]
            .iter()
            .enumerate()
            .map(|(i, n)| (i + 1, n))
        {
            let v = twin.real(n);
            assert!(
                (v - out[i]).abs() <= 1e-6 * fx,
                "step {k}: {n} {v} vs {}",
                out[i]
            );
        }
        assert_eq!(&twin.contact_states(&names), states, "step {k}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A named edge pressure is the input `<name>.p`: the bar of
/// tests/pressure_input.rs pulled by p = -20 on its end (F = 40) in one
/// step, its wall's reaction -40 and the end's stretch F L / (E A).
#[test]
fn pressure_input_in_the_fmu() {
    let text = common::bar_scene(
        "q8",
        [8, 2],
        "[[pressure]]\nname = \"pull\"\nset = \"bar.right\"\nvalue = 0.0\nfollower = false",
        1.0,
    );
    let dir = std::env::temp_dir().join(format!("contact2d-pressure-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("bar.toml");
    std::fs::write(&scene, &text).unwrap();
    let u = unpack(&scene, "pressure");
    let inst = Inst::new(&u, "pressure");
    inst.init();
    assert_eq!(inst.real("pull.p"), 0.0);
    assert_eq!(inst.set_real("pull.p", -20.0), OK);
    assert_eq!(inst.step(0.0, 1.0), OK);
    assert!(
        (inst.real("wall.Rx") + 40.0).abs() <= 1e-10,
        "{}",
        inst.real("wall.Rx")
    );
    // Released again: the bar springs back.
    assert_eq!(inst.set_real("pull.p", 0.0), OK);
    assert_eq!(inst.step(1.0, 1.0), OK);
    assert!(inst.real("wall.Rx").abs() <= 1e-10);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A scene's `[parameters]` are FMU parameters: set before initialisation,
/// they change every value of the scene that uses them (here the bar's
/// length and its end force: F L / (E A) exact), with the scene's checks
/// and file:line errors; a value that would change the interface (the
/// number of contactor nodes of the pair `under`, which the bar never
/// touches: 1 below it) is refused at fmi2ExitInitializationMode.
#[test]
fn scene_parameters_are_fmu_parameters() {
    let text = common::bar_scene(
        "q4",
        [8, 1],
        "[[driver]]\nname = \"pull\"\nset = \"bar.right\"\nfx = \"= force\"\n\n\
         [[rigid]]\nname = \"floor\"\npoints = [[20.0, -1.0], [-20.0, -1.0]]\n\n\
         [[contact]]\nname = \"under\"\ncontactor = \"bar.bottom\"\ntarget = \"floor\"",
        1.0,
    )
    .replacen(
        "size = [10.0, 1.0], divisions = [8, 1]",
        "size = [\"= length\", 1.0], divisions = [\"= 2 * half\", 1]",
        1,
    );
    let text = format!("[parameters]\nlength = 10.0\nhalf = 4\nforce = 40.0\n\n{text}");
    let dir = std::env::temp_dir().join(format!("contact2d-params-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("bar.toml");
    std::fs::write(&scene, &text).unwrap();
    let u = unpack(&scene, "params");
    let vars = variables(&contact2d::scene::load(&scene).unwrap());
    let length = vars.iter().find(|v| v.name == "length").unwrap();
    assert_eq!(
        length.causality,
        contact2d::fmi::variables::Causality::Parameter
    );

    // Defaults: F L / (E A) = 40 * 10 / 2000.
    let inst = Inst::new(&u, "defaults");
    assert_eq!(inst.real("length"), 10.0);
    inst.init();
    assert_eq!(inst.step(0.0, 1.0), OK);
    assert!((inst.real("pull.ux") - 0.2).abs() < 1e-12);
    assert_eq!(inst.real("under.gap[1]"), 1.0);

    // Longer and pulled less: 10 * 15 / 2000.
    let inst = Inst::new(&u, "set");
    assert_eq!(inst.set_real("length", 15.0), OK);
    assert_eq!(inst.set_real("force", 10.0), OK);
    inst.init();
    assert_eq!(inst.real("length"), 15.0);
    assert_eq!(inst.step(0.0, 1.0), OK);
    assert!((inst.real("pull.ux") - 0.075).abs() < 1e-12);

    // A length the generator refuses: an error at initialisation that names
    // the scene line and the expression.
    let inst = Inst::new(&u, "negative");
    assert_eq!(inst.set_real("length", -1.0), OK);
    assert_eq!(inst.init_status(), ERROR);
    let msg = inst.last_message();
    assert!(
        msg.contains("scene.toml:") && msg.contains("(from \"length\" = -1"),
        "{msg}"
    );

    // More elements: a new interface (more nodes), refused with the fix.
    let inst = Inst::new(&u, "finer");
    assert_eq!(inst.set_real("half", 8.0), OK);
    assert_eq!(inst.init_status(), ERROR);
    let msg = inst.last_message();
    assert!(
        msg.contains("half = 8") && msg.contains("export the scene again"),
        "{msg}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A scene that asks for more elements than its limit, or a scene.toml that
/// is a FIFO: fmi2Instantiate returns NULL at once with the reason in the
/// logger (issue 13: it aborted the host, or blocked it forever).
#[test]
fn instantiate_refuses_huge_meshes_and_fifos_with_a_message() {
    let text = common::bar_scene("q4", [100000, 100000], "", 1.0);
    let dir = std::env::temp_dir().join(format!("contact2d-huge-{}", std::process::id()));
    let resources = dir.join("resources");
    std::fs::create_dir_all(&resources).unwrap();
    std::fs::write(resources.join("scene.toml"), &text).unwrap();
    let u = Unpacked {
        resources: CString::new(format!("file://{}", resources.display())).unwrap(),
        guid: CString::new("{00000000-0000-0000-0000-000000000000}").unwrap(),
        vr: HashMap::new(),
        _dir: dir.clone(),
    };
    let started = std::time::Instant::now();
    let messages = Inst::new_or_messages(&u, "huge");
    assert!(started.elapsed().as_secs_f64() < 5.0);
    let all = messages.join("\n");
    assert!(
        all.contains("body[0].mesh.divisions = [100000, 100000]: 10000000000 elements"),
        "{all}"
    );
    // The scene as a FIFO.
    std::fs::remove_file(resources.join("scene.toml")).unwrap();
    let made = std::process::Command::new("mkfifo")
        .arg(resources.join("scene.toml"))
        .status()
        .unwrap();
    assert!(made.success());
    let all = Inst::new_or_messages(&u, "fifo").join("\n");
    assert!(all.contains("not a regular file"), "{all}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// What the re-entrant logger below calls back into.
struct Reentry {
    c: std::sync::atomic::AtomicPtr<c_void>,
    vr: u32,
    statuses: Mutex<Vec<fmi2Status>>,
    /// The lines it received.
    lines: Mutex<Vec<String>>,
    /// Whether it also frees the instance.
    free: std::sync::atomic::AtomicBool,
}

/// A master's logger that calls back into the instance that is logging:
/// fmi2GetReal, then (when asked) fmi2FreeInstance.
unsafe extern "C" fn reentrant_logger(
    env: fmi2ComponentEnvironment,
    _name: fmi2String,
    _status: fmi2Status,
    _category: fmi2String,
    _format: fmi2String,
    message: *const c_char,
) {
    let r = unsafe { &*(env as *const Reentry) };
    let text = unsafe { CStr::from_ptr(message) }
        .to_string_lossy()
        .into_owned();
    r.lines.lock().unwrap().push(text);
    let c = r.c.load(std::sync::atomic::Ordering::SeqCst);
    if c.is_null() {
        return;
    }
    let mut v = 0.0;
    let status = unsafe { (lib().fmi2GetReal.as_ref().unwrap())(c, &r.vr, 1, &mut v) };
    r.statuses.lock().unwrap().push(status);
    if r.free.load(std::sync::atomic::Ordering::SeqCst) {
        unsafe { (lib().fmi2FreeInstance.as_ref().unwrap())(c) };
    }
}

/// fmi2SetReal of NaN on `c` (logged, so the logger runs inside the
/// call), on a thread so that a deadlock fails the test instead of
/// hanging it: its status.
fn set_nan(c: fmi2Component, vr: u32) -> fmi2Status {
    let addr = c as usize;
    let (done, wait) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let c = addr as fmi2Component;
        let status = unsafe { (lib().fmi2SetReal.as_ref().unwrap())(c, &vr, 1, &f64::NAN) };
        done.send(status).unwrap();
    });
    wait.recv_timeout(std::time::Duration::from_secs(20))
        .expect("fmi2SetReal deadlocked in its logger")
}

/// A logger that calls back into the instance while it logs gets an error
/// instead of a deadlock or a use after free (issue 13, defect 7), and the
/// refusal is logged once the call has done its work (without recursing);
/// the instance works on afterwards. A free from inside the logger is
/// logged and carried out when the call in progress returns.
#[test]
fn a_logger_calling_back_gets_an_error_not_a_deadlock() {
    let u = hertz();
    let reentry = Box::new(Reentry {
        c: std::sync::atomic::AtomicPtr::new(null_mut()),
        vr: u.vr["press.uy"],
        statuses: Mutex::new(Vec::new()),
        lines: Mutex::new(Vec::new()),
        free: std::sync::atomic::AtomicBool::new(false),
    });
    let callbacks = callbacks(reentrant_logger, &*reentry as *const Reentry as *mut c_void);
    let l = lib();
    let name = CString::new("reentry").unwrap();
    let c = unsafe {
        (l.fmi2Instantiate.as_ref().unwrap())(
            name.as_ptr(),
            fmi2Type_fmi2CoSimulation,
            u.guid.as_ptr(),
            u.resources.as_ptr(),
            &*callbacks,
            0,
            1,
        )
    };
    assert!(!c.is_null());
    reentry.c.store(c, std::sync::atomic::Ordering::SeqCst);
    let vr = reentry.vr;
    assert_eq!(set_nan(c, vr), ERROR);
    let statuses = reentry.statuses.lock().unwrap().clone();
    assert!(
        !statuses.is_empty() && statuses.iter().all(|&s| s == ERROR),
        "{statuses:?}"
    );
    let lines = reentry.lines.lock().unwrap().clone();
    let refused = |l: &String| {
        l.starts_with("fmi2GetReal: refused: called from inside the logger during another call")
    };
    assert!(lines.iter().any(refused), "{lines:?}");
    // Not freed: the instance still answers.
    reentry
        .c
        .store(null_mut(), std::sync::atomic::Ordering::SeqCst);
    let mut v = 1.0;
    assert_eq!(
        unsafe { (l.fmi2GetReal.as_ref().unwrap())(c, &vr, 1, &mut v) },
        OK
    );
    assert_eq!(v, 0.0);

    // Freed from inside the logger: said, and done when the call returns
    // (the handle is not used again).
    reentry.lines.lock().unwrap().clear();
    reentry
        .free
        .store(true, std::sync::atomic::Ordering::SeqCst);
    reentry.c.store(c, std::sync::atomic::Ordering::SeqCst);
    assert_eq!(set_nan(c, vr), ERROR);
    let lines = reentry.lines.lock().unwrap().clone();
    let freed = "fmi2FreeInstance: the instance is in a call; it is freed when that call returns";
    assert!(lines.iter().any(|l| l == freed), "{lines:?}");
}

/// Time at the edges (issue 13, defect 4): the master's clock must agree
/// with the FMU's to a few units in the last place, not to 1e-9 of t (at t = 1.7e9 a clock off by a second passed); a step too
/// small for t to resolve (t + h == t) is a held step when the inputs did
/// not change, and an error that says why when they did.
#[test]
fn time_edges_have_defined_answers() {
    let u = hertz();
    let l = lib();
    let start = 1.7e9;
    let begin = |inst: &Inst| unsafe {
        assert_eq!(
            (l.fmi2SetupExperiment.as_ref().unwrap())(inst.c, 0, 0.0, start, 0, 0.0),
            OK
        );
        assert_eq!(
            (l.fmi2EnterInitializationMode.as_ref().unwrap())(inst.c),
            OK
        );
        assert_eq!((l.fmi2ExitInitializationMode.as_ref().unwrap())(inst.c), OK);
    };
    let inst = Inst::new(&u, "late");
    begin(&inst);
    // Steps of 0.1 summed by the FMU, multiplied out by the master: they
    // differ in the last bits, and are accepted.
    for k in 0..5 {
        assert_eq!(inst.set_real("press.uy", -0.001 * (k + 1) as f64), OK);
        assert_eq!(inst.step(start + 0.1 * k as f64, 0.1), OK, "step {k}");
    }
    let now = start + 0.5;
    // h = 1e-7 is below the resolution of t (2.4e-7): with the inputs held,
    // nothing to do.
    assert_eq!(now + 1e-7, now);
    let status = inst.step(now, 1e-7);
    assert_eq!(status, OK, "{}", inst.last_message());
    assert_eq!(inst.int("solver.iterations"), 0);
    // A new input in a step time cannot resolve: an error that says so.
    assert_eq!(inst.set_real("press.uy", -0.01), OK);
    assert_eq!(inst.step(now, 1e-7), ERROR);
    assert!(
        inst.last_message().contains("rounds to t"),
        "{}",
        inst.last_message()
    );

    // A clock one second off at t = 1.7e9 is refused.
    let inst = Inst::new(&u, "off");
    begin(&inst);
    assert_eq!(inst.step(start + 1.0, 0.1), ERROR);
    assert!(
        inst.last_message().contains("but the FMU is at t"),
        "{}",
        inst.last_message()
    );
}

/// The clock after a step to the largest f64 (issue 35, item 6):
/// `doStep(0, DBL_MAX)` is a step (held inputs, no iteration), and after it
/// the clock check still refuses a master at another time (the spacing of
/// f64 at DBL_MAX was taken as infinite, so any time passed); a step past
/// the largest f64 and one without a finite size are errors that say so.
#[test]
fn the_clock_stays_checked_after_a_step_to_the_largest_time() {
    let u = hertz();
    let inst = Inst::new(&u, "dbl_max");
    inst.init();
    assert_eq!(inst.step(0.0, f64::MAX), OK, "{:?}", inst.messages());
    for t in [0.0, 5.0, 1e300, 0.5 * f64::MAX] {
        assert_eq!(inst.step(t, 1.0), ERROR, "a master at t = {t:e}");
        assert!(
            inst.last_message()
                .contains("but the FMU is at t = 1.7976931348623157e308"),
            "{}",
            inst.last_message()
        );
    }
    assert_eq!(inst.step(f64::MAX, f64::MAX), ERROR);
    assert!(
        inst.last_message().contains("overflows"),
        "{}",
        inst.last_message()
    );
    for (t, h) in [
        (f64::MAX, f64::INFINITY),
        (f64::MAX, f64::NAN),
        (f64::INFINITY, 1.0),
    ] {
        assert_eq!(inst.step(t, h), ERROR, "t = {t}, h = {h}");
        assert!(
            inst.last_message().contains("must be finite"),
            "{}",
            inst.last_message()
        );
    }
    // A new input needs time to advance, which it cannot past DBL_MAX.
    assert_eq!(inst.set_real("press.uy", -0.01), OK);
    assert_eq!(inst.step(f64::MAX, 1.0), ERROR);
    assert!(
        inst.last_message().contains("rounds to t"),
        "{}",
        inst.last_message()
    );
}

// ---------------------------------------------------------------------------
// Directional derivatives.

impl Inst {
    fn save(&self) -> fmi2FMUstate {
        let mut s: fmi2FMUstate = null_mut();
        unsafe {
            assert_eq!(
                (lib().fmi2GetFMUstate.as_ref().unwrap())(self.c, &mut s),
                OK
            )
        };
        s
    }

    fn restore(&self, s: fmi2FMUstate) {
        unsafe { assert_eq!((lib().fmi2SetFMUstate.as_ref().unwrap())(self.c, s), OK) };
    }

    fn free_state(&self, mut s: fmi2FMUstate) {
        unsafe {
            assert_eq!(
                (lib().fmi2FreeFMUstate.as_ref().unwrap())(self.c, &mut s),
                OK
            )
        };
    }

    /// fmi2GetDirectionalDerivative: the status and dvUnknown.
    fn derivative(&self, unknown: &[u32], known: &[u32], seed: &[f64]) -> (fmi2Status, Vec<f64>) {
        let mut out = vec![f64::NAN; unknown.len()];
        let s = unsafe {
            (lib().fmi2GetDirectionalDerivative.as_ref().unwrap())(
                self.c,
                unknown.as_ptr(),
                unknown.len(),
                known.as_ptr(),
                known.len(),
                seed.as_ptr(),
                out.as_mut_ptr(),
            )
        };
        (s, out)
    }

    /// Every Integer output (node states and counts): the contact states.
    fn contact_states(&self, names: &[String]) -> Vec<i32> {
        names.iter().map(|n| self.int(n)).collect()
    }
}

/// What a derivative check measured: the largest error against central
/// differences as a fraction of the tolerance's scale, where, and the
/// number of derivatives compared.
#[derive(Debug, Default)]
struct Measured {
    worst: f64,
    /// The bound the worst error was held to.
    bound: f64,
    worst_at: String,
    compared: usize,
    /// Sticking and sliding contactor nodes at the state (all pairs).
    stick_slip: [i32; 2],
    /// Inputs none of whose changes (down to a tenth of the first eps)
    /// keeps the contact states: the outputs have a kink there.
    kinks: Vec<String>,
}

/// One derivative check: a scene, the step after which to check (0-based,
/// along the scene's own inputs), Newton's tolerance for the step and its
/// differences, and the inputs not differenced (with the reason in the
/// caller).
struct Check<'a> {
    scene: &'a Path,
    at: usize,
    tolerance: f64,
    skip: &'a [&'a str],
}

/// fmi2GetDirectionalDerivative at the state after step `at` of the scene's
/// own input history against central differences of that step: from the
/// state saved before it, the step is taken again with one input at
/// u +- eps, its outputs read, the state restored. eps is 1e-5 of the
/// input's scale, halved (twice at most) while either run changes any
/// contact state (`state[k]`, the counts) from the step's own or does not
/// converge: the derivative is that of the equilibrium with the contact
/// states held, and an input no change of which keeps them is a kink,
/// reported. The tolerance, 1e-6, is relative to max(|derivative|, output
/// scale / input scale): the differences carry the Newton residual (1e-11
/// of the forces, or `tolerance`) over 2 eps and a truncation of order eps^2
/// (measured below 2e-7 of that scale, the sheet's rotation against its
/// rigid channel the largest), so a wrong term of 1e-6 shows. The output
/// scale is the step's largest output of the same quantity (force, moment,
/// length), the input scale the largest value that kind of input takes
/// over the scene (1/1000 of the model when no length input moves; for
/// angles that over the model's size).
fn check_derivatives(check: &Check, tag: &str) -> Measured {
    use contact2d::fmi::variables::{Binding, Causality, PairField, Quantity, Type, Variable};
    let problem = contact2d::scene::load(check.scene).unwrap();
    let vars = variables(&problem);
    let inputs: Vec<&Variable> = vars
        .iter()
        .filter(|v| v.causality == Causality::Input)
        .collect();
    let derivable: Vec<&Variable> = vars
        .iter()
        .filter(|v| match v.binding {
            Binding::Reaction { .. } | Binding::DriverDisplacement { .. } => true,
            Binding::Pair { field, .. } => {
                matches!(
                    field,
                    PairField::Fx | PairField::Fy | PairField::Fn | PairField::Ft
                )
            }
            _ => false,
        })
        .collect();
    let integers: Vec<String> = vars
        .iter()
        .filter(|v| v.causality == Causality::Output && v.ty == Type::Integer)
        .filter(|v| !v.name.starts_with("solver."))
        .map(|v| v.name.clone())
        .collect();
    let times = &problem.times;
    let input_at =
        |v: &Variable, t: f64| contact2d::fmi::variables::input(&v.binding, &problem, t).unwrap();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &problem.mesh.nodes {
        for c in 0..2 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    let size = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    let largest = |q: Quantity| {
        (inputs.iter().filter(|v| v.quantity == q))
            .flat_map(|v| times.iter().map(move |&t| input_at(v, t).abs()))
            .fold(0.0, f64::max)
    };
    let length = if largest(Quantity::Length) > 0.0 {
        largest(Quantity::Length)
    } else {
        1e-3 * size
    };
    let input_scale = |v: &Variable| match v.quantity {
        Quantity::Length => length,
        Quantity::Angle => length / size,
        q => largest(q),
    };

    let u = unpack(check.scene, tag);
    let inst = Inst::new(&u, tag);
    inst.init();
    assert_eq!(inst.set_real("solver.tolerance", check.tolerance), OK);
    let set_inputs = |t: f64| {
        for v in &inputs {
            assert_eq!(inst.set_real(&v.name, input_at(v, t)), OK);
        }
    };
    let mut t = 0.0;
    for &t1 in &times[..check.at] {
        set_inputs(t1);
        assert_eq!(
            inst.step(t, t1 - t),
            OK,
            "{tag} to {t1}: {:?}",
            inst.messages()
        );
        t = t1;
    }
    let before = inst.save();
    let t1 = times[check.at];
    set_inputs(t1);
    assert_eq!(
        inst.step(t, t1 - t),
        OK,
        "{tag} to {t1}: {:?}",
        inst.messages()
    );
    // The derivative is the last increment's: a step taken in one.
    assert_eq!(inst.int("solver.substeps"), 0, "{tag}: no bisection");
    let states = inst.contact_states(&integers);
    let count = |key: &str| {
        (integers.iter().zip(&states))
            .filter(|(n, _)| n.ends_with(key))
            .map(|(_, s)| s)
            .sum()
    };
    let stick_slip = [count(".n_stick"), count(".n_slip")];
    let unknown: Vec<u32> = derivable.iter().map(|v| v.vr).collect();
    let mut output_scale = HashMap::new();
    for v in &derivable {
        let s = output_scale
            .entry(format!("{:?}", v.quantity))
            .or_insert(0.0f64);
        *s = s.max(inst.real(&v.name).abs());
    }
    let natural = |v: &Variable, input: &Variable| {
        output_scale[&format!("{:?}", v.quantity)] / input_scale(input)
    };
    let columns: Vec<Vec<f64>> = (inputs.iter())
        .map(|input| {
            let (status, dy) = inst.derivative(&unknown, &[input.vr], &[1.0]);
            assert_eq!(
                status,
                OK,
                "{tag}: d/d {}: {}",
                input.name,
                inst.last_message()
            );
            dy
        })
        .collect();
    // A seed of all the inputs at once is the sum of the columns (the
    // derivative is linear in the seed; the factorization kept at the state
    // solves it).
    let known: Vec<u32> = inputs.iter().map(|v| v.vr).collect();
    let seed: Vec<f64> = (0..inputs.len()).map(|i| 1.0 + i as f64).collect();
    let (status, dy) = inst.derivative(&unknown, &known, &seed);
    assert_eq!(status, OK);
    for (o, d) in dy.iter().enumerate() {
        let sum: f64 = columns.iter().zip(&seed).map(|(c, s)| s * c[o]).sum();
        let scale = (columns.iter().zip(&seed).zip(&inputs))
            .map(|((c, s), input)| s * c[o].abs().max(natural(derivable[o], input)))
            .fold(0.0, f64::max);
        assert!(
            (d - sum).abs() <= 1e-9 * scale,
            "{tag}: d {} for the seed of all inputs {d:e}, the sum of the columns {sum:e}",
            derivable[o].name
        );
    }

    let mut measured = Measured {
        stick_slip,
        ..Default::default()
    };
    for (input, dy) in inputs.iter().zip(&columns) {
        if check.skip.contains(&input.name.as_str()) {
            continue;
        }
        let value = input_at(input, t1);
        let initial = 1e-5 * input_scale(input);
        let mut eps = initial;
        let run = |x: f64| {
            inst.restore(before);
            set_inputs(t1);
            assert_eq!(inst.set_real(&input.name, x), OK);
            let converged = inst.step(t, t1 - t) == OK;
            let y: Vec<f64> = derivable.iter().map(|v| inst.real(&v.name)).collect();
            let held = converged && inst.contact_states(&integers) == states;
            (y, held, inst.real("solver.residual"))
        };
        let fd = loop {
            let (plus, same_plus, rho_plus) = run(value + eps);
            let (minus, same_minus, rho_minus) = run(value - eps);
            if same_plus && same_minus {
                let fd: Vec<f64> = plus
                    .iter()
                    .zip(&minus)
                    .map(|(p, m)| (p - m) / (2.0 * eps))
                    .collect();
                // The differences' noise: each run's outputs are off by about
                // its residual times the forces, over 2 eps.
                let noise = 4.0 * rho_plus.max(rho_minus) * input_scale(input) / eps;
                break Some((fd, noise.max(1e-6)));
            }
            eps *= 0.5;
            if eps < 0.2 * initial {
                break None;
            }
        };
        let Some((fd, bound)) = fd else {
            measured.kinks.push(input.name.clone());
            continue;
        };
        for ((v, d), f) in derivable.iter().zip(dy).zip(&fd) {
            let error = (d - f).abs() / d.abs().max(natural(v, input));
            measured.compared += 1;
            if error / bound >= measured.worst / measured.bound.max(f64::MIN_POSITIVE) {
                (measured.worst, measured.bound) = (error, bound);
                measured.worst_at = format!(
                    "t = {t1}: d {} / d {} = {d:e}, central differences {f:e} (eps {eps:e})",
                    v.name, input.name
                );
            }
        }
    }
    inst.restore(before);
    inst.free_state(before);
    measured
}

/// A temporary scene file with `text` (removed with its folder on drop).
struct TempScene(PathBuf);

impl TempScene {
    fn new(tag: &str, text: &str) -> TempScene {
        let dir = std::env::temp_dir().join(format!("contact2d-dd-{}-{tag}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("scene.toml");
        std::fs::write(&path, text).unwrap();
        TempScene(path)
    }
}

impl Drop for TempScene {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(self.0.parent().unwrap());
    }
}

/// The shipped scene `name` with each `(old, new)` replaced once.
fn edited(name: &str, edits: &[(&str, &str)]) -> String {
    let (text, _) = common::scene_text(name, edits);
    text
}

/// Runs the checks, prints what each measured, and fails on any error above
/// its bound, a kink other than `kinks` expects, or a state among `zones`
/// without both a stick zone and a slip zone.
fn run_checks(checks: &[Check], kinks: &[&[&str]], zones: &[usize]) {
    let mut failed = Vec::new();
    for (i, (check, expected)) in checks.iter().zip(kinks).enumerate() {
        let m = check_derivatives(check, &format!("dd{i}"));
        println!(
            "{} after step {} (stick/slip nodes {:?}): {} derivatives, worst {:.2e} of bound {:.1e} ({}); kinks {:?}",
            check.scene.display(),
            check.at,
            m.stick_slip,
            m.compared,
            m.worst,
            m.bound,
            m.worst_at,
            m.kinks
        );
        assert!(
            m.compared > 0,
            "{}: nothing compared",
            check.scene.display()
        );
        if m.worst > m.bound || m.kinks != *expected {
            failed.push(format!(
                "{}: {} kinks {:?}",
                check.scene.display(),
                m.worst_at,
                m.kinks
            ));
        }
        if zones.contains(&i) && m.stick_slip.contains(&0) {
            failed.push(format!(
                "{}: stick/slip nodes {:?}",
                check.scene.display(),
                m.stick_slip
            ));
        }
    }
    assert!(failed.is_empty(), "{failed:#?}");
}

/// The shipped scenes (every one has inputs), each after a step of its own
/// history, against central differences (`check_derivatives`).
///
/// Two kinds of input have no derivative to difference, and are the
/// solver's behaviour rather than the derivative's:
/// - a contactor node sticking with its tangential component prescribed
///   (the wire's far end; the pipe's nodes on its axis) slides for any
///   motion of that driver or of the target under it, so the wire's
///   `far_end.ux` and `cylinder.ux` are kinks (asserted);
/// - the pipe's axis drivers move a node that sits on the soil's node on
///   the symmetry plane, where a row is taken as acting on prescribed dofs
///   below 1e-6 of its weight (`NEGLIGIBLE_ROW`): its outputs jump by
///   hundreds of newtons between +-1e-8 m with the states kept (measured),
///   so the pipe's and the soil's axis inputs are not differenced; the
///   Newton tolerance is 1e-9 there (1e-11 does not converge: the steel
///   pipe in the soft soil).
#[test]
fn directional_derivatives_of_the_shipped_scenes() {
    let path = |s: &str| repo().join("scenes").join(s);
    let (pipe, hertz_a, hertz, sheet, wire) = (
        path("buried_pipe.toml"),
        path("hertz_axisymmetric.toml"),
        path("hertz_plane_strain.toml"),
        path("rubber_sheet.toml"),
        path("wire_winding.toml"),
    );
    let axes = ["soil_axis.ux", "pipe_axis_bottom.ux", "pipe_axis_top.ux"];
    let checks = [
        Check {
            scene: &pipe,
            at: 0,
            tolerance: 1e-10,
            skip: &axes,
        },
        Check {
            scene: &hertz_a,
            at: 3,
            tolerance: 1e-11,
            skip: &[],
        },
        Check {
            scene: &hertz,
            at: 3,
            tolerance: 1e-11,
            skip: &[],
        },
        // Total Lagrangian Mooney-Rivlin sliding with friction in a rigid
        // channel, at t = 5.5.
        Check {
            scene: &sheet,
            at: 10,
            tolerance: 1e-11,
            skip: &[],
        },
        // The snapped wire: a stick zone and a slip zone.
        Check {
            scene: &wire,
            at: 1,
            tolerance: 1e-11,
            skip: &[],
        },
    ];
    // The pipe and the wire hold a stick zone and a slip zone.
    run_checks(
        &checks,
        &[&[], &[], &[], &[], &["far_end.ux", "cylinder.ux"]],
        &[0, 4],
    );
}

/// The same on the verification scenes that exercise what the shipped ones
/// do not: a block with a stick zone and a slip zone on a rigid plane
/// (mu_s = mu_d), pressed and in the drag's transition, and dragged sliding
/// as the scene has it (mu_d < mu_s: pressed, a motion of the plane carries
/// its sticking nodes along, their rows holding them at their anchors, so
/// `plane.ux` has a derivative there too; until 2026-11-28 a free node off
/// its anchor by the plane's motion was read as driven and slid, a kink), a
/// frictional block on a flexible target under node-to-segment (the sliding
/// node's full linearisation: the turning segment, the moving contact
/// point; the shipped frictionless one runs mortar, the default), lift-off, an inclined plane, von Mises plasticity (the
/// consistent tangent from the step's start), a total Lagrangian strip, the
/// Lame cylinder, the cantilever; a force driver on the cantilever's tip
/// (`<driver>.uy` and its `.Fy` input) and an edge pressure input on a bar.
#[test]
fn directional_derivatives_of_the_verification_scenes() {
    let path = |s: &str| repo().join("scenes/verification").join(s);
    let block = TempScene::new(
        "block",
        &edited(
            "verification/sliding_block.toml",
            &[("mu_s = 0.3\nmu_d = 0.2", "mu_s = 0.3\nmu_d = 0.3")],
        ),
    );
    let flexible = TempScene::new(
        "flexible",
        &edited(
            "verification/flexible_target.toml",
            // Node-to-segment's sliding node, pinned (the scene's default
            // is mortar, whose frictional derivatives
            // `directional_derivatives_of_mortar_scenes` checks).
            &[(
                "mu_s = 0.0",
                "mu_s = 0.3\nformulation = \"node_to_segment\"",
            )],
        ),
    );
    let tip = TempScene::new(
        "tip",
        &edited(
            "verification/cantilever_tip_load.toml",
            &[(
                "[[force]]\nset = \"beam.tip\"\nfy = { function = \"ramp\", scale = -80.0 }",
                "[[driver]]\nname = \"tip\"\nset = \"beam.tip\"\nfy = { function = \"ramp\", scale = -80.0 }",
            )],
        ),
    );
    let bar = TempScene::new(
        "bar",
        &common::bar_scene(
            "q8",
            [8, 2],
            "[[function]]\nname = \"ramp\"\npoints = [[0.0, 0.0], [1.0, 1.0]]\n\n\
             [[pressure]]\nname = \"pull\"\nset = \"bar.right\"\n\
             value = { function = \"ramp\", scale = -20.0 }\nfollower = false",
            1.0,
        ),
    );
    let scenes = [
        path("sliding_block.toml"),
        path("lift_off.toml"),
        path("cgs4_inclined.toml"),
        path("plastic_strip.toml"),
        path("rubber_strip.toml"),
        path("lame_cylinder.toml"),
        path("cantilever_tip_load.toml"),
        path("flexible_target.toml"),
    ];
    let check = |scene, at| Check {
        scene,
        at,
        tolerance: 1e-11,
        skip: &[],
    };
    let checks = [
        check(&block.0, 1),
        check(&block.0, 5),
        check(&block.0, 12),
        check(&scenes[0], 1),
        check(&scenes[0], 20),
        check(&scenes[1], 1),
        check(&scenes[2], 1),
        check(&scenes[3], 2),
        check(&scenes[4], 1),
        check(&scenes[5], 0),
        check(&scenes[6], 1),
        check(&scenes[7], 1),
        check(&flexible.0, 19),
        check(&tip.0, 1),
        check(&bar.0, 0),
    ];
    let none: &[&str] = &[];
    let kinks = [none; 15];
    // The block pressed and in the drag's transition, and on the flexible
    // strip after the press, holds a stick zone and a slip zone.
    run_checks(&checks, &kinks, &[0, 1, 12]);
}

/// Mortar contact (`formulation = "mortar"`): the block on the coarse
/// flexible strip after the press and during the drag, frictionless and
/// with mu = 0.3 (after the press a stick zone and a slip zone; in the drag
/// every node slides); every derivative of a converged state against
/// central differences (`check_derivatives`). The frictional pair's
/// weighted slips are measured from where the increment started, in the
/// derivatives as in the increment (until 2026-11-28 they were measured
/// from the state itself, and came out 1e-6 to 3e-5 off).
#[test]
fn directional_derivatives_of_mortar_scenes() {
    let mortar = "formulation = \"mortar\"\nmu_s";
    let frictionless = TempScene::new(
        "mortar_strip",
        &edited("verification/flexible_target.toml", &[("mu_s", mortar)]),
    );
    let check = |scene, at| Check {
        scene,
        at,
        tolerance: 1e-11,
        skip: &[],
    };
    let checks = [check(&frictionless.0, 19), check(&frictionless.0, 40)];
    let none: &[&str] = &[];
    run_checks(&checks, &[none; 2], &[]);
    let frictional = edited(
        "verification/flexible_target.toml",
        &[("mu_s = 0.0", "mu_s = 0.3"), ("mu_s", mortar)],
    );
    let frictional = TempScene::new("mortar_mu", &frictional);
    run_checks(
        &[check(&frictional.0, 19), check(&frictional.0, 40)],
        &[none; 2],
        &[0],
    );
    // Symmetry planes: the buried pipe under mortar with mu = 0.3, its
    // contactor's end nodes on the symmetry axis (sticking, with no slip
    // row). As for node-to-segment (`directional_derivatives_of_the_
    // shipped_scenes`) the axis drivers are not compared: moving one
    // body's symmetry plane off the other's moves the end node's normal
    // ray off the target's end, a kink (measured on the quarter shrink fit
    // 16/23: d Ry / d hub_x_axis.uy 1.1e4, central differences 1.0e5).
    let pipe = TempScene::new(
        "mortar_pipe",
        &edited(
            "buried_pipe.toml",
            &[(
                "formulation = \"node_to_segment\"",
                "formulation = \"mortar\"",
            )],
        ),
    );
    let axes = ["soil_axis.ux", "pipe_axis_bottom.ux", "pipe_axis_top.ux"];
    // The tolerance the node-to-segment check uses on this scene (its LU
    // solves are good to about 1e-10 of the forces).
    let on_axes = |at| Check {
        scene: &pipe.0,
        at,
        tolerance: 1e-10,
        skip: &axes,
    };
    run_checks(&[on_axes(0), on_axes(3)], &[none; 2], &[0, 1]);
}

/// The hub's equilibrium in the derivatives: on the quarter shrink fit
/// under mortar with mu = 0.3, the contactor's end nodes lie on the
/// symmetry planes, with contact forces on the dofs their drivers hold.
/// For every input the pair's d Fx equals -d Rx of the hub's y-axis driver
/// and d Fy equals -d Ry of its x-axis driver (the contact force on the hub
/// is all its drivers hold): the pair's resultants change with the forces
/// its multipliers give, held components included
/// (`NodeForce::multipliers`; read off the out-of-balance force, which
/// counts them zero, they came out 2e-3 off the reactions'). An identity,
/// whichever side of a kink an input's derivative is taken on.
#[test]
fn mortar_resultant_derivatives_balance_the_reactions() {
    let scene = TempScene::new(
        "fit_balance",
        &edited("stress/shrink_fit.toml", &[("mu_s = 0.0", "mu_s = 0.3")]),
    );
    let problem = contact2d::scene::load(&scene.0).unwrap();
    let vars = variables(&problem);
    let vr = |name: &str| vars.iter().find(|v| v.name == name).unwrap().vr;
    let unknown = [
        vr("fit.Fx"),
        vr("hub_y_axis.Rx"),
        vr("fit.Fy"),
        vr("hub_x_axis.Ry"),
    ];
    let u = unpack(&scene.0, "fit_balance");
    let inst = Inst::new(&u, "fit_balance");
    inst.init();
    assert_eq!(inst.step(0.0, 1.0), OK, "{:?}", inst.messages());
    let inputs: Vec<_> = (vars.iter())
        .filter(|v| v.causality == contact2d::fmi::variables::Causality::Input)
        .collect();
    assert_eq!(inputs.len(), 4);
    for input in inputs {
        let (status, dy) = inst.derivative(&unknown, &[input.vr], &[1.0]);
        assert_eq!(status, OK, "{}", inst.last_message());
        for (f, r) in [(dy[0], dy[1]), (dy[2], dy[3])] {
            assert!(
                (f + r).abs() <= 1e-9 * f.abs().max(r.abs()),
                "d / d {}: pair {f:e}, reaction {r:e}",
                input.name
            );
        }
    }
}

/// A force input on a set that moves as one (`distribution = "rigid"`):
/// the sliding block pressed, then pulled sideways by `drag.Fx` on its top
/// into partial slip (the edges slide, the middle sticks), as the pull
/// grows. Its outputs are `drag.ux`, the top's common displacement, beside
/// the contact resultants.
#[test]
fn directional_derivatives_of_a_rigid_force_input() {
    let pulled = TempScene::new(
        "pulled",
        &edited(
            "verification/sliding_block.toml",
            &[
                ("ux = { function = \"drag\", scale = 0.2 }\n", ""),
                (
                    "[[contact]]",
                    "[[driver]]\nname = \"drag\"\nset = \"block.top\"\n\
                     fx = { function = \"drag\", scale = 2.5 }\ndistribution = \"rigid\"\n\n[[contact]]",
                ),
                // Held sideways by a force alone: it starts in touch.
                (
                    "points = [[10.0, 0.0], [-10.0, 0.0]]",
                    "points = [[10.0, 1e-8], [-10.0, 1e-8]]",
                ),
                (TIMES_LINE, "times = [0.5, 1.0, 1.5, 2.0]"),
            ],
        ),
    );
    let check = |at| Check {
        scene: &pulled.0,
        at,
        tolerance: 1e-11,
        skip: &[],
    };
    // Moving the plane under a block held sideways by a force carries the
    // block along (d drag.ux / d plane.ux = 1): its sticking nodes stay at
    // their anchors and its sliding edges slide on, no state changes.
    let none: &[&str] = &[];
    run_checks(&[check(2), check(3)], &[none, none], &[0, 1]);
}

/// fmi2GetDirectionalDerivative refuses with fmi2Error, and a message that
/// names the value reference, what has no derivative: an unknown value
/// reference, a count, a node state, a zone length, a per-node output, a
/// solver output or an input as the unknown; an output or a parameter as
/// the known; a non-finite seed; NULL arrays with a length. Before
/// fmi2ExitInitializationMode it is not allowed (fmi2Error, as for any call
/// the state machine does not allow); after fmi2Terminate it is. A pair
/// under the paper's decisions has no derivative, said by name. Nothing
/// crashes, and the instance steps on after each refusal.
#[test]
fn directional_derivative_refusals() {
    let u = hertz();
    let l = lib();
    let inst = Inst::new(&u, "ddbad");
    let (ry, uy) = (inst.vr("press.Ry"), inst.vr("press.uy"));
    let (s, _) = inst.derivative(&[ry], &[uy], &[1.0]);
    assert_eq!(s, ERROR);
    assert!(
        inst.last_message()
            .contains("not allowed in mode Instantiated"),
        "{}",
        inst.last_message()
    );
    unsafe {
        assert_eq!(
            (l.fmi2SetupExperiment.as_ref().unwrap())(inst.c, 0, 0.0, 0.0, 0, 0.0),
            OK
        );
        assert_eq!(
            (l.fmi2EnterInitializationMode.as_ref().unwrap())(inst.c),
            OK
        );
    }
    let (s, _) = inst.derivative(&[ry], &[uy], &[1.0]);
    assert_eq!(s, ERROR);
    assert!(
        inst.last_message()
            .contains("not allowed in mode Initialization")
    );
    unsafe { assert_eq!((l.fmi2ExitInitializationMode.as_ref().unwrap())(inst.c), OK) };
    step_hertz(&inst, 0, 2);
    let (s, good) = inst.derivative(&[ry], &[uy], &[1.0]);
    assert_eq!(s, OK);
    assert!(good[0].is_finite() && good[0] != 0.0, "{good:?}");
    let refused: Vec<(u32, u32, f64)> = vec![
        (99_999, uy, 1.0),
        (inst.vr("contact.n_stick"), uy, 1.0),
        (inst.vr("contact.state[1]"), uy, 1.0),
        (inst.vr("contact.slip_length"), uy, 1.0),
        (inst.vr("contact.tn[1]"), uy, 1.0),
        (inst.vr("solver.residual"), uy, 1.0),
        (uy, uy, 1.0),
        (ry, 99_998, 1.0),
        (ry, inst.vr("contact.Fn"), 1.0),
        (ry, inst.vr("solver.tolerance"), 1.0),
        (ry, uy, f64::NAN),
    ];
    for (unknown, known, seed) in refused {
        let (s, _) = inst.derivative(&[ry, unknown], &[known], &[seed]);
        assert_eq!(s, ERROR, "{unknown} / {known}");
        let msg = inst.last_message();
        let named = if unknown == ry { known } else { unknown };
        assert!(msg.contains(&format!("valueReference {named}")), "{msg}");
        assert!(msg.starts_with("fmi2GetDirectionalDerivative"), "{msg}");
    }
    assert!(
        inst.messages()
            .iter()
            .any(|m| m.contains("'contact.slip_length'") && m.contains("jumps"))
    );
    unsafe {
        let f = l.fmi2GetDirectionalDerivative.as_ref().unwrap();
        let mut out = [0.0];
        assert_eq!(f(inst.c, null(), 1, &uy, 1, &1.0, out.as_mut_ptr()), ERROR);
        assert!(inst.last_message().contains("NULL"));
        assert_eq!(f(inst.c, &ry, 1, &uy, 1, &1.0, null_mut()), ERROR);
        assert_eq!(f(inst.c, null(), 0, null(), 0, null(), null_mut()), OK);
        // No known: the derivative in the zero direction.
        assert_eq!(f(inst.c, &ry, 1, null(), 0, null(), out.as_mut_ptr()), OK);
        assert_eq!(out[0], 0.0);
        assert_eq!(f(null_mut(), &ry, 1, &uy, 1, &1.0, out.as_mut_ptr()), ERROR);
    }
    // The same answer as before the refusals, and the instance steps on.
    assert_eq!(inst.derivative(&[ry], &[uy], &[1.0]), (OK, good));
    step_hertz(&inst, 2, 3);
    unsafe { assert_eq!((l.fmi2Terminate.as_ref().unwrap())(inst.c), OK) };
    assert_eq!(inst.derivative(&[ry], &[uy], &[1.0]).0, OK);

    let paper = TempScene::new(
        "paper",
        &edited(
            "verification/sliding_block.toml",
            &[(
                "mu_s = 0.3\nmu_d = 0.2",
                "mu_s = 0.3\nmu_d = 0.2\ndecisions = \"paper\"",
            )],
        ),
    );
    let u = unpack(&paper.0, "paper");
    let inst = Inst::new(&u, "paper");
    inst.init();
    assert_eq!(inst.set_real("top.uy", -0.005), OK);
    assert_eq!(inst.step(0.0, 0.5), OK);
    let (s, _) = inst.derivative(&[inst.vr("top.Ry")], &[inst.vr("top.uy")], &[1.0]);
    assert_eq!(s, ERROR);
    assert!(
        inst.last_message()
            .contains("'base' uses the paper's decisions"),
        "{}",
        inst.last_message()
    );
}

/// The sensitivities factor a state's tangent once, at the first request,
/// and solve every later one with it; a step or a restored state makes a
/// new one.
#[test]
fn sensitivities_factor_once_per_state() {
    use contact2d::newton::{Input, Response};
    let problem =
        contact2d::scene::load(&repo().join("scenes/verification/sliding_block.toml")).unwrap();
    let mut solver = Solver::new(problem.clone()).unwrap();
    for &t in &problem.times[..6] {
        solver.advance(t, &mut |_, _| {}).unwrap();
    }
    let seed = [(
        Input::Driver {
            driver: 0,
            component: 0,
        },
        1.0,
    )];
    let rx = [Response::Reaction {
        index: 0,
        component: 0,
    }];
    let before = solver.factorizations();
    let first = solver.sensitivity(&seed, &rx).unwrap();
    assert_eq!(solver.factorizations(), before + 1);
    for _ in 0..3 {
        assert_eq!(solver.sensitivity(&seed, &rx).unwrap(), first);
    }
    assert_eq!(
        solver.factorizations(),
        before + 1,
        "solved with the kept factor"
    );
    let state = solver.state().clone();
    solver.advance(problem.times[6], &mut |_, _| {}).unwrap();
    let after_step = solver.factorizations();
    solver.sensitivity(&seed, &rx).unwrap();
    assert_eq!(
        solver.factorizations(),
        after_step + 1,
        "a new state, a new factor"
    );
    solver.restore(state);
    assert_eq!(
        solver.sensitivity(&seed, &rx).unwrap(),
        first,
        "the restored state's"
    );
    assert_eq!(solver.factorizations(), after_step + 2);
    // Not an input, not a result: refused by name.
    let bad = solver.sensitivity(&[(Input::Pressure { pressure: 0 }, 1.0)], &rx);
    assert!(bad.unwrap_err().contains("Pressure"));
}

/// The bytes of `inst`'s state, serialized.
fn serialized(inst: &Inst) -> Vec<u8> {
    let l = lib();
    let mut state: fmi2FMUstate = null_mut();
    let mut size = 0usize;
    unsafe {
        assert_eq!(
            (l.fmi2GetFMUstate.as_ref().unwrap())(inst.c, &mut state),
            OK
        );
        let sized = l.fmi2SerializedFMUstateSize.as_ref().unwrap();
        assert_eq!(sized(inst.c, state, &mut size), OK);
    }
    let mut bytes = vec![0 as c_char; size];
    unsafe {
        let serialize = l.fmi2SerializeFMUstate.as_ref().unwrap();
        assert_eq!(serialize(inst.c, state, bytes.as_mut_ptr(), size), OK);
        assert_eq!(
            (l.fmi2FreeFMUstate.as_ref().unwrap())(inst.c, &mut state),
            OK
        );
    }
    bytes.into_iter().map(|b| b as u8).collect()
}

/// Issue 56, item 2: a serialized state edited in one array (a contact
/// pair's node or segment memory, the rigid targets' poses, the running
/// strips' memory: emptied, cut by one, extended by one) still reads back,
/// but fmi2SetFMUstate refuses it with a message that says what does not
/// fit, and the instance keeps its own state: the next step converges.
/// (It used to be accepted, and the next step failed on "index out of
/// bounds".)
#[test]
fn a_state_of_the_wrong_shape_is_refused_when_set() {
    let u = unpack(&repo().join("scenes/running_capstan.toml"), "shape");
    let l = lib();
    let inst = Inst::new(&u, "shape");
    inst.init();
    assert_eq!(inst.step(0.0, 0.05), OK, "{:?}", inst.messages());
    let bytes = serialized(&inst);
    let start = bytes
        .iter()
        .position(|&b| b == b'{')
        .expect("JSON after the header");
    let (head, body) = bytes.split_at(start);
    let json: serde_json::Value = serde_json::from_slice(body).unwrap();
    // The arrays to damage, as JSON pointers.
    let contact = &json["state"]["contact"][0];
    let (variant, _) = contact.as_object().unwrap().iter().next().unwrap();
    let mut arrays = vec![
        format!("/state/contact/0/{variant}/nodes"),
        "/state/rigid".to_string(),
        "/state/running".to_string(),
    ];
    if contact[variant].get("segments").is_some() {
        arrays.push(format!("/state/contact/0/{variant}/segments"));
    }
    type Edit = fn(&mut Vec<serde_json::Value>);
    let edits: [(&str, Edit); 3] = [
        ("emptied", |a| a.clear()),
        ("cut by one", |a| {
            a.pop();
        }),
        ("extended by one", |a| a.push(a[0].clone())),
    ];
    let mut t = 0.05;
    for pointer in &arrays {
        for (how, edit) in &edits {
            let mut damaged = json.clone();
            let array = damaged
                .pointer_mut(pointer)
                .unwrap()
                .as_array_mut()
                .unwrap();
            assert!(!array.is_empty(), "{pointer} is empty");
            edit(array);
            let mut out = head.to_vec();
            out.extend(serde_json::to_vec(&damaged).unwrap());
            let mut state: fmi2FMUstate = null_mut();
            unsafe {
                let read = l.fmi2DeSerializeFMUstate.as_ref().unwrap();
                let status = read(inst.c, out.as_ptr() as *const c_char, out.len(), &mut state);
                assert_eq!(status, OK, "{pointer} {how}: {}", inst.last_message());
                let set = (l.fmi2SetFMUstate.as_ref().unwrap())(inst.c, state);
                assert_eq!(set, ERROR, "{pointer} {how}: accepted");
                assert_eq!(
                    (l.fmi2FreeFMUstate.as_ref().unwrap())(inst.c, &mut state),
                    OK
                );
            }
            let said = inst.last_message();
            assert!(
                said.starts_with("fmi2SetFMUstate: the state does not fit this instance's model"),
                "{pointer} {how}: {said}"
            );
            assert_eq!(
                inst.step(t, 0.05),
                OK,
                "{pointer} {how}: {:?}",
                inst.messages()
            );
            t += 0.05;
        }
    }
}
