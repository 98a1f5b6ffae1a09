//! hfray's firmware scene as a freestanding i486 Linux program: no libc, no
//! C runtime, no allocator, floating point on the x87 only.
//!
//! Built for `i586-unknown-linux-gnu` with `-C target-cpu=i486` (see
//! `../.cargo/config.toml`) and run under `qemu-i386 -cpu 486`, which
//! rejects any instruction the 486 lacks. It renders the same scene with the
//! same code (`../../src/scene.rs`), writes the frame to `frame-i486.ppm`
//! and prints one line on stdout:
//! `board=i486 scene=NAME frame_checksum=HEX stack_bytes=N render_stack_bytes=N ... hits=N ...`.
//! The scene variant (`scene::VARIANTS`) is the last command-line argument,
//! `base` without one.
//!
//! Built with `--features fixed-frame` it is the 486SX program: it draws the
//! fixed-point frame (`hfray::fixed_frame`, as the Cortex-M0 does) and
//! prints `board=i486sx`; its pixels run no x87 instruction, only its
//! per-frame set-up does (`f64`; on a 486SX the kernel's FPU emulation).
//!
//! # What the C runtime would have done, done here
//! - `_start` (assembly): clear the frame pointer, keep the entry stack
//!   pointer (it points at `argc`, `argv`), align the stack to 16 bytes,
//!   paint [`PAINT_BYTES`] below it with `0xCCCC_CCCC` (stack high-water),
//!   call [`start`].
//! - Linux system calls through `int 0x80`: `open`, `read`, `write`,
//!   `close`, `exit`.
//! - `memcpy`, `memmove`, `memset`, `memcmp`, `bcmp`: compiler_builtins for
//!   `*-linux-gnu` expects libc to provide them. They are written in
//!   assembly (`rep movsd`/`rep stosd` and `rep movsb`/`rep stosb`, `repe
//!   cmpsb`, all on the 486) because Rust loops could be turned back into
//!   calls to themselves.
//!
//! # x87 precision
//! The x87 keeps values in 80-bit registers; rustc's x87 code does not round
//! each `f32` operation to `f32` (only spills and stores round), so by
//! default a chain like `a * b + c` would be rounded once at the end, not
//! after each step as on SSE, VFP or soft-float, and the result would depend
//! on register allocation. [`start`] therefore sets the precision-control
//! field of the control word to 53 bits for the setup (all `f64`: the core's
//! transforms, the camera, the fields' grid maps) and to 24 bits for the
//! render (all `f32`, including the per-ray world-to-grid map), which rounds
//! every operation's significand to `f32` precision. That is exactly IEEE
//! `f32` unless a value leaves the `f32` exponent range, which the checksum
//! and work-counter comparison with the host would show. With 24 bits for
//! the whole program, or 53 or 64 bits for the render, the 8-bit frame of
//! the `base` scene still matches but its cell count differs by one.
#![no_std]
#![no_main]

#[path = "../../src/scene.rs"]
mod scene;

#[cfg(feature = "fixed-frame")]
use scene::FixedRenderer as Renderer;
#[cfg(not(feature = "fixed-frame"))]
use scene::Renderer;

/// The `board=` name printed.
const BOARD: &str = if cfg!(feature = "fixed-frame") {
    "i486sx"
} else {
    "i486"
};

use core::arch::{asm, global_asm};
use core::fmt::Write as _;
use core::ptr::addr_of_mut;

/// The `thesis` field, generated at run time (256 KiB; in `.bss`, as the
/// stack is capped at 64 KiB).
static mut THESIS_FIELD: [u8; scene::THESIS_SAMPLES] = [0; scene::THESIS_SAMPLES];
/// The skip pyramid of whichever field the scene draws (the largest, the
/// thesis field's, is 34 KB).
static mut PYRAMID: [u8; scene::THESIS_SKIP_BYTES] = [0; scene::THESIS_SKIP_BYTES];
/// Bytes of the cell maxima's table: the `thesis` field's cells (the
/// others have fewer).
const CELL_MAXIMA_BYTES: usize =
    (scene::THESIS_SIDE as usize - 1) * (scene::THESIS_SIDE as usize - 1);
