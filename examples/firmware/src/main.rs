//! hfray on bare metal: a cortex-m-rt application that renders the scene of
//! `scene.rs` (`base`: Maunga Whau, 96 × 64, one light, shadows; `lcd`, `thesis`, …) with
//! `hfray::render` from a height field held in flash, streams every scanline
//! to the host through semihosting, and reports the frame checksum and the
//! stack high-water mark.
//!
//! The scene variant (`scene::VARIANTS`: `base`, `reflect-1`, …) is the
//! last word of the semihosting command line (`SYS_GET_CMDLINE`; QEMU:
//! `-semihosting-config enable=on,target=native,arg=hfray-firmware,arg=NAME`),
//! `base` without one.
//!
//! No `std`, no allocator, no frame buffer: the only frame-sized state is one
//! row of `Rgb888` pixels (the board's widest frame) on the stack. The
//! `lcd` pyramid, and on the Cortex-M4F the `thesis` field and pyramid, are
//! in flash (`build.rs`). `sqrt-check` instead of a scene compares the
//! hardware square root with libm's (`check_sqrt`).
//!
//! Boards (chosen by target in `build.rs`):
//! - `thumbv6m-none-eabi`: BBC micro:bit (`qemu-system-arm -machine microbit`),
//!   Cortex-M0, 16 KiB RAM, software floating point.
//! - `thumbv7em-none-eabihf`: ARM MPS2-AN386 (`-machine mps2-an386`),
//!   Cortex-M4F with single-precision FPU.
//!
//! Output: the frame as a binary PPM in the host file `frame-BOARD.ppm`
//! (QEMU's working directory), and one line on the host's stdout:
//! `board=B scene=NAME frame_checksum=HEX stack_bytes=N render_stack_bytes=N
//! render_peak_stack_bytes=N setup_stack_bytes=N stack_limit_bytes=N model_bytes=N ... hits=N ...`.
//! Exits QEMU through semihosting (`SYS_EXIT`), non-zero on any failure.
//!
//! # Unsafe code (firmware crate only; the hfray core forbids it)
//! - Semihosting file I/O (`SYS_OPEN`/`SYS_WRITE`/`SYS_CLOSE`) and
//!   `SYS_GET_CMDLINE`: a `bkpt 0xAB` trap that reads or fills our buffers
//!   by address; `cortex-m-semihosting` offers no safe API for these, so
//!   [`HostFile`] and [`command_line`] wrap the raw calls.
//! - Stack high-water: cortex-m-rt's `paint-stack` feature fills the RAM
//!   between `_stack_end` (end of `.bss`) and `_stack_start` (initial SP)
//!   with `0xCCCC_CCCC` in the reset handler, before `main`. After the render
//!   [`stack_high_water`] reads that region with volatile loads through raw
//!   pointers made from the two linker symbols: it is memory outside any Rust
//!   object, so there is no safe way to look at it.
#![no_std]
#![no_main]

mod scene;

use core::fmt::Write as _;
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hio, nr, syscall};

/// Board name, from `build.rs` (follows the target).
const BOARD: &str = env!("HFRAY_BOARD");

/// The renderer: the fixed-point frame on the FPU-less Cortex-M0 (set by
/// `build.rs` unless the `float-frame` feature is on), `f32` elsewhere.
#[cfg(fixed_frame)]
const FRAME: scene::Frame = scene::Frame::Fixed;
#[cfg(not(fixed_frame))]
const FRAME: scene::Frame = scene::Frame::Float;

/// A host file opened through semihosting.
struct HostFile {
    handle: usize,
}

impl HostFile {
    /// Opens `name` (must end in NUL) for binary writing, truncating.
    fn create(name: &str) -> Result<Self, ()> {
        if !name.ends_with('\0') {
            return Err(());
        }
        // SAFETY: SYS_OPEN reads `name.len() - 1` bytes from `name`, which
        // lives for the duration of the call.
        let handle = unsafe {
            syscall!(
                OPEN,
                name.as_ptr(),
                nr::open::W_TRUNC_BINARY,
                name.len() - 1
            )
        };
        if handle as isize == -1 {
            Err(())
        } else {
            Ok(HostFile { handle })
        }
    }

