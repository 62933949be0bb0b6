//! The bad-input corpus (`tests/bad-input/`): every file there is a hostile or malformed scene
//! that once panicked, aborted, read outside its folder or rendered garbage (issue #20), and
//! `expected.toml` says what `umbra::scene::load` must answer now — an error containing the
//! listed text, or a scene. A panic fails the test with the file's name; a file missing from
//! the manifest fails it too.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Case {
    /// The defect it reproduces (issue #20's list).
    #[allow(dead_code)]
    defect: String,
    /// Text the error must contain; absent: the file must load.
    error: Option<String>,
}

fn corpus() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/bad-input")
}

/// `expected.toml`: file name → its case.
fn manifest() -> BTreeMap<String, Case> {
    let text = std::fs::read_to_string(corpus().join("expected.toml")).expect("tests/bad-input/expected.toml");
    toml::from_str(&text).expect("expected.toml parses")
}

/// `load`'s answer for `path`: `Ok(None)` for a scene, `Ok(Some(message))` for an error, `Err`
/// for a panic.
fn outcome(path: &Path) -> Result<Option<String>, String> {
    let spec = path.to_string_lossy().into_owned();
    std::panic::catch_unwind(|| umbra::scene::load(&spec).err().map(|e| e.to_string()))
        .map_err(|p| p.downcast_ref::<String>().cloned().unwrap_or_else(|| "panic".into()))
}

#[test]
fn every_file_in_the_bad_input_corpus_gets_its_expected_answer() {
    let cases = manifest();
    let mut failures = Vec::new();
    let mut files: Vec<PathBuf> =
        std::fs::read_dir(corpus()).expect("corpus folder").map(|e| e.unwrap().path()).collect();
    files.sort();
    let mut seen = 0;
    for path in files.iter().filter(|p| p.file_name().is_some_and(|n| n != "expected.toml" && n != "README.md")) {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let got = outcome(path);
        seen += 1;
        match (cases.get(&name), &got) {
            (_, Err(panic)) => failures.push(format!("{name}: PANICKED: {panic}")),
            (None, Ok(answer)) => failures.push(format!("{name}: not in expected.toml; answered {answer:?}")),
            (Some(Case { error: None, .. }), Ok(Some(e))) => failures.push(format!("{name}: should load, got {e}")),
            (Some(Case { error: Some(want), .. }), Ok(None)) => failures.push(format!("{name}: loaded; want {want:?}")),
            (Some(Case { error: Some(want), .. }), Ok(Some(e))) if !e.contains(want.as_str()) => {
                failures.push(format!("{name}: {e}\n    does not contain {want:?}"))
            }
            _ => println!("{name}: {}", got.ok().flatten().unwrap_or_else(|| "loads".into())),
        }
    }
    for name in cases.keys().filter(|n| !corpus().join(n).exists()) {
        failures.push(format!("{name}: listed in expected.toml but missing"));
    }
    assert!(failures.is_empty(), "{} of {seen} corpus files:\n{}", failures.len(), failures.join("\n"));
}

