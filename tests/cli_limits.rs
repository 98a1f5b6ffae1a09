//! The `render` command's limits, just past each: exit 1, `error: ...`
//! saying which limit, and no file under the output name (docs/limits.md).
//! Option ranges already pinned by tests/cli_render.rs (`--width 0`,
//! `--aa 99`, `--rows 5..2`) are not repeated.

#[path = "cli_common/mod.rs"]
mod cli_common;

use std::path::Path;
use std::process::Output;

use cli_common::{entries, run, temp_dir};

/// Exit status 1, one `error: ` message containing `needle`, and nothing
/// written into `dir` beyond what was there (`before`).
#[track_caller]
fn fails_cleanly(o: &Output, needle: &str, dir: &Path, before: &[&str]) {
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.starts_with("error: ") && stderr.contains(needle),
        "expected `{needle}` in: {stderr}"
    );
    assert_eq!(entries(dir), before, "files left behind");
}

#[test]
fn option_values_past_their_limits_are_errors() {
    let dir = temp_dir("lim-opts");
    let out = dir.join("o.tga");
    let out = out.to_str().unwrap();
    for (extra, needle) in [
        (
            ["--width", "65537"],
            "invalid value '65537' for '--width <W>': 65537 is outside 1..=65536",
        ),
        (
            ["--height", "65537"],
            "invalid value '65537' for '--height <H>': 65537 is outside 1..=65536",
        ),
        (
            ["--aa", "17"],
            "invalid value '17' for '--aa <N>': 17 is not in 1..=16",
        ),
        (
            ["--threads", "257"],
            "invalid value '257' for '--threads <N>': 257 is not in 1..=256",
        ),
        (
            ["--frames", "100001"],
            "invalid value '100001' for '--frames <N>': 100001 is not in 1..=100000",
        ),
        (["--rows", "0..201"], "goes past the image height 200"),
    ] {
        let mut args = vec!["examples/scenes/default.pov", "-o", out];
        args.extend(extra);
        fails_cleanly(&run(&args), needle, &dir, &[]);
    }
    std::fs::remove_dir(&dir).unwrap();
}

/// 65536 columns is a valid render size but more than a TGA header can
/// hold: the writer refuses before any row is traced, and the temporary
/// file is removed.
#[test]
fn tga_wider_than_65535_is_an_error_and_leaves_nothing() {
    let dir = temp_dir("lim-tga");
    let out = dir.join("wide.tga");
    let o = run(&[
        "examples/scenes/default.pov",
        "-o",
        out.to_str().unwrap(),
        "--width",
        "65536",
        "--height",
        "1",
    ]);
    fails_cleanly(&o, "TGA is limited to 65535x65535 pixels", &dir, &[]);
    std::fs::remove_dir(&dir).unwrap();
}

/// Scene files are read up to 16 MiB: a larger file, or one that never
/// ends (`/dev/zero`), is refused without reading it all.
#[test]
fn scene_file_over_16_mib_is_an_error() {
    let dir = temp_dir("lim-scene");
    let big = dir.join("big.pov");
    // Sparse: 16 MiB + 1 of zeros costs no disk.
    std::fs::File::create(&big)
        .unwrap()
        .set_len((16 << 20) + 1)
        .unwrap();
    let out = dir.join("o.tga");
    let o = run(&[big.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    fails_cleanly(
        &o,
        "big.pov: scene file is larger than 16777216 bytes",
        &dir,
        &["big.pov"],
    );
    #[cfg(unix)]
    {
        let o = run(&["/dev/zero", "-o", out.to_str().unwrap()]);
        fails_cleanly(
            &o,
            "/dev/zero: scene file is larger than",
            &dir,
            &["big.pov"],
        );
    }
    // At the limit it is read (and then parsed: NUL is not a token).
    std::fs::File::create(&big)
        .unwrap()
        .set_len(16 << 20)
        .unwrap();
    let o = run(&[big.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!stderr.contains("larger than"), "{stderr}");
    assert_eq!(o.status.code(), Some(1));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn scene_that_is_not_utf8_or_is_a_folder_is_an_error() {
    let dir = temp_dir("lim-utf8");
    let bad = dir.join("latin1.pov");
    std::fs::write(&bad, b"// caf\xe9\nsphere { 0, 1 }\n").unwrap();
    let out = dir.join("o.tga");
    let o = run(&[bad.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    fails_cleanly(
        &o,
        "latin1.pov: scene file is not UTF-8 text (invalid byte at offset 6)",
        &dir,
        &["latin1.pov"],
    );
    let o = run(&[dir.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    fails_cleanly(&o, "is a directory", &dir, &["latin1.pov"]);
    std::fs::remove_dir_all(&dir).unwrap();
}
