//! The `render` command against a hostile or careless user (issue 16):
//! it never overwrites an input, never follows a planted link, never
//! hangs on a FIFO, reports a file-size limit instead of dying of SIGXFSZ,
//! locates every error the scene causes and echoes input short and inert.
//! Each test writes its own small files. Limits: docs/limits.md.
#![cfg(unix)]

#[path = "cli_common/mod.rs"]
mod cli_common;

use std::os::unix::fs::symlink;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use cli_common::{entries, render_bin, stderr, temp_dir};

/// A 4×4 8-bit PGM: a small hill.
fn write_pgm(path: &Path) {
    let mut bytes = b"P5\n4 4\n255\n".to_vec();
    bytes.extend([
        0, 10, 10, 0, 10, 200, 180, 10, 10, 170, 160, 10, 0, 10, 10, 0,
    ]);
    std::fs::write(path, bytes).unwrap();
}

/// A scene reading `image` (a PGM) as a height field, plus `extra` text.
fn scene_text(image: &str, extra: &str) -> String {
    format!(
        "camera {{ location <0.5, 2, -1.5> look_at <0.5, 0, 0.5> }}\n\
         light_source {{ <2, 4, -3> color rgb 1 }}\n\
         height_field {{ pgm \"{image}\" pigment {{ color rgb 1 }} }}\n{extra}"
    )
}

/// `dir/hill.pgm` ([`write_pgm`]) and `dir/s.pov` ([`scene_text`] reading
/// it); returns the scene's path.
fn hill_scene(dir: &Path) -> PathBuf {
    write_pgm(&dir.join("hill.pgm"));
    let scene = dir.join("s.pov");
    std::fs::write(&scene, scene_text("hill.pgm", "")).unwrap();
    scene
}

/// Renders `scene` to `out` as [`run`] does, with `extra` arguments.
fn render(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![scene.to_str().unwrap(), "-o", out.to_str().unwrap()];
    args.extend(extra);
    run(&args)
}

/// `heap_peak_bytes` from the `--stats` line in `stderr`.
fn heap_peak(stderr: &str) -> u64 {
    stderr
        .split("heap_peak_bytes=")
        .nth(1)
        .and_then(|v| v.trim().parse().ok())
        .expect("heap_peak_bytes in --stats")
}

/// [`cli_common::run`] at 16×10, quiet.
fn run(args: &[&str]) -> Output {
    cli_common::run(&[args, &["--width", "16", "--height", "10", "--quiet"]].concat())
}

#[track_caller]
fn fails_with(o: &Output, needle: &str) -> String {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.starts_with("error: ") && e.contains(needle),
        "expected `{needle}` in: {e}"
    );
    e
}

/// The names in `dir` that are render temporaries.
fn partials(dir: &Path) -> Vec<String> {
    entries(dir)
        .into_iter()
        .filter(|n| n.contains(".partial-"))
        .collect()
}

// ------------------------------------------------------------ the output

