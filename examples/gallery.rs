//! `gallery`: the thesis's natural phenomena (§6.2), made with hfray's own
//! generators and data, rendered at 320×200 with 2×2 anti-aliasing (the
//! thesis's filter), plus a contact sheet.
//!
//! ```text
//! cargo run --release --example gallery -- OUTDIR
//! ```
//!
//! For every figure the gallery writes the height field (GIF or PGM) and a
//! POV-Ray scene file into `OUTDIR`, renders the scene exactly as
//! `cargo run --release --example render -- OUTDIR/NAME.pov -o NAME.png
//! --aa 2` would, and — for the outdoor scenes, as the thesis did by hand
//! (§6.2) — composites a cloud sky (a plasma) where primary rays hit
//! nothing. Then it writes `contact_sheet.png` (4 × 3 tiles) and
//! `gallery.md` (each image with its command and render time).
//!
//! | file | thesis | phenomenon |
//! |---|---|---|
//! | `dem_one_colour`, `dem_palette` | 6.4, 6.5 | real DEM (Rocky Mountain NP, Colorado) through the `.asc` importer, one colour and palette colours |
//! | `plasma_sea` | 6.8 | plasma mountains by a reflective sea |
//! | `island` | 6.12 | plasma island cut by `water_level` in the sea |
//! | `crater` | 4.3 | concentric circles of rising index |
//! | `drops_0..3` | 6.13–6.15 | water drops, four frames of one animation |
//! | `wood` | 6.16 | broken wood: fractal disc on a cylinder |
//! | `fire` | 6.18 | fire seen from above, y scaled down, fire palette |

#[path = "harness/mod.rs"]
mod harness;

use std::fmt::Write as _;
use std::ops::ControlFlow;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use harness::images::{load_height_field, terrain_palette, write_indexed_gif, Palette, SampleData};
use harness::png_out::PngWriter;
use harness::scene_io::{build_fields, load_fields, parse_file_scene, read_scene_text};
use harness::terrain;
use hfray::generate::{
    crater, drops, fire, plasma, wood, Crater, Drops, Fire, Plasma, Wood, FIRE_PALETTE,
};
use hfray::pixel::Rgb888;
use hfray::render::{render, render_depth, RenderSettings, Stats};
use hfray::scene::{ImageFormat, ParseOptions};
use hfray::HeightConvention;

const W: u32 = 320;
const H: u32 = 200;
const AA: u32 = 2;
/// Threads per render (the machine this was written on has 2 cores).
const THREADS: u32 = 2;

type Result<T> = std::result::Result<T, String>;

/// One figure: its scene file and how to finish it.
struct Shot {
    name: String,
    title: String,
    thesis: &'static str,
    clouds: bool,
}

