//! What a run leaves on disk: VTK files for ParaView (the solid, contact
//! surfaces and rigid targets at every converged increment, and a time
//! series) and the JSON summary of SPEC section 5. Writers only: they take
//! results, they never solve.

pub mod series;
pub mod summary;
pub mod vtk;

pub use series::{Frame, VtkSeries};
pub use summary::Summary;
pub use vtk::{PvdEntry, von_mises, write_pvd, write_vtu};
