//! The summary file of a run (SPEC section 5): one JSON object with the
//! scene, the number of unknowns, the wall time and one entry per increment,
//! in the FMU's names. Drivers keep their scene order (a JSON object written
//! in that order); a failed increment is the last entry, `converged: false`.

use crate::results::{DriverResult, StepResult};
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

    /// The entry of an increment that did not converge. What it does not
    /// know (final residual, reactions) is NaN, written as `null`.
    pub fn failed_step(
        time: f64,
        iterations: usize,
        substeps: usize,
        driver_names: impl IntoIterator<Item = String>,
    ) -> StepResult {
        StepResult {
            time,
            converged: false,
            iterations,
            substeps,
            residual: f64::NAN,
            neqc: 0,
            drivers: driver_names
                .into_iter()
                .map(|n| {
                    (
                        n,
                        DriverResult {
                            rx: f64::NAN,
                            ry: f64::NAN,
                            mz: None,
                        },
                    )
                })
                .collect(),
            pairs: Vec::new(),
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
        st.serialize_field("drivers", &Drivers(&r.drivers))?;
        // Contact pairs arrive with the contact algorithm.
        st.serialize_field("pairs", &EmptyObject)?;
        st.end()
    }
}

struct Drivers<'a>(&'a [(String, DriverResult)]);

impl Serialize for Drivers<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (name, r) in self.0 {
            m.serialize_entry(name, r)?;
        }
        m.end()
    }
}

struct EmptyObject;

impl Serialize for EmptyObject {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_map(Some(0))?.end()
    }
}