/// A rendered figure.
struct Rendered {
    shot: Shot,
    pixels: Vec<[u8; 3]>,
    seconds: f64,
    stats: Stats,
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((out, only)) = args.split_first() else {
        eprintln!("usage: gallery OUTDIR [NAME...]   (NAMEs: render only those figures)");
        return ExitCode::from(2);
    };
    match run(Path::new(out), only) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(out: &Path, only: &[String]) -> Result<()> {
    let start = Instant::now();
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut shots = Vec::new();
    shots.extend(dem(out)?);
    shots.push(plasma_sea(out)?);
    shots.push(island(out)?);
    shots.push(crater_scene(out)?);
    shots.extend(drops_frames(out)?);
    shots.push(wood_scene(out)?);
    shots.push(fire_scene(out)?);
    let generated = start.elapsed().as_secs_f64();
    if !only.is_empty() {
        shots.retain(|s| only.iter().any(|o| s.name.starts_with(o.as_str())));
    }

    let mut done = Vec::new();
    for shot in shots {
        let r = render_shot(out, shot)?;
        println!(
            "{:<16} {:>6.3} s  {:>8} rays  {}",
            r.shot.name,
            r.seconds,
            r.stats.rays(),
            r.shot.title
        );
        done.push(r);
    }
    contact_sheet(out, &done)?;
    write_markdown(out, &done)?;
    println!(
        "fields and scenes {generated:.2} s; total {:.2} s; wrote {}/contact_sheet.png and gallery.md",
        start.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}

// ------------------------------------------------------------ writing

fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
}

fn gif(path: &Path, w: u32, d: u32, indices: &[u8], palette: &Palette) -> Result<()> {
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    write_indexed_gif(
        std::io::BufWriter::new(file),
        w as u16,
        d as u16,
        indices,
        palette,
        false,
    )
    .map_err(|e| format!("{}: {e}", path.display()))
}

/// A palette through `(index, colour)` stops, linear between them.
fn palette_from(stops: &[(usize, [u8; 3])]) -> Palette {
    let mut p = [[0u8; 3]; 256];
    for win in stops.windows(2) {
        let ((i0, c0), (i1, c1)) = (win[0], win[1]);
        for (i, entry) in p.iter_mut().enumerate().take(i1 + 1).skip(i0) {
            let t = (i - i0) as f32 / (i1 - i0).max(1) as f32;
            for ch in 0..3 {
                entry[ch] =
                    (f32::from(c0[ch]) + t * (f32::from(c1[ch]) - f32::from(c0[ch]))).round() as u8;
            }
        }
    }
    p
}

/// Linear stretch of `values` (any range) to `0..=255`, rounding.
fn to_indices(values: &[f32]) -> Vec<u8> {
    let lo = values.iter().copied().fold(f32::INFINITY, f32::min);
    let hi = values.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    let span = (hi - lo).max(1e-9);
    values
        .iter()
        .map(|v| ((v - lo) / span * 255.0).round() as u8)
        .collect()
}

const SKY: &str = "background { color rgb <0.55, 0.7, 0.9> }";

// ------------------------------------------------------------ figures

/// §6.2.1.1, figures 6.4 and 6.5: a real DEM, through the `.asc`
/// importer and its quantiser, one colour and palette colours.
fn dem(out: &Path) -> Result<Vec<Shot>> {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data");
    let note_path = data.join("rmnp_co_152x187.txt");
    let note =
        std::fs::read_to_string(&note_path).map_err(|e| format!("{}: {e}", note_path.display()))?;
    let field = |key: &str| -> Result<f64> {
        note.lines()
            .find_map(|l| l.strip_prefix(key)?.strip_prefix('='))
            .and_then(|v| v.trim().parse().ok())
            .ok_or_else(|| format!("{}: no {key}", note_path.display()))
    };
    let (zmin, zmax) = (field("zmin_m")?, field("zmax_m")?);
    let png = data.join("rmnp_co_152x187.u16.png");
    let loaded = load_height_field(&png, ImageFormat::Png).map_err(|e| e.to_string())?;
    let SampleData::U16(raw) = loaded.sample_data() else {
        return Err(format!("{}: expected 16-bit samples", png.display()));
    };
    let (w, d) = (loaded.width(), loaded.depth());

    // Back to metres, as an ESRI ASCII grid (the format USGS-style data
    // comes in). Spacing ~233 m × 234 m (the data's note).
    let mut asc = format!(
        "ncols {w}\nnrows {d}\nxllcorner 0\nyllcorner 0\ndx 233\ndy 234\nNODATA_value -9999\n"
    );
    for row in raw.chunks(w as usize) {
        let line: Vec<String> = row
            .iter()
            .map(|&v| format!("{:.2}", zmin + f64::from(v) * (zmax - zmin) / 65535.0))
            .collect();
        asc += &line.join(" ");
        asc.push('\n');
    }
    let asc_path = out.join("rmnp_co.asc");
    write(&asc_path, &asc)?;

    let grid = terrain::parse_asc(&asc).map_err(|e| format!("{}: {e}", asc_path.display()))?;
    let q = terrain::quantise(
        &grid,
        &terrain::QuantiseOptions {
            bits: terrain::Bits::U8,
            fill: terrain::NoDataFill::Nearest,
            exaggeration: 2.0,
            metres_per_unit: 1.0,
        },
    )
    .map_err(|e| format!("{}: {e}", asc_path.display()))?;
    println!("rmnp_co.asc → rmnp_co.gif: {}", q.report());
    let terrain::Levels::U8(indices) = &q.levels else {
        unreachable!("8-bit asked")
    };
    gif(&out.join("rmnp_co.gif"), w, d, indices, &terrain_palette())?;
    let [_, sy, sz] = q
        .suggested_scale(HeightConvention::Indexed)
        .ok_or("DEM has no cell size")?;

    let scene = |colouring: &str| {
        format!(
            "// Rocky Mountain National Park, Colorado (examples/data/rmnp_co_152x187),
// converted to rmnp_co.asc and quantised by the gallery: {report}
// True proportions × 2 in y (the thesis lowered its Pikes Peak too).
#version 3.7;
global_settings {{ assumed_gamma 1.0 }}
camera {{ location <0.5, 0.45, -0.5> look_at <0.5, 0.05, 0.6> right x*image_width/image_height angle 50 }}
light_source {{ <-3, 4, -2> color rgb <1, 0.97, 0.9> }}
{SKY}
height_field {{
  gif \"rmnp_co.gif\" {colouring}
  smooth
  scale <1, {sy:.6}, {sz:.6}>
  finish {{ ambient 0.2 diffuse 0.8 }}
}}
",
            report = q.report()
        )
    };
    write(
        &out.join("dem_one_colour.pov"),
        &scene("pigment { color rgb <0.6, 0.55, 0.45> }"),
    )?;
    write(&out.join("dem_palette.pov"), &scene("image_map"))?;
    Ok(vec![
        Shot {
            name: "dem_one_colour".into(),
            title: "Real DEM, one colour".into(),
            thesis: "6.4",
            clouds: true,
        },
        Shot {
            name: "dem_palette".into(),
            title: "Real DEM, palette colours (`image_map`)".into(),
            thesis: "6.5",
            clouds: true,
        },
    ])
}

/// The thesis's plasma palette (§6.2.1.2): tones of blue, brown, green
/// and white, in that order; `sea` (1..=200) is the first index above
/// water, the land's tones spread over `sea..=255`.
fn land_palette(sea: usize) -> Palette {
    let land = |f: f32| sea + ((255 - sea) as f32 * f) as usize;
    palette_from(&[
        (0, [10, 25, 60]),
        (sea - 1, [40, 80, 130]),
        (sea, [150, 125, 85]),
        (land(0.08), [120, 95, 60]),
        (land(0.22), [60, 110, 45]),
        (land(0.6), [75, 100, 50]),
        (land(0.78), [110, 95, 80]),
        (land(0.88), [235, 235, 240]),
        (255, [255, 255, 255]),
    ])
}

/// §6.2.1.2, figure 6.8: plasma mountains by a reflective sea.
fn plasma_sea(out: &Path) -> Result<Shot> {
    let (w, d) = (512u32, 512u32);
    let mut g = vec![0u8; (w * d) as usize];
    plasma(
        &mut g,
        w,
        d,
        &Plasma {
            roughness: 0.58,
            seed: 1996,
        },
    )
    .map_err(|e| e.to_string())?;
    // Mountains behind, sea in front: tilt the fractal up towards the far
    // edge (image row 0 is the far, z = 1 edge).
    let tilted: Vec<f32> = g
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let far = 1.0 - (i as u32 / w) as f32 / (d - 1) as f32;
            // Sharpen the peaks, flatten the valleys, and rise inland.
            (f32::from(v) / 255.0).powf(1.6) * 0.8 + far * 0.4
        })
        .collect();
    let idx = to_indices(&tilted);
    let sea = 60usize;
    gif(&out.join("plasma_sea.gif"), w, d, &idx, &land_palette(sea))?;
    let wl = sea as f32 / 256.0;
    let scene = format!(
        "// Plasma mountains by the sea (thesis figure 6.8): plasma (roughness
// 0.58, seed 1996) tilted up towards the back, palette colours, a
// reflective plane at the water level (which also skips sunken cells).
#version 3.7;
global_settings {{ assumed_gamma 1.0 }}
camera {{ location <0, 1.25, -3.2> look_at <0, 0.65, 1> right x*image_width/image_height angle 50 }}
light_source {{ <-3, 8, -5> color rgb <1, 0.95, 0.85> }}
{SKY}
height_field {{
  gif \"plasma_sea.gif\" image_map
  water_level {wl:.6}
  smooth
  scale <5, 1.8, 3.5>
  translate <-2.5, 0, -1>
  finish {{ ambient 0.2 diffuse 0.8 }}
}}
plane {{
  y, {sea_y:.6}
  pigment {{ color rgb <0.12, 0.28, 0.45> }}
  finish {{ ambient 0.15 diffuse 0.4 reflection 0.6 }}
}}
",
        sea_y = wl * 1.8
    );
    write(&out.join("plasma_sea.pov"), &scene)?;
    Ok(Shot {
        name: "plasma_sea".into(),
        title: "Plasma mountains by a reflective sea".into(),
        thesis: "6.8",
        clouds: true,
    })
}

