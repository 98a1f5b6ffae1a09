//! Scenes: the model of a scene, and (soon) the POV-Ray subset parser.

pub mod model;

pub use model::*;
