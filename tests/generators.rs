//! The thesis's height-field generators (§4.2.2.2, §6.2): determinism
//! (seed → pinned checksum), value ranges, shapes and size errors.

use hfray::generate::*;

/// FNV-1a, 64-bit: a checksum that is the same everywhere.
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

fn grid(w: u32, d: u32) -> Vec<u8> {
    vec![0u8; (w * d) as usize]
}

fn min_max(g: &[u8]) -> (u8, u8) {
    (*g.iter().min().unwrap(), *g.iter().max().unwrap())
}

fn distinct(g: &[u8]) -> usize {
    let mut seen = [false; 256];
    for &v in g {
        seen[v as usize] = true;
    }
    seen.iter().filter(|&&s| s).count()
}

// ---------------------------------------------------------------- PRNG

#[test]
fn splitmix64_matches_reference_stream() {
    // Reference values of SplitMix64 seeded with 1234567 (the published
    // test vector of the algorithm's reference C implementation).
    let mut r = SplitMix64::new(1234567);
    let expected = [
        6457827717110365317u64,
        3203168211198807973,
        9817491932198370423,
        4593380528125082431,
        16408922859458223821,
    ];
    for e in expected {
        assert_eq!(r.next_u64(), e);
    }
}

#[test]
fn splitmix64_below_stays_below() {
    let mut r = SplitMix64::new(9);
    for n in [1u32, 2, 3, 7, 1000, u32::MAX] {
        for _ in 0..1000 {
            assert!(r.below(n) < n);
        }
    }
    assert_eq!(r.below(0), 0);
    for _ in 0..1000 {
        let u = r.next_unit();
        assert!((0.0..1.0).contains(&u));
        let s = r.next_signed_unit();
        assert!((-1.0..1.0).contains(&s));
    }
}

// ---------------------------------------------------------------- checksums

/// Seeds name fields: these checksums must never change. If one does,
/// every scene that names a seed renders differently — that is a breaking
/// change, not a test to update casually.
#[test]
fn generators_are_pinned_by_seed() {
    let (w, d) = (65u32, 49u32);
    let mut g = grid(w, d);

    plasma(
        &mut g,
        w,
        d,
        &Plasma {
            roughness: 0.55,
            seed: 1,
        },
    )
    .unwrap();
    let plasma_sum = fnv1a(&g);
    crater(&mut g, w, d, &Crater::default()).unwrap();
    let crater_sum = fnv1a(&g);
    drops(&mut g, w, d, &Drops::default()).unwrap();
    let drops_sum = fnv1a(&g);
    fire(
        &mut g,
        w,
        d,
        &Fire {
            iterations: 100,
            ..Fire::default()
        },
    )
    .unwrap();
    let fire_sum = fnv1a(&g);
    wood(&mut g, w, d, &Wood::default()).unwrap();
    let wood_sum = fnv1a(&g);

    let got = [plasma_sum, crater_sum, drops_sum, fire_sum, wood_sum];
    assert_eq!(got, PINNED);
}

/// plasma, crater, drops, fire, wood at 65×49 (see above).
const PINNED: [u64; 5] = [
    0xa833_f5b3_2b64_ca8b,
    0xbd17_40b1_d8cd_4b13,
    0xf78e_65ba_110d_f010,
    0xaece_03fc_c598_9498,
    0x4c22_21d6_4d67_a921,
];

#[test]
fn same_seed_same_bytes_other_seed_other_bytes() {
    let (w, d) = (40u32, 33u32);
    let (mut a, mut b) = (grid(w, d), grid(w, d));
    let p = Plasma {
        roughness: 0.6,
        seed: 42,
    };
    plasma(&mut a, w, d, &p).unwrap();
    plasma(&mut b, w, d, &p).unwrap();
    assert_eq!(a, b);
    plasma(&mut b, w, d, &Plasma { seed: 43, ..p }).unwrap();
    assert_ne!(a, b);

    let f = Fire {
        iterations: 50,
        seed: 5,
        ..Fire::default()
    };
    fire(&mut a, w, d, &f).unwrap();
    fire(&mut b, w, d, &f).unwrap();
    assert_eq!(a, b);
    fire(&mut b, w, d, &Fire { seed: 6, ..f }).unwrap();
    assert_ne!(a, b);

    let dr = Drops {
        seed: 3,
        ..Drops::default()
    };
    drops(&mut a, w, d, &dr).unwrap();
    drops(&mut b, w, d, &dr).unwrap();
    assert_eq!(a, b);
    drops(&mut b, w, d, &Drops { seed: 4, ..dr }).unwrap();
    assert_ne!(a, b);
}

