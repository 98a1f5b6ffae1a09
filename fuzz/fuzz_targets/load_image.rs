//! The harness's height-field image loaders (examples/harness/images.rs,
//! included as is) on arbitrary bytes. The first byte picks the format
//! (GIF, POT, PNG, PGM, PPM, TGA); the rest is the file. Decoding must
//! return a field or an error, never panic, and a decoded field must be
//! consistent: `width × depth` samples within the limits, a convention that
//! fits the sample width, and a core `HeightField` that accepts it.
#![no_main]

#[allow(dead_code)]
#[path = "../../examples/harness/images.rs"]
mod images;

use std::io::Cursor;

use hfray::scene::ImageFormat;
use libfuzzer_sys::fuzz_target;

const FORMATS: [ImageFormat; 6] = [
    ImageFormat::Gif,
    ImageFormat::Pot,
    ImageFormat::Png,
    ImageFormat::Pgm,
    ImageFormat::Ppm,
    ImageFormat::Tga,
];

fuzz_target!(|data: &[u8]| {
    let Some((&which, file)) = data.split_first() else {
        return;
    };
    let format = FORMATS[usize::from(which) % FORMATS.len()];
    match images::decode_height_field(Cursor::new(file), format) {
        Ok(field) => {
            let (w, d) = (u64::from(field.width()), u64::from(field.depth()));
            assert!(w >= 2 && d >= 2, "{w}x{d}");
            assert!(w <= images::MAX_SIDE && d <= images::MAX_SIDE);
            assert!(w * d <= images::MAX_SAMPLES);
            assert_eq!(field.sample_data().len() as u64, w * d);
            let core = field.height_field().expect("the core accepts a decoded field");
            assert_eq!((u64::from(core.width()), u64::from(core.depth())), (w, d));
            let _ = field.sample(field.width() - 1, field.depth() - 1).expect("last sample");
        }
        Err(message) => assert!(!message.is_empty()),
    }
});
