//! `embedded_graphics` for bare metal: render a height field built in code
//! into an `embedded-graphics` display, one `fill_contiguous` per row, on
//! a `thumbv7em-none-eabihf` target. The display is a stand-in for an SPI
//! driver (it hands each byte to a `send` function); a board crate would
//! pass its real driver instead.
#![no_std]
#![forbid(unsafe_code)]

use hfray::glam::{DVec3, Vec3};
use hfray::scene::{CameraDesc, Finish, Light, Object, Pigment, Scene, Shape};
use hfray::sink::embedded_graphics_core::draw_target::DrawTarget;
use hfray::sink::embedded_graphics_core::geometry::{OriginDimensions, Point, Size};
use hfray::sink::embedded_graphics_core::pixelcolor::{IntoStorage, Rgb565 as EgRgb565};
use hfray::sink::embedded_graphics_core::primitives::Rectangle;
use hfray::sink::embedded_graphics_core::Pixel as EgPixel;
use hfray::sink::DrawTargetSink;
use hfray::{
    render, HeightConvention, HeightField, RenderSettings, Rgb565, Samples, Stats, Transform,
};

/// Panel size (an ST7735 in landscape).
pub const WIDTH: u32 = 160;
/// Panel height.
pub const HEIGHT: u32 = 128;

/// 8 × 8 palette indices in flash: a ridge.
static TERRAIN: [u8; 64] = [
    0, 10, 30, 60, 60, 30, 10, 0, //
    10, 30, 70, 120, 110, 60, 20, 10, //
    20, 50, 110, 190, 160, 90, 40, 20, //
    20, 60, 140, 230, 200, 110, 50, 20, //
    20, 50, 120, 200, 180, 100, 40, 20, //
    10, 40, 90, 140, 130, 80, 30, 10, //
    10, 20, 50, 80, 70, 40, 20, 10, //
    0, 10, 20, 30, 30, 20, 10, 0, //
];

/// A byte sink standing in for the SPI bus.
pub type Bus<'a> = &'a mut dyn FnMut(&[u8]);

/// A 16-bit SPI panel: `send` takes the bytes a controller would get.
pub struct SpiPanel<F: FnMut(&[u8])> {
    /// The bus.
    pub send: F,
}

impl<F: FnMut(&[u8])> OriginDimensions for SpiPanel<F> {
    fn size(&self) -> Size {
        Size::new(WIDTH, HEIGHT)
    }
}

/// A window outside the panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutOfPanel;

impl<F: FnMut(&[u8])> DrawTarget for SpiPanel<F> {
    type Color = EgRgb565;
    type Error = OutOfPanel;

    fn draw_iter<I: IntoIterator<Item = EgPixel<EgRgb565>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), OutOfPanel> {
        for EgPixel(p, c) in pixels {
            self.fill_contiguous(&Rectangle::new(p, Size::new(1, 1)), [c])?;
        }
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = EgRgb565>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), OutOfPanel> {
        let Some(end) = area.bottom_right() else {
            return Ok(());
        };
        if area.top_left.x < 0
            || area.top_left.y < 0
            || end.x >= WIDTH as i32
            || end.y >= HEIGHT as i32
        {
            return Err(OutOfPanel);
        }
        let (x0, y0) = (area.top_left.x as u16, area.top_left.y as u16);
        let (x1, y1) = (end.x as u16, end.y as u16);
        let [a, b] = x0.to_be_bytes();
        let [c, d] = x1.to_be_bytes();
        let [e, f] = y0.to_be_bytes();
        let [g, h] = y1.to_be_bytes();
        (self.send)(&[a, b, c, d, e, f, g, h]);
        let n = area.size.width as usize * area.size.height as usize;
        for color in colors.into_iter().take(n) {
            let raw: u16 = color.into_storage();
            (self.send)(&raw.to_be_bytes());
        }
        Ok(())
    }
}

/// Why a frame was not drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrameError {
    /// The scene could not be built or rendered.
    Scene,
    /// The panel refused a row; the render stopped there.
    Panel(OutOfPanel),
}

/// Renders the ridge into `panel`: the render's counters, or why not.
pub fn render_frame(panel: &mut SpiPanel<Bus<'_>>) -> Result<Stats, FrameError> {
    let place = Transform::scale(DVec3::new(2.0, 0.5, 2.0))
        .and_then(|s| Transform::translate(DVec3::new(-1.0, 0.0, -1.0)).map(|t| s.then(&t)))
        .map_err(|_| FrameError::Scene)?;
    let field = HeightField::new(Samples::U8(&TERRAIN), 8, 8, HeightConvention::Indexed)
        .map_err(|_| FrameError::Scene)?;
    let fields = [field.with_transform(place)];
    let mut scene: Scene<'static, 1, 1, 0> = Scene {
        camera: CameraDesc {
            location: Vec3::new(0.0, 1.4, -2.4),
            look_at: Vec3::new(0.0, 0.15, 0.0),
            right: Vec3::new(WIDTH as f32 / HEIGHT as f32, 0.0, 0.0),
            ..CameraDesc::default()
        },
        background: Vec3::new(0.5, 0.7, 0.9),
        ..Scene::default()
    };
    let sun = Light {
        position: Vec3::new(-4.0, 6.0, -3.0),
        color: Vec3::ONE,
    };
    let terrain = Object {
        shape: Shape::HeightField {
            source: None,
            smooth: true,
            field_index: 0,
        },
        transform: place,
        pigment: Pigment {
            color: Vec3::new(0.45, 0.6, 0.3),
            ..Pigment::default()
        },
        finish: Finish::default(),
    };
    scene.lights.push(sun).map_err(|_| FrameError::Scene)?;
    scene.objects.push(terrain).map_err(|_| FrameError::Scene)?;

    // One row of RGB565: the only pixel memory (320 bytes).
    let mut line = [Rgb565::default(); WIDTH as usize];
    let mut sink = DrawTargetSink::new(panel, Point::zero());
    let stats = render(
        &scene,
        &fields,
        &RenderSettings::new(WIDTH, HEIGHT),
        &mut line,
        &mut sink.sink(),
    );
    sink.finish().map_err(FrameError::Panel)?;
    stats.map_err(|_| FrameError::Scene)
}

/// The same render, checksummed (FNV-1a over the bytes sent).
pub fn frame_checksum() -> Result<u32, FrameError> {
    let mut hash = 0x811c_9dc5u32;
    let mut send = |bytes: &[u8]| {
        for &b in bytes {
            hash = (hash ^ b as u32).wrapping_mul(0x0100_0193);
        }
    };
    let mut panel = SpiPanel {
        send: &mut send as Bus<'_>,
    };
    render_frame(&mut panel)?;
    Ok(hash)
}