/// Each cell's highest sample, one byte a cell, of whichever field the
/// scene draws (`HeightField::with_cell_maxima`, written before the frame),
/// with which the walks cull a cell above the ray by one byte
/// (`hfray::traversal`'s `CELL_MAXIMA` has the figures).
static mut CELL_MAXIMA: [u8; CELL_MAXIMA_BYTES] = [0; CELL_MAXIMA_BYTES];
/// The smooth-shading vertex normals of the scene's field in world space,
/// written at run time before the frame (the largest smooth field, `lcd`'s,
/// takes 341 KB; the `thesis` field is flat).
#[cfg(not(feature = "fixed-frame"))]
static mut NORMALS: [u8; scene::LCD_WORLD_NORMALS_BYTES] = [0; scene::LCD_WORLD_NORMALS_BYTES];
/// The row buffer, as wide as the widest frame (`thesis`, 320 pixels): in
/// `.bss`, not on the stack under the render.
static mut LINE: [hfray::Rgb888; scene::THESIS_WIDTH] =
    [hfray::Rgb888([0; 3]); scene::THESIS_WIDTH];

/// Bytes of stack painted below the entry stack pointer.
const PAINT_BYTES: usize = 32 * 1024;
const PAINT: u32 = 0xCCCC_CCCC;

// Entry point. The kernel leaves argc/argv/envp at esp; we need none of them.
global_asm!(
    ".globl _start",
    "_start:",
    "xor ebp, ebp",
    // esi: the entry stack pointer (argc, then argv[]); rep stosd keeps it.
    "mov esi, esp",
    "and esp, -16",
    // Paint PAINT_BYTES below esp (rep stosd goes upward from edi).
    "mov edi, esp",
    "sub edi, {paint_bytes}",
    "mov ecx, {paint_words}",
    "mov eax, {paint}",
    "cld",
    "rep stosd",
    // start(stack_top, entry_sp): arguments at [esp], [esp + 4], esp
    // 16-aligned at the call.
    "mov eax, esp",
    "sub esp, 8",
    "push esi",
    "push eax",
    "call {start}",
    "ud2",
    paint_bytes = const PAINT_BYTES,
    paint_words = const PAINT_BYTES / 4,
    paint = const PAINT,
    start = sym start,
);

// The C library functions the compiler emits calls to. `memcpy` and
// `memset` move whole dwords (`rep movsd`, `rep stosd`), then the 0-3 bytes
// left (`rep movsb`, `rep stosb`): a `rep` runs (and QEMU counts) one
// instruction per element, and the frame's ~200 copies average ~155 bytes
// (measured, i486 base frame: 15,386,388 -> 15,364,007 instructions; bytes
// only before). Unaligned dwords are fine on the x86. `memmove` (not run in
// the frame) and `memcmp` stay bytewise.
global_asm!(
    ".globl memcpy",
    "memcpy:",
    "push esi",
    "push edi",
    "mov edi, [esp + 12]",
    "mov esi, [esp + 16]",
    "mov ecx, [esp + 20]",
    "mov eax, edi",
    "mov edx, ecx",
    "shr ecx, 2",
    "cld",
    "rep movsd",
    "mov ecx, edx",
    "and ecx, 3",
    "rep movsb",
    "pop edi",
    "pop esi",
    "ret",
    "",
    ".globl memmove",
    "memmove:",
    "push esi",
    "push edi",
    "mov edi, [esp + 12]",
    "mov esi, [esp + 16]",
    "mov ecx, [esp + 20]",
    "mov eax, edi",
    "cmp edi, esi",
    "jbe 2f",
    // dest above src: copy backwards from the last byte.
    "lea esi, [esi + ecx - 1]",
    "lea edi, [edi + ecx - 1]",
    "std",
    "rep movsb",
    "cld",
    "jmp 3f",
    "2:",
    "cld",
    "rep movsb",
    "3:",
    "pop edi",
    "pop esi",
    "ret",
    "",
    ".globl memset",
    "memset:",
    "push edi",
    "mov edi, [esp + 8]",
    // The byte in all four bytes of eax.
    "movzx eax, byte ptr [esp + 12]",
    "imul eax, eax, 0x01010101",
    "mov ecx, [esp + 16]",
    "mov edx, ecx",
    "shr ecx, 2",
    "cld",
    "rep stosd",
    "mov ecx, edx",
    "and ecx, 3",
    "rep stosb",
    "mov eax, [esp + 8]",
    "pop edi",
    "ret",
    "",
    ".globl memcmp",
    ".globl bcmp",
    "memcmp:",
    "bcmp:",
    "push esi",
    "push edi",
    "mov esi, [esp + 12]",
    "mov edi, [esp + 16]",
    "mov ecx, [esp + 20]",
    "xor eax, eax",
    "cld",
    "repe cmpsb",
    "je 4f",
    "movzx eax, byte ptr [esi - 1]",
    "movzx ecx, byte ptr [edi - 1]",
    "sub eax, ecx",
    "4:",
    "pop edi",
    "pop esi",
    "ret",
);

