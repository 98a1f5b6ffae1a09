//! The `render` command never leaves a partial image under the requested
//! name: not when it is interrupted (SIGINT as Ctrl-C sends it, SIGTERM as
//! `kill` and service managers send it), and not when its input is bad. An
//! interrupted render removes its temporary file and exits with 130; a
//! failed one exits with 1 and leaves an existing file of that name as it
//! was.
//!
//! The binary is `target/<profile>/examples/render`, which `cargo test`
//! builds before the tests (see tests/cli_render.rs). Signals are sent with
//! the system's `kill` command.
#![cfg(unix)]

#[path = "cli_common/mod.rs"]
mod cli_common;

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use cli_common::{entries, render_bin, temp_dir};

/// Waits for the child to exit, killing it (and failing) after `limit`.
fn wait_with_limit(child: &mut Child, limit: Duration) -> std::process::ExitStatus {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("render did not exit within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Starts a render that takes minutes (the default scene, 4096² pixels,
/// 4×4 supersampling), waits until it is writing its temporary file, sends
/// `signal`, and checks the exit status, the message and that the output
/// folder is left empty.
fn interrupted_render_leaves_nothing(signal: &str, name: &str) {
    let dir = temp_dir(&format!("int-{name}"));
    let out = dir.join("big.tga");
    let mut child = Command::new(render_bin())
        .args([
            "examples/scenes/default.pov",
            "-o",
            out.to_str().unwrap(),
            "--width",
            "4096",
            "--height",
            "4096",
            "--aa",
            "4",
            "--quiet",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The temporary file appears once parsing and loading are done.
    let start = Instant::now();
    let partial = loop {
        let e = entries(&dir);
        if let Some(p) = e.iter().find(|n| n.starts_with(".big.tga.partial-")) {
            break p.clone();
        }
        if let Some(status) = child.try_wait().unwrap() {
            panic!("render exited early: {status}");
        }
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no temporary file after 60 s: {e:?}"
        );
        std::thread::sleep(Duration::from_millis(10));
    };
    // Let it write some rows first.
    std::thread::sleep(Duration::from_millis(300));
    assert!(
        entries(&dir).contains(&partial),
        "the render finished too soon"
    );
    let killed = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = wait_with_limit(&mut child, Duration::from_secs(30));
    let mut stderr = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr).unwrap();
    assert_eq!(
        status.code(),
        Some(130),
        "{signal}: {status}, stderr: {stderr}"
    );
    assert!(stderr.contains("interrupted"), "{stderr}");
    assert_eq!(
        entries(&dir),
        Vec::<String>::new(),
        "{signal} left files behind"
    );
    std::fs::remove_dir(&dir).unwrap();
}

#[test]
fn sigint_removes_the_partial_file_and_exits_130() {
    interrupted_render_leaves_nothing("-INT", "sigint");
}

#[test]
fn sigterm_removes_the_partial_file_and_exits_130() {
    interrupted_render_leaves_nothing("-TERM", "sigterm");
}

/// A scene with an error: `error: FILE:LINE:COL: message`, exit 1, and
/// the file already under the output name is untouched (the render never
/// got to replace it), with no temporary file beside it.
#[test]
fn bad_scene_keeps_an_existing_output_and_leaves_no_temporary() {
    let dir = temp_dir("int-bad");
    let scene = dir.join("bad.pov");
    std::fs::write(
        &scene,
        "camera { location <0, 1, -3> look_at 0 }\nsphere { <0, 0, 0>, 1 scale 0 }\n",
    )
    .unwrap();
    let out = dir.join("keep.tga");
    std::fs::write(&out, b"previous render").unwrap();
    let o = Command::new(render_bin())
        .args([scene.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr);
    let expected = format!("error: {}:2:", scene.display());
    assert!(stderr.starts_with(&expected), "{stderr}");
    assert_eq!(std::fs::read(&out).unwrap(), b"previous render");
    assert_eq!(entries(&dir), ["bad.pov", "keep.tga"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An error found while rendering rather than parsing (the output folder
/// vanishes, so the rename fails; or the image cannot be written) still
/// leaves nothing under the final name. Here: an output folder that does
/// not exist.
#[test]
fn unwritable_output_exits_1_and_creates_nothing() {
    let dir = temp_dir("int-nodir");
    let out = dir.join("missing").join("x.tga");
    let o = Command::new(render_bin())
        .args([
            "examples/scenes/default.pov",
            "-o",
            out.to_str().unwrap(),
            "--width",
            "8",
            "--height",
            "8",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.starts_with("error: ") && stderr.contains("x.tga"),
        "{stderr}"
    );
    assert!(!out.exists());
    assert_eq!(entries(&dir), Vec::<String>::new());
    std::fs::remove_dir_all(&dir).unwrap();
}