/// Figure 6.12: an island in the sea, cut by `water_level`.
fn island(out: &Path) -> Result<Shot> {
    let (w, d) = (257u32, 257u32);
    let mut g = vec![0u8; (w * d) as usize];
    plasma(
        &mut g,
        w,
        d,
        &Plasma {
            roughness: 0.62,
            seed: 12,
        },
    )
    .map_err(|e| e.to_string())?;
    // Raise the middle, sink the edges: one island.
    let shaped: Vec<f32> = g
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let (x, z) = ((i as u32 % w) as f32 / 256.0, (i as u32 / w) as f32 / 256.0);
            let r = ((x - 0.5).powi(2) + (z - 0.5).powi(2)).sqrt() / 0.5;
            f32::from(v) / 255.0 * 0.6 + (1.0 - r * r).max(-0.3) * 0.45
        })
        .collect();
    let idx = to_indices(&shaped);
    let sea = 150usize;
    gif(&out.join("island.gif"), w, d, &idx, &land_palette(sea))?;
    let wl = sea as f32 / 256.0;
    let scene = format!(
        "// An island in the sea (thesis figure 6.12): plasma (roughness 0.62,
// seed 12) raised in the middle; water_level removes everything under
// the sea, a reflective plane is the sea.
#version 3.7;
global_settings {{ assumed_gamma 1.0 }}
camera {{ location <0, 0.6, -3.6> look_at <0, 0.2, 0> right x*image_width/image_height angle 45 }}
light_source {{ <-5, 6, -2> color rgb <1, 0.95, 0.85> }}
{SKY}
height_field {{
  gif \"island.gif\" image_map
  water_level {wl:.6}
  smooth
  scale <3, 1.2, 3>
  translate <-1.5, -{base:.6}, -1.5>
  finish {{ ambient 0.2 diffuse 0.8 }}
}}
plane {{
  y, 0
  pigment {{ color rgb <0.05, 0.2, 0.35> }}
  finish {{ ambient 0.1 diffuse 0.35 reflection 0.5 }}
}}
",
        base = wl * 1.2
    );
    write(&out.join("island.pov"), &scene)?;
    Ok(Shot {
        name: "island".into(),
        title: "Island in the sea (`water_level`)".into(),
        thesis: "6.12",
        clouds: true,
    })
}

