//! Sinks and pixel formats: the same pixels whatever the format (after
//! conversion), the thread count or the band split, and the
//! `embedded-graphics` adapter (with `--features embedded-graphics`).

#[path = "../examples/harness/mod.rs"]
mod harness;

use std::ops::{ControlFlow, Range};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use harness::scene_io::{build_fields, load_fields, parse_file_scene, read_scene_text, FileScene};
use hfray::glam::Vec3;
use hfray::pixel::{
    bayer_threshold, expand_level, quantize_dithered, quantize_nearest, BAYER_8X8, CUBE_LEVELS,
    PALETTE_256_VGA, PALETTE_GRAYS_START,
};
use hfray::scene::{ParseOptions, Scene};
use hfray::{
    render, HeightField, Indexed8, Pixel, RenderSettings, Rgb565, Rgb565Dithered, Rgb888,
    PALETTE_256,
};

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/scenes/default.pov");

/// Parses the default scene (a palette-coloured, smooth, shadowed real
/// terrain under a sky) at `width × height` and hands it to `f`.
fn with_default_scene<R>(
    width: u32,
    height: u32,
    f: impl FnOnce(&FileScene<'_>, &[HeightField<'_>]) -> R,
) -> R {
    let path = Path::new(SCENE);
    let text = read_scene_text(path).expect("scene text");
    let options = ParseOptions::new(width, height);
    let scene = parse_file_scene(path, &text, &options, &mut |_| {}).expect("parse");
    let loaded = load_fields(&scene, path).expect("load fields");
    let fields = build_fields(&scene, &loaded).expect("build fields");
    f(&scene, &fields)
}

