//! contact2d: a 2D implicit finite-element solver for large-deformation
//! frictional contact (Bathe & Chaudhary 1984). Data flows one way:
//! scene -> problem (mesh, materials, loads) -> assembly -> Newton -> results.

pub mod assembly;
pub mod constraint;
pub mod contact;
pub mod element;
pub mod fmi;
pub mod kinematics;
pub mod linsolve;
pub mod material;
pub mod mesh;
pub mod newton;
pub mod output;
pub mod problem;
pub mod results;
pub mod running;
pub mod scene;
pub mod state;
pub mod strip;

/// Crate version and source revision of this build.
pub fn build_id() -> String {
    format!(
        "{} ({})",
        env!("CARGO_PKG_VERSION"),
        env!("CONTACT2D_REVISION")
    )
}
