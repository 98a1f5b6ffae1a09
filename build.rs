//! `cfg(x87)`: the target does its `f32` arithmetic on the x87 FPU (32-bit
//! x86 without SSE, as the i486 program is built). Stated once here; the
//! code uses it where a float operation is cheaper there on the bits.
//!
//! `cfg(desktop)`: a 64-bit desktop target (x86-64, aarch64), where code
//! size is cheap (the walks inline their builds) and 128-bit vector
//! compares are there (SSE2, NEON); bare metal and the 32-bit targets take
//! the other paths, measured on their frames at each site.

fn main() {
    cfg_aliases::cfg_aliases! {
        x87: { all(target_arch = "x86", not(target_feature = "sse")) },
        desktop: { any(target_arch = "x86_64", target_arch = "aarch64") },
    }
}
