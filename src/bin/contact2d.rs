//! The command line: `run` solves a scene's load history and writes what was
//! asked for (summary JSON, VTK series); `check` validates a scene and says
//! what it contains. Exit codes: 0 done, 1 a step failed or output could not
//! be written, 2 the scene (or the command line) is wrong.

use clap::{Parser, Subcommand};
use contact2d::newton::Solver;
use contact2d::output::{Frame, Summary, VtkSeries};
use contact2d::problem::{
    AnalysisKind, ContactFormulation, FrictionRule, Kinematics, MaterialSpec, Problem, Recovery,
    Scaled, Target,
};
use contact2d::results::{LogCategory, StepResult};
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::BTreeMap;
use std::io::{IsTerminal, Write as _};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (",
    env!("CONTACT2D_REVISION"),
    ")"
);

#[derive(Parser)]
#[command(
    name = "contact2d",
    version = VERSION,
    about = "2D implicit finite-element contact solver (Bathe & Chaudhary 1984)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve every increment of the scene's load history.
    Run {
        /// The scene file (TOML).
        scene: PathBuf,
        /// Write the JSON summary (SPEC section 5) to FILE.
        #[arg(long, value_name = "FILE")]
        summary: Option<PathBuf>,
        /// Write one .vtu per converged increment and a .pvd series into DIR.
        #[arg(long, value_name = "DIR")]
        vtk: Option<PathBuf>,
        /// Set a scene parameter ([parameters]) to another value; repeatable.
        #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parameter)]
        set: Vec<(String, f64)>,
        /// Print only errors (on stderr) and the final line; no progress bar.
        #[arg(short, long, conflicts_with = "verbose")]
        quiet: bool,
        /// Also print every Newton iteration and contact decision.
        #[arg(short, long)]
        verbose: bool,
        /// Write every line, Newton iterations and contact decisions
        /// included, to FILE (whatever --quiet or --verbose say).
        #[arg(long, value_name = "FILE")]
        log: Option<PathBuf>,
    },
    /// Build the FMU (FMI 2.0 co-simulation, or FMI 3.0 with --fmi 3) of a scene.
    Export {
        /// The scene file (TOML).
        scene: PathBuf,
        /// The FMU to write.
        #[arg(short, long, value_name = "NAME.fmu")]
        output: PathBuf,
        /// The FMI version: 2 (FMI 2.0, the default) or 3 (FMI 3.0, with a
        /// pair's per-node outputs as arrays).
        #[arg(long, value_name = "VERSION", default_value = "2", value_parser = ["2", "3"])]
        fmi: String,
        /// The shared library to ship (default: the portable build,
        /// target/x86_64-unknown-linux-gnu/fmu/libcontact2d.so, which
        /// scripts/build_fmu_library.sh builds first when it is missing or
        /// older than libcontact2d.so beside this executable).
        #[arg(long, value_name = "FILE")]
        library: Option<PathBuf>,
    },
    /// Print the scene's load history as the FMU's inputs: a CSV table
    /// (time, then one column per input variable) at t = 0 and at the end of
    /// every increment, as a master (e.g. fmpy's simulate_fmu) feeds them.
    Inputs {
        /// The scene file (TOML).
        scene: PathBuf,
        /// Write the table to FILE instead of standard output.
        #[arg(short, long, value_name = "FILE")]
        output: Option<PathBuf>,
    },
    /// Validate a scene and print what it contains.
    Check {
        /// The scene file (TOML).
        scene: PathBuf,
        /// Set a scene parameter ([parameters]) to another value; repeatable.
        #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parameter)]
        set: Vec<(String, f64)>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Run {
            scene,
            summary,
            vtk,
            set,
            quiet,
            verbose,
            log,
        } => {
            let verbosity = match (quiet, verbose) {
                (true, _) => Verbosity::Quiet,
                (_, true) => Verbosity::Verbose,
                _ => Verbosity::Normal,
            };
            let options = RunOptions {
                set: &set,
                summary: summary.as_deref(),
                vtk: vtk.as_deref(),
                log: log.as_deref(),
                verbosity,
            };
            run(&scene, &options)
        }
        Command::Check { scene, set } => check(&scene, &set),
        Command::Inputs { scene, output } => inputs(&scene, output.as_deref()),
        Command::Export {
            scene,
            output,
            fmi,
            library,
        } => export(&scene, &output, &fmi, library),
    }
}

