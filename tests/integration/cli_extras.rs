//! The command line's niceties: animated PNG and MP4 previews, scene templates, shell
//! completions, `--quiet` and `--verbose`, the progress bar, and refusing renders that
//! cannot fit in memory.

use crate::util::{example, stderr, stdout, Sandbox};

/// Decodes a PNG file's pixels as 8-bit RGBA.
fn rgba(path: &std::path::Path) -> Vec<u8> {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
        .into_raw()
}

#[test]
fn apng_holds_every_frame_losslessly_at_the_scene_fps() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&[
        "render",
        &example("spring.toml"),
        "--out",
        "f",
        "--frames",
        "0..12",
        "--apng",
        "spring.png",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains("spring.png"), "{}", stdout(&out));
    let file = std::fs::File::open(sandbox.path("spring.png")).expect("the APNG");
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .expect("a PNG");
    let control = reader.info().animation_control.expect("an animated PNG");
    assert_eq!((control.num_frames, control.num_plays), (12, 0));
    let mut buffer = vec![0; reader.output_buffer_size().expect("size")];
    for k in 0..12 {
        let info = reader.next_frame(&mut buffer).expect("a frame");
        let fctl = reader.info().frame_control.expect("frame control");
        assert_eq!((fctl.delay_num, fctl.delay_den), (1, 25), "1/fps seconds");
        let expected = rgba(&sandbox.path(&format!("f/frame_{k:06}.png")));
        assert!(
            buffer[..info.buffer_size()] == expected[..],
            "frame {k} differs from its PNG"
        );
    }
}

#[test]
fn mp4_without_ffmpeg_is_refused_before_rendering_anything() {
    let sandbox = Sandbox::new();
    std::fs::create_dir_all(sandbox.path("empty-bin")).expect("a folder");
    let path = sandbox.path("empty-bin");
    let out = sandbox.run_with_env(
        &[
            "render",
            &example("drag.toml"),
            "--out",
            "f",
            "--mp4",
            "drag.mp4",
        ],
        &[("PATH", path.as_os_str())],
    );
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("--mp4 needs ffmpeg"), "{err}");
    assert!(err.contains("no `ffmpeg` was found on PATH"), "{err}");
    assert!(!sandbox.path("f").exists(), "no frame was rendered");
    assert!(!sandbox.path("drag.mp4").exists());
}

#[cfg(unix)]
#[test]
fn mp4_pipes_every_frame_in_order_to_ffmpeg() {
    use std::os::unix::fs::PermissionsExt;
    let sandbox = Sandbox::new();
    // A stand-in for ffmpeg that records its arguments and copies its standard input
    // to the output file, its last argument.
    let script = sandbox.write(
        "bin/ffmpeg",
        "#!/bin/sh\nprintf '%s\\n' \"$@\" > \"$(dirname \"$0\")/args\"\nfor last; do :; done\ncat > \"$last\"\n",
    );
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    // The stand-in comes first on PATH; the rest of PATH gives it `cat` and `dirname`.
    let mut dirs = vec![sandbox.path("bin")];
    dirs.extend(std::env::split_paths(
        &std::env::var_os("PATH").unwrap_or_default(),
    ));
    let bin = std::env::join_paths(dirs).expect("a PATH");
    let out = sandbox.run_with_env(
        &[
            "render",
            &example("drag.toml"),
            "--out",
            "f",
            "--frames",
            "3..9",
            "--mp4",
            "drag.mp4",
        ],
        &[("PATH", bin.as_os_str())],
    );
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let mut piped = Vec::new();
    for k in 3..9 {
        piped.extend(std::fs::read(sandbox.path(&format!("f/frame_{k:06}.png"))).expect("frame"));
    }
    assert!(
        std::fs::read(sandbox.path("drag.mp4")).expect("the video") == piped,
        "ffmpeg received the frames' PNG bytes in order"
    );
    let args = std::fs::read_to_string(sandbox.path("bin/args")).expect("arguments");
    let args: Vec<&str> = args.lines().collect();
    let after = |flag: &str| args.iter().position(|a| *a == flag).map(|i| args[i + 1]);
    assert_eq!(after("-framerate"), Some("25"), "{args:?}");
    assert_eq!(after("-i"), Some("-"), "{args:?}");
    assert_eq!(after("-pix_fmt"), Some("yuv420p"), "{args:?}");
}

