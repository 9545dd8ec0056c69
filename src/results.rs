//! What one increment produced, in the names of the FMU and summary file
//! (SPEC section 5). Plain data: the CLI serializes it, the FMU reads it.

use serde::Serialize;

/// Force that a driver exerts on the body to impose its motion.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct DriverResult {
    #[serde(rename = "Rx")]
    pub rx: f64,
    #[serde(rename = "Ry")]
    pub ry: f64,
}

/// One converged (or failed) increment.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct StepResult {
    pub time: f64,
    pub converged: bool,
    /// Newton iterations summed over the sub-increments of this step.
    pub iterations: usize,
    /// Number of bisections used (0: the increment was taken whole).
    pub substeps: usize,
    /// Final relative force residual.
    pub residual: f64,
    /// Number of contact equations (0 until contact exists).
    pub neqc: usize,
    /// Per driver, by name, in scene order.
    pub drivers: Vec<(String, DriverResult)>,
}

/// Log categories; they are the FMU logger's categories.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LogCategory {
    Error,
    Warning,
    Newton,
    Contact,
}

impl LogCategory {
    pub fn fmi_name(self) -> &'static str {
        match self {
            LogCategory::Error => "logStatusError",
            LogCategory::Warning => "logStatusWarning",
            LogCategory::Newton => "logNewton",
            LogCategory::Contact => "logContact",
        }
    }
}