/// Renders `settings` into a `Vec` of `(y, row)`.
fn render_rows<P: Pixel + Default, const O: usize, const L: usize, const G: usize>(
    scene: &Scene<'_, O, L, G>,
    fields: &[HeightField<'_>],
    settings: &RenderSettings,
) -> Vec<(u32, Vec<P>)> {
    let mut line = vec![P::default(); settings.width as usize];
    let mut rows = Vec::new();
    let stats = render(scene, fields, settings, &mut line, &mut |y, row: &[P]| {
        rows.push((y, row.to_vec()));
        ControlFlow::Continue(())
    })
    .expect("render");
    assert!(!stats.cancelled);
    assert_eq!(stats.rows as usize, rows.len());
    rows
}

fn pixels<P: Copy>(rows: &[(u32, Vec<P>)]) -> Vec<P> {
    rows.iter().flat_map(|(_, r)| r.iter().copied()).collect()
}

// ---------------------------------------------------------------------------
// Quantisation, exhaustively.

#[test]
fn bayer_matrix_uses_every_threshold_once() {
    let mut seen = [false; 64];
    for row in BAYER_8X8 {
        for t in row {
            assert!(!seen[t as usize], "threshold {t} twice");
            seen[t as usize] = true;
        }
    }
    assert!(seen.iter().all(|&s| s));
    // Any aligned 8×8 tile, wherever it is in the image.
    let mut tile: Vec<u8> = (0..8)
        .flat_map(|y| (0..8).map(move |x| bayer_threshold(8 * 37 + x, 8 * 11 + y)))
        .collect();
    tile.sort_unstable();
    assert_eq!(tile, (0..64).collect::<Vec<u8>>());
}

#[test]
fn nearest_level_is_the_closest_for_every_byte() {
    for m in [1u8, 5, 6, 31, 63] {
        for v in 0..=255u8 {
            let q = quantize_nearest(v, m);
            assert!(q <= m);
            // Exact rational distance |q/m - v/255| scaled by 255·m.
            let d = |q: u32| (q as i64 * 255 - v as i64 * m as i64).abs();
            let best = (0..=m as u32).map(d).min().unwrap();
            assert_eq!(d(q as u32), best, "v {v} m {m}: level {q} is not nearest");
        }
    }
}

#[test]
fn expanded_levels_span_0_to_255_and_round_to_nearest() {
    for m in [5u8, 6, 31, 63] {
        assert_eq!(expand_level(0, m), 0);
        assert_eq!(expand_level(m, m), 255);
        for q in 0..=m {
            let exact = q as f64 * 255.0 / m as f64;
            assert!(
                (expand_level(q, m) as f64 - exact).abs() <= 0.5,
                "q {q} m {m}"
            );
        }
    }
}

#[test]
fn rgb565_round_trips_all_65536_codes() {
    for code in 0..=u16::MAX {
        let p = Rgb565(code);
        assert_eq!(Rgb565::from_rgb888(p.to_rgb888()), p, "code {code:#06x}");
        let (r, g, b) = p.levels();
        assert_eq!(Rgb565::from_levels(r, g, b), p);
    }
}

#[test]
fn rgb565_to_rgb888_is_rgb888_quantised_to_5_6_5_bits() {
    // Every byte value in every channel: the 565 colour shown is the 8-bit
    // colour moved to the nearest representable level, within half a step.
    for v in 0..=255u8 {
        let c = Rgb888([v, v, 255 - v]);
        let back = Rgb565::from_rgb888(c).to_rgb888().0;
        let half = [255.0 / 31.0 / 2.0, 255.0 / 63.0 / 2.0, 255.0 / 31.0 / 2.0];
        for ch in 0..3 {
            let err = (back[ch] as f64 - c.0[ch] as f64).abs();
            assert!(err <= half[ch] + 0.5, "v {v} ch {ch}: {back:?} vs {c:?}");
        }
    }
    // Known codes.
    assert_eq!(Rgb565::from_rgb888(Rgb888([255, 255, 255])), Rgb565(0xffff));
    assert_eq!(Rgb565::from_rgb888(Rgb888([255, 0, 0])), Rgb565(0xf800));
    assert_eq!(Rgb565::from_rgb888(Rgb888([0, 255, 0])), Rgb565(0x07e0));
    assert_eq!(Rgb565::from_rgb888(Rgb888([0, 0, 255])), Rgb565(0x001f));
    assert_eq!(Rgb565(0x0000).to_rgb888(), Rgb888([0, 0, 0]));
}

/// Mean over an aligned 8×8 tile of the shown 8-bit value of a flat
/// channel `v` dithered to `m + 1` levels.
fn dithered_tile_mean(v: u8, m: u8) -> f64 {
    let sum: u32 = BAYER_8X8
        .iter()
        .flatten()
        .map(|&t| expand_level(quantize_dithered(v, m, t), m) as u32)
        .sum();
    sum as f64 / 64.0
}

#[test]
fn dithering_mean_error_over_flat_tiles_is_below_one_8bit_level() {
    // The tile mean of the *levels* is within 1/128 of a step of v·m/255;
    // in 8-bit units that is at most 255/(128·5) ≈ 0.4, plus at most ½
    // from rounding the levels' own 8-bit values.
    for m in [5u8, 6, 31, 63] {
        let mut worst = 0.0f64;
        for v in 0..=255u8 {
            for t in 0..64 {
                assert!(quantize_dithered(v, m, t) <= m);
            }
            let err = (dithered_tile_mean(v, m) - v as f64).abs();
            worst = worst.max(err);
        }
        assert!(worst < 1.0, "m {m}: worst tile-mean error {worst}");
        // Without dithering the worst error is half a step: much larger.
        let undithered = (0..=255u8)
            .map(|v| (expand_level(quantize_nearest(v, m), m) as f64 - v as f64).abs())
            .fold(0.0, f64::max);
        assert!(undithered > 2.0 * worst, "m {m}: {undithered} vs {worst}");
    }
}

#[test]
fn palette_is_a_6x7x6_cube_plus_four_grays_all_distinct() {
    assert_eq!(CUBE_LEVELS, [6, 7, 6]);
    assert_eq!(PALETTE_256[0], [0, 0, 0]);
    assert_eq!(PALETTE_256[251], [255, 255, 255]);
    assert_eq!(PALETTE_256[42 + 6 + 1], [51, 43, 51]);
    assert_eq!(PALETTE_256[5 * 42 + 3 * 6], [255, 128, 0]);
    for k in 0..4u8 {
        let v = 51 * (k + 1);
        assert_eq!(PALETTE_256[(PALETTE_GRAYS_START + k) as usize], [v, v, v]);
    }
    let mut sorted = PALETTE_256.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    assert_eq!(sorted.len(), 256, "palette entries repeat");
    for (c, vga) in PALETTE_256.iter().zip(PALETTE_256_VGA.iter()) {
        for ch in 0..3 {
            assert!(vga[ch] <= 63);
            let exact = c[ch] as f64 * 63.0 / 255.0;
            assert!((vga[ch] as f64 - exact).abs() <= 0.5);
        }
    }
}

#[test]
fn indexed8_exact_grays_use_their_gray_entries() {
    for k in 1..=4u8 {
        let v = 51 * k;
        for (x, y) in [(0, 0), (3, 5), (7, 7), (100, 33)] {
            let p = Indexed8::from_rgb888(Rgb888([v, v, v]), x, y);
            assert_eq!(p.0, PALETTE_GRAYS_START + k - 1);
            assert_eq!(p.to_rgb888(), Rgb888([v, v, v]));
        }
    }
    // Black and white are exact cube corners at every threshold.
    for (x, y) in [(0, 0), (5, 2), (7, 6)] {
        assert_eq!(Indexed8::from_rgb888(Rgb888([0; 3]), x, y).0, 0);
        assert_eq!(Indexed8::from_rgb888(Rgb888([255; 3]), x, y).0, 251);
    }
}

#[test]
fn indexed8_flat_colour_tiles_average_to_the_colour() {
    // 17³ colours across the cube plus every gray: the tile mean of the
    // palette colours matches within one 8-bit level per channel.
    let mut colours: Vec<[u8; 3]> = (0..=255u8).map(|v| [v, v, v]).collect();
    for r in (0..=255u16).step_by(16) {
        for g in (0..=255u16).step_by(16) {
            for b in (0..=255u16).step_by(16) {
                colours.push([r.min(255) as u8, g.min(255) as u8, b.min(255) as u8]);
            }
        }
    }
    let mut worst = 0.0f64;
    for c in colours {
        let mut sum = [0u32; 3];
        for y in 0..8 {
            for x in 0..8 {
                let shown = Indexed8::from_rgb888(Rgb888(c), 16 + x, 40 + y).to_rgb888();
                for (s, v) in sum.iter_mut().zip(shown.0) {
                    *s += v as u32;
                }
            }
        }
        for ch in 0..3 {
            let err = (sum[ch] as f64 / 64.0 - c[ch] as f64).abs();
            worst = worst.max(err);
            assert!(
                err < 1.0,
                "colour {c:?} channel {ch}: tile mean off by {err}"
            );
        }
    }
    assert!(worst > 0.0);
}

// ---------------------------------------------------------------------------
// The same render in every format.

#[test]
fn formats_agree_with_rgb888_after_conversion() {
    let (w, h) = (64, 48);
    with_default_scene(w, h, |scene, fields| {
        let settings = RenderSettings::new(w, h);
        let rgb888 = pixels(&render_rows::<Rgb888, _, _, _>(scene, fields, &settings));
        let rgb565 = pixels(&render_rows::<Rgb565, _, _, _>(scene, fields, &settings));
        let dith565 = pixels(&render_rows::<Rgb565Dithered, _, _, _>(
            scene, fields, &settings,
        ));
        let indexed = pixels(&render_rows::<Indexed8, _, _, _>(scene, fields, &settings));
        let distinct: std::collections::HashSet<_> = rgb888.iter().collect();
        assert!(distinct.len() > 200, "scene too flat: {}", distinct.len());
        for (i, &c) in rgb888.iter().enumerate() {
            let (x, y) = (i as u32 % w, i as u32 / w);
            assert_eq!(rgb565[i], Rgb565::from_rgb888(c), "565 at ({x}, {y})");
            assert_eq!(
                dith565[i],
                Rgb565Dithered::from_rgb888(c, x, y),
                "dithered 565 at ({x}, {y})"
            );
            assert_eq!(
                indexed[i],
                Indexed8::from_rgb888(c, x, y),
                "indexed at ({x}, {y})"
            );
        }
    });
}

#[test]
fn dithered_formats_keep_a_flat_background_mean() {
    // No objects: every pixel is the background, a colour between levels.
    let scene: Scene<'static, 4, 1> = Scene {
        background: Vec3::new(0.3, 0.47, 0.71),
        ..Scene::default()
    };
    let (w, h) = (40, 24); // 5 × 3 aligned tiles
    let settings = RenderSettings::new(w, h);
    let want = Rgb888::from_linear(scene.background, 0, 0).0;
    let mean = |shown: Vec<Rgb888>| -> [f64; 3] {
        let mut s = [0.0; 3];
        for p in &shown {
            for (s, v) in s.iter_mut().zip(p.0) {
                *s += v as f64;
            }
        }
        s.map(|v| v / shown.len() as f64)
    };
    let dith = mean(
        pixels(&render_rows::<Rgb565Dithered, _, _, _>(
            &scene,
            &[],
            &settings,
        ))
        .iter()
        .map(|p| p.to_rgb888())
        .collect(),
    );
    let idx = mean(
        pixels(&render_rows::<Indexed8, _, _, _>(&scene, &[], &settings))
            .iter()
            .map(|p| p.to_rgb888())
            .collect(),
    );
    let flat = mean(
        pixels(&render_rows::<Rgb565, _, _, _>(&scene, &[], &settings))
            .iter()
            .map(|p| p.to_rgb888())
            .collect(),
    );
    let err = |m: [f64; 3]| {
        (0..3)
            .map(|c| (m[c] - want[c] as f64).abs())
            .fold(0.0, f64::max)
    };
    assert!(err(dith) < 1.0, "dithered 565 mean {dith:?} vs {want:?}");
    assert!(err(idx) < 1.0, "indexed mean {idx:?} vs {want:?}");
    // The undithered 565 is off by its quantisation step, the 256-colour
    // cube without dithering would be off by up to 25 levels.
    assert!(
        err(flat) > err(dith),
        "{flat:?} vs {dith:?} (want {want:?})"
    );
}