/// §4.2.2.2, figure 4.3: concentric circles of rising index.
fn crater_scene(out: &Path) -> Result<Shot> {
    let (w, d) = (257u32, 257u32);
    let mut g = vec![0u8; (w * d) as usize];
    let c = Crater {
        radius: 0.3,
        rim_width: 0.17,
        floor: 10,
        rim: 200,
        plain: 40,
        rings: 10,
        ..Crater::default()
    };
    crater(&mut g, w, d, &c).map_err(|e| e.to_string())?;
    let gray = palette_from(&[(0, [0, 0, 0]), (255, [255, 255, 255])]);
    gif(&out.join("crater.gif"), w, d, &g, &gray)?;
    let scene = format!(
        "// A crater (thesis §4.2.2.2): 10 concentric circles of rising index
// from the floor (10) to the rim (200), the wall falling to the plain (40).
#version 3.7;
global_settings {{ assumed_gamma 1.0 }}
camera {{ location <0, 1.3, -1.75> look_at <0, 0.05, 0.05> right x*image_width/image_height angle 45 }}
light_source {{ <-3, 2.5, 1> color rgb <1, 0.95, 0.85> }}
{SKY}
height_field {{
  gif \"crater.gif\"
  scale <2, 0.35, 2>
  translate <-1, 0, -1>
  pigment {{ color rgb <0.62, 0.55, 0.47> }}
  finish {{ ambient 0.15 diffuse 0.85 }}
}}
"
    );
    write(&out.join("crater.pov"), &scene)?;
    Ok(Shot {
        name: "crater".into(),
        title: "Crater: concentric circles of rising index".into(),
        thesis: "4.3",
        clouds: false,
    })
}

