//! The `render` command as a user meets it: exit codes, error messages with
//! their location, outputs of every kind, and no partial file on failure.

#[path = "cli_common/mod.rs"]
mod cli_common;

use std::path::Path;

use cli_common::{run, stderr, temp_dir};

fn no_partial_files(dir: &Path) {
    let left: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(left.is_empty(), "files left behind: {left:?}");
}

#[test]
fn default_scene_renders_to_tga_png_and_depth_pfm() {
    let dir = temp_dir("cli-ok");
    for (name, extra) in [
        ("a.tga", &[][..]),
        ("a.png", &[][..]),
        ("a.pfm", &["--aov", "depth"][..]),
    ] {
        let out = dir.join(name);
        let mut args = vec![
            "examples/scenes/default.pov",
            "-o",
            out.to_str().unwrap(),
            "--width",
            "64",
            "--height",
            "40",
            "--stats",
        ];
        args.extend_from_slice(extra);
        let o = run(&args);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let bytes = std::fs::read(&out).unwrap();
        match name {
            "a.tga" => assert_eq!(bytes.len(), 18 + 64 * 40 * 3),
            "a.png" => assert_eq!(&bytes[1..4], b"PNG"),
            _ => assert!(bytes.starts_with(b"Pf\n64 40\n-1.0\n")),
        }
        let s = stderr(&o);
        let line = s
            .lines()
            .find(|l| l.starts_with("stats: "))
            .expect("a stats line");
        for key in [
            "width=64",
            "height=40",
            "rays=",
            "primary=2560",
            "shadow=",
            "reflected=",
            "cells=",
            "tri_tests=",
            "hits=",
            "parse_seconds=",
            "trace_seconds=",
            "heap_peak_bytes=",
        ] {
            assert!(line.contains(key), "{key} missing in {line}");
        }
    }
}

#[test]
fn scene_syntax_error_exits_1_with_file_line_col_and_no_output() {
    let dir = temp_dir("cli-syntax");
    let scene = dir.join("bad.pov");
    std::fs::write(
        &scene,
        "camera { location <0, 1, -3> look_at <0, 0, 0> }\nsphere { <0,0,0>, }\n",
    )
    .unwrap();
    let out = dir.join("out.tga");
    let o = run(&[scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let s = stderr(&o);
    let expected = format!("error: {}:2:", scene.display());
    assert!(s.starts_with(&expected), "{s}");
    std::fs::remove_file(&scene).unwrap();
    no_partial_files(&dir);
}

#[test]
fn missing_height_field_image_is_named_in_the_error() {
    let dir = temp_dir("cli-missing");
    let scene = dir.join("s.pov");
    std::fs::write(
        &scene,
        "camera { location <0.5, 2, -1> look_at <0.5, 0, 0.5> }\nheight_field { gif \"nowhere.gif\" }\n",
    )
    .unwrap();
    let out = dir.join("out.tga");
    let o = run(&[scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("nowhere.gif"), "{}", stderr(&o));
    std::fs::remove_file(&scene).unwrap();
    no_partial_files(&dir);
}

#[test]
fn bad_arguments_exit_1_with_a_message() {
    for (args, needle) in [
        (
            &["examples/scenes/default.pov"][..],
            "the following required arguments were not provided:\n  --output <OUT>",
        ),
        (
            &["-o", "x.tga"][..],
            "the following required arguments were not provided:\n  <SCENE.pov>",
        ),
        (
            &["examples/scenes/default.pov", "-o", "x.bmp"][..],
            "unknown output type",
        ),
        (
            &["examples/scenes/default.pov", "-o", "x.tga", "--width", "0"][..],
            "--width",
        ),
        (
            &["examples/scenes/default.pov", "-o", "x.tga", "--aa", "99"][..],
            "--aa",
        ),
        (
            &[
                "examples/scenes/default.pov",
                "-o",
                "x.tga",
                "--rows",
                "5..2",
            ][..],
            "--rows",
        ),
        (
            &["examples/scenes/default.pov", "-o", "x.tga", "--frobnicate"][..],
            "unexpected argument '--frobnicate'",
        ),
        (
            &["no/such/scene.pov", "-o", "x.tga"][..],
            "no/such/scene.pov",
        ),
    ] {
        let o = run(args);
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        let s = stderr(&o);
        assert!(
            s.starts_with("error: ") && s.contains(needle),
            "{args:?}: {s}"
        );
    }
}

// Threads and row bands: `tests/sinks.rs` (`render_command_threads_*`,
// `render_command_row_bands_*`), on the default and the thesis scenes.
