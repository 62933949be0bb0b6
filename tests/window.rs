//! Every example's `--window` under Xvfb (the example engine's too: `embed_window`): 60 presented frames with one resize mid-run, a clean
//! exit with zero validation messages, a `--screenshot` equal to the headless render of the
//! same frame, and an X screenshot taken from outside the process (`xwd`) equal to it too.
//!
//! Each test starts its own Xvfb (Debian `xvfb`, installed by ci/setup.sh with `x11-apps` for
//! `xwd`) and runs the example binaries `cargo test` builds. SwiftShader's ICD has no X11
//! surface extension: there the example must fail with its typed "unsupported" error, and the
//! test says it skipped; lavapipe covers it. A last test drives a viewer with real X input
//! (`xdotool`, through the X server like a user's keyboard and mouse).

mod common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

/// The windowed run: 256×192, resized to 320×240 after 30 of its 60 frames.
const FRAMES: u64 = 60;
const START: (u32, u32) = (256, 192);
const RESIZED: (u32, u32) = (320, 240);

/// The example engine (`examples/embed`) in a window: its own device and swapchain, umbra's
/// shadows recorded into its frames, each frame blitted into the swapchain on the GPU.
#[test]
fn embed_window() {
    let x = Xvfb::start();
    let out = Command::new(common::example("embed"))
        .args(["--window", "--frames", "20", "--size", "256x192"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("DISPLAY", &x.display)
        .env("UMBRA_VALIDATION", "1")
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("start the example");
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    if !out.status.success() && skipped_on_swiftshader("embed", &stderr) {
        return;
    }
    assert!(out.status.success(), "embed --window failed\nstdout:\n{stdout}\nstderr:\n{stderr}");
    print!("{stdout}");
    assert!(stdout.contains("presented 20 frames") && stdout.contains("from the GPU"), "{stdout}");
    assert!(stdout.contains("validation messages: 0"), "{stdout}\n{stderr}");
    assert!(stdout.contains(" 0 submissions by umbra"), "{stdout}");
}

#[test]
fn render_window() {
    check_example("render", "render.png");
}

#[test]
fn shadow_map_window() {
    check_example("shadow_map", "shadow_map.png");
}

#[test]
fn shadow_volume_window() {
    check_example("shadow_volume", "shadow_volume.png");
}

#[test]
fn silhouette_map_window() {
    check_example("silhouette_map", "silhouette_map.png");
}

#[test]
fn hybrid_window() {
    check_example("hybrid", "hybrid.png");
}

#[test]
fn effects_window() {
    check_example("effects", "effects.png");
}

/// Keys and mouse, sent through the X server by xdotool, drive the viewer: the technique, view,
/// map-size and mask keys change what its title reports; with the animation paused, a mouse
/// drag (camera) and the arrow keys (light) each change the image; Esc quits cleanly with zero
/// validation messages.
#[test]
fn keys_and_mouse_drive_the_viewer() {
    let dir = common::output_dir("window-input");
    let x = Xvfb::start();
    let args = ["--window", "--frames", "100000", "--size", "256x192", "--out"].map(str::to_owned);
    let (mut child, errors, lines) = spawn_windowed("shadow_map", &x, &args, &dir);
    let Some(id) = wait_line(&lines, "window id ").map(|l| l["window id ".len()..].trim().to_owned()) else {
        let status = child.wait().expect("example exit");
        let stderr = errors.join().unwrap_or_default();
        if skipped_on_swiftshader("shadow_map", &stderr) {
            return;
        }
        panic!("no window ({status}): {stderr}");
    };
    let xdotool = |args: &[&str]| {
        let out =
            Command::new("xdotool").args(args).env("DISPLAY", &x.display).output().expect("xdotool (ci/setup.sh)");
        assert!(out.status.success(), "xdotool {args:?}: {}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stdout).trim().to_owned()
    };
    let title = || xdotool(&["getwindowname", &id]);
    let wait_title = |what: &dyn Fn(&str) -> bool, why: &str| {
        let deadline = Instant::now() + Duration::from_secs(90);
        loop {
            let t = title();
            if what(&t) {
                println!("title: {t}");
                return t;
            }
            assert!(Instant::now() < deadline, "{why}: the title stayed {t:?}");
            std::thread::sleep(Duration::from_millis(200));
        }
    };
    let field = |t: &str, name: &str| t.split(" · ").find(|f| f.starts_with(name)).unwrap_or_default().to_owned();
    xdotool(&["windowfocus", "--sync", &id]);
    wait_title(&|t| t.contains("GPU"), "the first frame's title");
    xdotool(&["key", "3"]);
    wait_title(&|t| t.contains(" · shadow_volume · "), "key 3 selects shadow volumes");
    xdotool(&["key", "4"]);
    wait_title(&|t| t.contains(" · hybrid · "), "key 4 selects the hybrid");
    xdotool(&["key", "v"]);
    wait_title(&|t| t.contains("view classification"), "V shows the classification");
    xdotool(&["key", "m"]);
    wait_title(&|t| t.contains("map 512"), "M cycles the map size");
    let mask = field(&title(), "mask ");
    xdotool(&["key", "k"]);
    wait_title(&|t| !field(t, "mask ").is_empty() && field(t, "mask ") != mask, "K cycles the mask");
    xdotool(&["key", "v", "v", "v", "p"]);
    wait_title(&|t| t.contains("paused") && t.contains("view image"), "P pauses, V back to the image");
    let shot = |lines: &Receiver<String>| {
        xdotool(&["key", "F12"]);
        let line = wait_line(lines, "screenshot of frame").expect("F12 saves a screenshot");
        let path = line.split("): ").nth(1).and_then(|p| p.split(" (animation").next()).expect("screenshot path");
        rgba(&image::open(path).expect("screenshot"))
    };
    let still = shot(&lines);
    assert_eq!(still.as_raw(), shot(&lines).as_raw(), "paused and untouched, two frames must be the same");
    xdotool(&["mousemove", "--window", &id, "100", "100", "mousedown", "1"]);
    xdotool(&["mousemove", "--window", &id, "170", "130", "mouseup", "1"]);
    let orbited = shot(&lines);
    assert_ne!(still.as_raw(), orbited.as_raw(), "a left drag must orbit the camera");
    xdotool(&["keydown", "Right"]);
    std::thread::sleep(Duration::from_millis(600));
    xdotool(&["keyup", "Right"]);
    let lit = shot(&lines);
    assert_ne!(orbited.as_raw(), lit.as_raw(), "the right arrow must move the light");
    xdotool(&["key", "Escape"]);
    let status = child.wait().expect("example exit");
    let stderr = errors.join().unwrap_or_default();
    let rest: Vec<String> = lines.iter().collect();
    println!("{}", rest.join("\n"));
    assert!(status.success(), "Esc must quit cleanly: {status}\n{stderr}");
    assert!(
        rest.iter().any(|l| l == "validation messages: 0 errors, 0 warnings"),
        "validation messages:\n{}\n{stderr}",
        rest.join("\n")
    );
}

/// Starts example `name` with `args` and `out` on display `x`, validation on: the child, its
/// stderr (read to the end on a thread) and its stdout lines as they come.
fn spawn_windowed(
    name: &str,
    x: &Xvfb,
    args: &[String],
    out: &Path,
) -> (Child, std::thread::JoinHandle<String>, Receiver<String>) {
    let mut child = Command::new(common::example(name))
        .args(args)
        .arg(out)
        .env("DISPLAY", &x.display)
        .env("UMBRA_VALIDATION", "1")
        .env("RUST_BACKTRACE", "0")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the example");
    let stderr = child.stderr.take().expect("piped stderr");
    let errors = std::thread::spawn(move || std::io::read_to_string(stderr).unwrap_or_default());
    let lines = lines_of(child.stdout.take().expect("piped stdout"));
    (child, errors, lines)
}

/// Lines of a child's output, as they come.
fn lines_of(out: impl std::io::Read + Send + 'static) -> Receiver<String> {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            if send.send(line).is_err() {
                break;
            }
        }
    });
    receive
}

