//! Errors compose: every public error type implements `core::error::Error`
//! (so `?` carries it into `Box<dyn Error>`), and each says what is wrong
//! where it happens.

use std::error::Error;

use hfray::camera::CameraError;
use hfray::generate::GenerateError;
use hfray::glam::DVec3;
use hfray::scene::{parse_scene, CameraDesc, Diagnostic, ParseOptions, Scene};
use hfray::shapes::ShapeError;
use hfray::skip::SkipError;
use hfray::transform::TransformError;
use hfray::{
    Camera, HeightConvention, HeightField, HeightFieldError, RenderError, Samples, SkipGrid,
    SkipLayout, Transform,
};

fn is_error<E: Error + Send + Sync + 'static>() {}

/// The error types this test knows, by name; `every_public_error_type_is_listed`
/// fails when the sources gain one that is not here.
const CHECKED: &[&str] = &[
    "CameraError",
    "Diagnostic",
    "GenerateError",
    "HeightFieldError",
    "RenderError",
    "ShapeError",
    "SkipError",
    "TransformError",
];

#[test]
fn every_public_error_type_implements_core_error() {
    is_error::<CameraError>();
    is_error::<Diagnostic<'static>>();
    is_error::<GenerateError>();
    is_error::<HeightFieldError>();
    is_error::<RenderError>();
    is_error::<ShapeError>();
    is_error::<SkipError>();
    is_error::<TransformError>();
}

/// Every `pub enum …Error` / `pub struct …Error` (and `Diagnostic`) under
/// `src/` is in [`CHECKED`], so a new error type cannot skip the check above.
#[test]
fn every_public_error_type_is_listed() {
    let mut found = Vec::new();
    let mut dirs = vec![std::path::PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/src"
    ))];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            for line in text.lines() {
                let line = line.trim_start();
                let Some(rest) = line
                    .strip_prefix("pub enum ")
                    .or_else(|| line.strip_prefix("pub struct "))
                else {
                    continue;
                };
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if name.ends_with("Error") || name == "Diagnostic" {
                    found.push(name);
                }
            }
        }
    }
    found.sort();
    found.dedup();
    assert_eq!(found, CHECKED, "add new error types to this test");
}

/// What a user writes: each fallible step of building a field, a skip grid,
/// a transform and a camera, carried out with `?`.
fn build_everything() -> Result<(), Box<dyn Error>> {
    let samples = [0u8, 10, 20, 30];
    let place = Transform::scale(DVec3::splat(2.0))?;
    let field = HeightField::new(Samples::U8(&samples), 2, 2, HeightConvention::Gray8)?
        .with_water_level(0.5)?
        .with_transform(place);
    let layout = SkipLayout::blocks(1);
    let mut buffer = vec![0u8; SkipGrid::bytes_needed_for(&field, layout)?];
    SkipGrid::build(&field, layout, &mut buffer)?;
    let _field = field.with_skip(&buffer)?;
    let _camera = Camera::new(&CameraDesc::default(), 0, 4)?; // fails: empty image
    Ok(())
}

fn parse_static_scene() -> Result<(), Box<dyn Error>> {
    let _scene: Scene<'static, 1, 1> = parse_scene(
        "sphere { <0, 0, 0>, 1 } bogus",
        &ParseOptions::new(320, 240),
        &mut |_| {},
    )?;
    Ok(())
}

#[test]
fn question_mark_carries_each_error_into_box_dyn_error() {
    let error = build_everything().unwrap_err();
    assert_eq!(
        error.downcast_ref::<CameraError>(),
        Some(&CameraError::EmptyImage)
    );
    let error = parse_static_scene().unwrap_err();
    assert!(
        error.downcast_ref::<Diagnostic<'static>>().is_some(),
        "{error}"
    );
}

/// A palette on a 16-bit field used to be accepted, and the render then
/// said the field "has none". `with_palette` now refuses it itself.
#[test]
fn with_palette_on_a_16_bit_field_is_an_error_at_that_call() {
    let samples = [0u16, 1000, 2000, 3000];
    let palette = [[0u8; 3]; 256];
    let field = HeightField::new(Samples::U16(&samples), 2, 2, HeightConvention::Gray16).unwrap();
    let error = field.with_palette(&palette).unwrap_err();
    assert_eq!(error, HeightFieldError::PaletteNeeds8Bit);
    assert!(error.to_string().contains("16-bit"), "{error}");
}
