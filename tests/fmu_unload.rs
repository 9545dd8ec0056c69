//! Loading, using and unloading the FMU's library in one process, again
//! and again from the same path, as a master that runs a model more than
//! once does (fmpy's `FMU2Slave.freeInstance()` unloads the library): the
//! process survives every cycle, grows by under 10 KiB a cycle, and no
//! copy of the library stays mapped. Each cycle starts and ends the
//! instance's solving thread (`src/fmi/worker.rs`), which must be gone
//! before fmi2FreeInstance returns: a thread left running in the library
//! after `dlclose` kills the host.
//!
//! Its own test binary: the process must hold no other handle on the
//! library, or `dlclose` would not unload it.

use contact2d::fmi::description::guid;
use fmi_sys::fmi2::*;
use std::ffi::{CString, c_char, c_void};
use std::path::{Path, PathBuf};

const OK: fmi2Status = fmi2Status_fmi2OK;

/// How far a cycle goes before fmi2FreeInstance and `dlclose`.
#[derive(Clone, Copy, Debug)]
enum Cycle {
    /// Instantiate only (no solving call, no thread).
    Instantiate,
    /// Instantiate, initialise, terminate.
    Initialise,
    /// Instantiate, initialise, one step, terminate.
    Step,
    /// Instantiate, initialise, one step, no fmi2Terminate.
    StepUnterminated,
    /// Instantiate, initialise, one step, then unload without
    /// fmi2FreeInstance (the master's leak: the instance's thread must
    /// still end before the library's code goes).
    Unfreed,
}

fn library_path() -> PathBuf {
    contact2d::fmi::export::find_library(Path::new(env!("CARGO_BIN_EXE_contact2d")))
        .expect("libcontact2d.so built beside the binary or under deps/")
}

/// The logger receives the message as its sixth argument (tests/fmu.rs
/// says why); the cycles log nothing on success, and a failure shows in
/// the statuses the test checks.
unsafe extern "C" fn quiet(
    _env: fmi2ComponentEnvironment,
    _name: fmi2String,
    _status: fmi2Status,
    _category: fmi2String,
    _message: fmi2String,
    _text: *const c_char,
) {
}

fn callbacks() -> fmi2CallbackFunctions {
    type Plain = unsafe extern "C" fn(
        fmi2ComponentEnvironment,
        fmi2String,
        fmi2Status,
        fmi2String,
        fmi2String,
        *const c_char,
    );
    type Variadic = unsafe extern "C" fn(
        fmi2ComponentEnvironment,
        fmi2String,
        fmi2Status,
        fmi2String,
        fmi2String,
        ...
    );
    fmi2CallbackFunctions {
        logger: Some(unsafe { std::mem::transmute::<Plain, Variadic>(quiet) }),
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut::<c_void>(),
    }
}

/// The scene as an unpacked FMU's resources: its URI and GUID.
struct Unit {
    resources: CString,
    guid: CString,
    dir: PathBuf,
}

impl Unit {
    fn new(scene: &str) -> Unit {
        let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join(scene);
        let stem = scene.file_stem().unwrap().to_string_lossy().into_owned();
        let dir =
            std::env::temp_dir().join(format!("contact2d-unload-{}-{stem}", std::process::id()));
        std::fs::create_dir_all(dir.join("resources")).unwrap();
        std::fs::copy(&scene, dir.join("resources/scene.toml")).unwrap();
        let problem = contact2d::scene::load(&scene).unwrap();
        let uri = format!("file://{}", dir.join("resources").display());
        Unit {
            resources: CString::new(uri).unwrap(),
            guid: CString::new(guid(&problem)).unwrap(),
            dir,
        }
    }
}

