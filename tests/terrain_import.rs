//! Real terrain import (§6.2.1.1): ESRI ASCII grids and plain arrays,
//! the careful quantiser (full range, round to nearest, step and level
//! report), no-data filling, vertical exaggeration, errors with lines.

#[path = "../examples/harness/terrain.rs"]
mod terrain;

use hfray::HeightConvention;
use terrain::*;

/// A 6×4 grid, 30 m cells, two no-data cells, elevations 1000..1150 m.
const SMALL_ASC: &str = "\
ncols         6
nrows         4
xllcorner     500000.0
yllcorner     4100000.0
cellsize      30
NODATA_value  -9999
1000 1010 1020 1030 1040 1050
1060 -9999 1080 1090 1100 1110
1120 1130 1140 -9999 1150 1149.5
1001 1002 1003 1004 1005 1006
";

fn q(grid: &Grid, bits: Bits, fill: NoDataFill) -> Quantised {
    quantise(
        grid,
        &QuantiseOptions {
            bits,
            fill,
            ..QuantiseOptions::default()
        },
    )
    .unwrap()
}

#[test]
fn asc_header_and_values_are_read() {
    let g = parse_asc(SMALL_ASC).unwrap();
    assert_eq!((g.ncols, g.nrows), (6, 4));
    assert_eq!(g.cellsize, Some([30.0, 30.0]));
    assert_eq!(g.origin, Some(Origin::Corner(500000.0, 4100000.0)));
    assert_eq!(g.nodata_value, Some(-9999.0));
    assert_eq!(g.nodata_count(), 2);
    assert_eq!(g.values[0], 1000.0);
    assert!(g.values[7].is_nan());
    assert_eq!(g.values[17], 1149.5);
    assert!(!g.looks_geographic());
}

#[test]
fn asc_round_trip_8_bit_with_nodata_and_step() {
    let g = parse_asc(SMALL_ASC).unwrap();
    let r = q(&g, Bits::U8, NoDataFill::Min);
    assert_eq!((r.width, r.depth), (6, 4));
    assert_eq!((r.min_m, r.max_m), (1000.0, 1150.0));
    // 150 m over 255 steps.
    assert!((r.step_m - 150.0 / 255.0).abs() < 1e-12, "{}", r.step_m);
    assert_eq!(r.nodata_filled, 2);
    // Full range: the minimum is level 0, the maximum level 255.
    assert_eq!(r.levels.get(0), 0);
    assert_eq!(r.levels.get(16), 255);
    // No-data filled with the minimum.
    assert_eq!(r.levels.get(7), 0);
    assert_eq!(r.levels.get(15), 0);
    // Every valid sample comes back within half a step; rounding to
    // nearest, not truncation: 1010 m is 17.0 steps, 1149.5 m is 254.15.
    for (i, &v) in g.values.iter().enumerate() {
        if !v.is_nan() {
            let back = r.elevation_m(r.levels.get(i));
            assert!(
                (back - v).abs() <= r.step_m / 2.0 + 1e-9,
                "{i}: {v} -> {back}"
            );
        }
    }
    assert_eq!(r.levels.get(1), 17);
    assert_eq!(r.levels.get(17), 254);
    assert!(r.max_error_m <= r.step_m / 2.0 + 1e-9);
    // 22 valid distinct elevations, 1000 m twice (once as fill): the
    // levels used are those of the valid data (1001..1006 m are 2..10).
    let mut distinct: Vec<u32> = (0..24).map(|i| r.levels.get(i)).collect();
    distinct.sort();
    distinct.dedup();
    assert_eq!(r.distinct_levels, distinct.len());
    assert_eq!(r.distinct_levels, 22);
    let report = r.report();
    assert!(report.contains("step 0.588235 m/level"), "{report}");
    assert!(report.contains("22 of 256 levels used"), "{report}");
    assert!(
        report.contains("2 no-data cells filled (with the minimum)"),
        "{report}"
    );
}

#[test]
fn nodata_filled_from_nearest_valid_cell() {
    let g = parse_asc(SMALL_ASC).unwrap();
    let r = q(&g, Bits::U16, NoDataFill::Nearest);
    assert_eq!(r.nodata_filled, 2);
    // Cell 7 (row 1, col 1): nearest in BFS order is its north
    // neighbour (1010 m); cell 15 (row 2, col 3): north, 1090 m.
    let at = |m: f64| ((m - 1000.0) / 150.0 * 65535.0).round() as u32;
    assert_eq!(r.levels.get(7), at(1010.0));
    assert_eq!(r.levels.get(15), at(1090.0));
}