/// The next line starting with `prefix` (others are skipped), within a minute and a half;
/// `None` when the output ends first.
fn wait_line(lines: &Receiver<String>, prefix: &str) -> Option<String> {
    let deadline = Instant::now() + Duration::from_secs(90);
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        match lines.recv_timeout(left) {
            Ok(l) if l.starts_with(prefix) => return Some(l),
            Ok(_) => {}
            Err(RecvTimeoutError::Disconnected) => return None,
            Err(RecvTimeoutError::Timeout) => panic!("no line starting with {prefix:?} in 90 s"),
        }
    }
}

/// On SwiftShader, whose ICD has no X11 surface extension, the example must stop with its
/// typed "unsupported" error; the skip is printed. Anywhere else nothing is skipped.
fn skipped_on_swiftshader(name: &str, stderr: &str) -> bool {
    let device = std::env::var("UMBRA_DEVICE").unwrap_or_default().to_lowercase();
    let unsupported = stderr.contains("unsupported on") && stderr.contains("window");
    if device.contains("swiftshader") && unsupported {
        println!(
            "SKIPPED {name} --window on SwiftShader: its ICD has no X11 surface extension, and the example \
             said so with its typed error; covered on lavapipe"
        );
        return true;
    }
    false
}

/// An Xvfb server on a display of its own, stopped on drop.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    fn start() -> Self {
        static NEXT: AtomicU32 = AtomicU32::new(0);
        let base = 200 + (std::process::id() % 400) * 8;
        for _ in 0..32 {
            let n = base + NEXT.fetch_add(1, Ordering::Relaxed);
            if Path::new(&format!("/tmp/.X{n}-lock")).exists() {
                continue;
            }
            let child = Command::new("Xvfb")
                .args([format!(":{n}").as_str(), "-screen", "0", "1024x768x24", "-nolisten", "tcp"])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .expect("Xvfb (Debian package xvfb; run ci/setup.sh)");
            let mut server = Xvfb { child, display: format!(":{n}") };
            let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
            let deadline = Instant::now() + Duration::from_secs(20);
            while Instant::now() < deadline {
                if socket.exists() {
                    return server;
                }
                if let Ok(Some(_)) = server.child.try_wait() {
                    break; // lost a race for this display: try the next
                }
                std::thread::sleep(Duration::from_millis(50));
            }
        }
        panic!("could not start Xvfb on any display");
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// What the windowed run printed and wrote.
struct WindowedRun {
    stdout: String,
    stderr: String,
    success: bool,
    /// The X screenshot of the window, taken while the run held its last frame.
    xwd: Option<Vec<u8>>,
}