/// The FMU's file name: `NAME` as given when it ends in `.fmu` (any case),
/// else `NAME.fmu` (a master looks for the extension; `h.v2` becomes
/// `h.v2.fmu`).
fn with_fmu_extension(output: &Path) -> PathBuf {
    match output.extension() {
        Some(e) if e.eq_ignore_ascii_case("fmu") => output.to_path_buf(),
        _ => {
            let mut name = output.as_os_str().to_owned();
            name.push(".fmu");
            PathBuf::from(name)
        }
    }
}

fn export(scene: &Path, output: &Path, fmi: &str, library: Option<PathBuf>) -> ExitCode {
    use contact2d::fmi::export::{FmiVersion, Packing};
    let output = &with_fmu_extension(output);
    let version = if fmi == "3" {
        FmiVersion::Fmi3
    } else {
        FmiVersion::Fmi2
    };
    // A scene that does not read fails before a library is built for it.
    if let Err(e) = contact2d::scene::load(scene) {
        return scene_failure(e);
    }
    // The portable library, the one made to ship, is packed thoroughly
    // (zopfli, once per build); a native or named one fast (zlib).
    let (library, packing) = match library {
        Some(named) => (named, Packing::Fast),
        None => match shipped_library() {
            Ok((library, true)) => (library, Packing::Thorough),
            Ok((library, false)) => (library, Packing::Fast),
            Err(msg) => return failure(msg),
        },
    };
    match contact2d::fmi::export::export_version(scene, output, &library, version, packing) {
        Ok(done) => {
            say(
                &None,
                &format!(
                    "{}: {} variables, {} bytes (library {})",
                    output.display(),
                    done.variables,
                    done.bytes,
                    library.display()
                ),
            );
            ExitCode::SUCCESS
        }
        Err(e @ contact2d::fmi::export::ExportError::Scene(_)) => scene_failure(e),
        Err(e) => failure(e),
    }
}

/// The library export ships when none is named: the portable one (glibc
/// 2.17, stripped), built first by `scripts/build_fmu_library.sh` of the
/// source tree this binary was built from when it is missing or older than
/// the native library beside this binary (the first export, and the first
/// after a change of the code). A binary away from its source tree ships
/// the native library with a warning. With whether it is the portable one.
fn shipped_library() -> Result<(PathBuf, bool), String> {
    use contact2d::fmi::export::default_library;
    let exe = std::env::current_exe().map_err(|e| format!("this executable's path: {e}"))?;
    if let Some((portable, true)) = default_library(&exe) {
        return Ok((portable, true));
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/build_fmu_library.sh");
    let target = exe.parent().and_then(Path::parent);
    if let (true, Some(target)) = (script.is_file(), target) {
        eprintln!(
            "export: building the portable library (glibc 2.17, stripped) with {}: about 5 minutes the first time, 1.5 after a change of the code",
            script.display()
        );
        let built = std::process::Command::new("bash")
            .arg(&script)
            .env("CARGO_TARGET_DIR", target)
            .stdout(std::io::stderr())
            .status()
            .map_err(|e| format!("cannot run {}: {e}", script.display()))?;
        return match default_library(&exe) {
            Some((portable, true)) if built.success() => Ok((portable, true)),
            _ => Err(format!(
                "{} failed ({built}): the portable library was not built; pass --library FILE to ship another",
                script.display()
            )),
        };
    }
    match default_library(&exe) {
        Some((native, _)) => {
            eprintln!(
                "warning: shipping {}, linked against this machine's glibc: the FMU may not load on an older Linux; this binary is away from its source tree ({}), whose scripts/build_fmu_library.sh builds the portable library (glibc 2.17) that export then ships",
                native.display(),
                env!("CARGO_MANIFEST_DIR")
            );
            Ok((native, false))
        }
        None => Err(
            "libcontact2d.so not found beside this executable: pass --library, or build from the source tree".into(),
        ),
    }
}

/// Scene error: printed with its file:line, exit code 2.
/// `NAME=VALUE` of `--set`.
fn parameter(arg: &str) -> Result<(String, f64), String> {
    let (name, value) = arg
        .split_once('=')
        .ok_or_else(|| format!("{arg:?}: NAME=VALUE expected"))?;
    let value: f64 = value
        .trim()
        .parse()
        .map_err(|_| format!("{arg:?}: the value {value:?} is not a number"))?;
    Ok((name.trim().to_string(), value))
}

fn scene_failure(msg: impl std::fmt::Display) -> ExitCode {
    eprintln!("error: {msg}");
    ExitCode::from(2)
}

fn failure(msg: impl std::fmt::Display) -> ExitCode {
    eprintln!("error: {msg}");
    ExitCode::from(1)
}

/// Prints a line on stdout, above the progress bar when there is one. A
/// closed stdout (`| head`) does not stop the solve.
fn say(bar: &Option<ProgressBar>, line: &str) {
    let print = || {
        let _ = writeln!(std::io::stdout(), "{line}");
    };
    match bar {
        Some(b) => b.suspend(print),
        None => print(),
    }
}

/// How much `run` prints on stdout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Verbosity {
    /// The final line only (errors go to stderr at every level).
    Quiet,
    /// What the scene is, a line per increment, bisections, the final line.
    Normal,
    /// Also every Newton iteration and contact decision.
    Verbose,
}

