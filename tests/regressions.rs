//! Regression tests for the inputs fuzzing found (fuzz/, `cargo +nightly
//! fuzz run TARGET`), one per case, named after it. Each states the input,
//! what went wrong, and what must hold now.

use std::ops::ControlFlow;

use hfray::scene::{parse_scene, ParseOptions, Scene};
use hfray::{render, LinearRgb, RenderSettings};

/// Renders `src` (no height fields) at `width × height` with `aa`, in
/// linear colour.
fn render_text(src: &str, width: u32, height: u32, aa: u32) -> Vec<LinearRgb> {
    let options = ParseOptions {
        image_width: width,
        image_height: height,
        ..ParseOptions::default()
    };
    let scene: Scene<'_, 16, 4> = parse_scene(src, &options, &mut |_| {}).unwrap();
    let mut line = vec![LinearRgb::default(); width as usize];
    let mut out = Vec::new();
    render(
        &scene,
        &[],
        &RenderSettings::new(width, height).with_aa(aa),
        &mut line,
        &mut |_, row: &[LinearRgb]| {
            out.extend_from_slice(row);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    out
}

/// fuzz/render_scene, crash-cf99b48367ff477b7b17b0597a99fb8102db3f0a
/// (minimised): `color 11111111111` sets all five channels, so filter and
/// transmit are 1.1e10 too. The light entering the sphere is multiplied by
/// `f·C + t` ≈ 1.2e20 at each surface, overflows `f32` on the way out
/// (+inf), while the local term, weighted by `1 − f − t` < 0, is −inf:
/// their sum was a NaN pixel. Colours must stay finite numbers, whatever the
/// (finite) scene values.
#[test]
fn huge_filter_and_transmit_gave_nan_pixels() {
    let src = "#declare R = .5;\n\
               camera{ orthographic location <0, 5, -5> /image_height }\n\
               sphere { <0, 1, 0>,R pigment { color 11111111111} }\n";
    let pixels = render_text(src, 16, 12, 2);
    assert_eq!(pixels.len(), 16 * 12);
    for (i, p) in pixels.iter().enumerate() {
        assert!(p.0.is_finite(), "pixel {i}: {:?}", p.0);
    }
}
