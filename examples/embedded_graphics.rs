//! `embedded_graphics`: render a scene straight into an `embedded-graphics`
//! display driver, one `fill_contiguous` per row, with no frame buffer on
//! the rendering side.
//!
//! ```text
//! cargo run --release --features embedded-graphics --example embedded_graphics -- \
//!     [SCENE.pov] [--width W] [--height H] [--dither] [-o PREVIEW.tga]
//! ```
//!
//! The display here is a mock of a 16-bit SPI LCD (ST7735/ST7789-like):
//! it implements `DrawTarget<Color = Rgb565>`, turns each row into the
//! big-endian bytes a controller takes over SPI (counted and checksummed)
//! and keeps them in its own "GRAM", the panel's memory, which `-o` saves
//! as a TGA preview. On hardware, replace it with the driver crate's
//! display: the render loop does not change. The defaults are the scene
//! `examples/scenes/default.pov` at 160×128 (an ST7735 panel).
//!
//! The library side of this (`hfray::sink::DrawTargetSink`) is `no_std`.
//! Its bare-metal twin, `examples/embedded_graphics_thumb/` (a `no_std`
//! library crate with a concrete SPI-panel `DrawTarget` and a scene built
//! in code), is built for `thumbv7em-none-eabihf` by `.ci/run`.

#[path = "harness/mod.rs"]
mod harness;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Dimensions, OriginDimensions, Point, Size};
use embedded_graphics_core::pixelcolor::{IntoStorage, Rgb565 as EgRgb565};
use embedded_graphics_core::primitives::{PointsIter, Rectangle};
use embedded_graphics_core::Pixel as EgPixel;
use harness::scene_io::{build_fields, load_fields, parse_file_scene, read_scene_text};
use harness::tga::TgaWriter;
use hfray::render::{render, RenderSettings, Stats};
use hfray::sink::{embedded_graphics_core, DrawTargetSink};
use hfray::{Pixel, Rgb565, Rgb565Dithered};

/// A mock SPI LCD: a window command plus pixel bytes per `fill_contiguous`.
struct MockLcd {
    size: Size,
    /// The panel's own memory (on real hardware it is inside the display).
    gram: Vec<u16>,
    fills: u32,
    bytes_sent: u64,
    /// FNV-1a over every byte sent, in order.
    checksum: u64,
}

impl MockLcd {
    fn new(width: u32, height: u32) -> Self {
        MockLcd {
            size: Size::new(width, height),
            gram: vec![0; (width * height) as usize],
            fills: 0,
            bytes_sent: 0,
            checksum: 0xcbf2_9ce4_8422_2325,
        }
    }

