//! `f32` square root in hardware where the chip has one, and the vector
//! lengths built on it.
//!
//! `core` has no stable `f32::sqrt`, and `libm::sqrtf` (what glam calls in
//! a `no_std` build) is bit-by-bit software on 32-bit ARM, where the FPU has
//! `vsqrt.f32`, and on the 486, where the x87 has `fsqrt`. Every IEEE square
//! root is correctly rounded, so each of these gives `libm::sqrtf`'s result
//! bit for bit: the firmware checks it on the Cortex-M4F and the 486 under
//! QEMU over 2^20 inputs and `run-qemu.sh` fails on any difference
//! (`sqrt_mismatches=0`), and the tests below check it on the host.
//!
//! The length and normalisation helpers repeat glam's arithmetic
//! (`Vec3::length`, `Vec3::normalize_or_zero`) operation for operation, so
//! swapping them in changes no bit of any result.

use glam::Vec3;

/// `√x`, correctly rounded (IEEE 754), the same bits as `libm::sqrtf`;
/// NaN for `x < 0`.
#[inline(always)]
pub fn sqrtf(x: f32) -> f32 {
    hardware_sqrtf(x)
}

// Measured (QEMU instruction counts, Cortex-M4F, issue 14): libm's software
// sqrtf ran 76 instructions per call (74,219 calls, 11.8% of the 96×64
// firmware frame);
// this is three (`bl`, `vsqrt.f32`, `bx lr`). With `fsqrt` below, the only
// `unsafe` in the core;
// `tests::sqrtf_matches_libm_bit_for_bit` and the firmware's own check under
// QEMU (`sqrt_mismatches=0`) cover it.
//
// A function in assembly rather than an inline `asm!`: Rust's `sreg`
// operands need the `vfp2` target feature, which includes double precision
// and so is off on single-precision FPUs (Cortex-M4F), and that feature
// cannot be enabled for one function on stable Rust. The hard-float
// calling convention passes and returns the value in `s0`.
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[allow(unsafe_code)]
mod vsqrt {
    core::arch::global_asm!(
        ".section .text.hfray_vsqrt_f32,\"ax\",%progbits",
        // The integrated assembler does not see the target's FPU here; name
        // the smallest one with `vsqrt.f32`: single precision only.
        ".fpu fpv4-sp-d16",
        ".globl hfray_vsqrt_f32",
        ".type hfray_vsqrt_f32,%function",
        ".thumb_func",
        "hfray_vsqrt_f32:",
        "vsqrt.f32 s0, s0",
        "bx lr",
        ".size hfray_vsqrt_f32, . - hfray_vsqrt_f32",
    );
}

#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[allow(unsafe_code)]
#[inline(always)]
fn hardware_sqrtf(x: f32) -> f32 {
    extern "C" {
        /// `s0 = √s0` (the assembly above).
        fn hfray_vsqrt_f32(x: f32) -> f32;
    }
    // SAFETY: the function above reads and writes `s0` only (caller-saved
    // under AAPCS-VFP), touches no memory and no stack, and every eabihf
    // ARM target has the VFP unit it needs.
    unsafe { hfray_vsqrt_f32(x) }
}

// Measured (QEMU, i486 firmware frame, issue 14): libm's software sqrtf
// was 16% of the 96×64 frame's instructions; `fsqrt` is one x87
// instruction. Loaded and stored as `f32`, the result is correctly rounded
// whatever the x87 precision control says (53- or 64-bit rounding first,
// then to 24 bits, is innocuous for a square root: 53 ≥ 2·24 + 2). Covered
// by `tests::sqrtf_matches_libm_bit_for_bit` where it runs and by the i486
// program's `sqrt-check` under `qemu-i386 -cpu 486` (`sqrt_mismatches=0`).
#[cfg(x87)]
#[allow(unsafe_code)]
#[inline(always)]
fn hardware_sqrtf(x: f32) -> f32 {
    let mut v = x;
    // SAFETY: reads and writes the local `v` through its address; all
    // eight x87 registers are declared clobbered, so the x87 stack is empty
    // on entry, and `fld`/`fstp` leave it empty again.
    unsafe {
        core::arch::asm!(
            "fld dword ptr [{v}]",
            "fsqrt",
            "fstp dword ptr [{v}]",
            v = in(reg) &mut v,
            out("st(0)") _, out("st(1)") _, out("st(2)") _, out("st(3)") _,
            out("st(4)") _, out("st(5)") _, out("st(6)") _, out("st(7)") _,
            options(nostack),
        );
    }
    v
}

#[cfg(not(any(all(target_arch = "arm", target_abi = "eabihf"), x87)))]
#[inline(always)]
fn hardware_sqrtf(x: f32) -> f32 {
    libm::sqrtf(x)
}

