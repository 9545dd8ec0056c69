//! contact2d: a 2D implicit finite-element solver for large-deformation
//! frictional contact (Bathe & Chaudhary 1984). Data flows one way:
//! scene -> problem (mesh, materials, loads) -> assembly -> Newton -> results.

pub mod mesh;
pub mod newton;
pub mod problem;
pub mod results;
pub mod state;
pub mod assembly;
pub mod element;
pub mod kinematics;
pub mod linsolve;
pub mod material;