// ---------------------------------------------------------------------------
// Bands in-process.

#[test]
fn bands_stacked_equal_the_full_image() {
    let (w, h) = (48, 40);
    with_default_scene(w, h, |scene, fields| {
        let full = render_rows::<Rgb888, _, _, _>(scene, fields, &RenderSettings::new(w, h));
        assert_eq!(
            full.iter().map(|(y, _)| *y).collect::<Vec<_>>(),
            (0..h).collect::<Vec<_>>()
        );
        let splits: [&[Range<u32>]; 3] = [
            &[0..39, 39..h],
            &[0..1, 1..17, 17..40],
            &[0..13, 13..14, 14..40],
        ];
        for split in splits {
            let mut stacked = Vec::new();
            for band in split.iter().cloned() {
                let settings = RenderSettings::new(w, h).with_rows(band.clone());
                let rows = render_rows::<Indexed8, _, _, _>(scene, fields, &settings);
                // Each row reports its index in the whole image.
                assert_eq!(
                    rows.iter().map(|(y, _)| *y).collect::<Vec<_>>(),
                    band.collect::<Vec<_>>()
                );
                stacked.extend(rows);
            }
            // Indexed8 dithers by (x, y): a band reproduces the full
            // image's dither pattern, not its own.
            let want: Vec<(u32, Vec<Indexed8>)> = full
                .iter()
                .map(|(y, r)| {
                    let row = r
                        .iter()
                        .enumerate()
                        .map(|(x, &c)| Indexed8::from_rgb888(c, x as u32, *y))
                        .collect();
                    (*y, row)
                })
                .collect();
            assert!(
                stacked == want,
                "split {split:?} differs from the full image"
            );
        }
    });
}

