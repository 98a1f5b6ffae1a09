//! The std harness's I/O: height-field loaders (every format, exact samples
//! and conventions, de-interlacing, errors that name the file), the
//! streaming TGA/PNG/PFM writers, the counting allocator, and the committed
//! elevation data.

#[path = "../examples/harness/mod.rs"]
mod harness;

use std::fs;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use harness::alloc_count::CountingAlloc;
use harness::images::{
    self, load_height_field, LoadedField, Palette, SampleData, MAX_SAMPLES, MAX_SIDE,
};
use harness::pfm::{self, PfmWriter};
use harness::png_out::PngWriter;
use harness::tga::{self, TgaWriter};
use hfray::scene::{ImageFormat, ParseOptions};
use hfray::HeightConvention;

#[global_allocator]
static ALLOC: CountingAlloc = CountingAlloc::new();

// ------------------------------------------------------------------ helpers

fn tmp_dir(test: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("harness_io")
        .join(test);
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

fn put(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    fs::write(&p, bytes).unwrap();
    p
}

fn load(path: &Path, format: ImageFormat) -> LoadedField {
    load_height_field(path, format).unwrap_or_else(|e| panic!("{e}"))
}

fn u8s(f: &LoadedField) -> &[u8] {
    match f.sample_data() {
        SampleData::U8(v) => v,
        SampleData::U16(_) => panic!("expected 8-bit samples"),
    }
}

fn u16s(f: &LoadedField) -> &[u16] {
    match f.sample_data() {
        SampleData::U16(v) => v,
        SampleData::U8(_) => panic!("expected 16-bit samples"),
    }
}

/// Asserts loading fails with a message that starts with the file name and
/// contains `needle`; returns the message.
fn load_err(path: &Path, format: ImageFormat, needle: &str) -> String {
    let e = load_height_field(path, format)
        .err()
        .unwrap_or_else(|| panic!("{} loaded, expected an error", path.display()));
    let s = e.to_string();
    assert!(
        s.starts_with(&format!("{}: ", path.display())),
        "message does not start with the file name: {s}"
    );
    assert_eq!(e.path(), path);
    assert!(s.contains(needle), "expected {needle:?} in: {s}");
    s
}

/// A deterministic pseudo-random byte stream.
fn lcg(seed: &mut u64) -> u8 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 33) as u8
}

/// A GIF with an arbitrary (possibly short) global palette, optionally
/// interlaced (rows stored in GIF pass order).
fn gif_bytes(w: u16, h: u16, indices: &[u8], palette: &[u8], interlaced: bool) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut enc = gif::Encoder::new(&mut out, w, h, palette).unwrap();
        let stored: Vec<u8> = if interlaced {
            images::gif_interlace_order(h as usize)
                .into_iter()
                .flat_map(|r| indices[r * w as usize..(r + 1) * w as usize].to_vec())
                .collect()
        } else {
            indices.to_vec()
        };
        let frame = gif::Frame {
            width: w,
            height: h,
            buffer: stored.into(),
            interlaced,
            ..gif::Frame::default()
        };
        enc.write_frame(&frame).unwrap();
    }
    out
}

fn png_bytes(
    w: u32,
    h: u32,
    color: png::ColorType,
    depth: png::BitDepth,
    data: &[u8],
    palette: Option<&[u8]>,
) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(color);
        enc.set_depth(depth);
        if let Some(p) = palette {
            enc.set_palette(p.to_vec());
        }
        let mut wr = enc.write_header().unwrap();
        wr.write_image_data(data).unwrap();
        wr.finish().unwrap();
    }
    out
}

fn be16_bytes(v: &[u16]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_be_bytes()).collect()
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut c = 0xffff_ffffu32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

fn png_chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    let mut body = kind.to_vec();
    body.extend_from_slice(data);
    out.extend_from_slice(&body);
    out.extend_from_slice(&crc32(&body).to_be_bytes());
}

/// A hand-made Adam7-interlaced 8-bit gray PNG (stored deflate blocks),
/// since the `png` crate's encoder does not interlace.
fn interlaced_gray_png(w: usize, h: usize, v: &[u8]) -> Vec<u8> {
    let v: Vec<u16> = v.iter().map(|&x| u16::from(x)).collect();
    interlaced_png(w, h, 8, &v)
}

/// [`interlaced_gray_png`] of 8- or 16-bit (`bits`) gray samples.
fn interlaced_png(w: usize, h: usize, bits: u8, v: &[u16]) -> Vec<u8> {
    const PASSES: [(usize, usize, usize, usize); 7] = [
        (0, 0, 8, 8),
        (4, 0, 8, 8),
        (0, 4, 4, 8),
        (2, 0, 4, 4),
        (0, 2, 2, 4),
        (1, 0, 2, 2),
        (0, 1, 1, 2),
    ];
    let mut raw = Vec::new();
    for (x0, y0, dx, dy) in PASSES {
        if x0 >= w || y0 >= h {
            continue;
        }
        for y in (y0..h).step_by(dy) {
            raw.push(0); // filter: none
            for x in (x0..w).step_by(dx) {
                if bits == 16 {
                    raw.extend_from_slice(&v[y * w + x].to_be_bytes());
                } else {
                    raw.push(v[y * w + x] as u8);
                }
            }
        }
    }
    // zlib: header, one stored block per 65535 bytes, Adler-32.
    let mut z = vec![0x78, 0x01];
    let blocks: Vec<&[u8]> = raw.chunks(65_535).collect();
    for (i, b) in blocks.iter().enumerate() {
        z.push(u8::from(i + 1 == blocks.len()));
        z.extend_from_slice(&(b.len() as u16).to_le_bytes());
        z.extend_from_slice(&(!(b.len() as u16)).to_le_bytes());
        z.extend_from_slice(b);
    }
    let (mut a, mut b) = (1u32, 0u32);
    for &x in &raw {
        a = (a + u32::from(x)) % 65_521;
        b = (b + a) % 65_521;
    }
    z.extend_from_slice(&(b << 16 | a).to_be_bytes());
    let mut out = vec![137, 80, 78, 71, 13, 10, 26, 10];
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&(w as u32).to_be_bytes());
    ihdr.extend_from_slice(&(h as u32).to_be_bytes());
    ihdr.extend_from_slice(&[bits, 0, 0, 0, 1]); // gray, Adam7
    png_chunk(&mut out, b"IHDR", &ihdr);
    png_chunk(&mut out, b"IDAT", &z);
    png_chunk(&mut out, b"IEND", &[]);
    out
}

fn tga_header(image_type: u8, w: u16, h: u16, bits: u8, descriptor: u8) -> Vec<u8> {
    let mut hd = vec![0u8; 18];
    hd[2] = image_type;
    hd[12..14].copy_from_slice(&w.to_le_bytes());
    hd[14..16].copy_from_slice(&h.to_le_bytes());
    hd[16] = bits;
    hd[17] = descriptor;
    hd
}

fn pnm(magic: &str, w: u32, h: u32, maxval: u32, body: &[u8]) -> Vec<u8> {
    let mut v = format!("{magic}\n{w} {h}\n{maxval}\n").into_bytes();
    v.extend_from_slice(body);
    v
}

// ---------------------------------------------------------------- GIF / POT

#[test]
fn gif_loader_gives_palette_indices_not_colours() {
    let dir = tmp_dir("gif_indices");
    let (w, h) = (5u16, 4u16);
    let indices: Vec<u8> = (0..20u8).map(|i| i.wrapping_mul(13)).collect();
    // A palette whose colours run opposite to the indices: heights must
    // still be the indices.
    let palette: Vec<u8> = (0..256u32)
        .flat_map(|i| [255 - i as u8, 7, i as u8])
        .collect();
    let p = put(&dir, "a.gif", &gif_bytes(w, h, &indices, &palette, false));
    let f = load(&p, ImageFormat::Gif);
    assert_eq!((f.width(), f.depth()), (5, 4));
    assert_eq!(f.convention(), HeightConvention::Indexed);
    assert_eq!(u8s(&f), &indices[..]);
    let pal = f.palette().expect("GIF palette");
    assert_eq!(pal[0], [255, 7, 0]);
    assert_eq!(pal[200], [55, 7, 200]);
    assert_eq!(f.height_units(1, 0), Some(13 * 256));
    // The core field borrows the samples and carries the palette.
    let field = f.height_field().unwrap();
    assert_eq!(field.palette().unwrap()[3], [252, 7, 3]);
}

