//! Test support shared by the integration tests: a deterministic PRNG, field
//! builders and the f64 brute-force oracle.
#![allow(dead_code)]

pub mod modes;
pub mod oracle;

/// SplitMix64: deterministic, seedable, no dependencies.
#[derive(Clone)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f64()
    }
    /// Uniform integer in lo..=hi.
    pub fn int(&mut self, lo: u32, hi: u32) -> u32 {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as u32
    }
    pub fn chance(&mut self, p: f64) -> bool {
        self.f64() < p
    }
}

/// A fractal-ish terrain with valleys and plateaus (deterministic).
pub fn terrain(rng: &mut Rng, w: u32, d: u32) -> Vec<u8> {
    let (a, b, c) = (
        rng.range(0.01, 0.2),
        rng.range(0.01, 0.2),
        rng.range(0.0, 6.0),
    );
    (0..w * d)
        .map(|i| {
            let (x, z) = ((i % w) as f64, (i / w) as f64);
            let v = 0.5
                + 0.25 * (x * a + c).sin() * (z * b).cos()
                + 0.15 * (x * a * 3.1 + z * b * 2.3).sin()
                + 0.1 * (x * 0.71 + z * 1.37).sin();
            (v.clamp(0.0, 1.0) * 255.0) as u8
        })
        .collect()
}

/// Kinds of height data the tests draw from: random and adversarial.
pub fn random_heights(rng: &mut Rng, w: u32, d: u32) -> Vec<u8> {
    let n = (w * d) as usize;
    match rng.int(0, 7) {
        0 => (0..n).map(|_| rng.next_u64() as u8).collect(),
        1 => vec![0; n],
        2 => vec![255; n],
        // Plateaus: few levels, large flat areas.
        3 => {
            let levels = [0u8, 64, 128, 200, 255];
            let block = rng.int(1, 8);
            (0..n)
                .map(|i| {
                    let (x, z) = (i as u32 % w / block, i as u32 / w / block);
                    levels[((x * 7 + z * 13) % 5) as usize]
                })
                .collect()
        }
        // Checkerboard of extremes: steepest possible slopes everywhere.
        4 => (0..n)
            .map(|i| {
                if (i as u32 % w + i as u32 / w).is_multiple_of(2) {
                    0
                } else {
                    255
                }
            })
            .collect(),
        // Ramp along x.
        5 => (0..n)
            .map(|i| ((i as u32 % w) * 255 / (w - 1).max(1)) as u8)
            .collect(),
        // Isolated spikes on flat ground.
        6 => (0..n)
            .map(|_| if rng.chance(0.05) { 255 } else { 10 })
            .collect(),
        // Smooth-ish terrain.
        _ => {
            let (a, b) = (rng.range(0.05, 0.5), rng.range(0.05, 0.5));
            (0..n)
                .map(|i| {
                    let (x, z) = ((i as u32 % w) as f64, (i as u32 / w) as f64);
                    (127.5 + 127.0 * (x * a).sin() * (z * b).cos()) as u8
                })
                .collect()
        }
    }
}