/// Where the lines of a run go: stdout as far as the verbosity asks (above
/// the progress bar), and every one of them to the log file when there is
/// one. A log that cannot be written is reported at the end (exit code 1);
/// the solve goes on.
struct Reporter {
    verbosity: Verbosity,
    bar: Option<ProgressBar>,
    log: Option<(PathBuf, std::io::BufWriter<std::fs::File>)>,
    log_error: Option<String>,
}

impl Reporter {
    fn line(&mut self, level: Verbosity, line: &str) {
        if self.verbosity >= level {
            say(&self.bar, line);
        }
        self.log(line);
    }

    /// A line for the log file only (the errors, which stderr shows).
    fn log(&mut self, line: &str) {
        if let Some((path, w)) = &mut self.log
            && self.log_error.is_none()
            && let Err(e) = writeln!(w, "{line}")
        {
            self.log_error = Some(format!("cannot write {}: {e}", path.display()));
        }
    }

    /// A message of the solver: Newton iterations and contact decisions at
    /// `--verbose`, warnings (bisections) by default, errors at `--verbose`
    /// (the reason of a failure ends the run on stderr).
    fn solver(&mut self, category: LogCategory, msg: &str) {
        let level = match category {
            LogCategory::Warning => Verbosity::Normal,
            LogCategory::Newton | LogCategory::Contact | LogCategory::Error => Verbosity::Verbose,
        };
        self.line(level, &format!("  [{}] {msg}", category.fmi_name()));
    }

    /// Flushes the log; the first error it met, if any.
    fn finish(&mut self) -> Result<(), String> {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
        if let Some((path, w)) = &mut self.log
            && self.log_error.is_none()
            && let Err(e) = w.flush()
        {
            self.log_error = Some(format!("cannot write {}: {e}", path.display()));
        }
        self.log_error.take().map_or(Ok(()), Err)
    }
}

/// What `run` was asked for besides the scene.
struct RunOptions<'a> {
    set: &'a [(String, f64)],
    summary: Option<&'a Path>,
    vtk: Option<&'a Path>,
    log: Option<&'a Path>,
    verbosity: Verbosity,
}