#[test]
fn gif_short_palette_is_padded_to_256_with_black() {
    let dir = tmp_dir("gif_short_palette");
    let indices = [0u8, 1, 2, 3, 3, 2, 1, 0];
    let palette = [10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120];
    let p = put(&dir, "s.gif", &gif_bytes(4, 2, &indices, &palette, false));
    let f = load(&p, ImageFormat::Gif);
    assert_eq!(u8s(&f), &indices[..]);
    let pal = f.palette().unwrap();
    assert_eq!(
        &pal[..4],
        &[[10, 20, 30], [40, 50, 60], [70, 80, 90], [100, 110, 120]]
    );
    assert!(pal[4..].iter().all(|&c| c == [0, 0, 0]));
}

#[test]
fn interlaced_gif_rows_come_out_in_image_order() {
    let dir = tmp_dir("gif_interlaced");
    // Every depth from 2 to 20 exercises each combination of the 4 passes.
    for h in 2u16..=20 {
        let w = 3u16;
        // Row r holds r*10 + column: any misplaced row shows.
        let indices: Vec<u8> = (0..h)
            .flat_map(|r| (0..w).map(move |c| (r * 10 + c) as u8))
            .collect();
        let bytes = gif_bytes(w, h, &indices, &[0; 768], true);
        // The file really is interlaced (image descriptor flag 0x40).
        let mut dec = gif::DecodeOptions::new().read_info(&bytes[..]).unwrap();
        assert!(dec.next_frame_info().unwrap().unwrap().interlaced);
        // Stored order differs from image order when h > 2.
        let p = put(&dir, &format!("i{h}.gif"), &bytes);
        let f = load(&p, ImageFormat::Gif);
        assert_eq!(u8s(&f), &indices[..], "depth {h}");
    }
}

#[test]
fn pot_loader_joins_left_high_and_right_low_bytes() {
    let dir = tmp_dir("pot");
    // 3x2 field stored as a 6x2 GIF: left half high bytes, right half low.
    let want: [u16; 6] = [0x0000, 0x1234, 0xffff, 0x00ff, 0xff00, 0x8001];
    let mut stored = Vec::new();
    for row in want.chunks(3) {
        stored.extend(row.iter().map(|v| (v >> 8) as u8));
        stored.extend(row.iter().map(|v| (v & 0xff) as u8));
    }
    let p = put(&dir, "f.pot", &gif_bytes(6, 2, &stored, &[0; 768], false));
    let f = load(&p, ImageFormat::Pot);
    assert_eq!((f.width(), f.depth()), (3, 2));
    assert_eq!(f.convention(), HeightConvention::Gray16);
    assert_eq!(u16s(&f), &want[..]);
    assert!(f.palette().is_none());
    assert_eq!(f.height_units(2, 0), Some(0xffff));
}

#[test]
fn pot_with_odd_width_is_an_error() {
    let dir = tmp_dir("pot_odd");
    let p = put(
        &dir,
        "odd.pot",
        &gif_bytes(5, 2, &[0; 10], &[0; 768], false),
    );
    load_err(&p, ImageFormat::Pot, "width must be even");
}

// ---------------------------------------------------------------------- PNG

#[test]
fn palette_png_keeps_indices_at_every_bit_depth() {
    use png::{BitDepth, ColorType};
    let dir = tmp_dir("png_palette");
    let palette: Vec<u8> = (0..256u32).flat_map(|i| [9, 255 - i as u8, 3]).collect();
    // 8-bit: 3x2.
    let idx8 = [0u8, 200, 255, 17, 1, 128];
    let p = put(
        &dir,
        "p8.png",
        &png_bytes(
            3,
            2,
            ColorType::Indexed,
            BitDepth::Eight,
            &idx8,
            Some(&palette),
        ),
    );
    let f = load(&p, ImageFormat::Png);
    assert_eq!(f.convention(), HeightConvention::Indexed);
    assert_eq!(u8s(&f), &idx8[..]);
    assert_eq!(f.palette().unwrap()[200], [9, 55, 3]);
    // 4-bit, width 5 (odd: the last byte of each row is half used).
    let idx4 = [1u8, 15, 0, 7, 9, 14, 2, 3, 4, 5];
    let pack4 = |r: &[u8]| vec![r[0] << 4 | r[1], r[2] << 4 | r[3], r[4] << 4];
    let mut data = pack4(&idx4[..5]);
    data.extend(pack4(&idx4[5..]));
    let p = put(
        &dir,
        "p4.png",
        &png_bytes(
            5,
            2,
            ColorType::Indexed,
            BitDepth::Four,
            &data,
            Some(&palette[..48]),
        ),
    );
    let f = load(&p, ImageFormat::Png);
    assert_eq!(u8s(&f), &idx4[..]);
    assert_eq!(f.palette().unwrap()[15], [9, 240, 3]);
    assert_eq!(f.palette().unwrap()[16], [0, 0, 0]);
    // 1-bit, width 10.
    let bits = [1u8, 0, 1, 1, 0, 0, 0, 1, 1, 0, 0, 1, 1, 1, 1, 1, 0, 0, 0, 0];
    let pack1 = |r: &[u8]| {
        let b0 = r[..8].iter().fold(0u8, |a, &b| a << 1 | b);
        let b1 = (r[8] << 7) | (r[9] << 6);
        vec![b0, b1]
    };
    let mut data = pack1(&bits[..10]);
    data.extend(pack1(&bits[10..]));
    let p = put(
        &dir,
        "p1.png",
        &png_bytes(
            10,
            2,
            ColorType::Indexed,
            BitDepth::One,
            &data,
            Some(&palette[..6]),
        ),
    );
    let f = load(&p, ImageFormat::Png);
    assert_eq!(u8s(&f), &bits[..]);
}

#[test]
fn gray8_png_is_gray8_exact() {
    let dir = tmp_dir("png_gray8");
    let v: Vec<u8> = (0..12u8).map(|i| i * 23).collect();
    let p = put(
        &dir,
        "g.png",
        &png_bytes(
            4,
            3,
            png::ColorType::Grayscale,
            png::BitDepth::Eight,
            &v,
            None,
        ),
    );
    let f = load(&p, ImageFormat::Png);
    assert_eq!(f.convention(), HeightConvention::Gray8);
    assert_eq!(u8s(&f), &v[..]);
    assert!(f.palette().is_none());
    assert_eq!(f.height_units(3, 2), Some(253 * 257));
}

#[test]
fn gray16_png_is_exact() {
    let dir = tmp_dir("png_gray16");
    let v: [u16; 6] = [0, 1, 255, 256, 0x1234, 65_535];
    let p = put(
        &dir,
        "g16.png",
        &png_bytes(
            3,
            2,
            png::ColorType::Grayscale,
            png::BitDepth::Sixteen,
            &be16_bytes(&v),
            None,
        ),
    );
    let f = load(&p, ImageFormat::Png);
    assert_eq!(f.convention(), HeightConvention::Gray16);
    assert_eq!(u16s(&f), &v[..]);
    // Gray + alpha, 16-bit: alpha ignored.
    let ga: Vec<u16> = v.iter().flat_map(|&g| [g, 0x5555]).collect();
    let p = put(
        &dir,
        "ga16.png",
        &png_bytes(
            3,
            2,
            png::ColorType::GrayscaleAlpha,
            png::BitDepth::Sixteen,
            &be16_bytes(&ga),
            None,
        ),
    );
    assert_eq!(u16s(&load(&p, ImageFormat::Png)), &v[..]);
}