#[test]
fn new_writes_a_template_that_renders_and_never_overwrites() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&["new", "demo"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = std::fs::read_to_string(sandbox.path("demo.toml")).expect("the template");
    assert!(text.starts_with("# A physframes scene"), "{text}");
    assert!(text.contains("physframes render demo.toml"), "{text}");
    let out = sandbox.run(&["render", "demo.toml", "--quiet"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(sandbox.frames("output/demo").len(), 51);
    let m = sandbox.manifest("output/demo");
    assert_eq!(m["status"], "complete");

    std::fs::write(sandbox.path("demo.toml"), "# my own work\n").expect("edit");
    let out = sandbox.run(&["new", "demo.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("demo.toml already exists"),
        "{}",
        stderr(&out)
    );
    assert_eq!(
        std::fs::read_to_string(sandbox.path("demo.toml")).expect("kept"),
        "# my own work\n"
    );
    let out = sandbox.run(&["new", "my scene"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!sandbox.path("my scene.toml").exists());
}

#[test]
fn completions_are_printed_for_each_shell() {
    let sandbox = Sandbox::new();
    for (shell, marker) in [
        ("bash", "complete -F _physframes"),
        ("zsh", "#compdef physframes"),
        ("fish", "complete -c physframes"),
    ] {
        let out = sandbox.run(&["completions", shell]);
        assert_eq!(out.status.code(), Some(0), "{shell}: {}", stderr(&out));
        let script = stdout(&out);
        assert!(script.contains(marker), "{shell}: no `{marker}`");
        for word in ["render", "resume", "set", "checkpoint-every"] {
            assert!(script.contains(word), "{shell}: no `{word}`");
        }
    }
    let out = sandbox.run(&["completions", "tcsh"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn quiet_prints_nothing_and_verbose_prints_the_details() {
    let sandbox = Sandbox::new();
    let scene = example("drag.toml");
    let out = sandbox.run(&[
        "render", &scene, "--out", "q", "--frames", "0..3", "--quiet",
    ]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!((stdout(&out), stderr(&out)), (String::new(), String::new()));
    let out = sandbox.run(&["-v", "render", &scene, "--out", "v", "--frames", "0..3"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let err = stderr(&out);
    for expected in [
        "scene `drag`: hash ",
        "drawing thread",
        "memory needed about",
    ] {
        assert!(err.contains(expected), "missing `{expected}` in:\n{err}");
    }
    assert!(stdout(&out).starts_with("wrote 3 frames of `drag`"));
    let out = sandbox.run(&["render", &scene, "--quiet", "--verbose"]);
    assert_eq!(out.status.code(), Some(2), "they contradict each other");
}

#[test]
fn the_progress_bar_is_hidden_when_stderr_is_not_a_terminal() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&["render", &example("spring.toml"), "--out", "f"]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(stderr(&out), "", "no progress output into a pipe");
}

/// On a terminal (here a pseudo-terminal from util-linux `script`), the bar shows the
/// frames, the rate and the time left.
#[cfg(target_os = "linux")]
#[test]
fn the_progress_bar_shows_frames_rate_and_time_left_on_a_terminal() {
    let has_script = std::process::Command::new("script")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_script {
        eprintln!("skipped: util-linux `script` is not installed");
        return;
    }
    let sandbox = Sandbox::new();
    let command = format!(
        "{} render {} --out f --threads 1",
        env!("CARGO_BIN_EXE_physframes"),
        example("spring.toml")
    );
    let out = std::process::Command::new("script")
        .args(["-qec", &command, "/dev/null"])
        .env("COLUMNS", "120")
        .current_dir(sandbox.dir.path())
        .output()
        .expect("script runs");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let shown = stdout(&out);
    assert!(shown.contains("/151 frames ("), "{shown}");
    assert!(shown.contains("/s, "), "{shown}");
    assert!(shown.contains(" left)"), "{shown}");
}

#[cfg(target_os = "linux")]
#[test]
fn a_render_that_cannot_fit_in_memory_is_refused_before_it_starts() {
    let sandbox = Sandbox::new();
    sandbox.write(
        "huge.toml",
        "[render]\nwidth = 16384\nheight = 16384\nview = { min = [0.0, 0.0], max = [1.0, 1.0] }\n",
    );
    // 1000 threads × 3 buffers × 1 GiB: no machine this runs on has 3 TiB free.
    let out = sandbox.run(&["render", "huge.toml", "--out", "f", "--threads", "1000"]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("this render needs about 2.9 TiB of memory"),
        "{err}"
    );
    assert!(err.contains("16384×16384×4 bytes = 1.0 GiB each"), "{err}");
    assert!(err.contains("is available; nothing was written"), "{err}");
    assert!(err.contains("hint: use --threads "), "{err}");
    assert!(!sandbox.path("f").exists());
}

#[test]
fn help_lists_every_command() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&["--help"]);
    assert_eq!(out.status.code(), Some(0));
    let text = stdout(&out);
    for command in [
        "render",
        "check",
        "export",
        "checkpoint",
        "new",
        "completions",
        "--quiet",
        "--verbose",
    ] {
        assert!(text.contains(command), "no `{command}` in:\n{text}");
    }
}
