//! The `render` command's `--walk` and `--coherence` options: every
//! combination writes the same image (decoded: TGA and PFM rows go out
//! bottom-up with coherence on), and `--stats` shows the work differ.

mod cli_common;

#[path = "../examples/harness/mod.rs"]
mod harness;

use std::process::Command;

use cli_common::render_bin;
use harness::pfm::read_pfm;
use harness::tga::read_tga_rgb;

/// `key=value` from the `--stats` line.
fn stat(stderr: &str, key: &str) -> u64 {
    let line = stderr
        .lines()
        .find(|l| l.starts_with("stats: "))
        .expect("a stats line");
    line.split_whitespace()
        .find_map(|kv| kv.strip_prefix(&format!("{key}=")))
        .unwrap_or_else(|| panic!("no {key} in {line}"))
        .parse()
        .unwrap()
}

/// Renders the level-view scene to `name` with `extra` options; returns
/// the decoded pixels (as bit patterns) and the stats line.
fn run(dir: &std::path::Path, name: &str, extra: &[&str]) -> (Vec<u32>, String) {
    let out = dir.join(name);
    let mut cmd = Command::new(render_bin());
    cmd.current_dir(env!("CARGO_MANIFEST_DIR")).args([
        "examples/scenes/level_rmnp.pov",
        "-o",
        out.to_str().unwrap(),
        "--width",
        "80",
        "--height",
        "50",
        "--stats",
        "--quiet",
    ]);
    cmd.args(extra);
    let o = cmd.output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{name} {extra:?}: {stderr}");
    let file = std::fs::File::open(&out).unwrap();
    let pixels = match name.rsplit('.').next().unwrap() {
        "tga" => read_tga_rgb(file)
            .unwrap()
            .pixels
            .iter()
            .map(|p| u32::from_le_bytes([p[0], p[1], p[2], 0]))
            .collect(),
        "png" => image::open(&out)
            .unwrap()
            .to_rgb8()
            .pixels()
            .map(|p| u32::from_le_bytes([p.0[0], p.0[1], p.0[2], 0]))
            .collect(),
        _ => read_pfm(file)
            .unwrap()
            .values
            .iter()
            .map(|v| v.to_bits())
            .collect(),
    };
    (pixels, stderr)
}

#[test]
fn every_walk_and_coherence_setting_writes_the_same_image() {
    let dir = std::env::temp_dir().join(format!("hfray-cli-walk-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, aov) in [
        ("a.tga", &[][..]),
        ("a.png", &[][..]),
        ("a.pfm", &["--aov", "depth"][..]),
    ] {
        let mut reference = None;
        for walk in ["flat", "blocks", "hierarchy"] {
            for coherence in ["on", "off"] {
                for threads in ["1", "3"] {
                    let mut extra = vec!["--walk", walk, "--coherence", coherence];
                    extra.extend_from_slice(&["--threads", threads]);
                    extra.extend_from_slice(aov);
                    let (pixels, stderr) = run(&dir, name, &extra);
                    let what = format!("{name} {extra:?}");
                    match &reference {
                        None => reference = Some(pixels),
                        Some(r) => assert!(*r == pixels, "{what} differs"),
                    }
                    // The work shows: blocks only with a skip grid in use,
                    // resumed walks only bottom-up (TGA, PFM) with coherence.
                    assert_eq!(stat(&stderr, "blocks") > 0, walk != "flat", "{what}");
                    let bottom_up = coherence == "on" && !name.ends_with(".png");
                    assert_eq!(stat(&stderr, "resumed") > 0, bottom_up, "{what}");
                }
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_walk_and_coherence_values_are_errors() {
    for (flag, value) in [("--walk", "fast"), ("--coherence", "maybe")] {
        let o = Command::new(render_bin())
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .args([
                "examples/scenes/level_rmnp.pov",
                "-o",
                "/nonexistent/x.tga",
                flag,
                value,
            ])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(1));
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(stderr.contains(flag) && stderr.contains(value), "{stderr}");
    }
}