#[test]
fn planted_symlink_at_an_old_style_temporary_name_is_never_followed() {
    // The temporary name used to be `.NAME.partial-PID`: a link planted
    // there for the next PIDs made the render overwrite its target. Now
    // the name has a random part and is created exclusively.
    let dir = temp_dir("hostile-link");
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "keep me").unwrap();
    let scene = hill_scene(&dir);
    let next_pid = Command::new("true").spawn().unwrap().id();
    for pid in next_pid..next_pid + 200 {
        symlink(&victim, dir.join(format!(".out.tga.partial-{pid}"))).unwrap();
    }
    let out = dir.join("out.tga");
    let o = render(&scene, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep me");
    let meta = std::fs::symlink_metadata(&out).unwrap();
    assert!(meta.file_type().is_file(), "the output is a regular file");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn symlink_planted_as_the_output_is_replaced_not_written_through() {
    let dir = temp_dir("hostile-outlink");
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "keep me").unwrap();
    let scene = hill_scene(&dir);
    let out = dir.join("out.tga");
    symlink(&victim, &out).unwrap();
    let o = render(&scene, &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep me");
    assert!(std::fs::symlink_metadata(&out)
        .unwrap()
        .file_type()
        .is_file());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn output_that_is_the_height_field_image_is_refused() {
    // The scene reads hill.tga; `-o hill.tga` would overwrite it.
    let dir = temp_dir("hostile-inimage");
    let image = dir.join("hill.tga");
    // A 2×2 8-bit gray TGA (type 3).
    let mut tga = vec![0, 0, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 2, 0, 8, 0x20];
    tga.extend([0, 50, 100, 150]);
    std::fs::write(&image, &tga).unwrap();
    let scene = "camera { location <0.5, 2, -1.5> look_at <0.5, 0, 0.5> }\n\
                 light_source { <2, 4, -3> color rgb 1 }\n\
                 height_field { tga \"hill.tga\" }\n";
    std::fs::write(dir.join("s.pov"), scene).unwrap();
    let o = render(&dir.join("s.pov"), &image, &[]);
    fails_with(&o, "the output is the same file as the input");
    assert_eq!(
        std::fs::read(&image).unwrap(),
        tga,
        "the input is untouched"
    );
    assert!(partials(&dir).is_empty(), "{:?}", entries(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn output_that_is_the_scene_file_is_refused() {
    // A scene file whose name has an image extension.
    let dir = temp_dir("hostile-inscene");
    write_pgm(&dir.join("hill.pgm"));
    let scene = dir.join("scene.png");
    let text = scene_text("hill.pgm", "");
    std::fs::write(&scene, &text).unwrap();
    let o = render(&scene, &scene, &[]);
    fails_with(&o, "the output is the same file as the input");
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), text);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn output_hard_linked_to_an_input_is_refused() {
    // Another name for the same inode (same device and inode).
    let dir = temp_dir("hostile-hardlink");
    let scene = hill_scene(&dir);
    std::fs::hard_link(dir.join("hill.pgm"), dir.join("alias.tga")).unwrap();
    let o = render(&scene, &dir.join("alias.tga"), &[]);
    fails_with(&o, "the output is the same file as the input");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn file_size_limit_is_an_error_and_removes_the_temporary() {
    // `ulimit -f 1`: at most one block. The render used to die of SIGXFSZ
    // with nothing on stderr, leaving its temporary file.
    let dir = temp_dir("hostile-fsize");
    let scene = hill_scene(&dir);
    let out = dir.join("out.tga");
    let o = Command::new("sh")
        .arg("-c")
        .arg("ulimit -f 1 && exec \"$0\" \"$@\"")
        .arg(render_bin())
        .args([scene.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .args(["--width", "400", "--height", "300", "--quiet"])
        .output()
        .unwrap();
    fails_with(&o, "file-size limit (ulimit -f)");
    assert_eq!(
        entries(&dir),
        ["hill.pgm", "s.pov"],
        "temporary left behind"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn killed_run_leaves_a_temporary_named_after_its_output_and_pid() {
    // SIGKILL cannot be caught: what is left must say what it is.
    let dir = temp_dir("hostile-kill");
    let out = dir.join("big.tga");
    let mut child = Command::new(render_bin())
        .args(["examples/scenes/default.pov", "-o", out.to_str().unwrap()])
        .args([
            "--width", "4096", "--height", "4096", "--aa", "4", "--quiet",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let left = loop {
        if let Some(p) = partials(&dir).pop() {
            break p;
        }
        assert!(start.elapsed() < Duration::from_secs(60), "no temporary");
        std::thread::sleep(Duration::from_millis(20));
    };
    child.kill().unwrap();
    child.wait().unwrap();
    let prefix = format!(".big.tga.partial-{}-", child.id());
    assert!(
        left.starts_with(&prefix) && left.len() == prefix.len() + 6,
        "{left} is not {prefix}XXXXXX"
    );
    assert_eq!(partials(&dir), [left]);
    std::fs::remove_dir_all(&dir).unwrap();
}

// ----------------------------------------------------------------- inputs

#[test]
fn fifo_named_as_height_field_image_is_an_error_not_a_hang() {
    let dir = temp_dir("hostile-fifo");
    let fifo = dir.join("hill.pgm");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    std::fs::write(dir.join("s.pov"), scene_text("hill.pgm", "")).unwrap();
    let mut child = Command::new(render_bin())
        .args([dir.join("s.pov").to_str().unwrap(), "-o"])
        .arg(dir.join("out.tga"))
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(20) {
            child.kill().unwrap();
            panic!("render blocked on the FIFO");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let o = child.wait_with_output().unwrap();
    let e = fails_with(&o, "is a FIFO (named pipe), not an image file");
    assert!(e.contains("s.pov:3:1:"), "located at the object: {e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn image_over_the_memory_budget_is_refused_and_the_budget_can_be_raised() {
    // A 2048×1024 8-bit PGM is 2 MiB of samples: over a 1 MiB budget.
    let dir = temp_dir("hostile-budget");
    let mut pgm = b"P5\n2048 1024\n255\n".to_vec();
    pgm.resize(pgm.len() + 2048 * 1024, 7);
    std::fs::write(dir.join("big.pgm"), pgm).unwrap();
    std::fs::write(dir.join("s.pov"), scene_text("big.pgm", "")).unwrap();
    let (scene, out) = (dir.join("s.pov"), dir.join("o.tga"));
    let small = render(&scene, &out, &["--max-image-mib", "1"]);
    let e = fails_with(&small, "image memory budget");
    assert!(e.contains("s.pov:3:1:") && e.contains("2048x1024"), "{e}");
    let o = render(&scene, &out, &["--max-image-mib", "4"]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn threads_256_at_65536_wide_are_capped_and_memory_stays_bounded() {
    // Used to take 0.9–1.2 GiB: 256 threads each queueing 16 rows.
    let dir = temp_dir("hostile-threads");
    let out = dir.join("wide.pfm");
    let o = Command::new(render_bin())
        .args(["examples/scenes/default.pov", "-o", out.to_str().unwrap()])
        .args(["--aov", "depth", "--width", "65536", "--height", "64"])
        .args(["--threads", "256", "--stats"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    assert!(e.contains("note: --threads 256 reduced to "), "{e}");
    let peak = heap_peak(&e);
    // Rows in flight are kept within 64 MiB; the scene and its field add
    // well under 8 MiB.
    assert!(peak < 72 << 20, "heap peak {peak} bytes");
    std::fs::remove_dir_all(&dir).unwrap();
}

// --------------------------------------------------------------- messages

#[test]
fn singular_height_field_transform_is_located_at_the_object() {
    // `scale 1e-38` passes the parser, but on an 8×8 field the world-to-
    // grid map (7 cells per unit) overflows f32: found when the field is
    // built, after parsing.
    let dir = temp_dir("hostile-singular");
    let mut pgm = b"P5\n8 8\n255\n".to_vec();
    pgm.extend((0..64u8).map(|i| i * 3));
    std::fs::write(dir.join("hill.pgm"), pgm).unwrap();
    let scene = "camera { location <0.5, 2, -1.5> look_at <0.5, 0, 0.5> }\n\
                 light_source { <2, 4, -3> color rgb 1 }\n\
                 \n  height_field { pgm \"hill.pgm\" scale 1e-38 }\n";
    std::fs::write(dir.join("s.pov"), scene).unwrap();
    let o = render(&dir.join("s.pov"), &dir.join("o.tga"), &[]);
    let e = fails_with(&o, "s.pov:4:3: height_field \"hill.pgm\": ");
    assert!(e.contains("singular"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn degenerate_cone_is_located_at_the_object() {
    // The ends differ in the scene's f64 but not in f32: the parser
    // accepts it, the renderer finds it degenerate.
    let dir = temp_dir("hostile-cone");
    let scene = "camera { location <0, 1, -3> look_at <0, 0, 0> }\n\
                 light_source { <2, 4, -3> color rgb 1 }\n\
                 sphere { <0, 0, 0>, 0.5 }\n\
                 cone { <0, 0, 0>, 1, <0, 1e-30, 0>, 0.5 }\n";
    std::fs::write(dir.join("s.pov"), scene).unwrap();
    let o = render(&dir.join("s.pov"), &dir.join("o.tga"), &[]);
    let e = fails_with(&o, "s.pov:4:1: cone: ");
    assert!(!e.contains("object 1"), "{e}");
    assert!(partials(&dir).is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn ten_megabyte_identifier_is_echoed_short() {
    let dir = temp_dir("hostile-ident");
    let scene = dir.join("s.pov");
    std::fs::write(&scene, "a".repeat(10 << 20)).unwrap();
    let o = render(&scene, &dir.join("o.tga"), &[]);
    let e = fails_with(&o, "unknown top-level item");
    assert!(e.len() < 400, "{} bytes of error", e.len());
    assert!(e.contains(&format!("`{}…`", "a".repeat(80))), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn control_characters_in_an_image_path_are_escaped() {
    let dir = temp_dir("hostile-ctrl");
    let scene = dir.join("s.pov");
    std::fs::write(&scene, scene_text("x\u{1b}[31m\u{7}.pgm", "")).unwrap();
    let o = render(&scene, &dir.join("o.tga"), &[]);
    let e = fails_with(&o, "x\\u{1b}[31m\\u{7}.pgm");
    assert!(!e.contains('\u{1b}') && !e.contains('\u{7}'), "{e:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn scene_starting_with_a_utf8_byte_order_mark_renders() {
    let dir = temp_dir("hostile-bom");
    let scene = hill_scene(&dir);
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(&scene, format!("\u{feff}{text}")).unwrap();
    let o = render(&scene, &dir.join("o.tga"), &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

// -------------------------------------------------------------- the CLI

#[test]
fn help_exits_0_and_describes_every_option_with_its_default() {
    let o = Command::new(render_bin()).arg("--help").output().unwrap();
    assert_eq!(o.status.code(), Some(0));
    let help = String::from_utf8_lossy(&o.stdout);
    for (option, default) in [
        ("--width", "[default: 320]"),
        ("--height", "[default: 200]"),
        ("--aa", "[default: 1]"),
        ("--threads", "[default: 1]"),
        ("--frames", "[default: 1]"),
        ("--max-image-mib", "[default: 256]"),
    ] {
        let line = help
            .lines()
            .find(|l| l.trim_start().starts_with(option))
            .unwrap_or_else(|| panic!("{option} missing from:\n{help}"));
        assert!(line.contains(default), "{line}");
    }
    for option in [
        "--output", "--rows", "--aov", "--stats", "--strict", "--quiet",
    ] {
        assert!(help.contains(option), "{option} missing from:\n{help}");
    }
}

#[test]
fn option_equals_value_is_accepted() {
    let dir = temp_dir("hostile-eq");
    let out = dir.join("o.tga");
    let o = Command::new(render_bin())
        .args(["examples/scenes/default.pov", "--width=24", "--height=16"])
        .arg(format!("--output={}", out.display()))
        .arg("--quiet")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    // TGA header: width and height at bytes 12..16.
    let tga = std::fs::read(&out).unwrap();
    assert_eq!(&tga[12..16], &[24, 0, 16, 0]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn unknown_option_gets_a_suggestion() {
    let o = run(&["examples/scenes/default.pov", "-o", "x.tga", "--widht", "3"]);
    let e = fails_with(&o, "unexpected argument '--widht'");
    assert!(e.contains("similar argument exists: '--width'"), "{e}");
}

#[test]
fn repeated_output_is_an_error() {
    let dir = temp_dir("hostile-twice");
    let (a, b) = (dir.join("a.tga"), dir.join("b.tga"));
    let o = run(&[
        "examples/scenes/default.pov",
        "-o",
        a.to_str().unwrap(),
        "-o",
        b.to_str().unwrap(),
    ]);
    fails_with(&o, "cannot be used multiple times");
    assert!(entries(&dir).is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn missing_output_folder_is_named_as_such() {
    let o = run(&["examples/scenes/default.pov", "-o", "no/such/folder/x.tga"]);
    fails_with(&o, "the output folder no/such/folder does not exist");
}

// ------------------------------------------------------------ peak memory

#[test]
fn render_peak_stays_under_512_mib_for_the_largest_input_the_defaults_accept() {
    // The largest scene file (16 MiB) naming the largest 8-bit image the
    // default 256 MiB image budget accepts with its skip pyramid (15000²),
    // rendered at default settings under a 512 MiB address-space limit.
    // docs/limits.md states the bound this checks.
    use std::io::Write;
    let dir = temp_dir("hostile-peak");
    let side = 15_000usize;
    {
        let file = std::fs::File::create(dir.join("big.pgm")).unwrap();
        let mut out = std::io::BufWriter::new(file);
        write!(out, "P5\n{side} {side}\n255\n").unwrap();
        let row: Vec<u8> = (0..side).map(|i| (i * 7 % 256) as u8).collect();
        for _ in 0..side {
            out.write_all(&row).unwrap();
        }
    }
    let mut text = scene_text("big.pgm", "");
    let pad = format!("// {}\n", "x".repeat(1000));
    while text.len() + pad.len() <= 16 << 20 {
        text += &pad;
    }
    std::fs::write(dir.join("s.pov"), &text).unwrap();
    let o = Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 524288 && exec \"$0\" \"$@\"")
        .arg(render_bin())
        .arg(dir.join("s.pov"))
        .arg("-o")
        .arg(dir.join("o.png"))
        .arg("--stats")
        .output()
        .unwrap();
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    let peak = heap_peak(&e);
    // Measured 272 170 581 bytes (260 MiB): the image budget plus the
    // scene text, well inside the stated 512 MiB.
    assert!(peak < 300 << 20, "heap peak {peak} bytes");
    std::fs::remove_dir_all(&dir).unwrap();
}