// ---------------------------------------------------------------- plasma

#[test]
fn plasma_uses_full_range_on_any_size() {
    for (w, d) in [
        (2u32, 2u32),
        (3, 2),
        (2, 3),
        (5, 7),
        (17, 17),
        (100, 37),
        (320, 200),
        (257, 257),
    ] {
        for seed in [0u64, 1, 2, u64::MAX] {
            let mut g = grid(w, d);
            plasma(
                &mut g,
                w,
                d,
                &Plasma {
                    roughness: 0.6,
                    seed,
                },
            )
            .unwrap();
            assert_eq!(min_max(&g), (0, 255), "{w}x{d} seed {seed}");
        }
    }
}

#[test]
fn plasma_uses_nearly_every_level() {
    // The thesis's plasma "uses almost all the palette's colours" (§6.2.1.2).
    for r in [0.45, 0.55, 0.7] {
        let (w, d) = (257u32, 257u32);
        let mut g = grid(w, d);
        plasma(
            &mut g,
            w,
            d,
            &Plasma {
                roughness: r,
                seed: 11,
            },
        )
        .unwrap();
        let n = distinct(&g);
        assert!(n >= 240, "roughness {r}: only {n} distinct levels");
    }
}

#[test]
fn plasma_writes_every_sample_whatever_the_buffer_held() {
    // In-place subdivision on a general size must reach every sample:
    // the output may not depend on what the buffer held before.
    for (w, d) in [(2u32, 2u32), (3, 5), (6, 4), (33, 10), (100, 37), (129, 65)] {
        let mut zeros = grid(w, d);
        let mut ones = vec![255u8; (w * d) as usize];
        let mut noise: Vec<u8> = (0..w * d).map(|i| (i * 37 % 251) as u8).collect();
        let p = Plasma {
            roughness: 0.5,
            seed: 8,
        };
        plasma(&mut zeros, w, d, &p).unwrap();
        plasma(&mut ones, w, d, &p).unwrap();
        plasma(&mut noise, w, d, &p).unwrap();
        assert_eq!(zeros, ones, "{w}x{d}");
        assert_eq!(zeros, noise, "{w}x{d}");
    }
}

#[test]
fn plasma_is_continuous_and_rougher_with_roughness() {
    let (w, d) = (129u32, 129u32);
    let mean_step = |r: f64| {
        let mut g = grid(w, d);
        plasma(
            &mut g,
            w,
            d,
            &Plasma {
                roughness: r,
                seed: 3,
            },
        )
        .unwrap();
        let mut sum = 0u64;
        let mut n = 0u64;
        for z in 0..d as usize {
            for x in 1..w as usize {
                let i = z * w as usize + x;
                sum += u64::from(g[i].abs_diff(g[i - 1]));
                n += 1;
            }
        }
        sum as f64 / n as f64
    };
    let smooth = mean_step(0.4);
    let rough = mean_step(0.75);
    // A continuous surface: neighbouring samples differ by a few levels.
    assert!(smooth < 4.0, "roughness 0.4: mean step {smooth}");
    assert!(rough > 2.0 * smooth, "0.75: {rough} vs 0.4: {smooth}");
}