fn run(scene: &Path, o: &RunOptions) -> ExitCode {
    let problem = match contact2d::scene::load_with(scene, o.set) {
        Ok(p) => p,
        Err(e) => return scene_failure(e),
    };
    if o.verbosity > Verbosity::Quiet {
        for w in &problem.warnings {
            eprintln!("warning: {w}");
        }
    }
    let times = problem.times.clone();
    let driver_names: Vec<String> = problem.drivers.iter().map(|d| d.name.clone()).collect();
    let rigid_names: Vec<String> = problem.rigids.iter().map(|r| r.name.clone()).collect();
    let pair_names: Vec<String> = problem.contacts.iter().map(|c| c.name.clone()).collect();
    let max_bisections = problem.solver.max_bisections;
    let title = problem.name.clone();
    let (n_nodes, n_elements) = (problem.mesh.nodes.len(), problem.mesh.elements.len());
    let mut solver = match Solver::new(problem) {
        Ok(s) => s,
        Err(e) => return scene_failure(format!("{}: {e}", scene.display())),
    };

    // Fail before solving when the outputs cannot be written.
    let log = match prepare_outputs(o) {
        Ok(log) => log,
        Err(e) => return failure(e),
    };
    let stem = scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());

    let bar = (o.verbosity > Verbosity::Quiet && std::io::stdout().is_terminal()).then(|| {
        let style =
            ProgressStyle::with_template("{bar:40} {pos}/{len} increments, {msg} [{elapsed}]")
                .unwrap_or_else(|_| ProgressStyle::default_bar());
        ProgressBar::new(times.len() as u64).with_style(style)
    });
    let mut out = Reporter {
        verbosity: o.verbosity,
        bar,
        log,
        log_error: None,
    };
    out.line(
        Verbosity::Normal,
        &format!("contact2d {VERSION}: {title} ({})", scene.display()),
    );
    out.line(
        Verbosity::Normal,
        &format!(
            "{}, {}, {} unknowns, {}",
            count(n_nodes, "node"),
            count(n_elements, "element"),
            solver.dofs(),
            count(times.len(), "increment")
        ),
    );

    let mut summary = Summary::new(scene.display().to_string(), title, solver.dofs());
    let mut series = o.vtk.map(|dir| VtkSeries::new(dir, &stem));
    let (mut solve_time, mut failed) = (Duration::ZERO, None);
    if let Some(series) = &mut series {
        let rest = solver.rest_step();
        if let Err(e) = write_frame(series, 0, &solver, &rest) {
            failed = Some(format!(
                "cannot write the VTK frame at t = {}: {e}",
                rest.time
            ));
        }
    }
    if failed.is_none() {
        let names = [driver_names, rigid_names, pair_names];
        let mut run = Increments {
            solver: &mut solver,
            out: &mut out,
            summary: &mut summary,
            series: series.as_mut(),
        };
        (solve_time, failed) = run.solve(&times, &names, max_bisections);
    }
    summary.wall_s = solve_time.as_secs_f64();
    let mut errors: Vec<String> = failed.into_iter().collect();
    if let Some(series) = &series
        && let Err(e) = series.write_pvd()
    {
        errors.push(format!("cannot write {}: {e}", series.pvd_path().display()));
    }
    if let Some(path) = o.summary {
        match summary.write(path) {
            Ok(()) => out.line(Verbosity::Normal, &format!("summary: {}", path.display())),
            Err(e) => errors.push(format!("cannot write {}: {e}", path.display())),
        }
    }
    let p = solver.phases();
    out.line(
        Verbosity::Verbose,
        &format!("time by phase (%): {}", p.summary()),
    );
    if errors.is_empty() {
        let done = format!(
            "done: {} increments in {:.3} s",
            summary.steps.len(),
            summary.wall_s
        );
        out.line(Verbosity::Quiet, &done);
    } else {
        for e in &errors {
            out.log(&format!("error: {e}"));
        }
    }
    errors.extend(out.finish().err());
    match errors.split_last() {
        None => ExitCode::SUCCESS,
        Some((last, first)) => {
            for e in first {
                eprintln!("error: {e}");
            }
            failure(last)
        }
    }
}

/// A run's increments, with what they write to.
struct Increments<'a> {
    solver: &'a mut Solver,
    out: &'a mut Reporter,
    summary: &'a mut Summary,
    series: Option<&'a mut VtkSeries>,
}

impl Increments<'_> {
    /// Solves the increments to `times`, one line and one summary entry
    /// each (a failed one's entry names the drivers, rigid targets and
    /// pairs of `names`); the solve's wall time, and the error that
    /// stopped it.
    fn solve(
        &mut self,
        times: &[f64],
        [drivers, rigids, pairs]: &[Vec<String>; 3],
        max_bisections: usize,
    ) -> (Duration, Option<String>) {
        let mut solve_time = Duration::ZERO;
        for (i, &t) in times.iter().enumerate() {
            let mut newton_lines = 0;
            let started = Instant::now();
            let result = self.solver.advance(t, &mut |cat, msg| {
                if cat == LogCategory::Newton {
                    newton_lines += 1;
                }
                self.out.solver(cat, msg);
            });
            solve_time += started.elapsed();
            let step = match result {
                Ok(step) => step,
                Err(e) => {
                    self.summary.steps.push(Summary::failed_step(
                        t,
                        newton_lines,
                        max_bisections,
                        drivers.iter().cloned(),
                        rigids.iter().cloned(),
                        pairs.iter().cloned(),
                    ));
                    return (solve_time, Some(e.to_string()));
                }
            };
            let mut line = step_line(i + 1, times.len(), &step);
            for (name, tie) in self.solver.tie_results() {
                let [fx, fy] = tie.force;
                line.push_str(&format!("  {name}: tie Fx = {fx:.6e} Fy = {fy:.6e}"));
            }
            self.out.line(Verbosity::Normal, &line);
            let written = (self.series.as_deref_mut()).map_or(Ok(()), |series| {
                write_frame(series, i + 1, self.solver, &step)
            });
            self.summary.steps.push(step);
            if let Some(b) = &self.out.bar {
                b.set_message(format!("t = {t}"));
                b.inc(1);
            }
            if let Err(e) = written {
                return (
                    solve_time,
                    Some(format!("cannot write the VTK frame at t = {t}: {e}")),
                );
            }
        }
        (solve_time, None)
    }
}

