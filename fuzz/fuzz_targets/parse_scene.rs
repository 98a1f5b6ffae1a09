//! The scene parser on arbitrary bytes: as `&str` when they are valid
//! UTF-8, and always also lossily converted. It must return a scene or a
//! diagnostic, never panic, overflow the stack or hang; a diagnostic's
//! position must lie inside the text (line ≥ 1, column ≥ 1, at most one line
//! past the last).
#![no_main]

use hfray::scene::{parse_scene, Diagnostic, ParseOptions};
use libfuzzer_sys::fuzz_target;

fn check<const O: usize, const L: usize, const G: usize>(src: &str, strict: bool) {
    let opts = ParseOptions {
        strict,
        ..ParseOptions::new(320, 240)
    };
    let lines = src.split('\n').count() as u32;
    let check_diag = |d: &Diagnostic<'_>| {
        assert!(d.line >= 1 && d.col >= 1, "bad position {}:{}", d.line, d.col);
        assert!(d.line <= lines + 1, "line {} past {lines}", d.line);
        // Display must not panic either.
        let _ = d.to_string();
    };
    let mut warnings = 0u32;
    match parse_scene::<O, L, G>(src, &opts, &mut |w| {
        warnings += 1;
        check_diag(w)
    }) {
        Ok(scene) => {
            assert!(scene.objects.len() <= O && scene.lights.len() <= L);
            // Every gradient index names a pooled gradient.
            assert!(scene.gradients.len() <= G);
            for o in &scene.objects {
                assert!(o.pigment.gradient.is_none_or(|i| usize::from(i) < scene.gradients.len()));
            }
            if strict {
                assert_eq!(warnings, 0, "strict parse succeeded after a warning");
            }
        }
        Err(e) => check_diag(&e),
    }
}

fuzz_target!(|data: &[u8]| {
    if let Ok(s) = std::str::from_utf8(data) {
        check::<32, 8, 4>(s, false);
        check::<1, 1, 0>(s, true);
    }
    let lossy = String::from_utf8_lossy(data);
    check::<4, 2, 1>(&lossy, false);
});
