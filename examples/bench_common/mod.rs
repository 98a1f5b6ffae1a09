//! Shared by the benchmark examples: a deterministic fractal terrain that
//! is the same landscape at every resolution, a POV-Ray camera for primary
//! rays, and timing helpers.
#![allow(dead_code)]

use std::time::Instant;

use hfray::glam::Vec3;

/// SplitMix64.
pub fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Value noise on the integer lattice, smoothly interpolated, in [0, 1).
fn value_noise(seed: u64, x: f64, z: f64) -> f64 {
    let (xi, zi) = (x.floor(), z.floor());
    let (fx, fz) = (x - xi, z - zi);
    let h = |a: f64, b: f64| {
        let k = mix(seed ^ mix((a as i64 as u64) ^ mix(b as i64 as u64)));
        (k >> 11) as f64 / (1u64 << 53) as f64
    };
    let s = |t: f64| t * t * (3.0 - 2.0 * t);
    let (sx, sz) = (s(fx), s(fz));
    let top = h(xi, zi) * (1.0 - sx) + h(xi + 1.0, zi) * sx;
    let bottom = h(xi, zi + 1.0) * (1.0 - sx) + h(xi + 1.0, zi + 1.0) * sx;
    top * (1.0 - sz) + bottom * sz
}

/// An `n × n` fractal terrain (fBm of value noise, 1/f amplitude), 8-bit,
/// row-major, image row 0 first. The same continuous landscape sampled at
/// any `n`, with octaves down to the sample spacing: a 4096² field is the
/// 256² one with more detail, so a fixed camera frames the same view.
pub fn fractal(n: u32, seed: u64) -> Vec<u8> {
    let octaves = (n as f64).log2().ceil() as u32 + 1;
    let mut out = Vec::with_capacity((n * n) as usize);
    let mut values = Vec::with_capacity((n * n) as usize);
    for row in 0..n {
        for col in 0..n {
            let (x, z) = (col as f64 / (n - 1) as f64, row as f64 / (n - 1) as f64);
            let mut v = 0.0;
            let mut amp = 1.0;
            let mut freq = 4.0;
            for o in 0..octaves {
                if freq > 2.0 * n as f64 {
                    break;
                }
                v += amp * (value_noise(seed + o as u64, x * freq, z * freq) - 0.5);
                amp *= 0.5;
                freq *= 2.0;
            }
            values.push(v);
        }
    }
    // Fixed mapping (not per-field normalisation) so every resolution maps
    // the same landscape to the same heights.
    for v in values {
        out.push(((v * 0.9 + 0.45).clamp(0.0, 1.0) * 255.0).round() as u8);
    }
    out
}

/// POV-Ray perspective camera (SPEC.md): `location`, `look_at`, `right`
/// = x·w/h, angle 60°.
pub struct PovCamera {
    pub location: Vec3,
    d: Vec3,
    r: Vec3,
    u: Vec3,
    w: u32,
    h: u32,
}

impl PovCamera {
    pub fn new(location: Vec3, look_at: Vec3, w: u32, h: u32, angle_deg: f32) -> Self {
        let right_len = w as f32 / h as f32;
        let d = (look_at - location).normalize() * (0.5 * right_len)
            / (angle_deg.to_radians() / 2.0).tan();
        let r = Vec3::Y.cross(d).normalize() * right_len;
        let u = d.cross(r).normalize();
        PovCamera {
            location,
            d,
            r,
            u,
            w,
            h,
        }
    }

    pub fn ray(&self, px: u32, py: u32) -> Vec3 {
        let x0 = (px as f32 + 0.5) / self.w as f32 - 0.5;
        let y0 = 0.5 - (py as f32 + 0.5) / self.h as f32;
        (self.d + self.r * x0 + self.u * y0).normalize()
    }
}

/// CPU time this thread has run, in seconds (Linux
/// `/proc/thread-self/schedstat`, nanoseconds); `None` elsewhere.
pub fn thread_cpu_secs() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: u64 = s.split_whitespace().next()?.parse().ok()?;
    Some(ns as f64 * 1e-9)
}

/// Runs `f` `runs` times; returns the median time of one call in seconds:
/// the thread's CPU time where the OS reports it (the machine is shared,
/// so wall time also counts time spent waiting for a core), else wall time.
/// The kernel updates that CPU time only every few milliseconds, so each
/// sample repeats `f` until it has run at least 0.25 s and is divided by
/// the repetitions.
pub fn median_secs(runs: usize, mut f: impl FnMut()) -> f64 {
    let reps = repetitions(&mut f);
    let mut t: Vec<f64> = (0..runs).map(|_| sample_secs(reps, &mut f)).collect();
    median(&mut t)
}

/// How many calls of `f` make one sample of at least 0.25 s (after one
/// warm-up call).
pub fn repetitions(f: &mut impl FnMut()) -> usize {
    let start = Instant::now();
    f();
    let once = start.elapsed().as_secs_f64().max(1e-6);
    ((0.25 / once).ceil() as usize).clamp(1, 10_000)
}

/// One sample: the time of one call of `f`, averaged over `reps` calls
/// (thread CPU time where the OS reports it, else wall time).
pub fn sample_secs(reps: usize, f: &mut impl FnMut()) -> f64 {
    let c0 = thread_cpu_secs();
    let s = Instant::now();
    for _ in 0..reps {
        f();
    }
    let wall = s.elapsed().as_secs_f64();
    let secs = match (c0, thread_cpu_secs()) {
        (Some(a), Some(b)) if b > a => b - a,
        _ => wall,
    };
    secs / reps as f64
}

/// The median of `v` (sorted in place).
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}
