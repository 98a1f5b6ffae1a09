#[path = "bench_common/mod.rs"]
mod bench_common;
use bench_common::{fractal, PovCamera};
use hfray::glam::{DVec3, Vec3};
use hfray::*;
fn main() {
    let n: u32 = std::env::args().nth(1).unwrap().parse().unwrap();
    let mode = std::env::args().nth(2).unwrap();
    let data = fractal(n, 7);
    let field = HeightField::new(Samples::U8(&data), n, n, HeightConvention::Gray8)
        .unwrap()
        .with_transform(Transform::scale(DVec3::new(1.0, 0.3, 1.0)).unwrap());
    let lg: u8 = std::env::args()
        .nth(3)
        .map(|a| a.parse().unwrap())
        .unwrap_or(3);
    let layout = if mode == "blocks" {
        SkipLayout::blocks(lg)
    } else {
        SkipLayout::pyramid(n, n, lg)
    };
    let mut buf = vec![0u8; SkipGrid::bytes_needed_for(&field, layout).unwrap()];
    let grid = SkipGrid::build(&field, layout, &mut buf).unwrap();
    let f = if mode == "flat" {
        field.clone().with_traversal(Traversal::Flat)
    } else {
        field.clone().with_skip(grid).unwrap()
    };
    let cam = PovCamera::new(
        Vec3::new(0.5, 0.8, -0.6),
        Vec3::new(0.5, 0.1, 0.5),
        320,
        200,
        60.0,
    );
    let t0 = bench_common::thread_cpu_secs().unwrap();
    let mut hits = 0;
    let mut c = Counters::default();
    for _ in 0..10 {
        for py in 0..200 {
            for px in 0..320 {
                let d = cam.ray(px, py);
                hits += f
                    .intersect_in::<f32>(
                        cam.location.to_array(),
                        d.to_array(),
                        0.0,
                        f32::MAX,
                        &mut c,
                    )
                    .is_some() as u32;
            }
        }
    }
    let s = bench_common::thread_cpu_secs().unwrap() - t0;
    println!(
        "{n} {mode} lg{lg} levels {} KiB {:.1} {hits} {:.3} Mrays/s cells {} blocks {} tri {}",
        layout.levels,
        buf.len() as f64 / 1024.0,
        640000.0 / s / 1e6,
        c.cells,
        c.blocks,
        c.triangle_tests
    );
}