// ---------------------------------------------------------------------------
// The `render` command: threads and --rows.

/// The `render` example binary, built (once per test run) in release mode
/// like the rest of `cargo test --release`.
fn render_command() -> &'static Path {
    static BIN: OnceLock<PathBuf> = OnceLock::new();
    BIN.get_or_init(|| {
        let out = Command::new(env!("CARGO"))
            .args(["build", "--release", "--example", "render"])
            .args(["--message-format", "json-render-diagnostics"])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .expect("run cargo");
        assert!(
            out.status.success(),
            "cargo build --example render failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
        // The compiler-artifact message of the example names its binary.
        let stdout = String::from_utf8_lossy(&out.stdout);
        let exe = stdout
            .lines()
            .filter(|l| l.contains("\"compiler-artifact\"") && l.contains("\"name\":\"render\""))
            .find_map(|l| {
                let start = l.find("\"executable\":\"")? + "\"executable\":\"".len();
                let end = start + l[start..].find('"')?;
                Some(PathBuf::from(&l[start..end]))
            })
            .expect("cargo named no executable for the render example");
        assert!(exe.is_file(), "{} is missing", exe.display());
        exe
    })
}

/// Runs the render command on the default scene and returns the TGA bytes.
fn run_render(dir: &Path, name: &str, w: u32, h: u32, extra: &[&str]) -> Vec<u8> {
    run_render_scene(SCENE, dir, name, w, h, extra)
}