#[test]
fn plasma_features_are_round_on_a_wide_grid() {
    // Splits keep cells nearly square, so a 513×65 strip is as rough
    // along z as along x (a naive both-axes split would make features 8×
    // wider than deep).
    let (w, d) = (513u32, 65u32);
    let mut g = grid(w, d);
    plasma(
        &mut g,
        w,
        d,
        &Plasma {
            roughness: 0.6,
            seed: 21,
        },
    )
    .unwrap();
    let (wu, du) = (w as usize, d as usize);
    let (mut sx, mut sz, mut n) = (0u64, 0u64, 0u64);
    for z in 0..du - 1 {
        for x in 0..wu - 1 {
            let i = z * wu + x;
            sx += u64::from(g[i].abs_diff(g[i + 1]));
            sz += u64::from(g[i].abs_diff(g[i + wu]));
            n += 1;
        }
    }
    let (mx, mz) = (sx as f64 / n as f64, sz as f64 / n as f64);
    assert!(mz < 1.5 * mx && mx < 1.5 * mz, "x step {mx}, z step {mz}");
}

#[test]
fn plasma_roughness_zero_is_a_smooth_blend() {
    let (w, d) = (33u32, 33u32);
    let mut g = grid(w, d);
    plasma(
        &mut g,
        w,
        d,
        &Plasma {
            roughness: 0.0,
            seed: 5,
        },
    )
    .unwrap();
    assert_eq!(min_max(&g), (0, 255));
    for z in 0..d as usize {
        for x in 1..w as usize {
            let i = z * w as usize + x;
            assert!(g[i].abs_diff(g[i - 1]) <= 12, "step at {x},{z}");
        }
    }
}

#[test]
fn plasma_rejects_bad_roughness() {
    let mut g = grid(4, 4);
    for r in [-0.1, 1.01, f64::NAN, f64::INFINITY] {
        let e = plasma(
            &mut g,
            4,
            4,
            &Plasma {
                roughness: r,
                seed: 0,
            },
        )
        .unwrap_err();
        assert!(
            matches!(
                e,
                GenerateError::Parameter {
                    name: "roughness",
                    ..
                }
            ),
            "{e}"
        );
    }
    assert!(g.iter().all(|&v| v == 0), "nothing written on error");
}

// ---------------------------------------------------------------- crater

#[test]
fn crater_rises_from_floor_to_rim_then_falls_to_plain() {
    let (w, d) = (201u32, 201u32);
    let mut g = grid(w, d);
    let c = Crater::default();
    crater(&mut g, w, d, &c).unwrap();
    let at = |x: usize, z: usize| g[z * w as usize + x];
    assert_eq!(at(100, 100), c.floor, "centre is the floor");
    assert_eq!(at(0, 0), c.plain, "corner is the plain");
    // Along a radius from the centre to the crest (0.3 · 200 = 60
    // samples), the index never falls and reaches the rim.
    let mut prev = 0u8;
    for x in 100..=160 {
        let v = at(x, 100);
        assert!(v >= prev, "falls at column {x}: {prev} -> {v}");
        prev = v;
    }
    assert_eq!(at(160, 100), c.rim, "crest");
    // Outside the crest the wall falls to the plain.
    let mut prev = 255u8;
    for x in 161..=200 {
        let v = at(x, 100);
        assert!(v <= prev, "rises outside the crest at column {x}");
        prev = v;
    }
    assert_eq!(at(200, 100), c.plain);
    // Terraces: the bowl holds exactly `rings` distinct levels.
    let mut bowl = Vec::new();
    for x in 100..=160 {
        bowl.push(at(x, 100));
    }
    assert_eq!(distinct(&bowl), c.rings as usize);
    // Round: the same at the same distance in the four directions.
    assert_eq!(at(130, 100), at(70, 100));
    assert_eq!(at(130, 100), at(100, 130));
    assert_eq!(at(130, 100), at(100, 70));
}

#[test]
fn crater_smooth_bowl_without_rings() {
    let (w, d) = (101u32, 101u32);
    let mut g = grid(w, d);
    let c = Crater {
        rings: 0,
        ..Crater::default()
    };
    crater(&mut g, w, d, &c).unwrap();
    let bowl: Vec<u8> = (50..=80).map(|x| g[50 * 101 + x]).collect();
    assert!(bowl.windows(2).all(|p| p[0] <= p[1]));
    assert!(distinct(&bowl) > 20);
}

