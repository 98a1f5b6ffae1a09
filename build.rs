//! `cfg(x87)`: the target does its `f32` arithmetic on the x87 FPU (32-bit
//! x86 without SSE, as the i486 program is built). Stated once here; the
//! code uses it where a float operation is cheaper there on the bits.
//!
//! `cfg(desktop)`: a 64-bit desktop target (x86-64, aarch64), where code
//! size is cheap (the walks inline their builds) and 128-bit vector
//! compares are there (SSE2, NEON); bare metal and the 32-bit targets take
//! the other paths, measured on their frames at each site.
//!
//! `cfg(as_chunks)`: the compiler has `<[T]>::as_chunks` (Rust 1.88, past
//! the crate's `rust-version`), which only the x87 builds use (one bounds
//! check for a skip block's bounds, `skip::CHUNKED_BOUNDS`); older
//! compilers build the other path.

fn main() {
    cfg_aliases::cfg_aliases! {
        x87: { all(target_arch = "x86", not(target_feature = "sse")) },
        desktop: { any(target_arch = "x86_64", target_arch = "aarch64") },
    }
    println!("cargo::rustc-check-cfg=cfg(as_chunks)");
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let version = std::process::Command::new(rustc)
        .arg("--version")
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok());
    // "rustc 1.95.0 (...)": the minor version.
    let minor = version
        .as_deref()
        .and_then(|v| v.split_whitespace().nth(1))
        .and_then(|v| v.split('.').nth(1))
        .and_then(|m| m.parse::<u32>().ok());
    if minor.is_some_and(|m| m >= 88) {
        println!("cargo::rustc-cfg=as_chunks");
    }
}