#[test]
fn low_bit_gray_png_scales_to_8_bits_and_gray_alpha_drops_alpha() {
    let dir = tmp_dir("png_gray_low");
    // 2-bit gray, 4x2: values 0..3 -> 0, 85, 170, 255.
    let vals = [0u8, 1, 2, 3, 3, 2, 1, 0];
    let data = [0b00_01_10_11, 0b11_10_01_00];
    let p = put(
        &dir,
        "g2.png",
        &png_bytes(
            4,
            2,
            png::ColorType::Grayscale,
            png::BitDepth::Two,
            &data,
            None,
        ),
    );
    let f = load(&p, ImageFormat::Png);
    assert_eq!(f.convention(), HeightConvention::Gray8);
    let want: Vec<u8> = vals.iter().map(|v| v * 85).collect();
    assert_eq!(u8s(&f), &want[..]);
    // 8-bit gray + alpha.
    let ga = [10u8, 0, 20, 255, 30, 7, 40, 9];
    let p = put(
        &dir,
        "ga8.png",
        &png_bytes(
            2,
            2,
            png::ColorType::GrayscaleAlpha,
            png::BitDepth::Eight,
            &ga,
            None,
        ),
    );
    assert_eq!(u8s(&load(&p, ImageFormat::Png)), &[10, 20, 30, 40]);
}

#[test]
fn rgb_png_height_is_red_high_green_low_and_16_bit_rgb_uses_pov_grey() {
    let dir = tmp_dir("png_rgb");
    let rgb = [0x12u8, 0x34, 0xff, 0, 0, 0, 255, 255, 255, 1, 2, 3];
    let p = put(
        &dir,
        "rgb.png",
        &png_bytes(2, 2, png::ColorType::Rgb, png::BitDepth::Eight, &rgb, None),
    );
    let f = load(&p, ImageFormat::Png);
    assert_eq!(f.convention(), HeightConvention::Gray16);
    assert_eq!(u16s(&f), &[0x1234, 0, 0xffff, 0x0102]);
    // RGBA 8: alpha ignored.
    let rgba = [0x12u8, 0x34, 0, 0, 9, 8, 7, 6, 1, 1, 1, 1, 200, 100, 0, 255];
    let p = put(
        &dir,
        "rgba.png",
        &png_bytes(
            2,
            2,
            png::ColorType::Rgba,
            png::BitDepth::Eight,
            &rgba,
            None,
        ),
    );
    assert_eq!(
        u16s(&load(&p, ImageFormat::Png)),
        &[0x1234, 0x0908, 0x0101, 200 * 256 + 100]
    );
    // RGB 16: POV-Ray grey .297 r + .589 g + .114 b, exact floor.
    let rgb16: [u16; 12] = [
        65_535, 65_535, 65_535, 0, 0, 0, 65_535, 0, 0, 1000, 2000, 3000,
    ];
    let p = put(
        &dir,
        "rgb16.png",
        &png_bytes(
            2,
            2,
            png::ColorType::Rgb,
            png::BitDepth::Sixteen,
            &be16_bytes(&rgb16),
            None,
        ),
    );
    // 0.297 * 65535 = 19463.895; 297*1000 + 589*2000 + 114*3000 = 1_817_000 / 1000.
    assert_eq!(
        u16s(&load(&p, ImageFormat::Png)),
        &[65_535, 0, 19_463, 1_817]
    );
}

#[test]
fn interlaced_png_rows_are_exact() {
    let dir = tmp_dir("png_adam7");
    let (w, h) = (11usize, 9usize);
    let v: Vec<u8> = (0..w * h).map(|i| (i * 7 % 251) as u8).collect();
    let p = put(&dir, "adam7.png", &interlaced_gray_png(w, h, &v));
    let f = load(&p, ImageFormat::Png);
    assert_eq!((f.width(), f.depth()), (11, 9));
    assert_eq!(u8s(&f), &v[..]);
}

#[test]
fn png_load_peak_memory_is_the_samples_plus_small_buffers() {
    let dir = tmp_dir("png_memory");
    let (w, h) = (1024u32, 1024u32);
    let v: Vec<u8> = (0..w * h).map(|i| (i % 253) as u8).collect();
    let p = put(
        &dir,
        "big.png",
        &png_bytes(
            w,
            h,
            png::ColorType::Grayscale,
            png::BitDepth::Eight,
            &v,
            None,
        ),
    );
    drop(v);
    let before = ALLOC.thread_snapshot();
    ALLOC.reset_thread_peak();
    let f = load(&p, ImageFormat::Png);
    let after = ALLOC.thread_snapshot();
    let samples = (w * h) as isize;
    let overhead = after.peak_bytes - before.current_bytes - samples;
    eprintln!("PNG 1024x1024 gray8 load: peak over samples = {overhead} bytes");
    assert!(overhead >= 0);
    // Rows are streamed: no second frame-sized buffer. The overhead is the
    // decoder's inflate state and row buffers, about constant: measured
    // 160 KB at 256², 291 KB at 1024², 294 KB at 4096².
    assert!(overhead < 512 * 1024, "overhead {overhead} bytes");
    assert_eq!(f.heap_bytes(), samples as usize);
}

// ------------------------------------------------------------------- Netpbm

#[test]
fn pgm_8bit_binary_and_ascii_are_gray8_exact() {
    let dir = tmp_dir("pgm8");
    let v = [0u8, 1, 127, 128, 254, 255];
    let p = put(&dir, "b.pgm", &pnm("P5", 3, 2, 255, &v));
    let f = load(&p, ImageFormat::Pgm);
    assert_eq!(f.convention(), HeightConvention::Gray8);
    assert_eq!(u8s(&f), &v[..]);
    // ASCII with comments in the header and free line breaks.
    let text = b"P2\n# a comment\n3 # width\n2\n# maxval next\n255\n0 1 127\n128\n254 255\n";
    let p = put(&dir, "a.pgm", text);
    let f = load(&p, ImageFormat::Pgm);
    assert_eq!(u8s(&f), &v[..]);
}

#[test]
fn pgm_16bit_is_big_endian_exact_and_other_maxvals_scale() {
    let dir = tmp_dir("pgm16");
    let v: [u16; 4] = [0, 0x0102, 0xfffe, 0xffff];
    let p = put(&dir, "w.pgm", &pnm("P5", 2, 2, 65_535, &be16_bytes(&v)));
    let f = load(&p, ImageFormat::Pgm);
    assert_eq!(f.convention(), HeightConvention::Gray16);
    assert_eq!(u16s(&f), &v[..]);
    // maxval 15: floor(65535 v / 15) = 4369 v.
    let p = put(&dir, "m15.pgm", &pnm("P5", 2, 2, 15, &[0, 1, 7, 15]));
    assert_eq!(
        u16s(&load(&p, ImageFormat::Pgm)),
        &[0, 4369, 30_583, 65_535]
    );
    // maxval 1000 (16-bit samples): floor(65535 v / 1000).
    let p = put(
        &dir,
        "m1000.pgm",
        &pnm("P5", 2, 2, 1000, &be16_bytes(&[0, 1, 500, 1000])),
    );
    assert_eq!(u16s(&load(&p, ImageFormat::Pgm)), &[0, 65, 32_767, 65_535]);
}

#[test]
fn ppm_height_is_red_high_green_low() {
    let dir = tmp_dir("ppm");
    let rgb = [0x12u8, 0x34, 0x99, 0, 0, 0, 255, 255, 255, 5, 6, 7];
    let p = put(&dir, "c.ppm", &pnm("P6", 2, 2, 255, &rgb));
    let f = load(&p, ImageFormat::Ppm);
    assert_eq!(f.convention(), HeightConvention::Gray16);
    assert_eq!(u16s(&f), &[0x1234, 0, 0xffff, 0x0506]);
    let p = put(
        &dir,
        "a.ppm",
        b"P3 2 2 255  18 52 153  0 0 0  255 255 255  5 6 7",
    );
    assert_eq!(
        u16s(&load(&p, ImageFormat::Ppm)),
        &[0x1234, 0, 0xffff, 0x0506]
    );
    // A gray PGM named with the ppm keyword still loads (POV-Ray's Netpbm
    // reader takes any of P2/P3/P5/P6).
    let p = put(&dir, "g.pgm", &pnm("P5", 2, 2, 255, &[1, 2, 3, 4]));
    assert_eq!(u8s(&load(&p, ImageFormat::Ppm)), &[1, 2, 3, 4]);
    // 16-bit colour: POV-Ray grey.
    let p = put(
        &dir,
        "w.ppm",
        &pnm(
            "P6",
            2,
            2,
            65_535,
            &be16_bytes(&[65_535, 65_535, 65_535, 0, 65_535, 0, 0, 0, 0, 0, 0, 1000]),
        ),
    );
    // 0.589 * 65535 = 38600.1; 0.114 * 1000 * 65535 / 65535 = 114.
    assert_eq!(u16s(&load(&p, ImageFormat::Ppm)), &[65_535, 38_600, 0, 114]);
}

