//! Single-thread benchmarks of the height-field walk:
//!
//! `cargo run --release --example bench [-- RUNS]`
//!
//! (c) scaling: primary rays of the same 320×200 view over the same fractal
//!     landscape sampled at 256², 1024² and 4096²;
//! (d) flat walk vs skip grid (one block level, pyramid) × numeric path.
//!
//! Every figure is the median of RUNS runs (default 5), all measured in
//! this one process, side by side.

#[path = "bench_common/mod.rs"]
mod bench_common;

use bench_common::{fractal, median_secs, PovCamera};
use hfray::glam::{DVec3, Vec3};
use hfray::{
    Counters, HeightConvention, HeightField, Real, Samples, SkipGrid, SkipLayout, Transform,
    Traversal,
};

const W: u32 = 320;
const H: u32 = 200;

/// The view of the benchmark scene (as in examples/scenes/bench512.pov):
/// the unit field scaled to <1, 0.3, 1>, seen from over its near edge.
fn camera() -> PovCamera {
    PovCamera::new(
        Vec3::new(0.5, 0.8, -0.6),
        Vec3::new(0.5, 0.1, 0.5),
        W,
        H,
        60.0,
    )
}

fn rays() -> Vec<(Vec3, Vec3)> {
    let cam = camera();
    let mut v = Vec::with_capacity((W * H) as usize);
    for py in 0..H {
        for px in 0..W {
            v.push((cam.location, cam.ray(px, py)));
        }
    }
    v
}

/// Primary rays per second over `field` in numeric type `S`; also returns
/// hits and cells + blocks visited per ray.
fn primary<S: Real>(
    field: &HeightField<'_>,
    rays: &[(Vec3, Vec3)],
    runs: usize,
) -> (f64, u64, f64) {
    let mut hits = 0;
    let mut c = Counters::default();
    let secs = median_secs(runs, || {
        hits = 0;
        c = Counters::default();
        for (o, d) in rays {
            let h = field.intersect_in::<S>(
                o.to_array().map(S::from_f32),
                d.to_array().map(S::from_f32),
                S::ZERO,
                S::MAX,
                &mut c,
            );
            hits += h.is_some() as u64;
        }
    });
    (
        rays.len() as f64 / secs,
        hits,
        (c.cells + c.blocks) as f64 / rays.len() as f64,
    )
}

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5);
    println!("hfray bench: single thread, median of {runs} runs, {W}x{H} primary rays");
    let rays = rays();
    let transform = Transform::scale(DVec3::new(1.0, 0.3, 1.0)).unwrap();

    println!("\n(c) scaling, same view, same landscape, f32");
    println!(
        "{:>6} {:>10} {:>12} {:>12} {:>10} {:>12} {:>9}",
        "field", "mode", "Mrays/s", "vs 256²", "hits", "visits/ray", "skip KiB"
    );
    let mut base: Option<(f64, f64)> = None;
    for n in [256u32, 1024, 4096] {
        let data = fractal(n, 7);
        let field = HeightField::new(Samples::U8(&data), n, n, HeightConvention::Gray8)
            .unwrap()
            .with_transform(transform);
        let layout = SkipLayout::pyramid(n, n, 3);
        let mut buf = vec![0u8; SkipGrid::bytes_needed_for(&field, layout).unwrap()];
        let grid = SkipGrid::build(&field, layout, &mut buf).unwrap();
        let flat = field.clone().with_traversal(Traversal::Flat);
        let hier = field.clone().with_skip(grid).unwrap();
        let (rf, hf, vf) = primary::<f32>(&flat, &rays, runs);
        let (rh, hh, vh) = primary::<f32>(&hier, &rays, runs);
        assert_eq!(hf, hh);
        let b = *base.get_or_insert((rf, rh));
        println!(
            "{:>6} {:>10} {:>12.3} {:>11.0}% {:>10} {:>12.1} {:>9}",
            n,
            "flat",
            rf / 1e6,
            100.0 * rf / b.0,
            hf,
            vf,
            0
        );
        println!(
            "{:>6} {:>10} {:>12.3} {:>11.0}% {:>10} {:>12.1} {:>9.1}",
            n,
            format!("pyr{}x8", layout.levels),
            rh / 1e6,
            100.0 * rh / b.1,
            hh,
            vh,
            buf.len() as f64 / 1024.0
        );
    }
}
