//! hfray: a `no_std`, allocation-free ray tracer for height fields.
//!
//! (Crate documentation is being written; see README.md.)
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]
// `!(a <= b)` is how this crate rejects NaN along with out-of-range values;
// rewriting it with `partial_cmp` would only obscure that.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod camera;
mod cell;
pub mod generate;
pub mod heightfield;
pub mod pixel;
pub mod ray;
pub mod real;
pub mod render;
pub mod scene;
pub mod shading;
pub mod shapes;
pub mod transform;
pub mod traversal;

pub use camera::{Camera, CameraError};
pub use glam;
pub use heapless;
pub use heightfield::{HeightConvention, HeightField, HeightFieldError, Samples};
pub use pixel::{LinearRgb, Pixel, Rgb888};
pub use ray::{FieldHit, Ray, Triangle};
pub use real::Real;
pub use render::{render, render_depth, RenderError, RenderSettings, Stats};
pub use shading::Tracer;
pub use transform::Transform;
pub use traversal::Counters;

/// The README's code examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