// ---------------------------------------------------------------------- TGA

#[test]
fn gray_tga_bottom_origin_is_flipped_to_image_order() {
    let dir = tmp_dir("tga_gray");
    // Bottom-left origin: the file's first row is the image's bottom row.
    let mut b = tga_header(3, 3, 2, 8, 0);
    b.extend_from_slice(&[4, 5, 6, 1, 2, 3]);
    let p = put(&dir, "g.tga", &b);
    let f = load(&p, ImageFormat::Tga);
    assert_eq!(f.convention(), HeightConvention::Gray8);
    assert_eq!(u8s(&f), &[1, 2, 3, 4, 5, 6]);
    // Top-left origin: as stored.
    let mut b = tga_header(3, 3, 2, 8, 0x20);
    b.extend_from_slice(&[1, 2, 3, 4, 5, 6]);
    let p = put(&dir, "t.tga", &b);
    assert_eq!(u8s(&load(&p, ImageFormat::Tga)), &[1, 2, 3, 4, 5, 6]);
}

#[test]
fn truecolor_tga_height_is_red_high_green_low() {
    let dir = tmp_dir("tga_rgb");
    // 24-bit BGR, top-left.
    let mut b = tga_header(2, 2, 2, 24, 0x20);
    b.extend_from_slice(&[0x99, 0x34, 0x12, 0, 0, 0, 255, 255, 255, 7, 6, 5]);
    let p = put(&dir, "c24.tga", &b);
    let f = load(&p, ImageFormat::Tga);
    assert_eq!(f.convention(), HeightConvention::Gray16);
    assert_eq!(u16s(&f), &[0x1234, 0, 0xffff, 0x0506]);
    // 32-bit BGRA, bottom-left.
    let mut b = tga_header(2, 2, 2, 32, 0x08);
    b.extend_from_slice(&[0x99, 0x34, 0x12, 0x80, 3, 2, 1, 0]); // bottom row
    b.extend_from_slice(&[0, 0, 0xff, 9, 0, 0xff, 0, 9]); // top row
    let p = put(&dir, "c32.tga", &b);
    assert_eq!(
        u16s(&load(&p, ImageFormat::Tga)),
        &[0xff00, 0x00ff, 0x1234, 0x0102]
    );
    // 16-bit 5-5-5 (POV-Ray shifts 5-bit channels left by 3).
    // r=31, g=16, b=1: bits 0 11111 10000 00001 = 0x7e01 little-endian.
    let mut b = tga_header(2, 2, 2, 16, 0x20);
    b.extend_from_slice(&[0x01, 0x7e, 0x00, 0x00, 0x00, 0x00, 0xff, 0x7f]);
    let p = put(&dir, "c16.tga", &b);
    assert_eq!(
        u16s(&load(&p, ImageFormat::Tga)),
        &[(248 << 8) | 128, 0, 0, (248 << 8) | 248]
    );
}

#[test]
fn colour_mapped_tga_keeps_indices_and_map() {
    let dir = tmp_dir("tga_mapped");
    let mut b = tga_header(1, 2, 2, 8, 0x20);
    b[1] = 1; // colour map present
    b[5..7].copy_from_slice(&3u16.to_le_bytes()); // 3 entries
    b[7] = 24;
    b.extend_from_slice(&[30, 20, 10, 60, 50, 40, 90, 80, 70]); // BGR entries
    b.extend_from_slice(&[2, 0, 1, 2]);
    let p = put(&dir, "m.tga", &b);
    let f = load(&p, ImageFormat::Tga);
    assert_eq!(f.convention(), HeightConvention::Indexed);
    assert_eq!(u8s(&f), &[2, 0, 1, 2]);
    let pal = f.palette().unwrap();
    assert_eq!(&pal[..3], &[[10, 20, 30], [40, 50, 60], [70, 80, 90]]);
    // An index outside the map is corrupt.
    let n = b.len();
    b[n - 1] = 3;
    let p = put(&dir, "bad.tga", &b);
    load_err(&p, ImageFormat::Tga, "outside the 3-entry colour map");
}

#[test]
fn rle_tga_packets_may_cross_rows() {
    let dir = tmp_dir("tga_rle");
    // 3x2 gray RLE, bottom-left: run of 4 x 9 (crosses the row end), then
    // a raw packet of 2: 1, 2.
    let mut b = tga_header(11, 3, 2, 8, 0);
    b.extend_from_slice(&[0x83, 9, 0x01, 1, 2]);
    let p = put(&dir, "r.tga", &b);
    let f = load(&p, ImageFormat::Tga);
    // File rows (bottom first): [9 9 9] [9 1 2] -> image rows top first.
    assert_eq!(u8s(&f), &[9, 1, 2, 9, 9, 9]);
    // RLE true colour.
    let mut b = tga_header(10, 2, 2, 24, 0x20);
    b.extend_from_slice(&[0x83, 0, 0x02, 0x01]);
    let p = put(&dir, "rc.tga", &b);
    assert_eq!(u16s(&load(&p, ImageFormat::Tga)), &[0x0102; 4]);
    // Truncated RLE stream.
    let mut b = tga_header(11, 3, 2, 8, 0);
    b.extend_from_slice(&[0x82, 9]);
    let p = put(&dir, "short.tga", &b);
    load_err(&p, ImageFormat::Tga, "truncated TGA");
}

// ------------------------------------------------------------------- errors

#[test]
fn missing_empty_and_directory_paths_are_errors_naming_the_file() {
    let dir = tmp_dir("errors_basic");
    for format in [
        ImageFormat::Gif,
        ImageFormat::Png,
        ImageFormat::Pgm,
        ImageFormat::Ppm,
        ImageFormat::Tga,
        ImageFormat::Pot,
    ] {
        load_err(&dir.join("nope.img"), format, "cannot open");
        let p = put(&dir, "empty.img", b"");
        load_err(&p, format, "file is empty");
        load_err(&dir, format, "directory");
    }
}

#[test]
fn corrupt_files_are_errors_naming_the_file() {
    let dir = tmp_dir("errors_corrupt");
    let junk = put(&dir, "junk.bin", b"this is not an image at all, just text.");
    load_err(&junk, ImageFormat::Gif, "corrupt or truncated GIF");
    load_err(&junk, ImageFormat::Pot, "POT");
    load_err(&junk, ImageFormat::Png, "PNG");
    load_err(&junk, ImageFormat::Pgm, "not a PGM/PPM file");
    load_err(&junk, ImageFormat::Tga, "TGA");
    // A valid GIF named as PNG, and the reverse.
    let gif = put(&dir, "g.gif", &gif_bytes(2, 2, &[0; 4], &[0; 6], false));
    load_err(&gif, ImageFormat::Png, "PNG");
    let png = put(
        &dir,
        "p.png",
        &png_bytes(
            2,
            2,
            png::ColorType::Grayscale,
            png::BitDepth::Eight,
            &[0; 4],
            None,
        ),
    );
    load_err(&png, ImageFormat::Gif, "GIF");
    // Netpbm specifics.
    let p = put(&dir, "big.pgm", &pnm("P5", 2, 2, 65_536, &[0; 16]));
    load_err(&p, ImageFormat::Pgm, "maxval is 65536");
    let p = put(&dir, "over.pgm", &pnm("P5", 2, 2, 100, &[0, 1, 101, 2]));
    load_err(
        &p,
        ImageFormat::Pgm,
        "sample value 101 in row 1 exceeds maxval 100",
    );
    let p = put(&dir, "pbm.pbm", b"P4\n8 2\n\x00\x00");
    load_err(&p, ImageFormat::Pgm, "not supported");
    let p = put(&dir, "letters.pgm", b"P2\n2 x\n255\n");
    load_err(&p, ImageFormat::Pgm, "expected height");
    // TGA specifics.
    let p = put(&dir, "t0.tga", &tga_header(0, 2, 2, 8, 0));
    load_err(&p, ImageFormat::Tga, "image type 0");
    let mut b = tga_header(3, 2, 2, 8, 0x10);
    b.extend_from_slice(&[0; 4]);
    let p = put(&dir, "rtl.tga", &b);
    load_err(&p, ImageFormat::Tga, "right to left");
}

