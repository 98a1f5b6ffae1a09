//! hfray's firmware scene as a freestanding i486 Linux program: no libc, no
//! C runtime, no allocator, floating point on the x87 only.
//!
//! Built for `i586-unknown-linux-gnu` with `-C target-cpu=i486` (see
//! `../.cargo/config.toml`) and run under `qemu-i386 -cpu 486`, which
//! rejects any instruction the 486 lacks. It renders the same scene with the
//! same code (`../../src/scene.rs`), writes the frame to `frame-i486.ppm`
//! and prints one line on stdout:
//! `board=i486 frame_checksum=HEX stack_bytes=N render_stack_bytes=N hits=N shadow_rays=N ...`.
//!
//! # What the C runtime would have done, done here
//! - `_start` (assembly): clear the frame pointer, align the stack to 16
//!   bytes, paint [`PAINT_BYTES`] below it with `0xCCCC_CCCC` (stack
//!   high-water), set the x87 control word, call [`start`].
//! - Linux system calls through `int 0x80`: `open`, `write`, `close`, `exit`.
//! - `memcpy`, `memmove`, `memset`, `memcmp`, `bcmp`: compiler_builtins for
//!   `*-linux-gnu` expects libc to provide them. They are written in
//!   assembly (`rep movsb`/`rep stosb`/`repe cmpsb`, all on the 486) because
//!   Rust loops could be turned back into calls to themselves.
//!
//! # x87 precision
//! The x87 keeps values in 80-bit registers; rustc's x87 code does not round
//! each `f32` operation to `f32` (only spills and stores round), so by
//! default a chain like `a * b + c` would be rounded once at the end, not
//! after each step as on SSE, VFP or soft-float, and the result would depend
//! on register allocation. [`start`] therefore sets the precision-control
//! field of the control word to 53 bits for the setup (all `f64`: the core's
//! transforms, the camera) and to 24 bits for the render (all `f32`), which
//! rounds every operation's significand to `f32` precision. That is exactly
//! IEEE `f32` unless a value leaves the `f32` exponent range, which the
//! checksum comparison with the host would show. With 53 or 64 bits during
//! the render, 4 pixels of the frame differ from the host's.
#![no_std]
#![no_main]

#[path = "../../src/scene.rs"]
mod scene;

use core::arch::{asm, global_asm};
use core::fmt::Write as _;

/// Bytes of stack painted below the entry stack pointer.
const PAINT_BYTES: usize = 16 * 1024;
const PAINT: u32 = 0xCCCC_CCCC;

// Entry point. The kernel leaves argc/argv/envp at esp; we need none of them.
global_asm!(
    ".globl _start",
    "_start:",
    "xor ebp, ebp",
    "and esp, -16",
    // Paint PAINT_BYTES below esp (rep stosd goes upward from edi).
    "mov edi, esp",
    "sub edi, {paint_bytes}",
    "mov ecx, {paint_words}",
    "mov eax, {paint}",
    "cld",
    "rep stosd",
    // start(stack_top): the argument at [esp], esp 16-aligned at the call.
    "mov eax, esp",
    "sub esp, 12",
    "push eax",
    "call {start}",
    "ud2",
    paint_bytes = const PAINT_BYTES,
    paint_words = const PAINT_BYTES / 4,
    paint = const PAINT,
    start = sym start,
);

// The C library functions the compiler emits calls to.
global_asm!(
    ".globl memcpy",
    "memcpy:",
    "push esi",
    "push edi",
    "mov edi, [esp + 12]",
    "mov esi, [esp + 16]",
    "mov ecx, [esp + 20]",
    "mov eax, edi",
    "cld",
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
    "mov eax, [esp + 12]",
    "mov ecx, [esp + 16]",
    "mov edx, edi",
    "cld",
    "rep stosb",
    "mov eax, edx",
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

fn fail(what: &str) -> ! {
    let _ = writeln!(Stdout, "board=i486 error={what}");
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

extern "C" fn start(stack_top: usize) -> ! {
    // Setup (f64 inside the core: transform composition and inverses).
    set_x87_precision(0b10);
    let model = match scene::build_scene() {
        Ok(s) => s,
        Err(_) => fail("scene"),
    };
    let fields = match scene::build_field(&model) {
        Ok(f) => [f],
        Err(_) => fail("field"),
    };
    // O_WRONLY | O_CREAT | O_TRUNC, mode 0644.
    let fd = syscall3(nr::OPEN, c"frame-i486.ppm".as_ptr() as u32, 0o1101, 0o644);
    if fd < 0 {
        fail("open");
    }
    let fd = fd as u32;
    if write_all(fd, scene::PPM_HEADER).is_err() {
        fail("write");
    }
    let renderer = match scene::Renderer::new(&model, &fields) {
        Ok(r) => r,
        Err(_) => fail("render-setup"),
    };
    let mut hash = scene::Fnv1a::default();
    // Pin the setup's results in memory before the precision changes:
    // black_box makes them escape, so their (f64/x87) computation cannot be
    // sunk below the `fldcw` (LLVM does not know the control word matters).
    core::hint::black_box(&model);
    core::hint::black_box(&fields);
    core::hint::black_box(&renderer);
    let setup_low = lowest_used_stack_address(stack_top);
    let render_sp = repaint_below_sp(stack_top);
    // The render: f32 only, so every x87 operation rounds to 24 bits.
    set_x87_precision(0b00);
    let stats = renderer.render(|_, line| {
        hash.update(line);
        write_all(fd, line)
    });
    set_x87_precision(0b10);
    let stats = match stats {
        Ok(s) => s,
        Err(_) => fail("write"),
    };
    syscall3(nr::CLOSE, fd, 0, 0);
    let render_low = lowest_used_stack_address(stack_top);
    let used = stack_top - setup_low.min(render_low);
    let render_used = render_sp - render_low;
    let _ = writeln!(
        Stdout,
        "board=i486 frame_checksum={:08x} stack_bytes={used} render_stack_bytes={render_used} \
         hits={} shadow_rays={} shadow_hits={} cells={} triangle_tests={}",
        hash.0, stats.hits, stats.shadow_rays, stats.shadow_hits, stats.cells, stats.triangle_tests
    );
    exit(0)
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    fail("panic")
}
