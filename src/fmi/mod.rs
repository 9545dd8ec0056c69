//! The FMU (FMI 2.0 co-simulation, SPEC section 4; and FMI 3.0 from the
//! same library): the variables of a scene, its `modelDescription.xml`,
//! one instance's state machine, the C interfaces, and `export`, which zips
//! them with the shared library.

mod boundary;
pub mod description;
pub mod export;
mod ffi;
mod ffi3;
pub mod fmi3;
pub mod instance;
pub mod variables;
mod worker;

/// The scene's file name inside the FMU's `resources/`.
pub const SCENE_FILE: &str = "scene.toml";
