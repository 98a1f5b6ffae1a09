//! `cfg(x87)`: the target does its `f32` arithmetic on the x87 FPU (32-bit
//! x86 without SSE, as the i486 program is built). Stated once here; the
//! code uses it where a float operation is cheaper there on the bits.

fn main() {
    cfg_aliases::cfg_aliases! {
        x87: { all(target_arch = "x86", not(target_feature = "sse")) },
    }
}
