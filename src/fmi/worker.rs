//! The calls that solve (a step, initialisation, directional derivatives)
//! run on a thread of the instance's own, started at its first such call
//! and ended when the instance is freed. faer's dense kernels keep buffers
//! in thread-locals whose destructors glibc registers against this library
//! (`__cxa_thread_atexit_impl`): made on the master's thread, they would
//! keep the library loaded after `dlclose` for as long as that thread
//! lives, and a master that loads a fresh copy per run (a sweep that
//! extracts an FMU per case) would keep every copy. Made on the instance's
//! thread, they go when it ends.
//!
//! Every live worker is listed (`LIVE`): should the library be unloaded
//! while one lives (a master that unloads without fmi2FreeInstance, or a
//! free deferred to a call that never returned), the library's destructor
//! ends and joins it before the library's code goes, instead of leaving a
//! thread parked in unmapped code.

use super::instance::{Instance, LogFn, Status};
use std::ffi::c_void;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};

// A plain POSIX thread: `std::thread::spawn` would itself register a
// thread-local destructor on the master's thread (its spawn hooks), which
// is what this module avoids.
unsafe extern "C" {
    fn pthread_create(
        thread: *mut usize,
        attr: *const c_void,
        start: extern "C" fn(*mut c_void) -> *mut c_void,
        arg: *mut c_void,
    ) -> i32;
    fn pthread_join(thread: usize, retval: *mut *mut c_void) -> i32;
}

/// The instance crosses to the worker thread and back.
const _: fn() = || {
    fn send<T: Send>() {}
    send::<Instance>();
};

type Line = (Status, String, String);