/// `|v|`, as `Vec3::length` computes it.
#[inline(always)]
pub(crate) fn length(v: Vec3) -> f32 {
    sqrtf(v.dot(v))
}

/// `v / |v|`, or zero if that is not finite; as `Vec3::normalize_or_zero`.
#[inline(always)]
pub(crate) fn normalize_or_zero(v: Vec3) -> Vec3 {
    normalize_or_zero_by(v, length(v))
}

/// `x > 0.0 && x <= f32::MAX`: `x` positive and finite (NaN is not).
///
/// On the x87 one integer compare on the bits: the positive finite floats
/// are the bit patterns `1..=0x7f7f_ffff` (zeros, infinities, NaNs and
/// negatives lie outside), where two float compares are `fucom`,
/// `fnstsw`, `sahf` and a jump each (`tests::positive_finite_on_the_bits`
/// checks every 251st pattern and the specials). So on Arm, where each is
/// `vcmp` and `vmrs` (soft float on the Cortex-M0): Cortex-M4F base frame
/// 12.94 -> 12.91 M instructions.
#[inline(always)]
pub(crate) fn is_positive_finite(x: f32) -> bool {
    #[cfg(any(target_arch = "arm", x87))]
    {
        x.to_bits().wrapping_sub(1) < 0x7f7f_ffff
    }
    #[cfg(not(any(target_arch = "arm", x87)))]
    {
        x > 0.0 && x <= f32::MAX
    }
}

/// [`normalize_or_zero`] of `v` given its `length(v)`.
#[inline(always)]
pub(crate) fn normalize_or_zero_by(v: Vec3, length: f32) -> Vec3 {
    let rcp = 1.0 / length;
    // `rcp.is_finite() && rcp > 0.0` as glam writes it, in two float
    // compares or one integer compare (`is_finite` is bit arithmetic: 15
    // more instructions on the Cortex-M4F); NaN fails them.
    if is_positive_finite(rcp) {
        v * rcp
    } else {
        Vec3::ZERO
    }
}

/// `v / |v|` (not finite for a zero `v`), as `Vec3::normalize`.
#[inline(always)]
pub(crate) fn normalize(v: Vec3) -> Vec3 {
    v * (1.0 / length(v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sqrtf_matches_libm_bit_for_bit() {
        // Every exponent, a spread of mantissas, and the specials.
        let mut bits = 0u32;
        for _ in 0..(1 << 20) {
            let x = f32::from_bits(bits);
            let (ours, libm) = (sqrtf(x), libm::sqrtf(x));
            assert!(
                ours.to_bits() == libm.to_bits() || (ours.is_nan() && libm.is_nan()),
                "{x:e}: {ours:e} vs {libm:e}"
            );
            bits = bits.wrapping_add(4093);
        }
        for x in [0.0, -0.0, f32::INFINITY, f32::MIN_POSITIVE, f32::MAX, 1e-45] {
            assert_eq!(sqrtf(x).to_bits(), libm::sqrtf(x).to_bits(), "{x:e}");
        }
        assert!(sqrtf(-1.0).is_nan() && sqrtf(f32::NAN).is_nan());
    }

    #[test]
    fn positive_finite_on_the_bits() {
        let bits = (0..=u32::MAX / 251).map(|k| k * 251);
        let specials = [
            0.0f32,
            -0.0,
            1e-45,
            -1e-45,
            f32::MIN_POSITIVE,
            f32::MAX,
            f32::MIN,
        ]
        .into_iter()
        .chain([
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
            1.0,
            -1.0,
        ])
        .map(f32::to_bits);
        for b in bits
            .chain(specials)
            .chain([0x7f7f_ffff, 0x7f80_0001, 0x8000_0001])
        {
            let x = f32::from_bits(b);
            assert_eq!(
                x.to_bits().wrapping_sub(1) < 0x7f7f_ffff,
                x > 0.0 && x <= f32::MAX,
                "{b:#x}"
            );
            assert_eq!(is_positive_finite(x), x > 0.0 && x <= f32::MAX, "{b:#x}");
        }
    }

    #[test]
    fn helpers_match_glam_bit_for_bit() {
        let vs = [
            Vec3::new(0.3, -1.7, 2.9),
            Vec3::new(1e-30, 1e-30, 0.0),
            Vec3::ZERO,
            Vec3::new(-4112.0, 1.0, 257.0),
        ];
        for v in vs {
            assert_eq!(length(v).to_bits(), v.length().to_bits());
            assert_eq!(normalize_or_zero(v), v.normalize_or_zero());
        }
    }
}