    /// Writes all of `bytes`. Bounded: each round writes at least one byte
    /// or fails.
    fn write_all(&mut self, mut bytes: &[u8]) -> Result<(), ()> {
        while !bytes.is_empty() {
            // SAFETY: SYS_WRITE reads `bytes.len()` bytes from `bytes`; it
            // returns how many were NOT written.
            let left = unsafe { syscall!(WRITE, self.handle, bytes.as_ptr(), bytes.len()) };
            if left == 0 {
                return Ok(());
            }
            if left >= bytes.len() {
                return Err(());
            }
            bytes = &bytes[bytes.len() - left..];
        }
        Ok(())
    }

    fn close(self) -> Result<(), ()> {
        // SAFETY: SYS_CLOSE takes the handle SYS_OPEN gave us.
        match unsafe { syscall!(CLOSE, self.handle) } {
            0 => Ok(()),
            _ => Err(()),
        }
    }
}

/// Bytes of command line [`command_line`] can hold.
const CMDLINE_BYTES: usize = 64;

/// The semihosting command line (`SYS_GET_CMDLINE`), or an empty one if
/// the host gives none. The returned slice borrows `buf`.
fn command_line(buf: &mut [u8; CMDLINE_BYTES]) -> &[u8] {
    // Parameter block: buffer address and its size; the host writes the
    // line (NUL-terminated) and replaces the size with the line's length.
    let mut block = [buf.as_mut_ptr() as usize, CMDLINE_BYTES];
    // SAFETY: the host writes at most `CMDLINE_BYTES` bytes into `buf` and
    // one word into `block`, both live and exclusively ours for the call.
    let status =
        unsafe { cortex_m_semihosting::syscall1(nr::GET_CMDLINE, block.as_mut_ptr() as usize) };
    if status != 0 {
        return &[];
    }
    let len = block[1].min(CMDLINE_BYTES);
    &buf[..len]
}

extern "C" {
    /// Initial stack pointer (top of RAM), from cortex-m-rt's `link.x`.
    static _stack_start: u32;
    /// Lowest address the stack may grow to (end of `.bss`/`.uninit`).
    static _stack_end: u32;
}

/// The value cortex-m-rt's `paint-stack` writes over the free RAM.
const PAINT: u32 = 0xCCCC_CCCC;

/// Lowest stack address ever written since the region was painted: scans
/// up from `_stack_end` for the first word that is not the paint. Bounded
/// by the region's size in words.
fn lowest_used_stack_address() -> usize {
    let start = core::ptr::addr_of!(_stack_start) as usize;
    let end = core::ptr::addr_of!(_stack_end) as usize;
    let mut addr = end;
    while addr < start {
        // SAFETY: `[end, start)` is RAM reserved for the stack by the linker
        // script; it is word aligned (link.x asserts it) and readable.
        let word = unsafe { core::ptr::read_volatile(addr as *const u32) };
        if word != PAINT {
            break;
        }
        addr += 4;
    }
    addr
}

/// Gap left unpainted just below the stack pointer when repainting, so the
/// painting code never writes over its own frame.
const REPAINT_GAP: usize = 256;

/// Paints `[_stack_end, sp - REPAINT_GAP)` again and returns `sp`, so a
/// later [`lowest_used_stack_address`] measures what runs after this call.
/// Inlined so `sp` is the caller's. Bounded by the region's size in words.
#[inline(always)]
fn repaint_below_sp() -> usize {
    let sp = cortex_m::register::msp::read() as usize;
    let end = core::ptr::addr_of!(_stack_end) as usize;
    let mut addr = end;
    while addr + REPAINT_GAP < sp {
        // SAFETY: `[end, sp - REPAINT_GAP)` is stack RAM below every live
        // frame (nothing runs but us: no interrupts are enabled).
        unsafe { core::ptr::write_volatile(addr as *mut u32, PAINT) };
        addr += 4;
    }
    sp
}

/// Opens or closes a segment of the frame for the instruction counter
/// (`tools/qemu-insn-count`: `frame=N` counts what runs inside the
/// segments): `mov r11, r11`, which changes nothing and which compilers do
/// not emit.
#[inline(always)]
fn frame_mark() {
    // SAFETY: copies r11 onto itself: no register, flag or memory changes.
    // Not `nomem`, so memory accesses stay on their side of it.
    unsafe { core::arch::asm!("mov r11, r11", options(nostack, preserves_flags)) };
}

/// Host stdout, or fail.
fn stdout() -> hio::HostStream {
    match hio::hstdout() {
        Ok(s) => s,
        Err(()) => fail(),
    }
}

/// Writes `parts` one after the other, as they are: not through `Display`,
/// whose padding code (about 1 KB) is then not linked.
fn write_parts(out: &mut hio::HostStream, parts: &[&str]) {
    for part in parts {
        let _ = out.write_str(part);
    }
}