#[test]
fn truncated_files_are_errors_naming_the_file() {
    let dir = tmp_dir("errors_truncated");
    let v: Vec<u8> = (0..64 * 64).map(|i| (i * 31 % 256) as u8).collect();
    let gif = gif_bytes(64, 64, &v, &[0; 768], false);
    let p = put(&dir, "t.gif", &gif[..gif.len() / 2]);
    load_err(&p, ImageFormat::Gif, "GIF");
    let png = png_bytes(
        64,
        64,
        png::ColorType::Grayscale,
        png::BitDepth::Eight,
        &v,
        None,
    );
    let p = put(&dir, "t.png", &png[..png.len() / 2]);
    load_err(&p, ImageFormat::Png, "PNG");
    let p = put(&dir, "t.pgm", &pnm("P5", 64, 64, 255, &v[..1000]));
    load_err(
        &p,
        ImageFormat::Pgm,
        "truncated PGM: the file ends in row 15 of 64",
    );
    let p = put(&dir, "ta.pgm", b"P2 3 2 255 1 2 3 4");
    load_err(&p, ImageFormat::Pgm, "truncated PGM");
    let p = put(&dir, "th.pgm", b"P5 3 ");
    load_err(&p, ImageFormat::Pgm, "before the height");
    let mut tga = tga_header(3, 64, 64, 8, 0);
    tga.extend_from_slice(&v[..100]);
    let p = put(&dir, "t.tga", &tga);
    load_err(&p, ImageFormat::Tga, "truncated TGA");
    let p = put(&dir, "h.tga", &tga[..10]);
    load_err(&p, ImageFormat::Tga, "18-byte header");
}

#[test]
fn sizes_over_the_limits_or_under_2x2_are_errors() {
    let dir = tmp_dir("errors_size");
    // Header-only files: the size check comes before any allocation.
    let p = put(
        &dir,
        "wide.pgm",
        &pnm("P5", MAX_SIDE as u32 + 1, 2, 255, &[]),
    );
    load_err(&p, ImageFormat::Pgm, "each side may be at most 65536");
    let p = put(&dir, "huge.pgm", &pnm("P5", 65_536, 65_536, 255, &[]));
    load_err(
        &p,
        ImageFormat::Pgm,
        &format!("at most {MAX_SAMPLES} (2^28)"),
    );
    const { assert!(MAX_SAMPLES == 1 << 28) };
    let p = put(&dir, "line.pgm", &pnm("P5", 5, 1, 255, &[0; 5]));
    load_err(&p, ImageFormat::Pgm, "at least 2x2");
    let p = put(&dir, "one.gif", &gif_bytes(1, 3, &[0; 3], &[0; 6], false));
    load_err(&p, ImageFormat::Gif, "at least 2x2");
    let p = put(&dir, "t.tga", &tga_header(2, 1, 1, 24, 0));
    load_err(&p, ImageFormat::Tga, "at least 2x2");
    // A 65535x65535 PNG header: over 2^28 samples, refused before decoding.
    let mut png = png_bytes(
        2,
        2,
        png::ColorType::Grayscale,
        png::BitDepth::Eight,
        &[0; 4],
        None,
    );
    png[16..20].copy_from_slice(&65_535u32.to_be_bytes());
    png[20..24].copy_from_slice(&65_535u32.to_be_bytes());
    let crc = crc32(&png[12..29]);
    png[29..33].copy_from_slice(&crc.to_be_bytes());
    let p = put(&dir, "huge.png", &png);
    load_err(&p, ImageFormat::Png, "(2^28)");
}

#[test]
fn every_prefix_and_byte_flip_of_each_format_loads_or_errors_without_panic() {
    let dir = tmp_dir("errors_fuzz");
    let v: Vec<u8> = (0..8 * 6).map(|i| (i * 37 % 256) as u8).collect();
    let mut tga = tga_header(3, 8, 6, 8, 0x20);
    tga.extend_from_slice(&v);
    let mut rle = tga_header(11, 8, 6, 8, 0);
    for c in v.chunks(4) {
        rle.push(0x03);
        rle.extend_from_slice(c);
    }
    let pal: Vec<u8> = (0..48).collect();
    let cases: Vec<(ImageFormat, Vec<u8>)> = vec![
        (ImageFormat::Gif, gif_bytes(8, 6, &v, &[7; 768], true)),
        (ImageFormat::Pot, gif_bytes(8, 6, &v, &[7; 768], false)),
        (
            ImageFormat::Png,
            png_bytes(
                8,
                6,
                png::ColorType::Grayscale,
                png::BitDepth::Eight,
                &v,
                None,
            ),
        ),
        (
            ImageFormat::Png,
            png_bytes(
                8,
                6,
                png::ColorType::Indexed,
                png::BitDepth::Eight,
                &v.iter().map(|x| x % 16).collect::<Vec<_>>(),
                Some(&pal),
            ),
        ),
        (ImageFormat::Png, interlaced_gray_png(8, 6, &v)),
        (ImageFormat::Pgm, pnm("P5", 8, 6, 255, &v)),
        (ImageFormat::Ppm, pnm("P6", 4, 4, 255, &v)),
        (ImageFormat::Tga, tga),
        (ImageFormat::Tga, rle),
    ];
    let mut seed = 42u64;
    let (mut ok, mut errors) = (0, 0);
    let mut check = |format: ImageFormat, b: &[u8]| {
        match images::decode_height_field(Cursor::new(b), format, &mut Default::default()) {
            Ok(f) => {
                // Whatever loads is a well-formed field.
                assert_eq!(f.sample_data().len(), (f.width() * f.depth()) as usize);
                f.height_field().unwrap();
                ok += 1;
            }
            Err(e) => {
                assert!(!e.is_empty());
                errors += 1;
            }
        }
    };
    for (format, bytes) in &cases {
        // Every proper prefix (empty included).
        for cut in 0..bytes.len() {
            check(*format, &bytes[..cut]);
        }
        // 500 random single-byte corruptions.
        for _ in 0..500 {
            let mut b = bytes.clone();
            let i = (usize::from(lcg(&mut seed)) << 8 | usize::from(lcg(&mut seed))) % b.len();
            b[i] ^= lcg(&mut seed) | 1;
            check(*format, &b);
        }
    }
    eprintln!("fuzz: {ok} loaded, {errors} errors, no panic");
    assert!(errors > ok);
    // Through the file system, errors name the file.
    for (k, (format, bytes)) in cases.iter().enumerate() {
        let p = put(&dir, &format!("half{k}"), &bytes[..bytes.len() / 2]);
        load_err(&p, *format, "");
    }
}

#[test]
fn load_error_displays_file_colon_message() {
    let e = images::LoadError::new(Path::new("dir/x.gif"), "something broke");
    assert_eq!(e.to_string(), "dir/x.gif: something broke");
    assert_eq!(e.message(), "something broke");
}