impl Drop for Unit {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// One load, use and unload of the library at `path`.
fn cycle(path: &Path, unit: &Unit, how: Cycle, k: usize) {
    let lib = unsafe { Fmi2Binding::new(path) }.expect("load the library");
    let callbacks = callbacks();
    let name = CString::new(format!("cycle{k}")).unwrap();
    let c = unsafe {
        (lib.fmi2Instantiate.as_ref().unwrap())(
            name.as_ptr(),
            fmi2Type_fmi2CoSimulation,
            unit.guid.as_ptr(),
            unit.resources.as_ptr(),
            &callbacks,
            0,
            0,
        )
    };
    assert!(!c.is_null(), "{how:?}, cycle {k}: fmi2Instantiate failed");
    let call = |what: &str, status: fmi2Status| {
        assert_eq!(status, OK, "{how:?}, cycle {k}: {what}");
    };
    unsafe {
        if !matches!(how, Cycle::Instantiate) {
            call(
                "fmi2SetupExperiment",
                (lib.fmi2SetupExperiment.as_ref().unwrap())(c, 0, 0.0, 0.0, 0, 0.0),
            );
            let enter = lib.fmi2EnterInitializationMode.as_ref().unwrap();
            call("fmi2EnterInitializationMode", enter(c));
            let exit = lib.fmi2ExitInitializationMode.as_ref().unwrap();
            call("fmi2ExitInitializationMode", exit(c));
        }
        if matches!(how, Cycle::Step | Cycle::StepUnterminated | Cycle::Unfreed) {
            let step = lib.fmi2DoStep.as_ref().unwrap();
            call("fmi2DoStep", step(c, 0.0, 0.5, 1));
        }
        if matches!(how, Cycle::Initialise | Cycle::Step) {
            call("fmi2Terminate", (lib.fmi2Terminate.as_ref().unwrap())(c));
        }
        if !matches!(how, Cycle::Unfreed) {
            (lib.fmi2FreeInstance.as_ref().unwrap())(c);
        }
    }
    drop(lib);
}

/// This process's threads.
fn threads() -> usize {
    std::fs::read_dir("/proc/self/task").unwrap().count()
}

/// Waits (up to 2 s) for the threads to be back to `n`: a joined thread
/// stays listed for a moment while the kernel ends it.
fn threads_back_to(n: usize) -> usize {
    for _ in 0..200 {
        if threads() <= n {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    threads()
}

fn resident_kib() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let line = status.lines().find(|l| l.starts_with("VmRSS")).unwrap();
    line.split_whitespace().nth(1).unwrap().parse().unwrap()
}

/// How many mappings of files named like the library this process has.
fn mapped(path: &Path) -> usize {
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let maps = std::fs::read_to_string("/proc/self/maps").unwrap();
    maps.lines()
        .filter(|l| l.trim_end().trim_end_matches(" (deleted)").ends_with(&name))
        .count()
}

/// One test at a time: each counts this process's threads and mappings.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// `cycles` cycles of `how` on `scene`: the growth per cycle (KiB) between
/// the smallest resident sizes of a window after the warm-up and of the
/// last window (the allocator keeps freed pages for a while).
fn growth_per_cycle(scene: &str, how: Cycle, cycles: usize) -> f64 {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let path = library_path();
    let unit = Unit::new(scene);
    let mut samples = Vec::with_capacity(cycles);
    for k in 0..cycles {
        let before = threads();
        cycle(&path, &unit, how, k);
        assert_eq!(
            mapped(&path),
            0,
            "{how:?}: cycle {k} left the library mapped"
        );
        let after = threads_back_to(before);
        assert_eq!(after, before, "{how:?}: cycle {k} left a thread");
        samples.push(resident_kib());
    }
    let (warm, w) = (20, 10);
    let early = *samples[warm..warm + w].iter().min().unwrap();
    let late = *samples[cycles - w..].iter().min().unwrap();
    (late as f64 - early as f64) / (cycles - warm - w) as f64
}

/// 100 cycles in each of the four ways with a free, on the sliding block
/// and on Hertz: every cycle survives, unloads the library and leaves no
/// thread, and the process grows by under 10 KiB a cycle (a thread left
/// behind, or a copy pinned by thread-local destructors, costs megabytes).
#[test]
fn load_use_free_unload_cycles_survive_and_leave_nothing() {
    let scenes = [
        "scenes/verification/sliding_block.toml",
        "scenes/hertz_plane_strain.toml",
    ];
    let ways = [
        Cycle::Instantiate,
        Cycle::Initialise,
        Cycle::Step,
        Cycle::StepUnterminated,
    ];
    for scene in scenes {
        for how in ways {
            let kib = growth_per_cycle(scene, how, 100);
            eprintln!("{scene}, {how:?}: {kib:.2} KiB per cycle");
            assert!(kib < 10.0, "{scene}, {how:?}: {kib:.2} KiB per cycle");
        }
    }
}

/// A master that unloads the library without freeing its instance: the
/// instance's memory is the master's leak, but its thread is ended and
/// joined by the library's destructor, so the process survives, no thread
/// stays and the library is unmapped (before, the thread stayed parked in
/// the unmapped library and the process died at the next cycle or two).
#[test]
fn unloading_without_a_free_ends_the_instance_s_thread() {
    for scene in [
        "scenes/verification/sliding_block.toml",
        "scenes/hertz_plane_strain.toml",
    ] {
        let kib = growth_per_cycle(scene, Cycle::Unfreed, 40);
        eprintln!("{scene}, unfreed: {kib:.2} KiB per cycle (the instances left)");
    }
}