fn run_windowed(name: &str, x: &Xvfb, screenshot: &Path, out: &Path) -> WindowedRun {
    let args = [
        "--window".into(),
        "--frames".into(),
        FRAMES.to_string(),
        "--size".into(),
        format!("{}x{}", START.0, START.1),
        "--resize-at".into(),
        format!("{}:{}x{}", FRAMES / 2, RESIZED.0, RESIZED.1),
        "--screenshot".into(),
        screenshot.display().to_string(),
        "--hold".into(),
        "3".into(),
        "--out".into(),
    ];
    let (mut child, errors, lines) = spawn_windowed(name, x, &args, out);
    let mut stdout = String::new();
    let mut window = None;
    let mut xwd = None;
    for line in lines {
        if let Some(id) = line.strip_prefix("window id ") {
            window = Some(id.trim().to_owned());
        }
        if line.starts_with("holding the last frame") {
            let id = window.clone().expect("the example printed its window id");
            xwd = Some(capture_xwd(&x.display, &id));
        }
        stdout += &line;
        stdout.push('\n');
    }
    let status = child.wait().expect("example exit");
    WindowedRun { stdout, stderr: errors.join().unwrap_or_default(), success: status.success(), xwd }
}

/// `xwd -id` of the window, from outside the process.
fn capture_xwd(display: &str, id: &str) -> Vec<u8> {
    let out = Command::new("xwd")
        .args(["-silent", "-id", id, "-display", display])
        .output()
        .expect("xwd (Debian package x11-apps; run ci/setup.sh)");
    assert!(out.status.success(), "xwd failed: {}", String::from_utf8_lossy(&out.stderr));
    out.stdout
}