/// A temporary folder for inputs that cannot live in the repository (FIFOs, links to devices).
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("umbra-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

#[test]
fn a_fifo_as_the_scene_is_refused_without_blocking() {
    let dir = scratch("fifo");
    let fifo = dir.join("scene.toml");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().expect("mkfifo").success());
    let e = umbra::scene::load(&fifo.to_string_lossy()).expect_err("a FIFO is no scene");
    assert!(e.to_string().contains("a FIFO, not a regular file"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn buffer_links_out_of_the_gltf_folder_are_not_followed() {
    let dir = scratch("links");
    let gltf = std::fs::read_to_string(corpus().join("gltf-uri-missing-bin.gltf")).unwrap();
    std::fs::write(dir.join("scene.gltf"), &gltf).unwrap();
    for target in ["/dev/zero", "/etc/passwd"] {
        let _ = std::fs::remove_file(dir.join("missing.bin"));
        std::os::unix::fs::symlink(target, dir.join("missing.bin")).unwrap();
        let e = umbra::scene::load(&dir.join("scene.gltf").to_string_lossy()).expect_err("a link out");
        assert!(e.to_string().contains("outside the glTF file's folder"), "{target}: {e}");
    }
    // From memory there is no folder at all: only embedded buffers.
    let e = umbra::scene::import_gltf_slice(gltf.as_bytes(), "memory").expect_err("no folder");
    assert!(e.to_string().contains("may only embed its buffers"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `Camera::MIN_NEAR_RATIO` refuses only a near plane whose depth cannot tell the scene's
/// farthest point from infinity: the open world of hard case 32 (near 0.1, 7e-7 of its reach)
/// is accepted, and its camera with the near plane just below the bound is refused, naming
/// depth precision. Hard case 07 sits just above `EXACT_NEAR_RATIO`, where shadow volumes are
/// measured exact.
#[test]
fn the_near_plane_bound_accepts_open_worlds_and_refuses_below_it() {
    let cases = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/hard-cases");
    let load = |file: &str| umbra::scene::load(&cases.join(file).to_string_lossy()).expect("the case loads");
    let bound = umbra::scene::Camera::MIN_NEAR_RATIO;
    let mut world = load("32-open-world-near-0-1-far-44-km.toml");
    let ratio = world.camera.near / world.camera_reach();
    println!("case 32: near / reach = {ratio:e}; bound {bound:e}");
    assert!(ratio < 1e-6 && ratio > bound, "case 32 should be an open world above the bound: {ratio:e}");
    world.validate().expect("an open world is accepted");
    world.camera.near = bound * world.camera_reach() * 0.99;
    let e = world.validate().expect_err("below the bound");
    assert!(e.to_string().contains("depth precision"), "{e}");
    world.camera.near = bound * world.camera_reach() * 1.01;
    world.validate().expect("just above the bound");

    let huge = load("07-huge-coordinates.toml");
    let ratio = huge.camera.near / huge.camera_reach();
    let exact = umbra::scene::Camera::EXACT_NEAR_RATIO;
    println!("case 07: near / reach = {ratio:e}; measured exact from {exact:e}");
    assert!((exact..exact * 1.25).contains(&ratio), "case 07 should sit just above the exact ratio: {ratio:e}");
}

/// `docs/input.md` tabulates the corpus: every file in it is listed there.
#[test]
fn the_input_document_lists_every_corpus_file() {
    let doc = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/input.md"))
        .expect("docs/input.md");
    let cases = manifest();
    let missing: Vec<_> = cases.keys().filter(|f| !doc.contains(&format!("`{f}`"))).collect();
    assert!(missing.is_empty(), "docs/input.md does not list {missing:?}");
}

/// The corpus files that load (a missing KTX2 texture, …) render on the suite's device with
/// the validation layer silent.
#[test]
fn corpus_files_that_load_render_validation_clean() {
    let cases = manifest();
    let loading: Vec<_> = cases.iter().filter(|(_, c)| c.error.is_none()).map(|(f, _)| f.clone()).collect();
    assert!(!loading.is_empty(), "the corpus has files that must load");
    common::with_context(|ctx| {
        let desc = umbra::shadows::RendererDesc::new(common::SIZE.0, common::SIZE.1);
        let mut renderer = umbra::shadows::Renderer::new(ctx, desc).expect("renderer");
        for file in &loading {
            let mut scene = umbra::scene::load(&corpus().join(file).to_string_lossy()).expect("loads");
            for light in &mut scene.lights {
                light.technique = umbra::scene::Technique::ShadowVolume;
            }
            let frame = renderer.render(&scene).unwrap_or_else(|e| panic!("{file}: {e}"));
            println!("{file}: {} triangles rendered on {}", frame.report.scene.triangles, frame.report.device);
        }
    });
}
