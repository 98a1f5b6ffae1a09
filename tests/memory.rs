//! The core performs no allocation while rendering: a counting global
//! allocator watches a full render of a scene with every kind of ray
//! (primary, shadow, reflected, transmitted) and sees 0 allocations and
//! 0 bytes. Loading the scene and its images (harness work) happens before
//! the counters are read.

#[path = "../examples/harness/mod.rs"]
mod harness;

use std::ops::ControlFlow;
use std::path::Path;

use harness::alloc_count::CountingAlloc;
use harness::scene_io::{build_fields, load_fields, parse_file_scene};
use hfray::pixel::Rgb888;
use hfray::render::{render, render_depth, RenderSettings};
use hfray::scene::ParseOptions;

#[global_allocator]
static ALLOC: CountingAlloc = CountingAlloc::new();

/// The thesis scene plus a glass sphere, so that transmitted rays happen.
const SCENE: &str = r#"
#include "colors.inc"
camera { location <-0.35, 0.75, -0.9> look_at <0.5, 0.05, 0.45> right x*image_width/image_height angle 50 }
light_source { <-2, 3, -1> color rgb <1, 0.95, 0.9> }
light_source { <3, 2, -2> color rgb 0.3 }
background { color rgb <0.5, 0.65, 0.85> }
height_field { gif "../data/maunga_whau_volcano_87x61.gif" smooth water_level 0.25 scale <1, 0.3, 0.7>
  pigment { color rgb <0.45, 0.6, 0.3> } finish { phong 0.3 } }
plane { y, 0.07 pigment { color rgb <0.1, 0.25, 0.4> } finish { reflection 0.5 } }
sphere { <0.3, 0.25, 0.1>, 0.12 pigment { color rgbt <1, 1, 1, 0.7> } finish { reflection 0.2 specular 0.5 } }
"#;

#[test]
fn full_render_performs_zero_allocations() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/memory_test.pov");
    let options = ParseOptions::new(160, 100);
    let scene = parse_file_scene(&path, SCENE, &options, &mut |w| panic!("{w}")).unwrap();
    let loaded = load_fields(&scene, &path).unwrap();
    let fields = build_fields(&scene, &loaded).unwrap();
    let settings = RenderSettings::new(160, 100).with_aa(2);
    let mut line = vec![Rgb888::default(); 160];
    let mut depth_line = vec![0f32; 160];
    let mut checksum = 0u64;

    ALLOC.reset_thread_peak();
    let before = ALLOC.thread_snapshot();
    let stats = render(&scene, &fields, &settings, &mut line, &mut |_, row| {
        for p in row {
            checksum = checksum.wrapping_mul(31).wrapping_add(u64::from(p.0[0]));
        }
        ControlFlow::Continue(())
    })
    .unwrap();
    let depth_stats = render_depth(&scene, &fields, &settings, &mut depth_line, &mut |_, _| {
        ControlFlow::Continue(())
    })
    .unwrap();
    let after = ALLOC.thread_snapshot();

    // The render did real work of every kind...
    assert_eq!(stats.primary_rays, 160 * 100 * 4);
    assert!(stats.shadow_rays > 0 && stats.reflected_rays > 0 && stats.transmitted_rays > 0);
    assert!(depth_stats.primary_rays > 0 && checksum != 0);
    // ...and asked the allocator for nothing.
    assert_eq!(
        after.allocations - before.allocations,
        0,
        "allocations during render"
    );
    assert_eq!(
        after.peak_bytes - before.current_bytes,
        0,
        "bytes during render"
    );
}