    fn send(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.checksum = (self.checksum ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
        self.bytes_sent += bytes.len() as u64;
    }
}

impl OriginDimensions for MockLcd {
    fn size(&self) -> Size {
        self.size
    }
}

/// What a bus error would look like.
#[derive(Debug)]
struct LcdError(&'static str);

impl DrawTarget for MockLcd {
    type Color = EgRgb565;
    type Error = LcdError;

    fn draw_iter<I: IntoIterator<Item = EgPixel<EgRgb565>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), LcdError> {
        // Pixel by pixel (other drawing code): one window per pixel.
        for EgPixel(p, c) in pixels {
            self.fill_contiguous(&Rectangle::new(p, Size::new(1, 1)), [c])?;
        }
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = EgRgb565>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), LcdError> {
        let clipped = area.intersection(&self.bounding_box());
        if clipped != *area {
            return Err(LcdError("window outside the panel"));
        }
        self.fills += 1;
        // CASET/RASET window, then RAMWR and the pixels, high byte first.
        let (x0, y0) = (area.top_left.x as u16, area.top_left.y as u16);
        let (x1, y1) = (
            x0 + area.size.width as u16 - 1,
            y0 + area.size.height as u16 - 1,
        );
        let mut cmd = [0u8; 8];
        cmd[..2].copy_from_slice(&x0.to_be_bytes());
        cmd[2..4].copy_from_slice(&x1.to_be_bytes());
        cmd[4..6].copy_from_slice(&y0.to_be_bytes());
        cmd[6..].copy_from_slice(&y1.to_be_bytes());
        self.send(&cmd);
        let mut n = 0usize;
        for (p, c) in area.points().zip(colors) {
            let raw: u16 = c.into_storage();
            self.send(&raw.to_be_bytes());
            self.gram[(p.y as u32 * self.size.width + p.x as u32) as usize] = raw;
            n += 1;
        }
        if n != area.size.width as usize * area.size.height as usize {
            return Err(LcdError("short pixel stream"));
        }
        Ok(())
    }
}

struct Options {
    scene: PathBuf,
    width: u32,
    height: u32,
    dither: bool,
    preview: Option<PathBuf>,
}

fn parse_args() -> Result<Options, String> {
    let mut o = Options {
        scene: Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/default.pov"),
        width: 160,
        height: 128,
        dither: false,
        preview: None,
    };
    let mut args = std::env::args().skip(1);
    let number = |flag: &str, v: Option<String>| -> Result<u32, String> {
        let v = v.ok_or_else(|| format!("{flag} needs a value"))?;
        match v.parse::<u32>() {
            Ok(n) if (1..=4096).contains(&n) => Ok(n),
            _ => Err(format!("{flag}: '{v}' is not within 1..=4096")),
        }
    };
    while let Some(a) = args.next() {
        match a.as_str() {
            "--width" => o.width = number("--width", args.next())?,
            "--height" => o.height = number("--height", args.next())?,
            "--dither" => o.dither = true,
            "-o" => o.preview = Some(args.next().ok_or("-o needs a file name")?.into()),
            flag if flag.starts_with('-') => return Err(format!("unknown option '{flag}'")),
            path => o.scene = path.into(),
        }
    }
    Ok(o)
}

/// Renders into the display through `DrawTargetSink`, in pixel format `P`.
fn render_to<P>(
    scene: &harness::scene_io::FileScene<'_>,
    fields: &[hfray::HeightField<'_>],
    settings: &RenderSettings,
    lcd: &mut MockLcd,
) -> Result<Stats, String>
where
    P: Pixel + Default + Into<EgRgb565>,
{
    // The only pixel memory on the rendering side: one row.
    let mut line = vec![P::default(); settings.width as usize];
    let mut sink = DrawTargetSink::new(lcd, Point::zero());
    let stats =
        render(scene, fields, settings, &mut line, &mut sink.sink()).map_err(|e| e.to_string())?;
    sink.finish().map_err(|e| format!("display: {}", e.0))?;
    Ok(stats)
}

fn run(o: &Options) -> Result<(), String> {
    let text = read_scene_text(&o.scene)?;
    let settings = RenderSettings::new(o.width, o.height);
    let scene = parse_file_scene(&o.scene, &text, &settings.parse_options(), &mut |w| {
        eprintln!("warning: {w}")
    })?;
    let loaded = load_fields(&scene, &o.scene)?;
    let fields = build_fields(&scene, &loaded)?;

    let mut lcd = MockLcd::new(o.width, o.height);
    let stats = if o.dither {
        render_to::<Rgb565Dithered>(&scene, &fields, &settings, &mut lcd)?
    } else {
        render_to::<Rgb565>(&scene, &fields, &settings, &mut lcd)?
    };
    println!(
        "{}x{} {}: {} rows, {} fill_contiguous calls, {} bytes over SPI, checksum {:016x}, {} rays",
        o.width,
        o.height,
        if o.dither {
            "RGB565 dithered"
        } else {
            "RGB565"
        },
        stats.rows,
        lcd.fills,
        lcd.bytes_sent,
        lcd.checksum,
        stats.rays()
    );

    if let Some(path) = &o.preview {
        let err = |e: std::io::Error| format!("{}: {e}", path.display());
        let mut tga = TgaWriter::create(path, o.width, o.height).map_err(err)?;
        for row in lcd.gram.chunks(o.width as usize) {
            let rgb: Vec<[u8; 3]> = row.iter().map(|&c| Rgb565(c).to_rgb888().0).collect();
            tga.write_row(&rgb).map_err(err)?;
        }
        tga.finish().map_err(err)?;
        println!("preview: {}", path.display());
    }
    Ok(())
}

fn main() -> ExitCode {
    match parse_args().and_then(|o| run(&o)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}