/// Linux i386 system call numbers.
mod nr {
    pub const EXIT: u32 = 1;
    pub const READ: u32 = 3;
    pub const WRITE: u32 = 4;
    pub const OPEN: u32 = 5;
    pub const CLOSE: u32 = 6;
}

/// `int 0x80` with up to three arguments. `ebx` cannot be named as an asm
/// operand (LLVM may use it), so it is swapped in and out around the trap.
fn syscall3(n: u32, a: u32, b: u32, c: u32) -> i32 {
    let ret: i32;
    // SAFETY: the Linux i386 system call ABI; the callers pass pointers to
    // live buffers with their true lengths.
    unsafe {
        asm!(
            "xchg ebx, {a}",
            "int 0x80",
            "xchg ebx, {a}",
            a = inout(reg) a => _,
            inlateout("eax") n => ret,
            in("ecx") b,
            in("edx") c,
            options(nostack),
        );
    }
    ret
}

fn exit(code: u32) -> ! {
    syscall3(nr::EXIT, code, 0, 0);
    // SAFETY: not reached (exit does not return); trap if it ever is.
    unsafe { asm!("ud2", options(noreturn)) }
}

/// Writes all of `bytes` to file descriptor `fd`. Bounded: every round
/// writes at least one byte or fails.
fn write_all(fd: u32, mut bytes: &[u8]) -> Result<(), i32> {
    while !bytes.is_empty() {
        let n = syscall3(nr::WRITE, fd, bytes.as_ptr() as u32, bytes.len() as u32);
        if n <= 0 {
            return Err(n);
        }
        bytes = &bytes[n as usize..];
    }
    Ok(())
}

/// `write(2)` to stdout as a `core::fmt` sink.
struct Stdout;

impl core::fmt::Write for Stdout {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        write_all(1, s.as_bytes()).map_err(|_| core::fmt::Error)
    }
}

/// x87 control word: all exceptions masked, round to nearest, precision
/// control `pc` (0b00 = 24-bit, 0b10 = 53-bit, 0b11 = 64-bit).
fn set_x87_precision(pc: u16) {
    let cw: u16 = 0x007F | (pc << 8);
    // SAFETY: loads the FPU control word from a local.
    // No `readonly`/`nomem`: the asm is then a compiler barrier for memory
    // accesses, so loads feeding the f32 work are not hoisted above it.
    unsafe { asm!("fldcw [{}]", in(reg) &cw, options(nostack)) };
}

