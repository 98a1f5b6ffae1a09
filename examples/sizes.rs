//! Prints the size in bytes of what the core holds, for memory-budget.md:
//! `cargo run --release --example sizes`.

use hfray::camera::Camera;
use hfray::render::{RenderSettings, Stats};
use hfray::scene::{Gradient, Object, Scene};
use hfray::shading::Tracer;
use hfray::traversal::{Counters, GridHit, GridRay};
use hfray::{FieldHit, HeightField, Ray, Transform};

fn main() {
    let rows: [(&str, usize); 17] = [
        (
            "HeightField (per field; samples are borrowed)",
            size_of::<HeightField<'static>>(),
        ),
        ("Transform (f64 matrix and inverse)", size_of::<Transform>()),
        ("Ray", size_of::<Ray>()),
        (
            "GridRay<f32> (per ray, in the walk)",
            size_of::<GridRay<f32>>(),
        ),
        ("GridHit<f32>", size_of::<GridHit<f32>>()),
        ("FieldHit", size_of::<FieldHit>()),
        ("Counters", size_of::<Counters>()),
        ("ColumnHint", size_of::<hfray::ColumnHint>()),
        ("Camera", size_of::<Camera>()),
        (
            "RayCull (per frame: the field box's hull, the skyline and the floor line)",
            size_of::<hfray::render::RayCull>(),
        ),
        ("RenderSettings", size_of::<RenderSettings>()),
        ("Stats", size_of::<Stats>()),
        (
            "Object (scene model, per object)",
            size_of::<Object<'static>>(),
        ),
        (
            "Scene<'_, 4, 1, 0> (no gradient pigments)",
            size_of::<Scene<'static, 4, 1, 0>>(),
        ),
        (
            "Gradient (per gradient pigment, in the scene's pool)",
            size_of::<Gradient>(),
        ),
        (
            "Scene<'_, 32, 8> (default capacities: 4 gradients)",
            size_of::<Scene<'static, 32, 8>>(),
        ),
        (
            "Tracer<32> (prepared objects, on the stack while rendering)",
            size_of::<Tracer<'static, 32>>(),
        ),
    ];
    for (name, bytes) in rows {
        println!("{bytes:>7}  {name}");
    }
}