// ---------------------------------------------------------------- drops

#[test]
fn drops_still_water_without_amplitude_and_rings_with_it() {
    let (w, d) = (64u32, 64u32);
    let mut g = grid(w, d);
    drops(
        &mut g,
        w,
        d,
        &Drops {
            amplitude: 0.0,
            ..Drops::default()
        },
    )
    .unwrap();
    assert!(g.iter().all(|&v| v == 128));
    drops(&mut g, w, d, &Drops::default()).unwrap();
    let (lo, hi) = min_max(&g);
    assert!(lo < 110 && hi > 146, "ripples: {lo}..{hi}");
}

#[test]
fn drops_frames_form_an_animation() {
    // Frames of one seed change with time, smoothly: two close frames
    // differ less than two distant ones.
    let (w, d) = (96u32, 96u32);
    let frame = |t: f64| {
        let mut g = grid(w, d);
        drops(
            &mut g,
            w,
            d,
            &Drops {
                time: t,
                ..Drops::default()
            },
        )
        .unwrap();
        g
    };
    let diff = |a: &[u8], b: &[u8]| -> u64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| u64::from(x.abs_diff(*y)))
            .sum()
    };
    let (f0, f1, f5) = (frame(0.400), frame(0.401), frame(0.600));
    assert_ne!(f0, f1);
    let (near, far) = (diff(&f0, &f1), diff(&f0, &f5));
    assert!(near * 3 < far, "0.400->0.401: {near}, 0.400->0.600: {far}");
}

#[test]
fn drops_rejects_bad_parameters() {
    let mut g = grid(8, 8);
    let base = Drops::default();
    for (p, name) in [
        (Drops { time: 1.5, ..base }, "time"),
        (Drops { count: 0, ..base }, "count"),
        (Drops { count: 33, ..base }, "count"),
        (
            Drops {
                wavelength: 0.0,
                ..base
            },
            "wavelength",
        ),
        (
            Drops {
                amplitude: f64::NAN,
                ..base
            },
            "amplitude",
        ),
    ] {
        match drops(&mut g, 8, 8, &p) {
            Err(GenerateError::Parameter { name: n, .. }) => assert_eq!(n, name),
            other => panic!("{name}: {other:?}"),
        }
    }
}

// ---------------------------------------------------------------- fire

fn luminance(c: [u8; 3]) -> u32 {
    2126 * u32::from(c[0]) + 7152 * u32::from(c[1]) + 722 * u32::from(c[2])
}

#[test]
fn fire_palette_black_blue_red_yellow_white() {
    assert_eq!(FIRE_PALETTE[0], [0, 0, 0]);
    assert_eq!(FIRE_PALETTE[255], [255, 255, 255]);
    // The thesis's order: blue, then red, then yellow between the ends.
    let blue = FIRE_PALETTE[48];
    let red = FIRE_PALETTE[112];
    let yellow = FIRE_PALETTE[192];
    assert!(blue[2] > 150 && blue[0] == 0 && blue[1] == 0, "{blue:?}");
    assert_eq!(red, [255, 0, 0]);
    assert_eq!(yellow, [255, 255, 0]);
    for i in 1..256 {
        assert!(
            luminance(FIRE_PALETTE[i]) >= luminance(FIRE_PALETTE[i - 1]),
            "brightness falls at {i}"
        );
    }
}

#[test]
fn fire_burns_at_the_bottom_and_cools_upwards() {
    let (w, d) = (80u32, 60u32);
    let mut g = grid(w, d);
    fire(
        &mut g,
        w,
        d,
        &Fire {
            iterations: 200,
            flame_height: 0.5,
            ..Fire::default()
        },
    )
    .unwrap();
    let row_mean = |r: usize| -> f64 {
        g[r * w as usize..(r + 1) * w as usize]
            .iter()
            .map(|&v| f64::from(v))
            .sum::<f64>()
            / f64::from(w)
    };
    // Mean heat falls going up, in bands of 10 rows.
    let bands: Vec<f64> = (0..6)
        .map(|b| (b * 10..b * 10 + 10).map(row_mean).sum::<f64>() / 10.0)
        .collect();
    for b in 1..6 {
        assert!(bands[b] >= bands[b - 1], "bands {bands:?}");
    }
    assert!(bands[5] > 80.0, "hot at the bottom: {bands:?}");
    // Flames reach about half way: the top rows are cold.
    assert!(bands[0] < 2.0, "cold at the top: {bands:?}");
}