/// Prints `board=B error=PARTS` and fails.
fn fail_because(out: &mut hio::HostStream, parts: &[&str]) -> ! {
    write_parts(out, &["board=", BOARD, " error="]);
    write_parts(out, parts);
    write_parts(out, &["\n"]);
    fail()
}

fn fail() -> ! {
    debug::exit(debug::EXIT_FAILURE);
    // Only reached if the debugger ignored the exit request.
    loop {
        cortex_m::asm::wfi();
    }
}

#[entry]
fn main() -> ! {
    let mut out = stdout();
    let variant = variant_from_command_line(&mut out);
    let kind = variant.kind();
    let model = match scene::build_scene(variant) {
        Ok(s) => s,
        Err(e) => fail_because(&mut out, &["scene:", scene::scene_error_name(&e)]),
    };
    // The base field's 724-byte pyramid is built on the stack; the larger
    // ones come from flash (build.rs), so no scene needs more RAM.
    let mut skip = [0u8; scene::SKIP_BYTES];
    let source = match kind {
        scene::FrameKind::Small => Ok((
            &scene::FIELD_SAMPLES[..],
            (scene::FIELD_WIDTH, scene::FIELD_DEPTH),
            scene::Pyramid::Build(&mut skip),
        )),
        scene::FrameKind::Lcd => Ok((
            &scene::LCD_FIELD_SAMPLES[..],
            (scene::LCD_FIELD_WIDTH, scene::LCD_FIELD_DEPTH),
            scene::Pyramid::Precomputed(&LCD_PYRAMID),
        )),
        scene::FrameKind::Thesis => thesis_source(),
    };
    // One call, so its temporaries (a `HeightField` is 520 bytes) are
    // laid out once in main's frame.
    let field = source
        .and_then(|(samples, size, pyramid)| scene::build_field(&model, samples, size, pyramid));
    // On the Cortex-M4F the smooth fields' vertex normals come from flash
    // (build.rs): the same normals, not computed per hit; in world space
    // where the table was written for the scene's placement.
    #[cfg(hfray_normals_in_flash)]
    let field = field.and_then(|f| match kind {
        scene::FrameKind::Small => match f.clone().with_world_normals(&BASE_WORLD_NORMALS) {
            Ok(world) => Ok(world),
            Err(hfray::heightfield::HeightFieldError::WorldNormalsPlacement) => {
                Ok(f.with_raw_normals(&BASE_NORMALS)?)
            }
            Err(e) => Err(e.into()),
        },
        scene::FrameKind::Lcd => Ok(f.with_world_normals(&LCD_WORLD_NORMALS)?),
        scene::FrameKind::Thesis => Ok(f),
    });
    // On the Cortex-M4F (RAM to spare) the `base` and `lcd` fields' cell
    // maxima (`HeightField::with_cell_maxima`, 28 KB of `.bss`: flash has
    // no room), with which the walks cull a cell by one byte.
    #[cfg(target_abi = "eabihf")]
    let field = field.and_then(|f| match kind {
        scene::FrameKind::Thesis => Ok(f),
        _ => {
            // SAFETY: `main` runs once and never returns, and this is the
            // table's only reference.
            let table = unsafe { &mut *core::ptr::addr_of_mut!(CELL_MAXIMA) };
            let cells = f.cell_count();
            Ok(f.with_cell_maxima(&mut table[..cells])?)
        }
    });
    let fields = match field {
        Ok(f) => [f],
        Err(e) => fail_because(&mut out, &["field:", scene::scene_error_name(&e)]),
    };
    let name = match BOARD {
        "microbit" => "frame-microbit.ppm\0",
        _ => "frame-mps2-an386.ppm\0",
    };
    let mut file = match HostFile::create(name) {
        Ok(f) => f,
        Err(()) => fail_because(&mut out, &["semihosting-open"]),
    };
    if file.write_all(kind.ppm_header()).is_err() {
        fail();
    }
    let mut hash = scene::Fnv1a::default();
    let mut line = [hfray::Rgb888::default(); LINE_PIXELS];
    // Total use since reset so far (setup), then measure the render alone.
    let setup_low = lowest_used_stack_address();
    let render_sp = repaint_below_sp();
    // The frame's instructions (`frame=` of the instruction counter): the
    // render (camera and tracer setup, every pixel, the conversion to the
    // bytes sent, the checksum, the semihosting calls' guest side); not the
    // scene, the field, its pyramid or the stack scans.
    frame_mark();
    let stats = scene::render(FRAME, kind, &model, &fields, &mut line, |bytes| {
        hash.update(bytes);
        file.write_all(bytes)
    });
    frame_mark();
    let stats = match stats {
        Ok(s) => s,
        Err(scene::FrameError::Render(e)) => {
            fail_because(&mut out, &["render:", scene::render_error_name(&e)])
        }
        Err(scene::FrameError::Sink(())) => fail_because(&mut out, &["semihosting-write"]),
    };
    if file.close().is_err() {
        fail();
    }
    let render_low = lowest_used_stack_address();
    let top = core::ptr::addr_of!(_stack_start) as usize;
    let limit = top - core::ptr::addr_of!(_stack_end) as usize;
    // Whole program: reset handler, main's frame, the deepest call below.
    let used = top - setup_low.min(render_low);
    // Setup alone (scene, field, file): reset to the deepest setup call.
    let setup_used = top - setup_low;
    // The render call alone, below main's frame.
    let render_used = render_sp - render_low;
    // The render's deepest point, from the top: main's frame plus the call.
    let render_peak = top - render_low;
    write_parts(&mut out, &["board=", BOARD, " scene=", variant.name()]);
    let _ = write!(
        out,
        " frame={FRAME:?} frame_checksum={:08x} stack_bytes={used} \
         render_stack_bytes={render_used} render_peak_stack_bytes={render_peak} \
         setup_stack_bytes={setup_used} stack_limit_bytes={limit} ",
        hash.0,
    );
    let _ = scene::write_sizes(&mut out, kind);
    let _ = out.write_str(" ");
    let _ = scene::write_work(&mut out, &stats);
    let _ = out.write_str("\n");
    debug::exit(debug::EXIT_SUCCESS);
    loop {
        cortex_m::asm::wfi();
    }
}

