//! What a run leaves on disk: VTK files for ParaView (one per increment and a
//! time series) and the JSON summary of SPEC section 5. Writers only: they
//! take results, they never solve.

pub mod summary;
pub mod vtk;

pub use summary::Summary;
pub use vtk::{von_mises, write_pvd, write_vtu};