#[test]
fn sixteen_bits_keep_every_centimetre() {
    // 200 × 3 samples, elevations in whole centimetres over 500 m: the
    // 8-bit grid uses all 256 levels, the 16-bit one (step 7.6 mm) keeps
    // every distinct input value distinct.
    let (w, d) = (200usize, 3usize);
    let values: Vec<f64> = (0..w * d)
        .map(|i| 2000.0 + ((i * 7919) % 50_001) as f64 / 100.0)
        .collect();
    let mut distinct_in = values.clone();
    distinct_in.sort_by(f64::total_cmp);
    distinct_in.dedup();
    let grid = Grid {
        ncols: w,
        nrows: d,
        values,
        cellsize: Some([10.0, 10.0]),
        origin: None,
        nodata_value: None,
    };
    let r8 = q(&grid, Bits::U8, NoDataFill::Min);
    let r16 = q(&grid, Bits::U16, NoDataFill::Min);
    assert_eq!(r8.distinct_levels, 256);
    assert_eq!(r16.distinct_levels, distinct_in.len());
    assert!(r16.step_m < 0.01);
    assert!((r8.step_m / r16.step_m - 65535.0 / 255.0).abs() < 1e-9);
    assert!(r16.max_error_m <= r16.step_m / 2.0 + 1e-9);
}

#[test]
fn flat_terrain_is_level_zero_with_zero_step() {
    let g = parse_array("5 5 5\n5 5 5\n", None).unwrap();
    let r = q(&g, Bits::U8, NoDataFill::Min);
    assert_eq!(r.step_m, 0.0);
    assert_eq!(r.distinct_levels, 1);
    assert!((0..6).all(|i| r.levels.get(i) == 0));
}

#[test]
fn exaggeration_scales_y_and_changes_no_sample() {
    let g = parse_asc(SMALL_ASC).unwrap();
    let opts = QuantiseOptions {
        bits: Bits::U16,
        ..QuantiseOptions::default()
    };
    let r1 = quantise(&g, &opts).unwrap();
    let r3 = quantise(
        &g,
        &QuantiseOptions {
            exaggeration: 3.0,
            ..opts
        },
    )
    .unwrap();
    assert_eq!(r1.levels, r3.levels);
    // 6 columns of 30 m: x spans 150 m; relief 150 m; z spans 90 m.
    let s1 = r1.suggested_scale(HeightConvention::Gray16).unwrap();
    let s3 = r3.suggested_scale(HeightConvention::Gray16).unwrap();
    let top = 65535.0 / 65536.0;
    assert_eq!(s1[0], 1.0);
    assert!((s1[1] * top - 1.0).abs() < 1e-12, "{s1:?}");
    assert!((s1[2] - 0.6).abs() < 1e-12, "{s1:?}");
    assert!((s3[1] - 3.0 * s1[1]).abs() < 1e-12);
    // A plain array has no cell size: no true proportions.
    let a = parse_array("1 2\n3 4\n", None).unwrap();
    assert_eq!(
        q(&a, Bits::U8, NoDataFill::Min).suggested_scale(HeightConvention::Gray8),
        None
    );
    // Geographic spacing converted by metres_per_unit.
    let r = quantise(
        &g,
        &QuantiseOptions {
            metres_per_unit: 2.0,
            ..opts
        },
    )
    .unwrap();
    assert_eq!(r.spacing_m, Some([60.0, 60.0]));
}

