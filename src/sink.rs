//! Sinks: where finished rows go.
//!
//! A sink is any `FnMut(u32, &[P]) -> ControlFlow<()>`: [`render`] calls it
//! once per finished row, in order, with the row's index in the *whole*
//! image (so a band rendered with
//! [`RenderSettings::with_rows`](crate::RenderSettings::with_rows) reports
//! its rows' true `y`) and the caller's line buffer, which is reused for
//! the next row as soon as the sink returns. Returning
//! [`ControlFlow::Break`] stops the render (`Stats::cancelled`). The
//! renderer keeps nothing else, so the sink decides what a frame costs:
//!
//! - a file writer (the `render` example streams TGA/PNG rows to disk),
//! - a checksum or a UART (firmware: nothing is kept at all),
//! - an SPI display taking [`Rgb565`](crate::pixel::Rgb565) rows,
//! - a VGA mode 13h screen taking [`Indexed8`](crate::pixel::Indexed8)
//!   rows (one copy per row into `0xA0000 + 320·y`),
//! - any `embedded-graphics` display driver, through `DrawTargetSink`
//!   (cargo feature `embedded-graphics`).
//!
//! # `embedded-graphics`
//!
//! With the `embedded-graphics` cargo feature (no_std, no allocation),
//! `DrawTargetSink` streams each row into any `embedded-graphics-core`
//! `DrawTarget` (display drivers, simulators) with one `fill_contiguous`
//! call on a 1-pixel-high rectangle: no frame buffer, whatever the display.
//!
//! [`render`]: crate::render::render
//! [`ControlFlow::Break`]: core::ops::ControlFlow::Break
#![cfg_attr(
    feature = "embedded-graphics",
    doc = r#"
Rows go to `origin + (0, y)` as a [`Rectangle`] of `width × 1`
([`DrawTarget::fill_contiguous`]); pixels convert with `Into<D::Color>`,
provided for

| line buffer `P` | display colour `D::Color` |
|---|---|
| [`Rgb565`](crate::pixel::Rgb565), [`Rgb565Dithered`](crate::pixel::Rgb565Dithered) | [`pixelcolor::Rgb565`] |
| [`Rgb888`](crate::pixel::Rgb888), [`Indexed8`](crate::pixel::Indexed8) (its palette colour) | [`pixelcolor::Rgb888`] |

A draw error stops the render at that row (the sink returns `Break`) and
[`DrawTargetSink::finish`] returns it. The crate re-exports
[`embedded_graphics_core`] so that the versions match.

[`Rectangle`]: embedded_graphics_core::primitives::Rectangle
[`DrawTarget::fill_contiguous`]: embedded_graphics_core::draw_target::DrawTarget::fill_contiguous
[`pixelcolor::Rgb565`]: embedded_graphics_core::pixelcolor::Rgb565
[`pixelcolor::Rgb888`]: embedded_graphics_core::pixelcolor::Rgb888
"#
)]

#[cfg(feature = "embedded-graphics")]
pub use self::eg::DrawTargetSink;
#[cfg(feature = "embedded-graphics")]
pub use embedded_graphics_core;

#[cfg(feature = "embedded-graphics")]
mod eg {
    use core::ops::ControlFlow;

    use embedded_graphics_core::draw_target::DrawTarget;
    use embedded_graphics_core::geometry::{Point, Size};
    use embedded_graphics_core::pixelcolor;
    use embedded_graphics_core::primitives::Rectangle;

    use crate::pixel::{Indexed8, Rgb565, Rgb565Dithered, Rgb888};