#[test]
fn format_for_path_maps_extensions() {
    assert_eq!(
        images::format_for_path(Path::new("a/B.GIF")),
        Some(ImageFormat::Gif)
    );
    assert_eq!(
        images::format_for_path(Path::new("x.pot")),
        Some(ImageFormat::Pot)
    );
    assert_eq!(
        images::format_for_path(Path::new("x.tga")),
        Some(ImageFormat::Tga)
    );
    assert_eq!(images::format_for_path(Path::new("x.jpg")), None);
    assert_eq!(images::format_for_path(Path::new("noext")), None);
}

#[test]
fn loaded_field_new_checks_its_parts() {
    let ok = LoadedField::new(
        SampleData::U8(vec![1, 2, 3, 4]),
        2,
        2,
        HeightConvention::Gray8,
        None,
    )
    .unwrap();
    assert_eq!(ok.height_units(1, 1), Some(4 * 257));
    assert_eq!(ok.sample(2, 0), None);
    assert!(LoadedField::new(
        SampleData::U8(vec![1; 3]),
        2,
        2,
        HeightConvention::Gray8,
        None
    )
    .is_err());
    assert!(LoadedField::new(
        SampleData::U8(vec![1; 4]),
        2,
        2,
        HeightConvention::Gray16,
        None
    )
    .is_err());
    assert!(LoadedField::new(
        SampleData::U16(vec![1; 4]),
        2,
        2,
        HeightConvention::Indexed,
        None
    )
    .is_err());
}

// ---------------------------------------------------------------------- TGA out

#[test]
fn tga_writer_streams_rows_and_round_trips() {
    let (w, h) = (7u32, 5u32);
    let px = |x: u32, y: u32| [(x * 30) as u8, (y * 50) as u8, (x * y * 7) as u8];
    let mut tga = TgaWriter::new(Vec::new(), w, h).unwrap();
    // The header is written first, before any row.
    for y in 0..h {
        let row: Vec<[u8; 3]> = (0..w).map(|x| px(x, y)).collect();
        tga.write_row(&row).unwrap();
        assert_eq!(tga.rows_written(), y + 1);
    }
    let bytes = tga.finish().unwrap();
    assert_eq!(bytes.len(), 18 + (w * h * 3) as usize);
    assert_eq!(bytes[2], 2, "uncompressed true colour");
    assert_eq!(bytes[16], 24);
    assert_eq!(bytes[17], 0x20, "top-left origin");
    assert_eq!(u16::from_le_bytes([bytes[12], bytes[13]]), 7);
    assert_eq!(u16::from_le_bytes([bytes[14], bytes[15]]), 5);
    // First pixel stored as BGR.
    let p = px(0, 0);
    assert_eq!(&bytes[18..21], &[p[2], p[1], p[0]]);
    let img = tga::read_tga_rgb(&bytes[..]).unwrap();
    assert_eq!((img.width, img.height), (w, h));
    for y in 0..h {
        for x in 0..w {
            assert_eq!(img.pixel(x, y), px(x, y));
        }
    }
    // The height-field loader reads the same file as red·256 + green.
    let dir = tmp_dir("tga_roundtrip");
    let p = put(&dir, "out.tga", &bytes);
    let f = load(&p, ImageFormat::Tga);
    let c = px(3, 4);
    assert_eq!(f.sample(3, 4), Some(u16::from(c[0]) << 8 | u16::from(c[1])));
}

#[test]
fn tga_reader_flips_bottom_origin_files() {
    let mut b = tga_header(2, 2, 2, 24, 0);
    // Bottom row first in the file.
    b.extend_from_slice(&[3, 2, 1, 6, 5, 4, 9, 8, 7, 12, 11, 10]);
    let img = tga::read_tga_rgb(&b[..]).unwrap();
    assert_eq!(img.row(0), &[[7, 8, 9], [10, 11, 12]]);
    assert_eq!(img.row(1), &[[1, 2, 3], [4, 5, 6]]);
}

#[test]
fn tga_writer_rejects_wrong_rows_and_incomplete_images() {
    let mut t = TgaWriter::new(Vec::new(), 2, 1).unwrap();
    assert!(t.write_row(&[[0; 3]; 3]).is_err());
    t.write_row(&[[0; 3]; 2]).unwrap();
    assert!(t.write_row(&[[0; 3]; 2]).is_err(), "too many rows");
    assert!(TgaWriter::new(Vec::new(), 2, 2).unwrap().finish().is_err());
    assert!(TgaWriter::new(Vec::new(), 70_000, 2).is_err());
    assert!(TgaWriter::new(Vec::new(), 0, 2).is_err());
}

// ---------------------------------------------------------------------- PNG out

#[test]
fn png_writer_streams_rows_and_round_trips() {
    let dir = tmp_dir("png_out");
    let path = dir.join("out.png");
    let (w, h) = (9u32, 4u32);
    let px = |x: u32, y: u32| [(x * 25) as u8, (y * 60) as u8, ((x + y) * 9) as u8];
    let mut out = PngWriter::create(&path, w, h).unwrap();
    for y in 0..h {
        let row: Vec<[u8; 3]> = (0..w).map(|x| px(x, y)).collect();
        out.write_row(&row).unwrap();
    }
    assert!(out.write_row(&[[0; 3]; 9]).is_err(), "too many rows");
    out.finish().unwrap();
    let img = image::open(&path).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (w, h));
    for y in 0..h {
        for x in 0..w {
            assert_eq!(img.get_pixel(x, y).0, px(x, y));
        }
    }
    // Incomplete images are refused.
    let mut short = PngWriter::create(&dir.join("short.png"), 2, 2).unwrap();
    short.write_row(&[[1; 3]; 2]).unwrap();
    assert!(short.finish().is_err());
}

// ---------------------------------------------------------------------- PFM out

#[test]
fn pfm_header_is_little_endian_and_rows_are_stored_bottom_to_top() {
    let (w, h) = (3u32, 4u32);
    // Row r (0 = top) holds r*10 + x; the bottom-right is +inf (no hit).
    let value = |x: u32, y: u32| {
        if (x, y) == (2, 3) {
            f32::INFINITY
        } else {
            (y * 10 + x) as f32 + 0.5
        }
    };
    let mut pfm = PfmWriter::new(Cursor::new(Vec::new()), w, h).unwrap();
    for y in 0..h {
        let row: Vec<f32> = (0..w).map(|x| value(x, y)).collect();
        pfm.write_row(&row).unwrap();
    }
    let bytes = pfm.finish().unwrap().into_inner();
    let header = b"Pf\n3 4\n-1.0\n";
    assert_eq!(&bytes[..header.len()], header);
    assert_eq!(bytes.len(), header.len() + 3 * 4 * 4);
    let f = |i: usize| {
        let o = header.len() + i * 4;
        f32::from_le_bytes(bytes[o..o + 4].try_into().unwrap())
    };
    // The file's first row is the image's bottom row (y = 3).
    assert_eq!(f(0), 30.5);
    assert_eq!(f(1), 31.5);
    assert_eq!(f(2), f32::INFINITY);
    // The file's last row is the top row (y = 0).
    assert_eq!(f(9), 0.5);
    assert_eq!(f(11), 2.5);
    let img = pfm::read_pfm(&bytes[..]).unwrap();
    assert_eq!((img.width, img.height, img.scale), (3, 4, -1.0));
    for y in 0..h {
        for x in 0..w {
            assert_eq!(img.get(x, y), value(x, y));
        }
    }
}

#[test]
fn pfm_writer_to_a_file_and_incomplete_maps_are_errors() {
    let dir = tmp_dir("pfm_file");
    let path = dir.join("d.pfm");
    let mut pfm = PfmWriter::create(&path, 2, 3).unwrap();
    for y in 0..3 {
        pfm.write_row(&[y as f32, -(y as f32)]).unwrap();
    }
    assert!(pfm.write_row(&[0.0, 0.0]).is_err());
    pfm.finish().unwrap();
    let img = pfm::read_pfm(fs::File::open(&path).unwrap()).unwrap();
    assert_eq!(img.values, vec![0.0, -0.0, 1.0, -1.0, 2.0, -2.0]);
    let mut short = PfmWriter::create(&dir.join("s.pfm"), 2, 2).unwrap();
    assert!(short.write_row(&[1.0]).is_err(), "wrong row length");
    short.write_row(&[1.0, 2.0]).unwrap();
    assert!(short.finish().is_err());
}