fn check_example(name: &str, headless_png: &str) {
    let dir = common::output_dir(&format!("window-{name}"));
    let x = Xvfb::start();
    let shot = dir.join("window.png");
    let _ = std::fs::remove_file(&shot);
    let run = run_windowed(name, &x, &shot, &dir);
    if !run.success && skipped_on_swiftshader(name, &run.stderr) {
        return;
    }
    assert!(run.success, "{name} --window failed\nstdout:\n{}\nstderr:\n{}", run.stdout, run.stderr);
    println!("{}", run.stdout.lines().filter(|l| !l.starts_with("  ")).collect::<Vec<_>>().join("\n"));
    assert!(run.stdout.contains(&format!("presented {FRAMES} frames")), "{name}: not {FRAMES} frames:\n{}", run.stdout);
    let recreations = count_before(&run.stdout, " swapchain recreation(s)");
    assert!(recreations >= 1, "{name}: the resize did not recreate the swapchain:\n{}", run.stdout);
    // Nothing per frame: a staging buffer per frame in flight (2) per size, one capture buffer.
    let buffers = count_before(&run.stdout, " presentation buffer(s) allocated");
    assert!(
        buffers <= 2 * (recreations + 1) + 1,
        "{name}: {buffers} presentation buffers for {FRAMES} frames and {recreations} recreations"
    );
    assert!(
        run.stdout.contains("validation messages: 0 errors, 0 warnings"),
        "{name}: validation messages:\n{}\n{}",
        run.stdout,
        run.stderr
    );
    let line = run.stdout.lines().find(|l| l.starts_with("screenshot of frame")).expect("a screenshot line");
    assert!(line.contains(&format!("({}x{})", RESIZED.0, RESIZED.1)), "{name}: screenshot not at the new size: {line}");
    let time = line.rsplit("--time ").next().and_then(|t| t.strip_suffix(')')).expect("the screenshot's time");

    // The same frame headless: same size, same animation time, no window.
    let headless = dir.join("headless");
    let out = Command::new(common::example(name))
        .args(["--size", &format!("{}x{}", RESIZED.0, RESIZED.1), "--time", time, "--warmup", "0", "--out"])
        .arg(&headless)
        .env("UMBRA_VALIDATION", "1")
        .output()
        .expect("headless run");
    assert!(out.status.success(), "{name} headless failed: {}", String::from_utf8_lossy(&out.stderr));
    let window = rgba(&image::open(&shot).expect("window screenshot"));
    let reference = rgba(&image::open(headless.join(headless_png)).expect("headless render"));
    let diff = max_difference(&window, &reference);
    println!("{name}: window screenshot vs headless render at --time {time}: max difference {diff}/255");
    assert!(diff <= 1, "{name}: the window's frame differs from the headless render by {diff}/255");

    // What the X server shows in the window, read from outside the process.
    let xwd = run.xwd.expect("an xwd capture while the last frame was held");
    let shown = decode_xwd(&xwd);
    std::fs::write(dir.join("xwd.xwd"), &xwd).expect("write xwd");
    shown.save(dir.join("xwd.png")).expect("write xwd.png");
    let diff = max_difference(&without_alpha(&shown), &without_alpha(&window));
    println!("{name}: xwd of the window vs the screenshot: max difference {diff}/255");
    assert!(diff <= 1, "{name}: the X server shows pixels {diff}/255 away from the presented frame");
}

/// The number just before `suffix` in the run's summary line.
fn count_before(stdout: &str, suffix: &str) -> u32 {
    let line = stdout.lines().find(|l| l.contains(suffix)).unwrap_or_else(|| panic!("no {suffix:?} in:\n{stdout}"));
    let before = &line[..line.find(suffix).unwrap_or(0)];
    before
        .rsplit(' ')
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no count before {suffix:?}: {line}"))
}

fn rgba(img: &image::DynamicImage) -> image::RgbaImage {
    img.to_rgba8()
}

fn without_alpha(img: &image::RgbaImage) -> image::RgbaImage {
    let mut out = img.clone();
    out.pixels_mut().for_each(|p| p.0[3] = 255);
    out
}

/// Largest per-channel difference; the sizes must match.
fn max_difference(a: &image::RgbaImage, b: &image::RgbaImage) -> u8 {
    assert_eq!(a.dimensions(), b.dimensions(), "image sizes differ");
    a.as_raw().iter().zip(b.as_raw()).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0)
}

/// Decodes an XWD dump of a 24/32-bit TrueColor window (what Xvfb `-screen 0 WxHx24` gives).
fn decode_xwd(data: &[u8]) -> image::RgbaImage {
    let field = |i: usize| u32::from_be_bytes(data[4 * i..4 * i + 4].try_into().expect("xwd header"));
    let (header, depth, width, height) = (field(0) as usize, field(3), field(4), field(5));
    let (byte_order, bits_per_pixel, bytes_per_line) = (field(7), field(11), field(12) as usize);
    let (red, green, blue, colors) = (field(14), field(15), field(16), field(19) as usize);
    assert!(depth == 24 && bits_per_pixel == 32, "xwd: depth {depth}, {bits_per_pixel} bits per pixel");
    let pixels = &data[header + 12 * colors..];
    image::RgbaImage::from_fn(width, height, |x, y| {
        let at = y as usize * bytes_per_line + 4 * x as usize;
        let b: [u8; 4] = pixels[at..at + 4].try_into().expect("xwd pixel");
        let v = if byte_order == 0 { u32::from_le_bytes(b) } else { u32::from_be_bytes(b) };
        let channel = |mask: u32| ((v & mask) >> mask.trailing_zeros()) as u8;
        image::Rgba([channel(red), channel(green), channel(blue), 255])
    })
}