/// §6.2.2, figures 6.13–6.15: water drops, four frames.
fn drops_frames(out: &Path) -> Result<Vec<Shot>> {
    let (w, d) = (257u32, 257u32);
    let mut g = vec![0u8; (w * d) as usize];
    let water = palette_from(&[(0, [0, 0, 0]), (255, [255, 255, 255])]);
    let mut shots = Vec::new();
    for (k, t) in [0.30, 0.45, 0.60, 0.75].into_iter().enumerate() {
        let p = Drops {
            time: t,
            count: 6,
            seed: 7,
            amplitude: 70.0,
            wavelength: 0.045,
            speed: 0.6,
            damping: 1.5,
            ..Drops::default()
        };
        drops(&mut g, w, d, &p).map_err(|e| e.to_string())?;
        let name = format!("drops_{k}");
        gif(&out.join(format!("{name}.gif")), w, d, &g, &water)?;
        let scene = format!(
            "// Water drops (thesis §6.2.2), frame {k}: clock {t} of one animation
// (6 drops, seed 7); the water surface is a height field, y scaled down,
// in a tank of four walls.
#version 3.7;
global_settings {{ assumed_gamma 1.0 }}
camera {{ location <0, 1.25, -1.6> look_at <0, 0, 0.05> right x*image_width/image_height angle 50 }}
light_source {{ <-2, 1.2, 3> color rgb <1, 1, 1> }}
light_source {{ <1, 3, -2> color rgb <0.35, 0.35, 0.35> }}
background {{ color rgb <0.75, 0.8, 0.85> }}
height_field {{
  gif \"{name}.gif\"
  smooth
  scale <2, 0.12, 2>
  translate <-1, -0.06, -1>
  pigment {{ color rgb <0.15, 0.35, 0.55> }}
  finish {{ ambient 0.15 diffuse 0.7 phong 0.8 phong_size 60 reflection 0.25 }}
}}
box {{ <-1.05, -0.3, -1.05>, <-1, 0.08, 1.05> pigment {{ color rgb <0.6, 0.6, 0.62> }} }}
box {{ <1, -0.3, -1.05>, <1.05, 0.08, 1.05> pigment {{ color rgb <0.6, 0.6, 0.62> }} }}
box {{ <-1.05, -0.3, 1>, <1.05, 0.08, 1.05> pigment {{ color rgb <0.6, 0.6, 0.62> }} }}
box {{ <-1.05, -0.3, -1.05>, <1.05, 0.08, -1> pigment {{ color rgb <0.6, 0.6, 0.62> }} }}
"
        );
        write(&out.join(format!("{name}.pov")), &scene)?;
        shots.push(Shot {
            name,
            title: format!("Water drops, frame {k} (clock {t})"),
            thesis: "6.13–6.15",
            clouds: false,
        });
    }
    Ok(shots)
}

