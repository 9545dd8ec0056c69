//! The FMU (FMI 2.0 co-simulation, SPEC section 4): the variables of a
//! scene, its `modelDescription.xml`, one instance's state machine, the C
//! interface, and `export`, which zips them with the shared library.

pub mod description;
pub mod export;
mod ffi;
pub mod instance;
pub mod variables;

/// The scene's file name inside the FMU's `resources/`.
pub const SCENE_FILE: &str = "scene.toml";