#[test]
fn fire_iterations_are_consecutive_frames() {
    let (w, d) = (48u32, 40u32);
    let run = |n: u32| {
        let mut g = grid(w, d);
        fire(
            &mut g,
            w,
            d,
            &Fire {
                iterations: n,
                ..Fire::default()
            },
        )
        .unwrap();
        g
    };
    assert!(run(0).iter().all(|&v| v == 0), "no iterations: cold");
    // Heat rises at most two rows per iteration (a sample reads the row
    // two below): after 5 iterations only the bottom 11 rows can be warm.
    let early = run(5);
    let cold = (d as usize - 11) * w as usize;
    assert!(early[..cold].iter().all(|&v| v == 0));
    assert!(early[cold..(d as usize - 3) * w as usize]
        .iter()
        .any(|&v| v > 0));
    // Frame n+1 is frame n advanced by the rule: every sample not reading
    // the re-lit bottom row (rows 0..depth−3) is the mean of frame n's samples (x−1, y+1),
    // (x, y+1), (x+1, y+1), (x, y+2), less a cooling of at most
    // 2 · 255 / (flame_height · depth) levels.
    let (a, b) = (run(120), run(121));
    let (wu, du) = (w as usize, d as usize);
    let max_cool = 2.0 * 255.0 / (Fire::default().flame_height * d as f64) + 1.0;
    for y in 0..du - 3 {
        for x in 0..wu {
            let at = |yy: usize, xx: usize| f64::from(a[yy * wu + xx]);
            let mean = (at(y + 1, x.saturating_sub(1))
                + at(y + 1, x)
                + at(y + 1, (x + 1).min(wu - 1))
                + at((y + 2).min(du - 1), x))
                / 4.0;
            let v = f64::from(b[y * wu + x]);
            assert!(
                v <= mean + 0.5 && v >= mean - max_cool,
                "({x},{y}): {v} from mean {mean}"
            );
        }
    }
}

// ---------------------------------------------------------------- wood

#[test]
fn wood_is_zero_outside_the_circle_and_positive_inside() {
    let (w, d) = (101u32, 81u32);
    let mut g = grid(w, d);
    let p = Wood {
        low: 10,
        radius: 0.4,
        ..Wood::default()
    };
    wood(&mut g, w, d, &p).unwrap();
    for z in 0..d as usize {
        for x in 0..w as usize {
            let (u, v) = (x as f64 / 100.0 - 0.5, z as f64 / 80.0 - 0.5);
            let r = (u * u + v * v).sqrt();
            let s = g[z * w as usize + x];
            if r > 0.4 + 1e-9 {
                assert_eq!(s, 0, "outside at {x},{z}");
            } else if r < 0.4 - 1e-9 {
                assert!(s >= 10, "inside at {x},{z}: {s}");
            }
        }
    }
    // The fractal inside is rough: many levels.
    assert!(distinct(&g) > 100);
    assert!(matches!(
        wood(&mut g, w, d, &Wood { low: 0, ..p }),
        Err(GenerateError::Parameter { name: "low", .. })
    ));
}