/// §6.2.3, figure 6.16: broken wood — a fractal disc on a cylinder.
fn wood_scene(out: &Path) -> Result<Shot> {
    let (w, d) = (257u32, 257u32);
    let mut g = vec![0u8; (w * d) as usize];
    let p = Wood {
        roughness: 0.7,
        seed: 3,
        radius: 0.49,
        low: 1,
        grain: 6,
        ..Wood::default()
    };
    wood(&mut g, w, d, &p).map_err(|e| e.to_string())?;
    let gray = palette_from(&[(0, [0, 0, 0]), (255, [255, 255, 255])]);
    gif(&out.join("wood.gif"), w, d, &g, &gray)?;
    let scene = "// Broken wood (thesis §6.2.3): a cylinder and a height field. The field
// is a fractal (roughness 0.7, grain 6: fibres) inside a circle, index 0
// outside; water_level 0.5/256 removes the outside; the disc sits on the
// cylinder's top as its broken end.
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <1.6, 2.3, -2.4> look_at <0, 0.85, 0> right x*image_width/image_height angle 40 }
light_source { <-3, 6, -4> color rgb <1, 0.95, 0.88> }
light_source { <4, 3, -1> color rgb <0.25, 0.25, 0.3> }
background { color rgb <0.55, 0.7, 0.9> }
cylinder {
  <0, 0, 0>, <0, 1, 0>, 0.5
  pigment { color rgb <0.33, 0.2, 0.1> }
  finish { ambient 0.15 diffuse 0.8 }
}
height_field {
  gif \"wood.gif\"
  water_level 0.001953
  scale <1, 0.45, 1>
  translate <-0.5, 0.999, -0.5>
  pigment { color rgb <0.85, 0.68, 0.45> }
  finish { ambient 0.15 diffuse 0.85 }
}
plane {
  y, 0
  pigment { color rgb <0.35, 0.45, 0.25> }
  finish { ambient 0.15 diffuse 0.7 }
}
";
    write(&out.join("wood.pov"), scene)?;
    Ok(Shot {
        name: "wood".into(),
        title: "Broken wood: fractal disc on a cylinder".into(),
        thesis: "6.16",
        clouds: false,
    })
}

/// §6.2.4, figure 6.18: fire from above, y scaled down, fire palette.
fn fire_scene(out: &Path) -> Result<Shot> {
    let (w, d) = (320u32, 200u32);
    let mut g = vec![0u8; (w * d) as usize];
    fire(
        &mut g,
        w,
        d,
        &Fire {
            iterations: 400,
            seed: 1996,
            flame_height: 0.85,
            fuel: 0.6,
        },
    )
    .map_err(|e| e.to_string())?;
    gif(&out.join("fire.gif"), w, d, &g, &FIRE_PALETTE)?;
    let scene = "// Fire (thesis §6.2.4): each pixel the mean of its neighbours below,
// propagated upward from a random hot row (400 iterations); palette black,
// blue, red, yellow, white; y scaled down to a slab and seen from straight
// above: the relief and shadows read as smoke.
#version 3.7;
global_settings { assumed_gamma 1.0 }
camera { location <0.8, 2.2, 0.5> look_at <0.8, 0, 0.5> sky <0, 0, 1> right x*image_width/image_height angle 40.1 }
light_source { <-1.5, 1.5, 1.5> color rgb <0.9, 0.9, 0.9> }
background { color rgb <0, 0, 0> }
height_field {
  gif \"fire.gif\" image_map
  scale <1.6, 0.12, 1>
  finish { ambient 0.6 diffuse 0.6 }
}
";
    write(&out.join("fire.pov"), scene)?;
    Ok(Shot {
        name: "fire".into(),
        title: "Fire from above, y scaled down".into(),
        thesis: "6.18",
        clouds: false,
    })
}

