// What `build.rs` precomputes into the Cortex-M flash (the `lcd` and
// `thesis` skip pyramids, the `thesis` field, vertex normals) and the other
// programs make at run time, included by both `scene.rs` and `build.rs` so
// they make the same bytes.

/// Samples per row of the embedded field.
pub const FIELD_WIDTH: u32 = 87;
/// Rows of the embedded field.
pub const FIELD_DEPTH: u32 = 61;

/// Maunga Whau (Mt Eden), 87 × 61 8-bit gray samples, image row 0 (north)
/// first: `data/maunga_whau_87x61.u8.raw`, decoded from the shared PNG by
/// `tools/png_to_raw.py` (provenance in `data/maunga_whau_volcano_87x61.txt`).
/// A `static`, so on the microcontrollers it stays in flash.
pub static FIELD_SAMPLES: [u8; (FIELD_WIDTH * FIELD_DEPTH) as usize] =
    *include_bytes!("../data/maunga_whau_87x61.u8.raw");

/// The embedded field's placement: the 860 m × 600 m survey (10 m
/// spacing) scaled to 1 × 0.698 in x/z, its 101 m relief to 0.25 in y
/// (about 2× exaggerated), centred on the origin in x/z.
pub fn field_transform() -> Result<hfray::Transform, hfray::transform::TransformError> {
    let scale = hfray::Transform::scale(hfray::glam::DVec3::new(1.0, 0.25, 600.0 / 860.0))?;
    let shift = hfray::Transform::translate(hfray::glam::DVec3::new(-0.5, 0.0, -0.35))?;
    Ok(scale.then(&shift))
}

/// Samples per row of the `lcd` scene's field.
pub const LCD_FIELD_WIDTH: u32 = 152;
/// Rows of the `lcd` scene's field.
pub const LCD_FIELD_DEPTH: u32 = 187;

/// Rocky Mountain National Park, 152 × 187 8-bit gray samples (about 233 m
/// spacing, 2281–4261 m), image row 0 (north) first:
/// `data/rmnp_co_152x187.u8.raw` (provenance in `data/rmnp_co_152x187.txt`).
/// In flash on the microcontrollers.
pub static LCD_FIELD_SAMPLES: [u8; (LCD_FIELD_WIDTH * LCD_FIELD_DEPTH) as usize] =
    *include_bytes!("../data/rmnp_co_152x187.u8.raw");

/// The `lcd` field's placement: 152 × 187 samples at about 233 m, 35.4 km ×
/// 43.6 km scaled to 1 × 1.236 in x/z, its 1,980 m relief to 0.112 in y
/// (2× exaggerated), centred on the origin in x/z.
pub fn lcd_field_transform() -> Result<hfray::Transform, hfray::transform::TransformError> {
    let scale = hfray::Transform::scale(hfray::glam::DVec3::new(1.0, 0.112, 1.236))?;
    let shift = hfray::Transform::translate(hfray::glam::DVec3::new(-0.5, 0.0, -0.618))?;
    Ok(scale.then(&shift))
}

/// Side of the `thesis` scene's square field (the thesis's 512 × 512).
pub const THESIS_SIDE: u32 = 512;
/// Samples of the `thesis` field.
pub const THESIS_SAMPLES: usize = (THESIS_SIDE * THESIS_SIDE) as usize;

/// The `thesis` field's generator: `hfray::generate::plasma` (the thesis's
/// own fractal, §6.2.1.2), integer arithmetic, so the same bytes on every
/// target. Programs generate it at run time (the i486, the host) or at
/// build time into flash (the Cortex-M4F, `build.rs`, with this same
/// function).
pub fn thesis_field(out: &mut [u8]) -> Result<(), hfray::generate::GenerateError> {
    let params = hfray::generate::Plasma {
        roughness: 0.55,
        seed: 1996,
    };
    hfray::generate::plasma(out, THESIS_SIDE, THESIS_SIDE, &params)
}

/// The skip pyramid every firmware field is walked through: fan-out 4
/// (4-, 16-, 64-cell blocks, as deep as `SkipLayout::pyramid` goes).
pub const fn skip_layout(width: u32, depth: u32) -> hfray::SkipLayout {
    hfray::SkipLayout::pyramid(width, depth, 2)
}