#[test]
fn wood_grain_runs_fibres_along_z() {
    let (w, d) = (129u32, 129u32);
    let (wu, du) = (w as usize, d as usize);
    let steps = |g: &[u8]| {
        // Mean |step| along x and along z, inside the disc only.
        let (mut sx, mut sz, mut n) = (0u64, 0u64, 0u64);
        for z in 40..du - 40 {
            for x in 40..wu - 40 {
                let i = z * wu + x;
                sx += u64::from(g[i].abs_diff(g[i + 1]));
                sz += u64::from(g[i].abs_diff(g[i + wu]));
                n += 1;
            }
        }
        (sx as f64 / n as f64, sz as f64 / n as f64)
    };
    let mut iso = grid(w, d);
    wood(&mut iso, w, d, &Wood::default()).unwrap();
    let (ix, iz) = steps(&iso);
    assert!(ix < 2.0 * iz && iz < 2.0 * ix, "isotropic: {ix} vs {iz}");
    let mut fib = grid(w, d);
    wood(
        &mut fib,
        w,
        d,
        &Wood {
            grain: 6,
            ..Wood::default()
        },
    )
    .unwrap();
    let (fx, fz) = steps(&fib);
    assert!(fz * 3.0 < fx, "fibres along z: x step {fx}, z step {fz}");
    // Still a disc on 0, and the same disc.
    for i in 0..wu * du {
        assert_eq!(fib[i] == 0, iso[i] == 0, "sample {i}");
    }
    assert!(matches!(
        wood(
            &mut fib,
            w,
            d,
            &Wood {
                grain: 0,
                ..Wood::default()
            }
        ),
        Err(GenerateError::Parameter { name: "grain", .. })
    ));
}

// ---------------------------------------------------------------- sizes

type Gen = fn(&mut [u8], u32, u32) -> Result<(), GenerateError>;

fn all_generators() -> [(&'static str, Gen); 5] {
    [
        ("plasma", |g, w, d| plasma(g, w, d, &Plasma::default())),
        ("crater", |g, w, d| crater(g, w, d, &Crater::default())),
        ("drops", |g, w, d| drops(g, w, d, &Drops::default())),
        ("fire", |g, w, d| {
            fire(
                g,
                w,
                d,
                &Fire {
                    iterations: 3,
                    ..Fire::default()
                },
            )
        }),
        ("wood", |g, w, d| wood(g, w, d, &Wood::default())),
    ]
}

#[test]
fn every_generator_rejects_wrong_sizes_without_writing() {
    for (name, gen) in all_generators() {
        let mut g = vec![7u8; 12];
        assert_eq!(
            gen(&mut g, 4, 4),
            Err(GenerateError::SizeMismatch {
                expected: 16,
                actual: 12
            }),
            "{name}"
        );
        assert_eq!(
            gen(&mut g, 12, 1),
            Err(GenerateError::TooSmall {
                width: 12,
                depth: 1,
                min_side: 2
            }),
            "{name}"
        );
        assert!(matches!(
            gen(&mut g, 1, 12),
            Err(GenerateError::TooSmall { .. })
        ));
        assert!(matches!(
            gen(&mut g, 0, 0),
            Err(GenerateError::TooSmall { .. })
        ));
        assert!(matches!(
            gen(&mut g, MAX_SIDE + 1, 2),
            Err(GenerateError::TooLarge { .. })
        ));
        assert!(matches!(
            gen(&mut g, u32::MAX, u32::MAX),
            Err(GenerateError::TooLarge { .. })
        ));
        assert!(g.iter().all(|&v| v == 7), "{name} wrote on error");
        let mut ok = vec![7u8; 6];
        gen(&mut ok, 3, 2).unwrap_or_else(|e| panic!("{name} 3x2: {e}"));
        let mut ok = vec![7u8; 6];
        gen(&mut ok, 2, 3).unwrap_or_else(|e| panic!("{name} 2x3: {e}"));
    }
}

#[test]
fn errors_say_what_is_wrong() {
    let mut g = vec![0u8; 3];
    let e = plasma(&mut g, 2, 2, &Plasma::default()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "grid needs 4 samples but the output slice holds 3"
    );
    let e = fire(
        &mut [0u8; 4],
        2,
        2,
        &Fire {
            fuel: 2.0,
            ..Fire::default()
        },
    )
    .unwrap_err();
    assert_eq!(e.to_string(), "parameter `fuel` must be within [0, 1]");
}
