//! The summary file of a run (SPEC section 5): one JSON object with the
//! scene, the number of unknowns, the wall time and one entry per increment,
//! in the FMU's names. Drivers and contact pairs keep their scene order (JSON
//! objects written in that order); a failed increment is the last entry,
//! `converged: false`. A value that is not known is written as `null`.

use crate::constraint::TieResult;
use crate::results::{DriverResult, PairResult, StepResult};
use serde::Serialize;
use serde::ser::{SerializeMap, SerializeStruct, Serializer};
use std::io::{self, BufWriter, Write};
use std::path::Path;

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Summary {
    /// The scene file as given on the command line.
    pub scene: String,
    /// Number of unknowns of the linear system.
    pub dofs: usize,
    /// Wall time of the solve, seconds.
    pub wall_s: f64,
    #[serde(serialize_with = "steps_json")]
    pub steps: Vec<StepResult>,
    /// The scene's title.
    pub title: String,
    /// Crate version and source revision that produced the file.
    pub build: String,
}

impl Summary {
    pub fn new(scene: impl Into<String>, title: impl Into<String>, dofs: usize) -> Self {
        Summary {
            scene: scene.into(),
            dofs,
            wall_s: 0.0,
            steps: Vec::new(),
            title: title.into(),
            build: crate::build_id(),
        }
    }

    /// The entry of an increment that did not converge, with the same keys
    /// as a converged one so that a reader need not tell them apart to index
    /// them. What it does not know is written as `null`: the final residual,
    /// every driver's Rx and Ry, every rigid target's Rx, Ry and Mz (rigid
    /// targets follow the drivers, as in a converged step), and every pair's
    /// Fx, Fy, Fn, Ft, n_stick, n_slip, n_open, stick_length and
    /// slip_length. A pair's `nodes` holds
    /// five empty arrays: the node count is not known here, and a reader
    /// that loops over the nodes of every step needs no special case.
    pub fn failed_step(
        time: f64,
        iterations: usize,
        substeps: usize,
        driver_names: impl IntoIterator<Item = String>,
        rigid_names: impl IntoIterator<Item = String>,
        pair_names: impl IntoIterator<Item = String>,
    ) -> StepResult {
        let unknown = |mz| DriverResult {
            rx: f64::NAN,
            ry: f64::NAN,
            mz,
            ..Default::default()
        };
        let drivers = (driver_names.into_iter().map(|n| (n, unknown(None))))
            .chain(
                rigid_names
                    .into_iter()
                    .map(|n| (n, unknown(Some(f64::NAN)))),
            )
            .collect();
        let pairs = pair_names
            .into_iter()
            .map(|n| {
                let pair = PairResult {
                    fx: f64::NAN,
                    fy: f64::NAN,
                    fn_: f64::NAN,
                    ft: f64::NAN,
                    ..PairResult::default()
                };
                (n, pair)
            })
            .collect();
        StepResult {
            time,
            converged: false,
            iterations,
            substeps,
            residual: f64::NAN,
            solves: 0,
            factorizations: 0,
            fallbacks: 0,
            neqc: 0,
            drivers,
            pairs,
            ties: Vec::new(),
            running: Vec::new(),
        }
    }

    pub fn to_json(&self) -> String {
        // Plain data with string keys: serialization cannot fail.
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    pub fn write(&self, path: &Path) -> io::Result<()> {
        let mut w = BufWriter::new(std::fs::File::create(path)?);
        serde_json::to_writer_pretty(&mut w, self).map_err(io::Error::other)?;
        w.write_all(b"\n")?;
        w.flush()
    }
}

fn steps_json<S: Serializer>(steps: &[StepResult], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(steps.iter().map(StepJson))
}

/// One increment in the summary's shape: drivers and pairs as objects.
struct StepJson<'a>(&'a StepResult);

impl Serialize for StepJson<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let r = self.0;
        let mut st = s.serialize_struct("Step", 8)?;
        st.serialize_field("time", &r.time)?;
        st.serialize_field("converged", &r.converged)?;
        st.serialize_field("iterations", &r.iterations)?;
        st.serialize_field("substeps", &r.substeps)?;
        st.serialize_field("residual", &r.residual)?;
        st.serialize_field("neqc", &r.neqc)?;
        st.serialize_field("drivers", &Named(&r.drivers, |d| d))?;
        st.serialize_field("pairs", &Named(&r.pairs, PairJson))?;
        if !r.ties.is_empty() {
            st.serialize_field("ties", &Named(&r.ties, TieJson))?;
        }
        if !r.running.is_empty() {
            st.serialize_field("running", &Named(&r.running, |r| r))?;
        }
        st.end()
    }
}

/// Named entries as one JSON object whose keys keep the slice's order, each
/// value serialized in the shape the function gives it.
struct Named<'a, T, W>(&'a [(String, T)], fn(&'a T) -> W);

impl<'a, T, W: Serialize> Serialize for Named<'a, T, W> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (name, v) in self.0 {
            m.serialize_entry(name, &(self.1)(v))?;
        }
        m.end()
    }
}

/// A tie in the summary's shape: its resultant on the tied nodes and, per
/// tied node (the tie's node order), the current position and the forces
/// along the surface normal (`fn`, compression positive) and tangent (`ft`).
struct TieJson<'a>(&'a TieResult);

impl Serialize for TieJson<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let t = self.0;
        let mut st = s.serialize_struct("Tie", 3)?;
        st.serialize_field("Fx", &t.force[0])?;
        st.serialize_field("Fy", &t.force[1])?;
        st.serialize_field(
            "nodes",
            &TieNodes {
                x: t.position.iter().map(|p| p[0]).collect(),
                y: t.position.iter().map(|p| p[1]).collect(),
                fn_: &t.normal,
                ft: &t.tangential,
            },
        )?;
        st.end()
    }
}

#[derive(Serialize)]
struct TieNodes<'a> {
    x: Vec<f64>,
    y: Vec<f64>,
    #[serde(rename = "fn")]
    fn_: &'a [f64],
    ft: &'a [f64],
}

/// A pair in the summary's shape. Its node counts are `null` when nothing is
/// known about its nodes (no node arrays: the entry of a failed increment);
/// a pair always has contactor nodes, so a solved one never looks like that.
struct PairJson<'a>(&'a PairResult);

impl Serialize for PairJson<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let p = self.0;
        let known = !p.nodes.state.is_empty();
        let count = |n: usize| known.then_some(n);
        let mut st = s.serialize_struct("Pair", 10)?;
        st.serialize_field("Fx", &p.fx)?;
        st.serialize_field("Fy", &p.fy)?;
        st.serialize_field("Fn", &p.fn_)?;
        st.serialize_field("Ft", &p.ft)?;
        st.serialize_field("n_stick", &count(p.n_stick))?;
        st.serialize_field("n_slip", &count(p.n_slip))?;
        st.serialize_field("n_open", &count(p.n_open))?;
        let length = |l: f64| known.then_some(l);
        st.serialize_field("stick_length", &length(p.stick_length))?;
        st.serialize_field("slip_length", &length(p.slip_length))?;
        st.serialize_field("nodes", &p.nodes)?;
        st.end()
    }
}
