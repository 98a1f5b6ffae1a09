//! hfray: a `no_std`, allocation-free ray tracer for height fields.
//!
//! (Crate documentation is being written; see README.md.)
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod cell;
pub mod generate;
pub mod heightfield;
pub mod ray;
pub mod real;
pub mod scene;
pub mod transform;
pub mod traversal;

pub use glam;
pub use heapless;
pub use heightfield::{HeightConvention, HeightField, HeightFieldError, Samples};
pub use ray::{FieldHit, Ray, Triangle};
pub use real::Real;
pub use transform::Transform;
pub use traversal::Counters;