/// Bytes of the cell maxima's table: the `lcd` field's cells (the `base`
/// field has fewer).
#[cfg(target_abi = "eabihf")]
const CELL_MAXIMA_BYTES: usize =
    (scene::LCD_FIELD_WIDTH as usize - 1) * (scene::LCD_FIELD_DEPTH as usize - 1);

/// The cell maxima's table (`.bss`), written once by `main`.
#[cfg(target_abi = "eabihf")]
static mut CELL_MAXIMA: [u8; CELL_MAXIMA_BYTES] = [0; CELL_MAXIMA_BYTES];

/// The `lcd` field's skip pyramid, built by `build.rs` (3.8 KB of flash
/// instead of RAM).
static LCD_PYRAMID: [u8; scene::LCD_SKIP_BYTES] =
    *include_bytes!(concat!(env!("OUT_DIR"), "/lcd_pyramid.bin"));

/// The `lcd` field's smooth-shading vertex normals in world space for the
/// scene's placement, written by `build.rs`
/// (`HeightField::write_world_normals`: 12 bytes a vertex, 341 KB of
/// flash), where the board has room. Measured on the `lcd` frame: smooth
/// normals 246 → 102 instructions a hit against POV-Ray's `i16` normals in
/// flash (170 KB, carried to world space and normalised per vertex).
#[cfg(hfray_normals_in_flash)]
static LCD_WORLD_NORMALS: [u8; scene::LCD_WORLD_NORMALS_BYTES] =
    *include_bytes!(concat!(env!("OUT_DIR"), "/lcd_world_normals.bin"));

/// The embedded (`base`) field's world-space vertex normals, as
/// [`LCD_WORLD_NORMALS`] (64 KB of flash).
#[cfg(hfray_normals_in_flash)]
static BASE_WORLD_NORMALS: [u8; scene::WORLD_NORMALS_BYTES] =
    *include_bytes!(concat!(env!("OUT_DIR"), "/base_world_normals.bin"));

/// The embedded field's vertex normals as POV-Ray stores them
/// (`HeightField::write_raw_normals`, 32 KB of flash), for the scenes that
/// turn it (`reflect-*`), where the world-space table does not fit
/// (measured on the `base` frame: smooth normals 487 → 257 instructions a
/// hit against computing them).
#[cfg(hfray_normals_in_flash)]
static BASE_NORMALS: [u8; scene::FIELD_WIDTH as usize * scene::FIELD_DEPTH as usize * 6] =
    *include_bytes!(concat!(env!("OUT_DIR"), "/base_normals.bin"));