/// Opens or closes a segment of the frame for the instruction counter
/// (`tools/qemu-insn-count`: `frame=N` counts what runs inside the
/// segments): `xchg bx, bx`, which changes nothing and which compilers do
/// not emit.
#[inline(always)]
fn frame_mark() {
    // SAFETY: swaps bx with itself: no register, flag or memory changes.
    // Not `nomem`, so memory accesses stay on their side of it. Aligned to
    // 4 bytes (the padding is a nop or two, run once), so that the 3-byte
    // marker never straddles a page: QEMU hands the counting plugin only the
    // first page's bytes of such an instruction, which then is no marker
    // (seen once, at 0x42affe: the frame closed after the set-up).
    unsafe {
        asm!(
            ".p2align 2",
            "xchg bx, bx",
            options(nostack, preserves_flags)
        )
    };
}

fn fail(what: &str) -> ! {
    // Strings as they are, not through `Display`, whose padding code
    // (about 1 KB) is then not linked.
    for part in ["board=", BOARD, " error=", what, "\n"] {
        let _ = Stdout.write_str(part);
    }
    exit(1)
}

/// Lowest stack address written since painting: scans up from
/// `top - PAINT_BYTES` for the first word that is not the paint. Bounded by
/// `PAINT_BYTES / 4` reads.
fn lowest_used_stack_address(top: usize) -> usize {
    let mut addr = top - PAINT_BYTES;
    while addr < top {
        // SAFETY: `[top - PAINT_BYTES, top)` is the stack below the entry
        // stack pointer, which `_start` wrote (so it is mapped).
        if unsafe { core::ptr::read_volatile(addr as *const u32) } != PAINT {
            break;
        }
        addr += 4;
    }
    addr
}

/// Gap left unpainted just below the stack pointer when repainting.
const REPAINT_GAP: usize = 256;

/// Paints `[top - PAINT_BYTES, esp - REPAINT_GAP)` again and returns `esp`
/// (the caller's: inlined), so a later scan measures what runs after it.
#[inline(always)]
fn repaint_below_sp(top: usize) -> usize {
    let sp: usize;
    // SAFETY: reads the stack pointer.
    unsafe { asm!("mov {}, esp", out(reg) sp, options(nomem, nostack)) };
    let mut addr = top - PAINT_BYTES;
    while addr + REPAINT_GAP < sp {
        // SAFETY: below every live frame; `_start` mapped it.
        unsafe { core::ptr::write_volatile(addr as *mut u32, PAINT) };
        addr += 4;
    }
    sp
}

/// The last command-line argument (`argv[argc - 1]` when `argc >= 2`),
/// at most 64 bytes of it; empty if there is none. `entry_sp` is the stack
/// pointer the kernel handed to `_start`: `argc`, then the `argv` pointers.
fn last_argument(entry_sp: usize) -> &'static [u8] {
    // SAFETY: the Linux i386 process entry ABI: `[entry_sp]` is argc,
    // followed by argc pointers to NUL-terminated strings that live (on
    // the stack above us) for the whole process and are never written.
    unsafe {
        let argc = *(entry_sp as *const usize);
        if argc < 2 {
            return &[];
        }
        let arg = *((entry_sp + 4 * argc) as *const *const u8);
        let mut len = 0;
        while len < 64 && *arg.add(len) != 0 {
            len += 1;
        }
        core::slice::from_raw_parts(arg, len)
    }
}

/// `VmPeak` and `VmHWM` of `/proc/self/status` in KiB: the peak address
/// space (what `ulimit -v` caps) and the peak resident set. 0 where they
/// cannot be read; under QEMU they are QEMU's own. Not inlined, and called
/// after the stack measurement: its 2 KiB buffer is not part of the figure.
#[inline(never)]
fn vm_peak_and_hwm_kib() -> (u32, u32) {
    let fd = syscall3(nr::OPEN, c"/proc/self/status".as_ptr() as u32, 0, 0);
    if fd < 0 {
        return (0, 0);
    }
    let mut buf = [0u8; 2048];
    let mut len = 0;
    // Bounded: every round reads at least one byte or stops.
    while len < buf.len() {
        let n = syscall3(
            nr::READ,
            fd as u32,
            buf[len..].as_mut_ptr() as u32,
            (buf.len() - len) as u32,
        );
        if n <= 0 {
            break;
        }
        len += n as usize;
    }
    syscall3(nr::CLOSE, fd as u32, 0, 0);
    let text = &buf[..len];
    (status_kib(text, b"VmPeak:"), status_kib(text, b"VmHWM:"))
}