/// The folders of the outputs made, and the log file opened: an error that
/// names the path when one cannot be.
fn prepare_outputs(
    o: &RunOptions,
) -> Result<Option<(PathBuf, std::io::BufWriter<std::fs::File>)>, String> {
    if let Some(dir) = o.vtk
        && let Err(e) = std::fs::create_dir_all(dir)
    {
        return Err(format!("cannot create {}: {e}", dir.display()));
    }
    for path in [o.summary, o.log].into_iter().flatten() {
        if let Some(parent) = path.parent()
            && !parent.as_os_str().is_empty()
            && let Err(e) = std::fs::create_dir_all(parent)
        {
            return Err(format!("cannot create {}: {e}", parent.display()));
        }
    }
    match o.log.map(|p| (p, std::fs::File::create(p))) {
        None => Ok(None),
        Some((p, Ok(f))) => Ok(Some((p.to_path_buf(), std::io::BufWriter::new(f)))),
        Some((p, Err(e))) => Err(format!("cannot create {}: {e}", p.display())),
    }
}

/// One frame of the VTK series: the solver's converged state with the
/// contact results of `step`.
fn write_frame(
    series: &mut VtkSeries,
    index: usize,
    solver: &Solver,
    step: &StepResult,
) -> std::io::Result<()> {
    let stress = solver.element_stresses();
    let plastic = solver.element_plastic_strains();
    let frame = Frame {
        time: step.time,
        u: &solver.state().u,
        stress: &stress,
        plastic_strain: plastic.as_deref(),
        pairs: &step.pairs,
        rigid_poses: &solver.state().rigid,
    };
    series.write_frame(index, solver.problem(), &frame)
}

/// One line per increment: time, work (Newton iterations, linear solves,
/// factorizations, bisections), residual, NEQC, driver reactions
/// (and a rigid target's moment), then per contact pair its resultants and
/// node counts by state.
fn step_line(i: usize, n: usize, s: &StepResult) -> String {
    use std::fmt::Write;
    let mut line = format!(
        "step {i}/{n}  t = {}  iterations {}  solves {}  factorizations {}  substeps {}  |r|/F = {:.3e}  NEQC {}",
        s.time, s.iterations, s.solves, s.factorizations, s.substeps, s.residual, s.neqc
    );
    for (name, r) in &s.drivers {
        let _ = write!(line, "  {name}: Rx = {:.6e} Ry = {:.6e}", r.rx, r.ry);
        if let Some(mz) = r.mz {
            let _ = write!(line, " Mz = {mz:.6e}");
        }
    }
    for (name, p) in &s.pairs {
        let _ = write!(
            line,
            "  {name}: Fn = {:.6e} Ft = {:.6e} stick/slip/open = {}/{}/{}",
            p.fn_, p.ft, p.n_stick, p.n_slip, p.n_open
        );
    }
    line
}

fn inputs(scene: &Path, output: Option<&Path>) -> ExitCode {
    use contact2d::fmi::variables::{Causality, input, variables};
    let problem = match contact2d::scene::load(scene) {
        Ok(p) => p,
        Err(e) => return scene_failure(e),
    };
    let vars: Vec<_> = variables(&problem)
        .into_iter()
        .filter(|v| v.causality == Causality::Input)
        .collect();
    let mut text = std::iter::once("time".to_string())
        .chain(vars.iter().map(|v| v.name.clone()))
        .collect::<Vec<_>>()
        .join(",");
    text.push('\n');
    for t in std::iter::once(0.0).chain(problem.times.iter().copied()) {
        let row = std::iter::once(t)
            .chain(vars.iter().filter_map(|v| input(&v.binding, &problem, t)))
            .map(|x| format!("{x:e}"))
            .collect::<Vec<_>>()
            .join(",");
        text.push_str(&row);
        text.push('\n');
    }
    let written = match output {
        Some(path) => std::fs::write(path, &text).map_err(|e| format!("{}: {e}", path.display())),
        None => std::io::stdout()
            .write_all(text.as_bytes())
            .map_err(|e| format!("standard output: {e}")),
    };
    match written {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => failure(&e),
    }
}

