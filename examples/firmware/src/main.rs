//! hfray on bare metal: proof that the core links with neither `std` nor an
//! allocator. (Phase 1: a few rays against a small grid in flash.)
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use hfray::glam::Vec3;
use hfray::{HeightConvention, HeightField, Ray, Samples};

/// A 4 × 4 grid in flash (`static`, so it lives in `.rodata`).
static GRID: [u8; 16] = [
    0, 10, 20, 30, //
    10, 60, 80, 40, //
    20, 90, 120, 50, //
    30, 40, 50, 60,
];

#[entry]
fn main() -> ! {
    let field = match HeightField::new(Samples::U8(&GRID), 4, 4, HeightConvention::Gray8) {
        Ok(f) => f,
        Err(_) => exit_failure(),
    };
    let mut hits = 0u32;
    for i in 0..4 {
        let x = 0.1 + 0.25 * i as f32;
        let ray = Ray::new(Vec3::new(x, 2.0, 0.4), Vec3::new(0.05, -1.0, 0.02));
        if let Some(hit) = field.intersect(&ray, 0.0, f32::INFINITY) {
            hits += 1;
            hprintln!("ray {}: t={} cell=({}, {})", i, hit.t, hit.cell_x, hit.cell_z);
        }
    }
    hprintln!("hits={}", hits);
    debug::exit(if hits == 4 { debug::EXIT_SUCCESS } else { debug::EXIT_FAILURE });
    loop {}
}

fn exit_failure() -> ! {
    debug::exit(debug::EXIT_FAILURE);
    loop {}
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    debug::exit(debug::EXIT_FAILURE);
    loop {}
}