/// The number after `key` in `/proc/self/status` text, 0 if absent.
/// Bounded by the text's length.
fn status_kib(text: &[u8], key: &[u8]) -> u32 {
    let Some(at) = text.windows(key.len()).position(|w| w == key) else {
        return 0;
    };
    text[at + key.len()..]
        .iter()
        .skip_while(|b| **b == b' ' || **b == b'\t')
        .take_while(|b| b.is_ascii_digit())
        .fold(0u32, |v, b| {
            v.saturating_mul(10).saturating_add((b - b'0') as u32)
        })
}

extern "C" fn start(stack_top: usize, entry_sp: usize) -> ! {
    // Setup (f64 inside the core: transform composition and inverses).
    set_x87_precision(0b10);
    let arg = last_argument(entry_sp);
    if arg == b"sqrt-check" {
        check_sqrt()
    }
    let variant = if arg.is_empty() {
        scene::Variant::Base
    } else {
        match scene::Variant::by_name(arg) {
            Some(v) => v,
            None => fail("unknown-scene"),
        }
    };
    let kind = variant.kind();
    let model = match scene::build_scene(variant) {
        Ok(s) => s,
        Err(_) => fail("scene"),
    };
    // SAFETY: taken once, here, in a single-threaded program; nothing else
    // names these statics.
    let (thesis, pyramid, line) = unsafe {
        (
            &mut *addr_of_mut!(THESIS_FIELD),
            &mut *addr_of_mut!(PYRAMID),
            &mut *addr_of_mut!(LINE),
        )
    };
    // The thesis field is generated at run time, as the thesis did
    // (integer arithmetic: the same bytes as the host's).
    let (samples, size) = match kind.field_samples(thesis) {
        Ok(s) => s,
        Err(_) => fail("field-samples"),
    };
    let field = match scene::build_field(&model, samples, size, scene::Pyramid::Build(pyramid)) {
        Ok(f) => f,
        Err(_) => fail("field"),
    };
    // The smooth fields' vertex normals, written once here in world space
    // for the field as placed (POV-Ray computes its own when it reads a
    // smooth field; the Cortex-M4F keeps them in flash) instead of per hit
    // in the frame: the same normals. Their arithmetic is `f32`, so it runs
    // under the render's 24-bit precision.
    #[cfg(not(feature = "fixed-frame"))]
    let field = if matches!(kind, scene::FrameKind::Thesis) {
        field
    } else {
        // SAFETY: taken once, here; nothing else names this static.
        let normals = unsafe { &mut *addr_of_mut!(NORMALS) };
        let Some(table) = normals.get_mut(..field.world_normals_bytes()) else {
            fail("normals")
        };
        set_x87_precision(0b00);
        let written = field.write_world_normals(table);
        core::hint::black_box(&table);
        set_x87_precision(0b10);
        match written.and_then(|()| field.with_world_normals(table)) {
            Ok(f) => f,
            Err(_) => fail("normals"),
        }
    };
    // SAFETY: taken once, here; nothing else names this static.
    let maxima = unsafe { &mut *addr_of_mut!(CELL_MAXIMA) };
    let cells = field.cell_count();
    let Some(table) = maxima.get_mut(..cells) else {
        fail("cell-maxima")
    };
    let field = match field.with_cell_maxima(table) {
        Ok(f) => f,
        Err(_) => fail("cell-maxima"),
    };
    let fields = [field];
    // O_WRONLY | O_CREAT | O_TRUNC, mode 0644.
    let fd = syscall3(nr::OPEN, c"frame-i486.ppm".as_ptr() as u32, 0o1101, 0o644);
    if fd < 0 {
        fail("open");
    }
    let fd = fd as u32;
    if write_all(fd, kind.ppm_header()).is_err() {
        fail("write");
    }
    // The frame's instructions (`frame=` of the instruction counter): the
    // renderer's setup (camera, tracer) and the render; not the scene, the
    // field, its pyramid or the stack scans.
    frame_mark();
    let renderer = match Renderer::new(kind, &model, &fields) {
        Ok(r) => r,
        Err(_) => fail("render-setup"),
    };
    frame_mark();
    let mut hash = scene::Fnv1a::default();
    // Pin the setup's results in memory before the precision changes:
    // black_box makes them escape, so their (f64/x87) computation cannot be
    // sunk below the `fldcw` (LLVM does not know the control word matters).
    core::hint::black_box(&model);
    core::hint::black_box(&fields);
    core::hint::black_box(&renderer);
    let setup_low = lowest_used_stack_address(stack_top);
    let render_sp = repaint_below_sp(stack_top);
    frame_mark();
    // The render: f32 only, so every x87 operation rounds to 24 bits. The
    // fixed-point frame runs no x87 instruction, not even these.
    let float_frame = !cfg!(feature = "fixed-frame");
    if float_frame {
        set_x87_precision(0b00);
    }
    let stats = renderer.render(line, |bytes| {
        hash.update(bytes);
        write_all(fd, bytes)
    });
    if float_frame {
        set_x87_precision(0b10);
    }
    frame_mark();
    let stats = match stats {
        Ok(s) => s,
        Err(_) => fail("write"),
    };
    syscall3(nr::CLOSE, fd, 0, 0);
    let render_low = lowest_used_stack_address(stack_top);
    let used = stack_top - setup_low.min(render_low);
    let setup_used = stack_top - setup_low;
    let render_used = render_sp - render_low;
    let render_peak = stack_top - render_low;
    let (vm_peak, vm_hwm) = vm_peak_and_hwm_kib();
    let _ = Stdout.write_str("board=");
    let _ = Stdout.write_str(BOARD);
    let _ = Stdout.write_str(" scene=");
    let _ = Stdout.write_str(variant.name());
    let _ = write!(
        Stdout,
        " frame_checksum={:08x} stack_bytes={used} \
         render_stack_bytes={render_used} render_peak_stack_bytes={render_peak} \
         setup_stack_bytes={setup_used} vm_peak_kib={vm_peak} \
         vm_hwm_kib={vm_hwm} ",
        hash.0,
    );
    let _ = scene::write_sizes(&mut Stdout, kind);
    let _ = Stdout.write_str(" ");
    let _ = scene::write_work(&mut Stdout, &stats);
    let _ = Stdout.write_str("\n");
    exit(0)
}