fn check(scene: &Path, set: &[(String, f64)]) -> ExitCode {
    let problem = match contact2d::scene::load_with(scene, set) {
        Ok(p) => p,
        Err(e) => return scene_failure(e),
    };
    for w in &problem.warnings {
        eprintln!("warning: {w}");
    }
    let mut text = describe(scene, &problem);
    let solver = Solver::new(problem);
    if let Ok(s) = &solver {
        text += &format!("unknowns: {}\nok\n", s.dofs());
    }
    let _ = std::io::stdout().write_all(text.as_bytes());
    match solver {
        Ok(_) => ExitCode::SUCCESS,
        Err(e) => scene_failure(format!("{}: {e}", scene.display())),
    }
}

fn scaled(s: &Scaled, p: &Problem) -> String {
    match s.function.and_then(|f| p.functions.get(f)) {
        Some(f) => format!("{} * {}(t)", s.scale, f.name),
        None => format!("{}", s.scale),
    }
}

/// What `check` prints about a scene.
fn describe(scene: &Path, p: &Problem) -> String {
    let mut o = String::new();
    describe_header(&mut o, scene, p);
    describe_materials(&mut o, p);
    describe_bodies(&mut o, p);
    describe_drivers(&mut o, p);
    describe_rigids(&mut o, p);
    describe_contacts(&mut o, p);
    describe_loads(&mut o, p);
    describe_steps(&mut o, p);
    o
}

/// The scene, its analysis and kinematics, parameters and mesh.
fn describe_header(o: &mut String, scene: &Path, p: &Problem) {
    use std::fmt::Write;
    let _ = writeln!(o, "scene: {} ({})", p.name, scene.display());
    let analysis = match p.analysis {
        AnalysisKind::PlaneStrain { thickness } => format!("plane strain, thickness {thickness}"),
        AnalysisKind::PlaneStress { thickness } => format!("plane stress, thickness {thickness}"),
        AnalysisKind::Axisymmetric => "axisymmetric".into(),
    };
    let kinematics = match p.kinematics {
        Kinematics::SmallStrain => "small strain",
        Kinematics::MaterialNonlinearOnly => "materially-nonlinear-only",
        Kinematics::TotalLagrangian => "total Lagrangian",
    };
    let _ = writeln!(o, "analysis: {analysis}; kinematics: {kinematics}");
    if !p.parameters.is_empty() {
        let list: Vec<String> = (p.parameters.iter())
            .map(|q| {
                let set = if q.value == q.default {
                    String::new()
                } else {
                    format!(" (scene: {})", q.default)
                };
                format!("{} = {}{set}", q.name, q.value)
            })
            .collect();
        let _ = writeln!(o, "parameters: {}", list.join(", "));
    }
    let _ = writeln!(
        o,
        "mesh: {}, {}",
        count(p.mesh.nodes.len(), "node"),
        count(p.mesh.elements.len(), "element")
    );
}