// ------------------------------------------------------------ allocator

#[test]
fn counting_allocator_counts_a_known_allocation() {
    const N: usize = 1 << 20;
    let global_before = ALLOC.snapshot();
    let before = ALLOC.thread_snapshot();
    ALLOC.reset_thread_peak();
    let v: Vec<u8> = Vec::with_capacity(N);
    let v = std::hint::black_box(v);
    let during = ALLOC.thread_snapshot();
    assert_eq!(during.allocations, before.allocations + 1);
    assert_eq!(during.current_bytes, before.current_bytes + N as isize);
    assert_eq!(during.peak_bytes, before.current_bytes + N as isize);
    drop(v);
    let after = ALLOC.thread_snapshot();
    assert_eq!(after.current_bytes, before.current_bytes);
    assert_eq!(
        after.peak_bytes, during.peak_bytes,
        "peak is kept after the free"
    );
    // Process-wide counters only grow in total (other tests run in parallel).
    let global_after = ALLOC.snapshot();
    assert!(global_after.total_allocated_bytes >= global_before.total_allocated_bytes + N as u64);
    assert!(global_after.allocations > global_before.allocations);
    assert!(global_after.deallocations > global_before.deallocations);
    assert!(global_after.peak_bytes >= N);
    // Growing by realloc counts the new size; another thread's allocations
    // do not show in this thread's counters.
    ALLOC.reset_thread_peak();
    let base = ALLOC.thread_snapshot().current_bytes;
    let mut g: Vec<u8> = Vec::with_capacity(1000);
    g.reserve_exact(5000);
    let g = std::hint::black_box(g);
    assert_eq!(
        ALLOC.thread_snapshot().current_bytes,
        base + g.capacity() as isize
    );
    std::thread::spawn(|| std::hint::black_box(vec![0u8; N]).len())
        .join()
        .unwrap();
    // (Spawning itself may leave a few bytes of thread bookkeeping here.)
    let now = ALLOC.thread_snapshot();
    let extra = now.current_bytes - (base + g.capacity() as isize);
    assert!((0..4096).contains(&extra), "{extra}");
    assert!(now.peak_bytes < base + N as isize);
}

// ------------------------------------------------------------ committed data

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data");

/// `width` and `height` from a provenance note.
fn note_size(stem: &str) -> (u32, u32) {
    let note = fs::read_to_string(format!("{DATA}/{stem}.txt")).unwrap();
    let get = |k: &str| -> u32 {
        note.lines()
            .find_map(|l| l.strip_prefix(&format!("{k}=")))
            .unwrap_or_else(|| panic!("{stem}.txt has no {k}="))
            .trim()
            .parse()
            .unwrap()
    };
    (get("width"), get("height"))
}

const DEMS: [(&str, u32, u32); 2] = [
    ("maunga_whau_volcano_87x61", 87, 61),
    ("rmnp_co_152x187", 152, 187),
];

#[test]
fn committed_dems_load_with_the_sizes_their_notes_give() {
    for (stem, w, h) in DEMS {
        assert_eq!(note_size(stem), (w, h));
        let u8f = load(
            Path::new(&format!("{DATA}/{stem}.u8.png")),
            ImageFormat::Png,
        );
        let u16f = load(
            Path::new(&format!("{DATA}/{stem}.u16.png")),
            ImageFormat::Png,
        );
        assert_eq!((u8f.width(), u8f.depth()), (w, h), "{stem}");
        assert_eq!((u16f.width(), u16f.depth()), (w, h), "{stem}");
        assert_eq!(u8f.convention(), HeightConvention::Gray8);
        assert_eq!(u16f.convention(), HeightConvention::Gray16);
        let (a, b) = (u8s(&u8f), u16s(&u16f));
        // Both quantise zmin..zmax linearly: the full range is used, and the
        // two agree to within half an 8-bit step.
        assert_eq!(a.iter().min(), Some(&0));
        assert_eq!(a.iter().max(), Some(&255));
        assert_eq!(b.iter().min(), Some(&0));
        assert_eq!(b.iter().max(), Some(&65_535));
        let worst = a
            .iter()
            .zip(b)
            .map(|(&x, &y)| (i64::from(x) * 257 - i64::from(y)).abs())
            .max()
            .unwrap();
        assert!(worst <= 129, "{stem}: u8 and u16 differ by {worst}/65535");
        for f in [&u8f, &u16f] {
            let field = f.height_field().unwrap();
            assert!(field.palette().is_none());
        }
    }
}

#[test]
fn committed_gifs_hold_the_u8_heights_as_indices_with_the_terrain_palette() {
    for (stem, w, h) in DEMS {
        let gif = load(Path::new(&format!("{DATA}/{stem}.gif")), ImageFormat::Gif);
        let png = load(
            Path::new(&format!("{DATA}/{stem}.u8.png")),
            ImageFormat::Png,
        );
        assert_eq!((gif.width(), gif.depth()), (w, h));
        assert_eq!(gif.convention(), HeightConvention::Indexed);
        assert_eq!(u8s(&gif), u8s(&png), "{stem}: GIF indices != u8 PNG gray");
        assert_eq!(gif.palette(), Some(&images::terrain_palette()));
        // Same samples, indexed convention: heights 256·v (POV-Ray's GIF
        // reading), vs 257·v for the gray PNG.
        assert_eq!(
            gif.height_units(5, 5).unwrap(),
            256 * u32::from(png.sample(5, 5).unwrap())
        );
        let field = gif.height_field().unwrap();
        assert!(field.palette().is_some());
    }
}

#[test]
fn terrain_palette_runs_green_to_brown_to_grey_to_white() {
    let p: Palette = images::terrain_palette();
    let [r, g, b] = p[0];
    assert!(g > r && g > b, "lowlands green: {:?}", p[0]);
    let [r, g, b] = p[140];
    assert!(r > g && g > b, "brown: {:?}", p[140]);
    let [r, g, b] = p[200];
    assert!(
        r.abs_diff(g) < 10 && g.abs_diff(b) < 10,
        "grey: {:?}",
        p[200]
    );
    assert_eq!(p[255], [255, 255, 255]);
}

/// Rewrites `examples/data/*.gif` from the `.u8.png` files (index = gray
/// value, terrain palette). Run with
/// `cargo test --release --test harness_io -- --ignored regenerate_committed_gifs`.
#[test]
#[ignore = "writes into examples/data; run by hand to regenerate the GIFs"]
fn regenerate_committed_gifs() {
    for (stem, w, h) in DEMS {
        let png = load(
            Path::new(&format!("{DATA}/{stem}.u8.png")),
            ImageFormat::Png,
        );
        let mut out = Vec::new();
        images::write_indexed_gif(
            &mut out,
            w as u16,
            h as u16,
            u8s(&png),
            &images::terrain_palette(),
            false,
        )
        .unwrap();
        fs::write(format!("{DATA}/{stem}.gif"), out).unwrap();
    }
}

// ------------------------------------------- hostile images (issue 16)

/// The signature and IHDR of a `w`×`h` gray PNG of `bits` bits, Adam7
/// interlaced, followed by `idat` as its only IDAT chunk and no IEND: a
/// header that claims a huge image over a few bytes of data.
fn png_header_only(w: u32, h: u32, bits: u8, idat: &[u8]) -> Vec<u8> {
    let mut out = vec![137, 80, 78, 71, 13, 10, 26, 10];
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&w.to_be_bytes());
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[bits, 0, 0, 0, 1]);
    png_chunk(&mut out, b"IHDR", &ihdr);
    png_chunk(&mut out, b"IDAT", idat);
    out
}