/// Runs the render command on `scene` and returns the TGA bytes.
fn run_render_scene(
    scene: &str,
    dir: &Path,
    name: &str,
    w: u32,
    h: u32,
    extra: &[&str],
) -> Vec<u8> {
    let out = dir.join(name);
    let result = Command::new(render_command())
        .arg(scene)
        .arg("-o")
        .arg(&out)
        .args(["--width", &w.to_string(), "--height", &h.to_string()])
        .arg("--quiet")
        .args(extra)
        .output()
        .expect("run render");
    assert!(
        result.status.success(),
        "render {extra:?} failed: {}",
        String::from_utf8_lossy(&result.stderr)
    );
    std::fs::read(&out).expect("read output")
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hfray-sinks-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

const TGA_HEADER: usize = 18;

#[test]
fn render_command_threads_give_identical_bytes() {
    let dir = temp_dir("threads");
    // 61 rows: 8 bands of 8 rows, the last one short.
    let (w, h) = (72, 61);
    let one = run_render(&dir, "t1.tga", w, h, &["--threads", "1"]);
    assert_eq!(one.len(), TGA_HEADER + (w * h * 3) as usize);
    for threads in ["2", "3", "8"] {
        let many = run_render(
            &dir,
            &format!("t{threads}.tga"),
            w,
            h,
            &["--threads", threads],
        );
        assert!(one == many, "--threads {threads} differs from --threads 1");
    }
    // A scene with water, a reflective sea plane and shadows, too.
    let thesis = "examples/scenes/thesis.pov";
    let thesis_one = run_render_scene(thesis, &dir, "s1.tga", 80, 50, &["--threads", "1"]);
    let thesis_three = run_render_scene(thesis, &dir, "s3.tga", 80, 50, &["--threads", "3"]);
    assert!(
        thesis_one == thesis_three,
        "thesis.pov: --threads 3 differs from --threads 1"
    );
    // And the command agrees with an in-process render, byte for byte
    // (TGA rows are BGR).
    let inproc = with_default_scene(w, h, |scene, fields| {
        pixels(&render_rows::<Rgb888, _, _, _>(
            scene,
            fields,
            &RenderSettings::new(w, h),
        ))
    });
    let bgr: Vec<u8> = inproc
        .iter()
        .flat_map(|p| [p.0[2], p.0[1], p.0[0]])
        .collect();
    assert!(
        one[TGA_HEADER..] == bgr[..],
        "render command differs from render()"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn render_command_row_bands_stack_to_the_full_image() {
    let dir = temp_dir("rows");
    let (w, h) = (64, 45);
    let full = run_render(&dir, "full.tga", w, h, &[]);
    let splits: [&[Range<u32>]; 2] = [&[0..20, 20..21, 21..45], &[0..7, 7..45]];
    for (k, split) in splits.iter().enumerate() {
        let mut stacked = Vec::new();
        for (i, band) in split.iter().enumerate() {
            let rows = format!("{}..{}", band.start, band.end);
            // Threads inside a band too: bands do not start on a multiple
            // of the 8-row work unit.
            let part = run_render(
                &dir,
                &format!("s{k}_{i}.tga"),
                w,
                h,
                &["--rows", &rows, "--threads", "2"],
            );
            assert_eq!(
                part.len(),
                TGA_HEADER + (w * band.len() as u32 * 3) as usize
            );
            // The band's header says the band's height.
            assert_eq!(
                u16::from_le_bytes([part[14], part[15]]) as usize,
                band.len()
            );
            stacked.extend_from_slice(&part[TGA_HEADER..]);
        }
        assert!(
            stacked[..] == full[TGA_HEADER..],
            "bands {split:?} stacked differ from the full image"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------
// embedded-graphics.

#[cfg(feature = "embedded-graphics")]
mod embedded_graphics {
    use super::*;
    use hfray::sink::embedded_graphics_core::draw_target::DrawTarget;
    use hfray::sink::embedded_graphics_core::geometry::{Dimensions, Point, Size};
    use hfray::sink::embedded_graphics_core::pixelcolor::{self as eg, RgbColor};
    use hfray::sink::embedded_graphics_core::primitives::Rectangle;
    use hfray::sink::embedded_graphics_core::Pixel as EgPixel;
    use hfray::sink::DrawTargetSink;

    /// A display that records every `fill_contiguous` call and can be
    /// told to fail on one.
    struct Recorder<C> {
        size: Size,
        fills: Vec<(Rectangle, Vec<C>)>,
        fail_at: Option<usize>,
    }

    impl<C> Recorder<C> {
        fn new(width: u32, height: u32) -> Self {
            Recorder {
                size: Size::new(width, height),
                fills: Vec::new(),
                fail_at: None,
            }
        }
    }

    impl<C> Dimensions for Recorder<C> {
        fn bounding_box(&self) -> Rectangle {
            Rectangle::new(Point::zero(), self.size)
        }
    }

    #[derive(Debug, PartialEq)]
    struct BusError(usize);

    impl<C: eg::PixelColor> DrawTarget for Recorder<C> {
        type Color = C;
        type Error = BusError;
        fn draw_iter<I: IntoIterator<Item = EgPixel<C>>>(&mut self, _: I) -> Result<(), BusError> {
            panic!("the sink must draw rows with fill_contiguous");
        }
        fn fill_contiguous<I: IntoIterator<Item = C>>(
            &mut self,
            area: &Rectangle,
            colors: I,
        ) -> Result<(), BusError> {
            if self.fail_at == Some(self.fills.len()) {
                return Err(BusError(self.fills.len()));
            }
            self.fills.push((*area, colors.into_iter().collect()));
            Ok(())
        }
    }

    #[test]
    fn rows_arrive_at_their_y_as_one_row_rectangles() {
        let (w, h) = (40, 30);
        with_default_scene(w, h, |scene, fields| {
            let want = render_rows::<Rgb565, _, _, _>(scene, fields, &RenderSettings::new(w, h));
            let mut display = Recorder::<eg::Rgb565>::new(100, 100);
            let origin = Point::new(7, 11);
            let mut line = vec![Rgb565::default(); w as usize];
            // A band: rows 5..23 of the image.
            let settings = RenderSettings::new(w, h).with_rows(5..23);
            let mut lcd = DrawTargetSink::new(&mut display, origin);
            let stats = render(scene, fields, &settings, &mut line, &mut lcd.sink()).unwrap();
            assert!(!stats.cancelled);
            assert_eq!(lcd.finish(), Ok(18));
            assert_eq!(display.fills.len(), 18);
            for (k, (area, colours)) in display.fills.iter().enumerate() {
                let y = 5 + k as u32;
                assert_eq!(
                    *area,
                    Rectangle::new(Point::new(7, 11 + y as i32), Size::new(w, 1))
                );
                let expect: Vec<eg::Rgb565> = want[y as usize]
                    .1
                    .iter()
                    .map(|p| {
                        let (r, g, b) = p.levels();
                        eg::Rgb565::new(r, g, b)
                    })
                    .collect();
                assert_eq!(colours, &expect, "row {y}");
            }
        });
    }

    #[test]
    fn rgb888_and_indexed8_convert_to_eg_rgb888() {
        let p: eg::Rgb888 = Rgb888([1, 2, 3]).into();
        assert_eq!((p.r(), p.g(), p.b()), (1, 2, 3));
        let q: eg::Rgb888 = Indexed8(5 * 42 + 3 * 6).into();
        assert_eq!((q.r(), q.g(), q.b()), (255, 128, 0));
        let d: eg::Rgb565 = Rgb565Dithered(Rgb565(0xf81f)).into();
        assert_eq!((d.r(), d.g(), d.b()), (31, 0, 31));
        let scene: Scene<'static, 4, 1> = Scene {
            background: Vec3::new(0.2, 0.5, 0.9),
            ..Scene::default()
        };
        let mut display = Recorder::<eg::Rgb888>::new(16, 4);
        let mut line = [Indexed8::default(); 16];
        let mut sink = DrawTargetSink::new(&mut display, Point::zero());
        render(
            &scene,
            &[],
            &RenderSettings::new(16, 4),
            &mut line,
            &mut sink.sink(),
        )
        .unwrap();
        assert_eq!(sink.finish(), Ok(4));
        for (area, colours) in &display.fills {
            for (x, c) in colours.iter().enumerate() {
                let want =
                    Indexed8::from_linear(scene.background, x as u32, area.top_left.y as u32)
                        .to_rgb888()
                        .0;
                assert_eq!([c.r(), c.g(), c.b()], want);
            }
        }
    }

    #[test]
    fn failing_draw_target_stops_the_render() {
        let scene: Scene<'static, 4, 1> = Scene {
            background: Vec3::splat(0.5),
            ..Scene::default()
        };
        let mut display = Recorder::<eg::Rgb565>::new(32, 32);
        display.fail_at = Some(3);
        let mut line = [Rgb565::default(); 32];
        let mut lcd = DrawTargetSink::new(&mut display, Point::zero());
        let stats = render(
            &scene,
            &[],
            &RenderSettings::new(32, 32),
            &mut line,
            &mut lcd.sink(),
        )
        .unwrap();
        assert!(stats.cancelled, "the render went on after the draw error");
        assert_eq!(stats.rows, 4, "rows 0..3 drawn, row 3 failed");
        assert_eq!(lcd.rows_drawn(), 3);
        assert_eq!(lcd.error(), Some(&BusError(3)));
        // A later row is refused without touching the display.
        assert!(lcd.row(4, &line).is_break());
        assert_eq!(lcd.finish(), Err(BusError(3)));
        assert_eq!(display.fills.len(), 3);
    }
}