#[test]
fn asc_variants_center_origin_dx_dy_wrapped_rows_any_case() {
    let text = "NCOLS 3\nNROWS 2\nXLLCENTER -105.5\nYLLCENTER 40.1\nDX 0.001\nDY 0.002\n\
                1 2\n3 4 5\n6\n";
    let g = parse_asc(text).unwrap();
    assert_eq!(g.values, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    assert_eq!(g.cellsize, Some([0.001, 0.002]));
    assert_eq!(g.origin, Some(Origin::Center(-105.5, 40.1)));
    assert_eq!(g.nodata_value, None);
    assert!(g.looks_geographic());
}

#[test]
fn plain_arrays_with_commas_comments_and_nodata() {
    let g = parse_array("# heights\n1, 2, 3\n\n4,-1,6\n", Some(-1.0)).unwrap();
    assert_eq!((g.ncols, g.nrows), (3, 2));
    assert_eq!(g.nodata_count(), 1);
    let r = q(&g, Bits::U8, NoDataFill::Nearest);
    assert_eq!(r.levels.get(4), r.levels.get(1), "filled from the north");
}

fn err(r: Result<Grid, TerrainError>) -> TerrainError {
    r.expect_err("should fail")
}

#[test]
fn errors_name_the_line_and_the_problem() {
    // Unknown keyword.
    let e = err(parse_asc("ncols 2\nnrows 2\ncolour 5\n"));
    assert_eq!(e.line, Some(3));
    assert_eq!(
        e.to_string(),
        "line 3: bad header: unknown keyword `colour`"
    );
    // Missing keyword: reported at the end of the header.
    let e = err(parse_asc(
        "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\n1 2\n3 4\n",
    ));
    assert_eq!(e.to_string(), "line 4: bad header: missing `cellsize`");
    // Bad header value.
    let e = err(parse_asc("ncols two\n"));
    assert_eq!(e.line, Some(1));
    assert!(matches!(e.kind, TerrainErrorKind::BadHeader(_)));
    // Duplicate keyword.
    let e = err(parse_asc("ncols 2\nNCOLS 2\n"));
    assert_eq!(e.to_string(), "line 2: bad header: `NCOLS` given twice");
    // Non-integer count.
    let e = err(parse_asc(
        "ncols 2.5\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2\n",
    ));
    assert!(e.to_string().contains("is not a count"), "{e}");
    // Mixed corner/center.
    let e = err(parse_asc(
        "ncols 2\nnrows 2\nxllcorner 0\nyllcenter 0\ncellsize 1\n1 2\n3 4\n",
    ));
    assert!(e.to_string().contains("mixes a corner and a center"), "{e}");

    let head = "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 10\nNODATA_value -9999\n";
    // Non-numeric token, with its line.
    let e = err(parse_asc(&format!("{head}1 2 3\n4 x5 6\n")));
    assert_eq!(e.line, Some(8));
    assert_eq!(e.to_string(), "line 8: `x5` is not a finite number");
    let e = err(parse_asc(&format!("{head}1 2 3\n4 NaN 6\n")));
    assert_eq!(e.kind, TerrainErrorKind::NotNumeric("NaN".into()));
    // Too few values: the line of the last value.
    let e = err(parse_asc(&format!("{head}1 2 3\n4 5\n\n")));
    assert_eq!(e.line, Some(8));
    assert_eq!(
        e.kind,
        TerrainErrorKind::WrongCount {
            expected: 6,
            found: 5
        }
    );
    assert_eq!(
        e.to_string(),
        "line 8: expected 6 values (ncols × nrows), found only 5"
    );
    // Too many: the line of the first extra value.
    let e = err(parse_asc(&format!("{head}1 2 3\n4 5 6\n\n7\n")));
    assert_eq!(e.line, Some(10));
    assert!(e.to_string().contains("this one is extra"), "{e}");
    // Too small.
    let e = err(parse_asc(
        "ncols 1\nnrows 5\nxllcorner 0\nyllcorner 0\ncellsize 1\n1\n2\n3\n4\n5\n",
    ));
    assert!(matches!(
        e.kind,
        TerrainErrorKind::TooSmall { ncols: 1, nrows: 5 }
    ));
    // All no-data: a quantiser error.
    let g = parse_asc(&format!("{head}-9999 -9999 -9999\n-9999 -9999 -9999\n")).unwrap();
    let e = quantise(&g, &QuantiseOptions::default()).unwrap_err();
    assert_eq!(e.kind, TerrainErrorKind::AllNoData);
    assert_eq!(e.to_string(), "every cell is no-data");
    // Ragged plain array.
    let e = err(parse_array("1 2 3\n4 5 6\n7 8\n", None));
    assert_eq!(
        e.to_string(),
        "line 3: row has 2 values but the first row has 3"
    );
    // Bad options.
    let g = parse_array("1 2\n3 4\n", None).unwrap();
    let e = quantise(
        &g,
        &QuantiseOptions {
            exaggeration: 0.0,
            ..QuantiseOptions::default()
        },
    )
    .unwrap_err();
    assert!(matches!(e.kind, TerrainErrorKind::BadOption(_)));
}

#[test]
fn pgm_files_read_back_exactly_and_read_grid_detects_the_format() {
    let dir = std::env::temp_dir().join(format!("hfray-terrain-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let asc = dir.join("small.asc");
    std::fs::write(&asc, SMALL_ASC).unwrap();
    let g = read_grid(&asc).unwrap();
    assert_eq!(g.cellsize, Some([30.0, 30.0]));
    let arr = dir.join("small.txt");
    std::fs::write(&arr, "1 2 3\n4 5 6\n").unwrap();
    assert_eq!(read_grid(&arr).unwrap().ncols, 3);
    let e = read_grid(&dir.join("missing.asc")).unwrap_err();
    assert!(matches!(e.kind, TerrainErrorKind::Io(_)));

    for bits in [Bits::U8, Bits::U16] {
        let r = q(&g, bits, NoDataFill::Nearest);
        let path = dir.join(format!("small-{bits:?}.pgm"));
        r.write_pgm(&path).unwrap();
        let img = image::open(&path).unwrap();
        assert_eq!((img.width(), img.height()), (6, 4));
        let back: Vec<u32> = match bits {
            Bits::U8 => img
                .to_luma8()
                .into_raw()
                .into_iter()
                .map(u32::from)
                .collect(),
            Bits::U16 => img
                .to_luma16()
                .into_raw()
                .into_iter()
                .map(u32::from)
                .collect(),
        };
        let want: Vec<u32> = (0..24).map(|i| r.levels.get(i)).collect();
        assert_eq!(back, want, "{bits:?}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn quantised_grid_builds_a_height_field() {
    let g = parse_asc(SMALL_ASC).unwrap();
    let r = q(&g, Bits::U16, NoDataFill::Min);
    let f = hfray::HeightField::new(r.levels.samples(), 6, 4, HeightConvention::Gray16);
    assert!(f.is_ok());
}