/// The `thesis` field and its pyramid in flash, where the board has room:
/// generated at build time by `build.rs` with `scene::thesis_field`
/// (256 KiB; the micro:bit's flash is 256 KiB in all).
#[cfg(hfray_thesis_in_flash)]
static THESIS_SAMPLES: [u8; scene::THESIS_SAMPLES] =
    *include_bytes!(concat!(env!("OUT_DIR"), "/thesis_field.u8"));
#[cfg(hfray_thesis_in_flash)]
static THESIS_PYRAMID: [u8; scene::THESIS_SKIP_BYTES] =
    *include_bytes!(concat!(env!("OUT_DIR"), "/thesis_pyramid.bin"));

/// Pixels in the row buffer: the widest frame this board renders.
#[cfg(hfray_thesis_in_flash)]
const LINE_PIXELS: usize = scene::THESIS_WIDTH;
/// Pixels in the row buffer: the widest frame this board renders.
#[cfg(not(hfray_thesis_in_flash))]
const LINE_PIXELS: usize = scene::LCD_WIDTH;

/// Samples, size and pyramid of a field.
type FieldSource = (&'static [u8], (u32, u32), scene::Pyramid<'static>);

/// The `thesis` scene's field, from flash.
#[cfg(hfray_thesis_in_flash)]
fn thesis_source() -> Result<FieldSource, scene::SceneError> {
    let side = (scene::THESIS_SIDE, scene::THESIS_SIDE);
    Ok((
        &THESIS_SAMPLES,
        side,
        scene::Pyramid::Precomputed(&THESIS_PYRAMID),
    ))
}

/// The `thesis` scene is not in this board's flash.
#[cfg(not(hfray_thesis_in_flash))]
fn thesis_source() -> Result<FieldSource, scene::SceneError> {
    Err(scene::SceneError::NotInThisBuild)
}

/// The scene the command line names; runs the `sqrt-check` instead if it
/// says so. Not inlined: the line's buffer then lives in this call's frame,
/// not in `main`'s frame, which stays on the stack under the render.
#[inline(never)]
fn variant_from_command_line(out: &mut hio::HostStream) -> scene::Variant {
    let mut cmdline = [0u8; CMDLINE_BYTES];
    let variant = scene::variant_from_cmdline(command_line(&mut cmdline));
    if variant_is_sqrt_check(&cmdline) {
        check_sqrt(out)
    }
    match variant {
        Some(v) => v,
        None => fail_because(out, &["unknown-scene"]),
    }
}

/// `true` if the command line's last word is `sqrt-check`.
fn variant_is_sqrt_check(line: &[u8; CMDLINE_BYTES]) -> bool {
    let end = line.iter().position(|&b| b == 0).unwrap_or(CMDLINE_BYTES);
    line[..end].ends_with(b" sqrt-check") || &line[..end] == b"sqrt-check"
}

/// Inputs [`check_sqrt`] compares: every 4093rd bit pattern, so all
/// exponents, signs, subnormals, infinities and NaNs are among them.
const SQRT_CHECKS: u32 = 1 << 20;

/// The `sqrt-check` run: `hfray::math::sqrtf` (`vsqrt.f32` on the
/// Cortex-M4F) against `libm::sqrtf`, bit for bit, printed as
/// `sqrt_checked=N sqrt_mismatches=M`; exits, non-zero on any mismatch.
fn check_sqrt(out: &mut hio::HostStream) -> ! {
    let mut bits = 0u32;
    let mut mismatches = 0u32;
    for _ in 0..SQRT_CHECKS {
        let x = f32::from_bits(bits);
        let (ours, reference) = (hfray::math::sqrtf(x), libm::sqrtf(x));
        if ours.to_bits() != reference.to_bits() && !(ours.is_nan() && reference.is_nan()) {
            mismatches += 1;
        }
        bits = bits.wrapping_add(4093);
    }
    write_parts(out, &["board=", BOARD, " scene=sqrt-check "]);
    let _ = writeln!(
        out,
        "sqrt_checked={SQRT_CHECKS} sqrt_mismatches={mismatches}"
    );
    if mismatches == 0 {
        debug::exit(debug::EXIT_SUCCESS);
    }
    fail()
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    // Keep the message out: formatting it would pull core::fmt's panic
    // machinery into every build. The exit status tells the script.
    if let Ok(mut out) = hio::hstdout() {
        let _ = out.write_str("error=panic\n");
    }
    fail()
}