    /// Streams rows into an `embedded-graphics` [`DrawTarget`], one
    /// [`fill_contiguous`](DrawTarget::fill_contiguous) per row (see the
    /// [module docs](super)).
    ///
    /// ```
    /// # use embedded_graphics_core::{draw_target::DrawTarget, geometry::{Dimensions, Point, Size},
    /// #     pixelcolor::Rgb565 as EgRgb565, primitives::Rectangle, Pixel as EgPixel};
    /// use hfray::sink::DrawTargetSink;
    /// use hfray::{render, scene::Scene, RenderSettings, Rgb565};
    /// # struct Lcd { rows: u32 }
    /// # impl Dimensions for Lcd {
    /// #     fn bounding_box(&self) -> Rectangle { Rectangle::new(Point::zero(), Size::new(16, 8)) }
    /// # }
    /// # impl DrawTarget for Lcd {
    /// #     type Color = EgRgb565;
    /// #     type Error = ();
    /// #     fn draw_iter<I: IntoIterator<Item = EgPixel<EgRgb565>>>(&mut self, _: I) -> Result<(), ()> {
    /// #         Ok(())
    /// #     }
    /// #     fn fill_contiguous<I>(&mut self, _: &Rectangle, _: I) -> Result<(), ()>
    /// #     where I: IntoIterator<Item = EgRgb565> {
    /// #         self.rows += 1;
    /// #         Ok(())
    /// #     }
    /// # }
    /// # let mut display = Lcd { rows: 0 };
    /// // `display`: any DrawTarget<Color = Rgb565>, e.g. an ST7789 driver.
    /// let scene: Scene<'_, 4, 1> = Scene::default();
    /// let mut line = [Rgb565::default(); 16];
    /// let mut lcd = DrawTargetSink::new(&mut display, Point::zero());
    /// render(&scene, &[], &RenderSettings::new(16, 8), &mut line, &mut lcd.sink())
    ///     .expect("valid scene");
    /// assert_eq!(lcd.finish(), Ok(8)); // rows drawn, or the display's error
    /// # assert_eq!(display.rows, 8);
    /// ```
    pub struct DrawTargetSink<'a, D: DrawTarget> {
        target: &'a mut D,
        origin: Point,
        rows: u32,
        error: Option<D::Error>,
    }

    impl<D: DrawTarget> core::fmt::Debug for DrawTargetSink<'_, D> {
        fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
            f.debug_struct("DrawTargetSink")
                .field("origin", &self.origin)
                .field("rows", &self.rows)
                .field("failed", &self.error.is_some())
                .finish()
        }
    }

    impl<'a, D: DrawTarget> DrawTargetSink<'a, D> {
        /// A sink drawing image pixel `(x, y)` at `origin + (x, y)` of
        /// `target`.
        pub fn new(target: &'a mut D, origin: Point) -> Self {
            DrawTargetSink {
                target,
                origin,
                rows: 0,
                error: None,
            }
        }

        /// Draws image row `y`; [`ControlFlow::Break`] once the target has
        /// returned an error (kept for [`finish`](Self::finish); later rows
        /// are not drawn). A row whose position does not fit in `i32` is
        /// off every display and is skipped.
        pub fn row<P: Copy + Into<D::Color>>(&mut self, y: u32, row: &[P]) -> ControlFlow<()> {
            if self.error.is_some() {
                return ControlFlow::Break(());
            }
            let top = i32::try_from(y)
                .ok()
                .and_then(|y| self.origin.y.checked_add(y));
            let (Some(top), Ok(width)) = (top, u32::try_from(row.len())) else {
                return ControlFlow::Continue(());
            };
            let area = Rectangle::new(Point::new(self.origin.x, top), Size::new(width, 1));
            match self
                .target
                .fill_contiguous(&area, row.iter().map(|&p| p.into()))
            {
                Ok(()) => {
                    self.rows += 1;
                    ControlFlow::Continue(())
                }
                Err(e) => {
                    self.error = Some(e);
                    ControlFlow::Break(())
                }
            }
        }

        /// The sink as the closure [`render`](crate::render::render) takes:
        /// `render(.., &mut line, &mut lcd.sink())`.
        pub fn sink<P: Copy + Into<D::Color>>(
            &mut self,
        ) -> impl FnMut(u32, &[P]) -> ControlFlow<()> + use<'_, 'a, D, P> {
            move |y, row| self.row(y, row)
        }

        /// Rows drawn so far.
        pub fn rows_drawn(&self) -> u32 {
            self.rows
        }

        /// The target's error, if a draw failed.
        pub fn error(&self) -> Option<&D::Error> {
            self.error.as_ref()
        }

        /// The number of rows drawn, or the target's error if a draw
        /// failed (the render then stopped at that row).
        pub fn finish(self) -> Result<u32, D::Error> {
            match self.error {
                Some(e) => Err(e),
                None => Ok(self.rows),
            }
        }
    }

    impl From<Rgb565> for pixelcolor::Rgb565 {
        #[inline]
        fn from(p: Rgb565) -> Self {
            let (r, g, b) = p.levels();
            pixelcolor::Rgb565::new(r, g, b)
        }
    }

    impl From<Rgb565Dithered> for pixelcolor::Rgb565 {
        #[inline]
        fn from(p: Rgb565Dithered) -> Self {
            p.0.into()
        }
    }

    impl From<Rgb888> for pixelcolor::Rgb888 {
        #[inline]
        fn from(p: Rgb888) -> Self {
            let [r, g, b] = p.0;
            pixelcolor::Rgb888::new(r, g, b)
        }
    }

    impl From<Indexed8> for pixelcolor::Rgb888 {
        /// The palette colour ([`PALETTE_256`](crate::pixel::PALETTE_256)).
        #[inline]
        fn from(p: Indexed8) -> Self {
            p.to_rgb888().into()
        }
    }
}
