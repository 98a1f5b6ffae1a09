//! hfray vs parry3d 0.31 `HeightField`: the same primary rays over the same
//! 512² fractal field, hits cross-checked, single thread. Run by
//! `cargo run --release --example bench` (section b), or alone:
//! `cargo run --release --manifest-path examples/bench_parry/Cargo.toml [-- RUNS]`.

#[path = "../../bench_common/mod.rs"]
mod bench_common;

use bench_common::{fractal, median, repetitions, sample_secs, PovCamera};
use hfray::glam::{DVec3, Vec3};
use hfray::{
    Counters, HeightConvention, HeightField, Ray, Samples, SkipGrid, SkipLayout, Transform,
};

const W: u32 = 320;
const H: u32 = 200;

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5);
    let cam = PovCamera::new(
        Vec3::new(0.5, 0.8, -0.6),
        Vec3::new(0.5, 0.1, 0.5),
        W,
        H,
        60.0,
    );
    let rays: Vec<Ray> = (0..H)
        .flat_map(|py| (0..W).map(move |px| (px, py)))
        .map(|(px, py)| Ray::new(cam.location, cam.ray(px, py)))
        .collect();
    section(runs, &rays);
}

fn section(runs: usize, rays: &[Ray]) {
    use parry3d::math::Vector as PVec;
    use parry3d::query::{Ray as PRay, RayCast};
    use parry3d::shape::HeightField as PField;
    use parry3d::utils::Array2;

    println!(
        "\n(b) primary rays only, 512² fractal, {W}x{H} rays, hfray vs parry3d 0.31 HeightField"
    );
    let n = 512u32;
    let data = fractal(n, 7);
    let field = HeightField::new(Samples::U8(&data), n, n, HeightConvention::Gray8)
        .unwrap()
        .with_transform(Transform::scale(DVec3::new(1.0, 0.3, 1.0)).unwrap());
    // parry: heights (row i along z, column j along x), column-major; vertex
    // (i, j) at (-0.5 + j/(n-1), h, -0.5 + i/(n-1)) times `scale`; its
    // default cell split is (x0,z0),(x0,z1),(x1,z0) + the other half, the
    // same diagonal as POV-Ray's. So our object space is parry's shifted by
    // (0.5, 0, 0.5), with the same (1, 0.3, 1) scale.
    let mut col_major = Vec::with_capacity((n * n) as usize);
    for x in 0..n {
        for z in 0..n {
            col_major.push(field.height(x, z).expect("in the grid"));
        }
    }
    let pf = PField::new(
        Array2::new(n as usize, n as usize, col_major),
        PVec::new(1.0, 0.3, 1.0),
    );
    let shift = Vec3::new(0.5, 0.0, 0.5);
    let prays: Vec<PRay> = rays
        .iter()
        .map(|r| {
            let o = r.origin - shift;
            PRay::new(
                PVec::new(o.x, o.y, o.z),
                PVec::new(r.direction.x, r.direction.y, r.direction.z),
            )
        })
        .collect();
    let layout = SkipLayout::pyramid(n, n, 2);
    let mut buf = vec![0u8; SkipGrid::bytes_needed_for(&field, layout).unwrap()];
    SkipGrid::build(&field, layout, &mut buf).unwrap();
    let ours = field.clone().with_skip(&buf).unwrap();
    // Agreement on the sample.
    let (mut both, mut only_ours, mut only_parry, mut max_dt) = (0u32, 0u32, 0u32, 0f32);
    let (mut checked, mut confirmed) = (0u32, 0u32);
    for (r, pr) in rays.iter().zip(&prays) {
        let a = ours.intersect(r, 0.0, f32::INFINITY);
        let b = pf.cast_local_ray(pr, f32::MAX, true);
        match (a, b) {
            (Some(a), Some(b)) => {
                both += 1;
                max_dt = max_dt.max((a.t - b).abs());
            }
            (Some(a), None) => {
                only_ours += 1;
                if checked < 40 {
                    checked += 1;
                    if let Some(t) = brute_force(&field, r) {
                        if (t - a.t as f64).abs() < 1e-4 {
                            confirmed += 1;
                        }
                    }
                }
            }
            (None, Some(_)) => only_parry += 1,
            _ => {}
        }
    }
    println!(
        "  agreement: both hit {both}, only hfray {only_ours}, only parry {only_parry}, max |Δt| {max_dt:.2e} (field is 1 unit wide)"
    );
    println!(
        "  of the first {checked} rays only hfray hits, an f64 brute force over all 522,242 triangles confirms {confirmed} (same t within 1e-4)"
    );
    // Interleaved: each run times both once, so the ratio compares samples
    // taken side by side (the machine is shared); medians of each, and the
    // median of the per-run ratios.
    let mut ours_f = || {
        let mut c = Counters::default();
        for r in rays {
            std::hint::black_box(ours.intersect_counted(r, 0.0, f32::INFINITY, &mut c));
        }
    };
    let mut parry_f = || {
        for pr in &prays {
            std::hint::black_box(pf.cast_local_ray(pr, f32::MAX, true));
        }
    };
    let (ours_reps, parry_reps) = (repetitions(&mut ours_f), repetitions(&mut parry_f));
    let (mut ours_t, mut parry_t, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..runs {
        let a = sample_secs(ours_reps, &mut ours_f);
        let b = sample_secs(parry_reps, &mut parry_f);
        ours_t.push(a);
        parry_t.push(b);
        ratios.push(b / a);
    }
    let ours_rate = rays.len() as f64 / median(&mut ours_t);
    let parry_rate = prays.len() as f64 / median(&mut parry_t);
    let ratio = median(&mut ratios);
    println!("  hfray pyramid f32   {:>8.3} Mrays/s", ours_rate / 1e6);
    println!("  parry3d HeightField {:>8.3} Mrays/s", parry_rate / 1e6);
    println!("  hfray / parry3d = {ratio:.1}x (median of per-run ratios; target >= 20x)");
}

/// Nearest hit of `ray` with every triangle of the field (POV-Ray split),
/// Möller–Trumbore in f64, object space = world / (1, 0.3, 1).
fn brute_force(field: &HeightField<'_>, ray: &Ray) -> Option<f64> {
    let (w, d) = (field.width(), field.depth());
    let o = ray.origin.as_dvec3();
    let dir = ray.direction.as_dvec3();
    let p = |x: u32, z: u32| {
        DVec3::new(
            x as f64 / (w - 1) as f64,
            field.height(x, z).expect("in the grid") as f64 * 0.3,
            z as f64 / (d - 1) as f64,
        )
    };
    let mut best: Option<f64> = None;
    for z in 0..d - 1 {
        for x in 0..w - 1 {
            for [a, b, c] in [
                [p(x, z), p(x + 1, z), p(x, z + 1)],
                [p(x + 1, z + 1), p(x, z + 1), p(x + 1, z)],
            ] {
                let (e1, e2) = (b - a, c - a);
                let q = dir.cross(e2);
                let det = e1.dot(q);
                if det == 0.0 {
                    continue;
                }
                let inv = 1.0 / det;
                let s = o - a;
                let u = s.dot(q) * inv;
                let r = s.cross(e1);
                let v = dir.dot(r) * inv;
                let t = e2.dot(r) * inv;
                if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t >= 0.0 && best.is_none_or(|b| t < b) {
                    best = Some(t);
                }
            }
        }
    }
    best
}