// ------------------------------------------------------------ rendering

/// One thread's band: its pixels, its depths (with clouds), its counters.
type Band = (Vec<[u8; 3]>, Vec<f32>, Stats);

/// Renders the scene on `THREADS` threads (one band of rows each) into a
/// frame, composites clouds if asked, and writes `NAME.png`.
fn render_shot(out: &Path, shot: Shot) -> Result<Rendered> {
    let path = out.join(format!("{}.pov", shot.name));
    let text = read_scene_text(&path)?;
    let opts = ParseOptions::new(W, H);
    let scene = parse_file_scene(&path, &text, &opts, &mut |w| eprintln!("warning: {w}"))?;
    let loaded = load_fields(&scene, &path)?;
    let fields = build_fields(&scene, &loaded)?;

    let t0 = Instant::now();
    let settings = RenderSettings::new(W, H).with_aa(AA);
    let bands: Vec<_> = (0..THREADS)
        .map(|k| (H * k / THREADS)..(H * (k + 1) / THREADS))
        .collect();
    let (scene, fields) = (&scene, &fields);
    let results: Vec<Result<Band>> = std::thread::scope(|s| {
        let handles: Vec<_> = bands
            .iter()
            .map(|band| {
                let settings = settings.clone().with_rows(band.clone());
                let clouds = shot.clouds;
                s.spawn(move || -> Result<Band> {
                    let mut rgb = Vec::new();
                    let mut line = vec![Rgb888::default(); W as usize];
                    let mut stats = render(scene, fields, &settings, &mut line, &mut |_, r| {
                        rgb.extend(r.iter().map(|p| p.0));
                        ControlFlow::Continue(())
                    })
                    .map_err(|e| e.to_string())?;
                    let mut depth = Vec::new();
                    if clouds {
                        let mut line = vec![0f32; W as usize];
                        let s2 = render_depth(scene, fields, &settings, &mut line, &mut |_, r| {
                            depth.extend_from_slice(r);
                            ControlFlow::Continue(())
                        })
                        .map_err(|e| e.to_string())?;
                        stats.merge(&Stats { rows: 0, ..s2 });
                    }
                    Ok((rgb, depth, stats))
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err("render thread panicked".into()))
            })
            .collect()
    });
    let mut pixels = Vec::with_capacity((W * H) as usize);
    let mut depth = Vec::new();
    let mut stats = Stats::default();
    for r in results {
        let (rgb, dep, s) = r.map_err(|e| format!("{}: {e}", path.display()))?;
        pixels.extend(rgb);
        depth.extend(dep);
        stats.merge(&s);
    }
    if shot.clouds {
        composite_clouds(&mut pixels, &depth)?;
    }
    let seconds = t0.elapsed().as_secs_f64();

    let png = out.join(format!("{}.png", shot.name));
    write_png(&png, W, H, &pixels)?;
    Ok(Rendered {
        shot,
        pixels,
        seconds,
        stats,
    })
}

/// Lays a cloud sky (a plasma, seed 6) over the sky: in each column, the
/// pixels from the top down to the first one whose primary ray hit
/// something — as the thesis pasted cloud photographs behind its renders.
/// Misses below a hit (under the terrain's edge) keep the background.
fn composite_clouds(pixels: &mut [[u8; 3]], depth: &[f32]) -> Result<()> {
    let mut cloud = vec![0u8; (W * H) as usize];
    plasma(
        &mut cloud,
        W,
        H,
        &Plasma {
            roughness: 0.55,
            seed: 6,
        },
    )
    .map_err(|e| e.to_string())?;
    for x in 0..W as usize {
        for y in 0..H as usize {
            let i = y * W as usize + x;
            if depth[i].is_finite() {
                break;
            }
            let v = y as f32 / (H - 1) as f32;
            // Zenith deep blue to pale horizon.
            let sky = [0.30 + 0.35 * v, 0.48 + 0.30 * v, 0.80 + 0.12 * v];
            let c = (f32::from(cloud[i]) / 255.0 - 0.45) / 0.4;
            let a = c.clamp(0.0, 1.0);
            let a = a * a * (3.0 - 2.0 * a) * 0.9;
            let shade = 0.82 + 0.18 * (1.0 - v);
            for ch in 0..3 {
                let c = sky[ch] * (1.0 - a) + shade * a;
                pixels[i][ch] = (c * 255.0).round().clamp(0.0, 255.0) as u8;
            }
        }
    }
    Ok(())
}

fn write_png(path: &Path, w: u32, h: u32, pixels: &[[u8; 3]]) -> Result<()> {
    let err = |e: std::io::Error| format!("{}: {e}", path.display());
    let mut png = PngWriter::create(path, w, h).map_err(err)?;
    for row in pixels.chunks(w as usize) {
        png.write_row(row).map_err(err)?;
    }
    png.finish().map_err(err)
}

// ------------------------------------------------------------ sheet

const COLS: u32 = 4;
const GAP: u32 = 4;

fn contact_sheet(out: &Path, done: &[Rendered]) -> Result<()> {
    let rows = (done.len() as u32).div_ceil(COLS);
    let sw = COLS * W + (COLS + 1) * GAP;
    let sh = rows * H + (rows + 1) * GAP;
    let mut sheet = vec![[24u8, 24, 24]; (sw * sh) as usize];
    for (k, r) in done.iter().enumerate() {
        let (cx, cy) = (k as u32 % COLS, k as u32 / COLS);
        let (x0, y0) = (GAP + cx * (W + GAP), GAP + cy * (H + GAP));
        for y in 0..H {
            let src = &r.pixels[(y * W) as usize..((y + 1) * W) as usize];
            let at = ((y0 + y) * sw + x0) as usize;
            sheet[at..at + W as usize].copy_from_slice(src);
        }
    }
    write_png(&out.join("contact_sheet.png"), sw, sh, &sheet)
}

fn write_markdown(out: &Path, done: &[Rendered]) -> Result<()> {
    let mut md = String::from(
        "# hfray gallery: the thesis's natural phenomena\n\n\
         Made by `cargo run --release --example gallery -- OUTDIR` (320×200, \
         2×2 anti-aliasing, 2 threads), which writes each height field \
         (GIF), its scene (`NAME.pov`) and its image (`NAME.png`) into \
         `OUTDIR`. Each image is its scene rendered exactly as the command \
         shows (byte-identical PNG); the outdoor scenes (\"+ clouds\") then \
         get a cloud sky composited where primary rays hit nothing, as the \
         thesis did (§6.2). Render time: wall clock for the trace on 2 \
         threads, including the depth pass for the cloud mask (it varies with \
         the machine's load).\n\n\
         ![contact sheet](contact_sheet.png)\n\n\
         Contact sheet order: left to right, top to bottom.\n\n\
         | # | image | phenomenon | thesis fig. | command | render time |\n\
         |---|---|---|---|---|---|\n",
    );
    for (k, r) in done.iter().enumerate() {
        let _ = writeln!(
            md,
            "| {k} | `{n}.png` | {t} | {f} | `cargo run --release --example render -- OUTDIR/{n}.pov -o {n}.png --aa 2 --threads 2`{c} | {s:.2} s |",
            k = k + 1,
            n = r.shot.name,
            t = r.shot.title,
            f = r.shot.thesis,
            c = if r.shot.clouds { " + clouds" } else { "" },
            s = r.seconds,
        );
    }
    write(&out.join("gallery.md"), &md)
}