/// A call's work, its borrows' lifetime erased: the calling thread waits
/// until the worker has run it (`Worker::run`).
struct Job(*mut (dyn FnMut() + 'static));
unsafe impl Send for Job {}

/// What the two threads hand each other: the job, then the log lines it
/// writes as they come and that it is done; or that the worker must end.
#[derive(Default)]
struct Mailbox {
    job: Option<Job>,
    lines: Vec<Line>,
    done: bool,
    quit: bool,
}

#[derive(Default)]
struct Post {
    mailbox: Mutex<Mailbox>,
    to_worker: Condvar,
    to_caller: Condvar,
}

impl Post {
    fn open(&self) -> MutexGuard<'_, Mailbox> {
        self.mailbox.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// The live workers' threads and mailboxes, with the process that
/// started each.
static LIVE: Mutex<Vec<(u32, usize, Arc<Post>)>> = Mutex::new(Vec::new());

fn live() -> MutexGuard<'static, Vec<(u32, usize, Arc<Post>)>> {
    LIVE.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Ends the thread of `post` and waits until it is gone.
fn end(thread: usize, post: &Post) {
    post.open().quit = true;
    post.to_worker.notify_one();
    unsafe { pthread_join(thread, std::ptr::null_mut()) };
}

/// Run by the dynamic loader when it unloads the library (and at exit):
/// the workers still alive in this process are ended and joined.
extern "C" fn end_every_worker() {
    let pid = std::process::id();
    let workers = std::mem::take(&mut *live());
    for (owner, thread, post) in workers {
        if owner == pid {
            end(thread, &post);
        }
    }
}

#[used]
#[unsafe(link_section = ".fini_array")]
static END_EVERY_WORKER: extern "C" fn() = end_every_worker;

/// An instance's thread for the calls that solve.
pub(super) struct Worker {
    thread: usize,
    post: Arc<Post>,
    /// The process that started the thread: a child forked from it has the
    /// worker's memory but not its thread.
    pid: u32,
}

extern "C" fn serve(post: *mut c_void) -> *mut c_void {
    let post = unsafe { Arc::from_raw(post as *const Post) };
    loop {
        let job = {
            let mut mailbox = post.open();
            loop {
                if let Some(job) = mailbox.job.take() {
                    break job;
                }
                if mailbox.quit {
                    return std::ptr::null_mut();
                }
                mailbox = (post.to_worker.wait(mailbox)).unwrap_or_else(PoisonError::into_inner);
            }
        };
        // The job catches its own panics (`Worker::run`).
        unsafe { (*job.0)() };
        post.open().done = true;
        post.to_caller.notify_one();
    }
}

impl Worker {
    /// The thread, waiting for work; None when no thread could start.
    pub(super) fn start() -> Option<Worker> {
        let post = Arc::new(Post::default());
        let arg = Arc::into_raw(Arc::clone(&post)) as *mut c_void;
        let mut thread = 0usize;
        if unsafe { pthread_create(&mut thread, std::ptr::null(), serve, arg) } != 0 {
            drop(unsafe { Arc::from_raw(arg as *const Post) });
            return None;
        }
        let pid = std::process::id();
        live().push((pid, thread, Arc::clone(&post)));
        Some(Worker { thread, post, pid })
    }

    /// Whether the thread runs in this process (not in the parent of a
    /// forked child that inherited the instance).
    pub(super) fn here(&self) -> bool {
        self.pid == std::process::id()
    }

    /// Runs `f` on the instance on the worker thread; the log lines it
    /// writes reach the instance's logger on this thread, in order, while
    /// it runs. A panic in `f` is raised again here.
    pub(super) fn run<R>(&self, inst: &mut Instance, f: impl FnOnce(&mut Instance) -> R) -> R {
        let sink = Arc::clone(&self.post);
        let to_post: LogFn = Box::new(move |status, category, msg| {
            let line = (status, category.to_string(), msg.to_string());
            sink.open().lines.push(line);
            sink.to_caller.notify_one();
        });
        let mut logger = inst.replace_logger(to_post);
        let mut outcome = None;
        let mut f = Some(f);
        let mut work = || {
            if let Some(f) = f.take() {
                outcome = Some(catch_unwind(AssertUnwindSafe(|| f(&mut *inst))));
            }
        };
        let job: *mut (dyn FnMut() + '_) = &mut work;
        // Sound as a scoped thread is: this thread waits below until the
        // worker has run the job, so every borrow in it outlives that run.
        let job = unsafe {
            std::mem::transmute::<*mut (dyn FnMut() + '_), *mut (dyn FnMut() + 'static)>(job)
        };
        {
            let mut mailbox = self.post.open();
            mailbox.done = false;
            mailbox.job = Some(Job(job));
        }
        self.post.to_worker.notify_one();
        loop {
            let (lines, done) = {
                let mut mailbox = self.post.open();
                while mailbox.lines.is_empty() && !mailbox.done {
                    mailbox =
                        (self.post.to_caller.wait(mailbox)).unwrap_or_else(PoisonError::into_inner);
                }
                (std::mem::take(&mut mailbox.lines), mailbox.done)
            };
            for (status, category, msg) in lines {
                logger(status, &category, &msg);
            }
            if done {
                break;
            }
        }
        drop(inst.replace_logger(logger));
        match outcome {
            Some(Ok(r)) => r,
            Some(Err(panic)) => resume_unwind(panic),
            None => unreachable!("the worker ran the job"),
        }
    }
}

/// The thread ends, and its thread-locals with it, before the instance's
/// memory goes. (In a forked child there is no thread to end.)
impl Drop for Worker {
    fn drop(&mut self) {
        if !self.here() {
            return;
        }
        let mut live = live();
        let listed = live.iter().position(|(_, t, _)| *t == self.thread);
        // Not listed: the library's destructor has ended it already.
        if let Some(k) = listed {
            live.swap_remove(k);
            drop(live);
            end(self.thread, &self.post);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::results::LogCategory;

    /// The sliding block's instance with a logger that records each line
    /// and the thread it was called on.
    fn instance(lines: &Arc<Mutex<Vec<(String, std::thread::ThreadId)>>>) -> Instance {
        let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes/verification/sliding_block.toml");
        let problem = crate::scene::load(&scene).unwrap();
        let guid = super::super::description::guid(&problem);
        let lines = Arc::clone(lines);
        let log: LogFn = Box::new(move |_, _, msg| {
            let me = std::thread::current().id();
            lines.lock().unwrap().push((msg.to_string(), me));
        });
        Instance::new("worker", &scene, &guid, true, log).unwrap()
    }

    /// The job runs on another thread; its log lines reach the logger on
    /// the calling thread, in order; a second job runs on the same thread;
    /// a panic in a job is raised on the caller, and the instance logs to
    /// its own logger afterwards.
    #[test]
    fn jobs_run_on_the_worker_and_log_on_the_caller() {
        let lines = Arc::new(Mutex::new(Vec::new()));
        let mut inst = instance(&lines);
        lines.lock().unwrap().clear();
        let worker = Worker::start().expect("a thread");
        let here = std::thread::current().id();
        let mut ran_on = Vec::new();
        for _ in 0..2 {
            ran_on.push(worker.run(&mut inst, |inst| {
                for k in 0..3 {
                    inst.log(LogCategory::Warning, &format!("line {k}"));
                }
                std::thread::current().id()
            }));
        }
        assert_ne!(ran_on[0], here);
        assert_eq!(ran_on[0], ran_on[1], "one thread per worker");
        let said: Vec<_> = lines.lock().unwrap().drain(..).collect();
        let texts: Vec<&str> = said.iter().map(|(m, _)| m.as_str()).collect();
        assert_eq!(texts, ["line 0", "line 1", "line 2"].repeat(2));
        assert!(
            said.iter().all(|(_, t)| *t == here),
            "logged off the caller's thread"
        );

        let panicked = catch_unwind(AssertUnwindSafe(|| {
            worker.run(&mut inst, |inst| {
                inst.log(LogCategory::Warning, "before");
                panic!("in the job")
            })
        }));
        let payload = panicked.expect_err("the job's panic reaches the caller");
        assert_eq!(payload.downcast_ref::<&str>(), Some(&"in the job"));
        inst.log(LogCategory::Warning, "after");
        let texts: Vec<String> = lines
            .lock()
            .unwrap()
            .iter()
            .map(|(m, _)| m.clone())
            .collect();
        assert_eq!(texts, ["before", "after"]);
        drop(worker);
    }
}