/// Decodes `bytes` within `budget`, returning the error and the thread's
/// peak heap growth while decoding.
fn decode_peak(bytes: &[u8], format: ImageFormat, budget: u64) -> (String, isize) {
    let before = ALLOC.thread_snapshot();
    ALLOC.reset_thread_peak();
    let result = images::decode_height_field(
        Cursor::new(bytes),
        format,
        &mut images::DecodeBudget::new(budget),
    );
    let peak = ALLOC.thread_snapshot().peak_bytes - before.current_bytes;
    (result.expect_err("must fail"), peak)
}

#[test]
fn interlaced_16_bit_png_rows_are_exact() {
    let (w, h) = (13usize, 10usize);
    let v: Vec<u16> = (0..w * h).map(|i| (i * 4099 % 65_521) as u16).collect();
    let f = images::decode_height_field(
        Cursor::new(interlaced_png(w, h, 16, &v)),
        ImageFormat::Png,
        &mut Default::default(),
    )
    .unwrap();
    assert_eq!(f.convention(), HeightConvention::Gray16);
    assert_eq!(u16s(&f), &v[..]);
}

#[test]
fn interlaced_16_bit_png_of_16384_squared_is_refused_by_the_budget_before_allocating() {
    // 512 MiB of samples claimed by a few bytes: over the 256 MiB default.
    let bytes = png_header_only(16_384, 16_384, 16, &[0x78, 0x01]);
    let (e, peak) = decode_peak(&bytes, ImageFormat::Png, images::DEFAULT_DECODE_BUDGET);
    assert!(
        e.contains("16384x16384 interlaced PNG's 16-bit samples (and a bit each to put them in order) need 544.0 MiB"),
        "{e}"
    );
    assert!(e.contains("image memory budget has 256.0 MiB left"), "{e}");
    // The PNG decoder's own state (about 150 KB), no samples.
    assert!(peak < 1 << 20, "{peak} bytes allocated before refusing");
}

#[test]
fn truncated_interlaced_png_commits_little_before_failing() {
    // 69 bytes claiming 16384² 16-bit, within a budget large enough to
    // try: the frame used to be zero-filled (512 MiB) before any data.
    let mut bytes = png_header_only(16_384, 16_384, 16, &[0x78, 0x01, 0x01, 0x10, 0x00]);
    bytes.resize(69, 0);
    let (e, peak) = decode_peak(&bytes, ImageFormat::Png, 1 << 30);
    assert!(e.contains("PNG"), "{e}");
    assert!(peak < 1 << 20, "{peak} bytes committed for a 69-byte file");
}

#[test]
fn truncated_pot_commits_little_before_failing() {
    // A POT (GIF of twice the width) claiming 65534×16384, interlaced,
    // whose image data stops after a few bytes.
    let (fw, fh) = (65_534u16, 16_384u16);
    let mut gif = b"GIF89a".to_vec();
    gif.extend_from_slice(&fw.to_le_bytes());
    gif.extend_from_slice(&fh.to_le_bytes());
    gif.extend_from_slice(&[0x80, 0, 0]); // a 2-entry global palette
    gif.extend_from_slice(&[0, 0, 0, 255, 255, 255]);
    gif.push(0x2c);
    gif.extend_from_slice(&[0, 0, 0, 0]);
    gif.extend_from_slice(&fw.to_le_bytes());
    gif.extend_from_slice(&fh.to_le_bytes());
    gif.push(0x40); // interlaced
    gif.extend_from_slice(&[2, 3, 0x44, 0x01, 0x05]); // LZW, then nothing
    let (e, peak) = decode_peak(&gif, ImageFormat::Pot, 4 << 30);
    assert!(e.contains("POT"), "{e}");
    assert!(peak < 1 << 20, "{peak} bytes committed for a truncated POT");
}

#[test]
fn interlaced_gif_and_pot_decode_in_image_order_from_file_order() {
    // Rows decoded in pass order, then put in image order in place.
    let (w, h) = (6u16, 11u16);
    let idx: Vec<u8> = (0..w * h).map(|i| (i * 37 % 256) as u8).collect();
    let palette: Vec<u8> = (0..=255u8).flat_map(|i| [i, i, i]).collect();
    let bytes = gif_bytes(w, h, &idx, &palette, true);
    let f = images::decode_height_field(
        Cursor::new(&bytes),
        ImageFormat::Gif,
        &mut Default::default(),
    )
    .unwrap();
    assert_eq!(u8s(&f), &idx[..]);
    let pot = images::decode_height_field(
        Cursor::new(&bytes),
        ImageFormat::Pot,
        &mut Default::default(),
    )
    .unwrap();
    let hw = usize::from(w / 2);
    for row in 0..usize::from(h) {
        for col in 0..hw {
            let i = row * usize::from(w) + col;
            let want = u16::from(idx[i]) << 8 | u16::from(idx[i + hw]);
            assert_eq!(u16s(&pot)[row * hw + col], want, "row {row} col {col}");
        }
    }
}

#[test]
fn non_regular_files_are_refused_before_opening() {
    let dir = tmp_dir("not_regular");
    let fifo = dir.join("pipe.png");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    // Would block forever in open(2) if opened like a file.
    let e = load_height_field(&fifo, ImageFormat::Png).unwrap_err();
    assert!(
        e.message()
            .contains("is a FIFO (named pipe), not an image file"),
        "{e}"
    );
    let e = load_height_field(&dir, ImageFormat::Png).unwrap_err();
    assert!(e.message().contains("is a directory"), "{e}");
    let e = load_height_field(Path::new("/dev/zero"), ImageFormat::Png).unwrap_err();
    assert!(e.message().contains("is a device"), "{e}");
}

/// A scene of `objects` height fields, each naming one of `images`.
fn scene_of_fields(dir: &Path, images: &[&str], objects: usize) -> PathBuf {
    let mut text = String::from("camera { location <0.5, 2, -1.5> look_at <0.5, 0, 0.5> }\n");
    for i in 0..objects {
        text += &format!(
            "height_field {{ pgm \"{}\" translate <{i}, 0, 0> }}\n",
            images[i % images.len()]
        );
    }
    put(dir, "s.pov", text.as_bytes())
}

#[test]
fn sixty_four_fields_naming_one_image_share_one_decode() {
    use harness::scene_io::{load_fields_within, parse_file_scene_located};
    let dir = tmp_dir("shared_decode");
    put(&dir, "hill.pgm", &pnm("P5", 256, 256, 255, &[9; 256 * 256]));
    let path = scene_of_fields(&dir, &["hill.pgm"], 64);
    let text = fs::read_to_string(&path).unwrap();
    let (scene, source) =
        parse_file_scene_located(&path, &text, &ParseOptions::new(320, 200), &mut |_| {}).unwrap();
    let mut budget = images::DecodeBudget::default();
    let fields = load_fields_within(&scene, &source, &mut budget).unwrap();
    assert_eq!(fields.len(), 64);
    assert!(fields.iter().all(|f| std::sync::Arc::ptr_eq(f, &fields[0])));
    // One image's samples and skip pyramid, not 64.
    let one = 256 * 256 + fields[0].skip_bytes().unwrap().len() as u64;
    assert_eq!(budget.used(), one);
}

#[test]
fn memory_budget_is_shared_across_fields() {
    use harness::scene_io::{load_fields_within, parse_file_scene_located};
    let dir = tmp_dir("budget_total");
    // Two different 1024² images: 1 MiB of samples each, within 1.5 MiB
    // one at a time but not together.
    put(&dir, "a.pgm", &pnm("P5", 1024, 1024, 255, &[1; 1 << 20]));
    put(&dir, "b.pgm", &pnm("P5", 1024, 1024, 255, &[2; 1 << 20]));
    let path = scene_of_fields(&dir, &["a.pgm", "b.pgm"], 2);
    let text = fs::read_to_string(&path).unwrap();
    let (scene, source) =
        parse_file_scene_located(&path, &text, &ParseOptions::new(320, 200), &mut |_| {}).unwrap();
    let mut budget = images::DecodeBudget::new(3 << 19);
    let e = load_fields_within(&scene, &source, &mut budget).unwrap_err();
    assert!(
        e.contains("s.pov:3:1: "),
        "located at the second field: {e}"
    );
    assert!(e.contains("image memory budget"), "{e}");
}