/// `n` things, the noun in the plural unless there is one.
fn count(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

/// The materials and their laws.
fn describe_materials(o: &mut String, p: &Problem) {
    use std::fmt::Write;
    let _ = writeln!(o, "materials:");
    for m in &p.materials {
        let law = match &m.spec {
            MaterialSpec::LinearElastic { e, nu } => format!("linear_elastic, E = {e}, nu = {nu}"),
            MaterialSpec::MooneyRivlin { c1, c2 } => {
                format!("mooney_rivlin (incompressible, plane stress), C1 = {c1}, C2 = {c2}")
            }
            MaterialSpec::VonMises { e, nu, sigma_y, h } => format!(
                "von_mises (linear isotropic hardening), E = {e}, nu = {nu}, sigma_y = {sigma_y}, H = {h}"
            ),
        };
        let _ = writeln!(o, "  {}: {law}", m.name);
    }
}

/// The bodies: elements by kind, nodes, material and their sets.
fn describe_bodies(o: &mut String, p: &Problem) {
    use std::fmt::Write;
    let _ = writeln!(o, "bodies:");
    for b in &p.bodies {
        let elements = p.mesh.elements.get(b.elements.clone()).unwrap_or(&[]);
        let mut kinds: BTreeMap<String, usize> = BTreeMap::new();
        for e in elements {
            *kinds.entry(format!("{:?}", e.kind)).or_default() += 1;
        }
        let kinds: Vec<String> = kinds.iter().map(|(k, n)| format!("{n} {k}")).collect();
        let material = p.materials.get(b.material).map_or("?", |m| m.name.as_str());
        let _ = writeln!(
            o,
            "  {}: {} ({}), {}, material {material}",
            b.name,
            count(elements.len(), "element"),
            kinds.join(", "),
            count(b.nodes.len(), "node")
        );
        // Set name -> (nodes, edges, elements) of this body.
        let prefix = format!("{}.", b.name);
        let mut sets: BTreeMap<&str, [Option<usize>; 3]> = BTreeMap::new();
        let counts = (p.mesh.node_sets.iter().map(|(k, v)| (0, k, v.len())))
            .chain(p.mesh.edge_sets.iter().map(|(k, v)| (1, k, v.len())))
            .chain(p.mesh.element_sets.iter().map(|(k, v)| (2, k, v.len())));
        for (c, name, n) in counts {
            if let Some(short) = name.strip_prefix(&prefix) {
                sets.entry(short).or_default()[c] = Some(n);
            }
        }
        let sets: Vec<String> = sets
            .iter()
            .map(|(name, counts)| {
                let parts: Vec<String> = counts
                    .iter()
                    .zip(["node", "edge", "element"])
                    .filter_map(|(n, what)| n.map(|n| count(n, what)))
                    .collect();
                format!("{name} ({})", parts.join(", "))
            })
            .collect();
        let _ = writeln!(o, "    sets: {}", sets.join(", "));
    }
}

/// The time functions and the drivers.
fn describe_drivers(o: &mut String, p: &Problem) {
    use std::fmt::Write;
    if !p.functions.is_empty() {
        let _ = writeln!(o, "functions:");
        for f in &p.functions {
            let _ = writeln!(o, "  {}: {}", f.name, count(f.points.len(), "point"));
        }
    }

    let _ = writeln!(o, "drivers:");
    if p.drivers.is_empty() {
        let _ = writeln!(o, "  (none)");
    }
    for d in &p.drivers {
        let comp = |c: usize| match (d.displacement(c), d.force(c)) {
            (Some(s), _) => format!("{} = {}", ["ux", "uy"][c], scaled(s, p)),
            (None, Some(s)) => format!("{} = {} (resultant)", ["fx", "fy"][c], scaled(s, p)),
            (None, None) => format!("{} = free", ["ux", "uy"][c]),
        };
        let _ = writeln!(
            o,
            "  {}: {}, {}, {}",
            d.name,
            count(d.nodes.len(), "node"),
            comp(0),
            comp(1)
        );
    }
}

/// The rigid targets: points, reference point, motion.
fn describe_rigids(o: &mut String, p: &Problem) {
    use std::fmt::Write;
    if !p.rigids.is_empty() {
        let _ = writeln!(o, "rigid targets:");
    }
    for r in &p.rigids {
        let [x, y] = r.reference;
        let motion = [("ux", &r.ux), ("uy", &r.uy), ("theta", &r.theta)];
        let driven: Vec<String> = (motion.iter())
            .filter(|(_, s)| s.function.is_some() || s.scale != 0.0)
            .map(|(c, s)| format!("{c} = {}", scaled(s, p)))
            .collect();
        let held: Vec<&str> = (motion.iter())
            .filter(|(_, s)| s.function.is_none() && s.scale == 0.0)
            .map(|(c, _)| *c)
            .collect();
        let mut line = format!(
            "  {}: {}, {}, reference ({x}, {y}); driven: {}",
            r.name,
            count(r.points.len(), "point"),
            count(r.points.len().saturating_sub(1), "segment"),
            if driven.is_empty() {
                "none".to_string()
            } else {
                driven.join(", ")
            }
        );
        if !held.is_empty() {
            line += &format!("; held at 0: {}", held.join(", "));
        }
        let _ = writeln!(o, "{line}");
    }
}

/// The contact pairs.
fn describe_contacts(o: &mut String, p: &Problem) {
    use std::fmt::Write;
    if !p.contacts.is_empty() {
        let _ = writeln!(o, "contact pairs:");
    }
    let body_name = |i: usize| p.bodies.get(i).map_or("?", |b| b.name.as_str());
    for c in &p.contacts {
        let target = match &c.target {
            Target::Body { body, segments, .. } => {
                format!(
                    "body {} ({})",
                    body_name(*body),
                    count(segments.len(), "segment")
                )
            }
            Target::Rigid(r) => match p.rigids.get(*r) {
                Some(r) => format!(
                    "rigid {} ({})",
                    r.name,
                    count(r.points.len().saturating_sub(1), "segment")
                ),
                None => "rigid ?".into(),
            },
        };
        let rule = match c.rule {
            FrictionRule::MuDAfterSlip => "mu_d after first slip",
            FrictionRule::AlwaysMuS => "mu_s throughout",
        };
        let recovery = match c.recovery {
            Recovery::Consistent => "consistent",
            Recovery::Lumped => "lumped",
        };
        // Rule and recovery are node-to-segment's; a mortar pair is
        // frictionless and its tractions are its multipliers.
        let how = match c.formulation {
            ContactFormulation::NodeToSegment => format!("rule: {rule}, recovery: {recovery}"),
            ContactFormulation::Mortar => "formulation: mortar".to_string(),
        };
        let _ = writeln!(
            o,
            "  {}: contactor {} ({}, {}) against {target}, mu_s = {}, mu_d = {}, {how}",
            c.name,
            body_name(c.body),
            count(c.contactor.len(), "node"),
            if c.closed { "closed" } else { "open" },
            c.mu_s,
            c.mu_d
        );
    }
}

/// Pressures, forces, body forces and initial stresses.
fn describe_loads(o: &mut String, p: &Problem) {
    use std::fmt::Write;
    let body_name = |i: usize| p.bodies.get(i).map_or("?", |b| b.name.as_str());
    let _ = writeln!(o, "loads:");
    let loads = p.pressures.len() + p.forces.len() + p.body_forces.len() + p.initial_stresses.len();
    if loads == 0 {
        let _ = writeln!(o, "  (none)");
    }
    for l in &p.pressures {
        let _ = writeln!(
            o,
            "  pressure {} on {} ({})",
            scaled(&l.value, p),
            count(l.edges.len(), "edge"),
            if l.follower { "follower" } else { "dead" }
        );
    }
    for l in &p.forces {
        let _ = writeln!(
            o,
            "  force fx = {}, fy = {} at each of {}",
            scaled(&l.fx, p),
            scaled(&l.fy, p),
            count(l.nodes.len(), "node")
        );
    }
    for l in &p.body_forces {
        let _ = writeln!(
            o,
            "  body force bx = {}, by = {} on {}",
            scaled(&l.bx, p),
            scaled(&l.by, p),
            body_name(l.body)
        );
    }
    for l in &p.initial_stresses {
        let [xx, yy, zz, xy] = l.stress;
        let _ = writeln!(
            o,
            "  initial stress xx = {xx}, yy = {yy}, zz = {zz}, xy = {xy} in {}",
            body_name(l.body)
        );
    }
}

/// The increments and the solver settings.
fn describe_steps(o: &mut String, p: &Problem) {
    use std::fmt::Write;
    match (p.times.first(), p.times.last()) {
        (Some(first), Some(last)) => {
            let _ = writeln!(
                o,
                "steps: {}, t = {first} .. {last}",
                count(p.times.len(), "increment")
            );
        }
        _ => {
            let _ = writeln!(o, "steps: none");
        }
    }
    let s = &p.solver;
    let _ = writeln!(
        o,
        "solver: force_tolerance {:e}, displacement_tolerance {:e}, energy_tolerance {:e}, \
         max_iterations {}, max_bisections {}",
        s.force_tolerance,
        s.displacement_tolerance,
        s.energy_tolerance,
        s.max_iterations,
        s.max_bisections
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use contact2d::results::{DriverResult, PairResult};

    #[test]
    fn step_line_has_moments_and_pairs() {
        let step = StepResult {
            time: 0.5,
            converged: true,
            iterations: 3,
            substeps: 0,
            solves: 3,
            factorizations: 2,
            fallbacks: 0,
            residual: 1e-9,
            neqc: 4,
            drivers: vec![
                ("base".into(), DriverResult::default()),
                (
                    "die".into(),
                    DriverResult {
                        rx: 1.0,
                        ry: -2.0,
                        mz: Some(0.25),
                        ..Default::default()
                    },
                ),
            ],
            pairs: vec![(
                "die_on_block".into(),
                PairResult {
                    fn_: 2.0,
                    ft: -0.5,
                    n_stick: 1,
                    n_slip: 2,
                    n_open: 3,
                    ..PairResult::default()
                },
            )],
            ties: vec![],
            running: vec![],
        };
        assert_eq!(
            step_line(1, 2, &step),
            "step 1/2  t = 0.5  iterations 3  solves 3  factorizations 2  substeps 0  |r|/F = 1.000e-9  NEQC 4  \
             base: Rx = 0.000000e0 Ry = 0.000000e0  \
             die: Rx = 1.000000e0 Ry = -2.000000e0 Mz = 2.500000e-1  \
             die_on_block: Fn = 2.000000e0 Ft = -5.000000e-1 stick/slip/open = 1/2/3"
        );
    }
}