/// Inputs [`check_sqrt`] compares per precision setting: every 4093rd
/// bit pattern, so all exponents, signs, subnormals, infinities and NaNs
/// are among them.
const SQRT_CHECKS: u32 = 1 << 20;

/// The `sqrt-check` run: `hfray::math::sqrtf` (`fsqrt` here) against
/// `libm::sqrtf`, bit for bit, under the x87 precision settings of the
/// render (24 bits), the setup (53) and the reset default (64); prints
/// `sqrt_checked=N sqrt_mismatches=M` and exits, non-zero on any mismatch.
fn check_sqrt() -> ! {
    let mut mismatches = 0u32;
    for pc in [0b00, 0b10, 0b11] {
        set_x87_precision(pc);
        let mut bits = 0u32;
        for _ in 0..SQRT_CHECKS {
            let x = core::hint::black_box(f32::from_bits(bits));
            let (ours, reference) = (hfray::math::sqrtf(x), libm::sqrtf(x));
            if ours.to_bits() != reference.to_bits() && !(ours.is_nan() && reference.is_nan()) {
                mismatches += 1;
            }
            bits = bits.wrapping_add(4093);
        }
    }
    set_x87_precision(0b10);
    let _ = writeln!(
        Stdout,
        "board=i486 scene=sqrt-check sqrt_checked={} sqrt_mismatches={mismatches}",
        3 * SQRT_CHECKS
    );
    exit(if mismatches == 0 { 0 } else { 1 })
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    fail("panic")
}
