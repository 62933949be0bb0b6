//! Hostile command lines (issue #20): every numeric flag of the examples is bounded when it is
//! parsed (the message names the flag), device limits reach the command line as the
//! renderer's typed errors, and every output error names its path. No run may panic (exit
//! code 101) or exit 0, and none may leave a validation message behind.

mod common;

use std::path::Path;
use std::process::Command;

/// What a run of an example said and how it ended.
struct Run {
    code: Option<i32>,
    output: String,
}

/// Runs `example` with `args` (validation layer on, the test's UMBRA_DEVICE).
fn run(example: &str, args: &[&str]) -> Run {
    let out = Command::new(common::example(example))
        .args(args)
        .env("UMBRA_VALIDATION", "1")
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("example runs");
    let output = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    Run { code: out.status.code(), output }
}

/// Asserts that `example args` fails cleanly (exit 1 or 2: no panic, no crash) and says
/// every one of `needles`.
fn refused(example: &str, args: &[&str], needles: &[&str]) -> String {
    let r = run(example, args);
    let first = r.output.lines().find(|l| l.contains("rror")).unwrap_or("").to_owned();
    println!("{example} {}: exit {:?}: {first}", args.join(" "), r.code);
    assert!(matches!(r.code, Some(1 | 2)), "{example} {args:?}: exit {:?} (not a clean refusal)\n{}", r.code, r.output);
    assert!(!r.output.contains("panicked"), "{example} {args:?} panicked:\n{}", r.output);
    assert!(!r.output.contains("VUID") && !r.output.contains("Validation Error"), "{example} {args:?}:\n{}", r.output);
    for needle in needles {
        assert!(r.output.contains(needle), "{example} {args:?}: no {needle:?} in:\n{}", r.output);
    }
    r.output
}

/// Cheap headless arguments: a small frame, no warm-up, `out` as the output folder.
fn small<'a>(out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["--scene", "cylinder", "--size", "64x48", "--warmup", "0", "--out", out];
    args.extend_from_slice(extra);
    args
}

#[test]
fn shadow_volume_takes_1_to_64_lights() {
    for n in ["4294967295", "0", "65"] {
        refused("shadow_volume", &["--lights", n], &["--lights", "1..=64"]);
    }
}

#[test]
fn shadow_map_refuses_non_finite_and_absurd_bias_and_normal_offset() {
    for bias in ["nan,nan", "inf,-inf", "2,1e30", "1e30,2"] {
        refused("shadow_map", &["--bias", bias], &["--bias", "shadow_map.bias", "a finite number in 0..="]);
    }
    for offset in ["nan", "1e30", "inf"] {
        refused("shadow_map", &["--normal-offset", offset], &["--normal-offset", "not a finite number"]);
    }
    refused("shadow_map", &["--normal-offset=-1"], &["--normal-offset"]);
}

#[test]
fn every_numeric_flag_is_bounded_when_parsed() {
    let cases: [(&str, &[&str], &str); 13] = [
        ("render", &["--time", "nan"], "--time"),
        ("render", &["--time", "inf"], "--time"),
        ("render", &["--window", "--frames", "1", "--hold", "nan"], "--hold"),
        ("render", &["--window", "--frames", "1", "--hold=-1"], "--hold"),
        ("render", &["--warmup", "100000000"], "--warmup"),
        ("render", &["--window", "--frames", "0"], "--frames"),
        ("render", &["--size", "0x10"], "--size"),
        ("render", &["--window", "--resize-at", "0:64x48"], "--resize-at"),
        ("shadow_map", &["--sm-size", "0"], "--sm-size"),
        ("silhouette_map", &["--sm-size", "16"], "--sm-size"),
        ("hybrid", &["--sm-size", "0"], "--sm-size"),
        ("effects", &["--time", "nan"], "--time"),
        ("shadow_volume", &["--size", "64x0"], "--size"),
    ];
    for (example, args, flag) in cases {
        let output = refused(example, args, &[flag]);
        assert!(output.contains(&format!("'{flag} <")), "clap names the flag:\n{output}");
        // Blamed on the flag, not on what the value would have broken later.
        assert!(!output.contains("light 0"), "{output}");
    }
}

#[test]
fn output_errors_name_the_path() {
    let dir = common::output_dir("cli-input-out");
    let file = dir.join("a-file");
    std::fs::write(&file, "not a folder").unwrap();
    let below_file = file.join("sub");
    // An output folder whose render.png is a folder: the PNG cannot be written.
    let blocked = dir.join("blocked");
    std::fs::create_dir_all(blocked.join("render.png")).unwrap();
    let path = |p: &Path| p.to_str().expect("UTF-8 test path").to_owned();
    let cases = [
        (path(&file), path(&file)),
        (path(&below_file), path(&below_file)),
        ("/proc/umbra-no-such-folder".to_owned(), "/proc/umbra-no-such-folder".to_owned()),
        (path(&blocked), path(&blocked.join("render.png"))),
    ];
    for (out, named) in cases {
        refused("render", &small(&out, &[]), &[&named]);
    }
    // The examples' own images go through the same helper.
    std::fs::create_dir_all(blocked.join("shadow_volume_overdraw.png")).unwrap();
    let out = path(&blocked);
    refused("shadow_volume", &small(&out, &["--show-volumes"]), &[&path(&blocked.join("shadow_volume_overdraw.png"))]);
}

#[test]
fn device_limits_reach_the_command_line_as_typed_errors() {
    let caps = common::with_context(|ctx| ctx.capabilities().clone());
    let dir = common::output_dir("cli-input-limits");
    let out = dir.to_str().expect("UTF-8 test path");
    // The fuzzing report's cube map: within lavapipe's maxImageDimensionCube (32768), over
    // every other limit of a D32 cube on both drivers.
    let args = ["--scene", "cubes", "--size", "64x48", "--warmup", "0", "--out", out, "--sm-size", "32768"];
    let output = refused("shadow_map", &args, &["shadow map of light 0: resolution 32768", &caps.device_name]);
    assert!(output.contains(" is ") && output.contains("texels per side"), "{output}");
    let mut sizes = vec![format!("{}x8", caps.max_image_dimension_2d + 1)];
    if caps.max_framebuffer_width < caps.max_image_dimension_2d {
        // SwiftShader: 8200 fits maxImageDimension2D (16384), not maxFramebufferWidth (8192).
        sizes.push(format!("{}x8", caps.max_framebuffer_width + 8));
    }
    for size in &sizes {
        let args = ["--scene", "cylinder", "--size", size, "--warmup", "0", "--out", out];
        let output = refused("render", &args, &[&format!("invalid target size {size}"), &caps.device_name]);
        if size.starts_with(&(caps.max_framebuffer_width + 8).to_string()) {
            assert!(output.contains("maxFramebufferWidth is 8192"), "{output}");
        }
    }
}
