#[test]
fn up() {
    let g = image::open(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden/render_island_32x24.png")).unwrap().to_rgb8();
    image::imageops::resize(&g, 256, 192, image::imageops::FilterType::Nearest).save("/tmp/hfdump/golden_big.png").unwrap();
    for n in ["pov", "hfray"] {
        let g = image::open(format!("/tmp/povcmp/{n}.png")).unwrap().to_rgb8();
        g.save(format!("/tmp/povcmp/{n}_big.png")).unwrap();
    }
}
