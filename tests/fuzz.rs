//! A mutation fuzzer for umbra's loaders (glTF JSON, `.glb`, TOML scene files), run as a test.
//!
//! Seeds are the repository's own inputs: the hard-case scenes, the bad-input corpus and the
//! small assets. Each case takes one seed and applies one to four mutations — byte flips,
//! insertions, deletions and truncation on the raw bytes, or, structure-aware, a JSON or TOML
//! value swapped for an extreme one (`0`, `-1`, `2³²−1`, `2⁶³`, `1e38`, `nan`, `inf`, a huge
//! index), a key deleted, an array emptied or doubled — and loads the result. A case passes
//! when the loader returns (`Ok` or a typed error) without panicking. A panicking input is
//! written to `$CARGO_TARGET_TMPDIR/fuzz-crashes/` and named in the failure, to be added to
//! `tests/bad-input/` with its expected answer.
//!
//! CI runs `UMBRA_FUZZ_CASES` (default 10 000) cases in each of its three runs, from seed 1
//! (`UMBRA_DEVICE=llvmpipe-mesa-22`), 2 (`swiftshader`) and 3 (`llvmpipe-mesa-25`; 0
//! otherwise); the longer run is
//! `UMBRA_FUZZ_CASES=200000 UMBRA_FUZZ_SEED=$RANDOM cargo test --release --test fuzz -- --nocapture`.

mod common;

use std::path::{Path, PathBuf};

/// SplitMix64: small, seedable, good enough to pick mutations.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Gltf,
    Glb,
    Toml,
}

struct Seed {
    path: PathBuf,
    kind: Kind,
    bytes: Vec<u8>,
}

fn seeds() -> Vec<Seed> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for dir in ["tests/hard-cases", "tests/bad-input", "assets"] {
        let mut entries: Vec<PathBuf> =
            std::fs::read_dir(root.join(dir)).expect("seed folder").map(|e| e.unwrap().path()).collect();
        entries.sort();
        for path in entries {
            let kind = match path.extension().and_then(|e| e.to_str()) {
                Some("gltf") => Kind::Gltf,
                Some("glb") if std::fs::metadata(&path).unwrap().len() < 200_000 => Kind::Glb,
                Some("toml") if path.file_name().is_some_and(|n| n != "expected.toml") => Kind::Toml,
                _ => continue,
            };
            let bytes = std::fs::read(&path).unwrap();
            out.push(Seed { path, kind, bytes });
        }
    }
    out
}

const EXTREMES: &[&str] = &[
    "0",
    "-1",
    "1",
    "3",
    "255",
    "65535",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "1e38",
    "-1e38",
    "1e-38",
    "1e11",
    "0.5",
    "99",
];

/// A JSON or TOML number literal (JSON gets no `nan`/`inf`; TOML does).
fn extreme(rng: &mut Rng, toml: bool) -> String {
    let specials = ["nan", "inf", "-inf", "-0.0"];
    if toml && rng.below(5) == 0 {
        return specials[rng.below(specials.len())].to_string();
    }
    EXTREMES[rng.below(EXTREMES.len())].to_string()
}

/// Descends `depth` levels into `v` along random children, then mutates what it finds.
fn mutate_json(v: &mut serde_json::Value, rng: &mut Rng) {
    let depth = rng.below(8) + 1;
    mutate_json_at(v, depth, rng);
}

fn mutate_json_at(v: &mut serde_json::Value, depth: usize, rng: &mut Rng) {
    use serde_json::Value;
    if depth > 0 {
        match v {
            Value::Array(a) if !a.is_empty() => {
                let i = rng.below(a.len());
                return mutate_json_at(&mut a[i], depth - 1, rng);
            }
            Value::Object(o) if !o.is_empty() => {
                let i = rng.below(o.len());
                if let Some(child) = o.values_mut().nth(i) {
                    return mutate_json_at(child, depth - 1, rng);
                }
            }
            _ => {}
        }
    }
    match (v, rng.below(4)) {
        (Value::Object(o), 0) if !o.is_empty() => {
            let k = o.keys().nth(rng.below(o.len())).cloned().unwrap_or_default();
            o.remove(&k);
        }
        (Value::Array(a), 1) => {
            let copy = a.clone();
            a.extend(copy);
        }
        (Value::Array(a), 2) => a.clear(),
        (n, _) => *n = serde_json::from_str(&extreme(rng, false)).unwrap_or(Value::Null),
    }
}

fn mutate_toml(text: &str, rng: &mut Rng) -> String {
    // Replace one number literal (or append a key line) textually: keeps the TOML parseable
    // more often than byte flips do.
    let numbers: Vec<(usize, usize)> = {
        let b = text.as_bytes();
        let mut spans = Vec::new();
        let mut i = 0;
        while i < b.len() {
            if b[i].is_ascii_digit() && (i == 0 || !b[i - 1].is_ascii_alphanumeric() && b[i - 1] != b'_') {
                let start = i;
                while i < b.len() && (b[i].is_ascii_alphanumeric() || b"._+-".contains(&b[i])) {
                    i += 1;
                }
                spans.push((start, i));
            }
            i += 1;
        }
        spans
    };
    if numbers.is_empty() || rng.below(6) == 0 {
        let keys = ["repeat", "segments", "rings", "depth", "shadow_map_size", "range", "intensity", "near", "far"];
        return format!("{text}\n{} = {}\n", keys[rng.below(keys.len())], extreme(rng, true));
    }
    let (a, b) = numbers[rng.below(numbers.len())];
    format!("{}{}{}", &text[..a], extreme(rng, true), &text[b..])
}

fn mutate_bytes(bytes: &mut Vec<u8>, rng: &mut Rng) {
    if bytes.is_empty() {
        bytes.push(rng.next() as u8);
        return;
    }
    let at = rng.below(bytes.len());
    match rng.below(4) {
        0 => bytes[at] ^= 1 << rng.below(8),
        1 => bytes[at] = [0, 0xff, b'"', b'{', b'9', b'-'][rng.below(6)],
        2 => {
            bytes.remove(at);
        }
        _ => bytes.truncate(at),
    }
}

/// The GLB's JSON chunk as a value, and a rebuilder that puts a mutated one back.
fn glb_json(bytes: &[u8]) -> Option<(serde_json::Value, Vec<u8>)> {
    let len = u32::from_le_bytes(bytes.get(12..16)?.try_into().ok()?) as usize;
    let json = serde_json::from_slice(bytes.get(20..20 + len)?).ok()?;
    Some((json, bytes.get(20 + len..)?.to_vec()))
}

fn glb(json: &serde_json::Value, rest: &[u8]) -> Vec<u8> {
    let mut text = serde_json::to_vec(json).unwrap();
    text.resize(text.len().div_ceil(4) * 4, b' ');
    let total = 12 + 8 + text.len() + rest.len();
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((text.len() as u32).to_le_bytes());
    out.extend(0x4E4F_534Au32.to_le_bytes());
    out.extend(text);
    out.extend(rest);
    out
}

fn mutated(seed: &Seed, rng: &mut Rng) -> Vec<u8> {
    let mut bytes = seed.bytes.clone();
    for _ in 0..rng.below(4) + 1 {
        let structured = rng.below(4) != 0;
        bytes = match (seed.kind, structured) {
            (Kind::Gltf, true) => match serde_json::from_slice::<serde_json::Value>(&bytes) {
                Ok(mut v) => {
                    mutate_json(&mut v, rng);
                    serde_json::to_vec(&v).unwrap()
                }
                Err(_) => bytes,
            },
            (Kind::Glb, true) => match glb_json(&bytes) {
                Some((mut v, rest)) => {
                    mutate_json(&mut v, rng);
                    glb(&v, &rest)
                }
                None => bytes,
            },
            (Kind::Toml, true) => mutate_toml(&String::from_utf8_lossy(&bytes), rng).into_bytes(),
            (_, false) => {
                mutate_bytes(&mut bytes, rng);
                bytes
            }
        };
    }
    bytes
}

/// Loads `bytes` as the seed's kind would be loaded.
fn load(seed: &Seed, bytes: &[u8]) -> Option<umbra::scene::Scene> {
    match seed.kind {
        Kind::Gltf | Kind::Glb => umbra::scene::import_gltf_slice(bytes, "fuzz").ok(),
        Kind::Toml => {
            let dir = seed.path.parent().unwrap_or(Path::new("."));
            umbra::scene::parse_scene(&String::from_utf8_lossy(bytes), dir, "fuzz").ok()
        }
    }
}

/// `UMBRA_FUZZ_SEED`, else one fixed seed per CI driver run (ci/drivers.sh's names), so the
/// suite's three runs fuzz different cases.
fn fuzz_seed() -> u64 {
    let default = match std::env::var("UMBRA_DEVICE").as_deref() {
        Ok("llvmpipe-mesa-22" | "llvmpipe") => 1,
        Ok("swiftshader") => 2,
        Ok("llvmpipe-mesa-25") => 3,
        _ => 0,
    };
    env_u64("UMBRA_FUZZ_SEED", default)
}

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

#[test]
fn mutated_scenes_never_panic_the_loaders() {
    let seeds = seeds();
    assert!(seeds.len() >= 60, "only {} seeds", seeds.len());
    let cases = env_u64("UMBRA_FUZZ_CASES", 10_000);
    let seed = fuzz_seed();
    let mut rng = Rng(seed);
    let crashes_dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz-crashes");
    let (mut loaded, mut crashes) = (0u64, Vec::new());
    // Panics on this thread are caught and reported below; other tests' panics print as usual.
    let fuzzing = std::thread::current().id();
    let report: std::sync::Arc<dyn Fn(&std::panic::PanicHookInfo) + Send + Sync> = std::panic::take_hook().into();
    let others = report.clone();
    std::panic::set_hook(Box::new(move |info| {
        if std::thread::current().id() != fuzzing {
            others(info)
        }
    }));
    let start = std::time::Instant::now();
    for case in 0..cases {
        let s = &seeds[rng.below(seeds.len())];
        let bytes = mutated(s, &mut rng);
        match std::panic::catch_unwind(|| load(s, &bytes).is_some()) {
            Ok(ok) => loaded += ok as u64,
            Err(panic) => {
                let why = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()));
                std::fs::create_dir_all(&crashes_dir).unwrap();
                let ext = s.path.extension().unwrap().to_string_lossy();
                let file = crashes_dir.join(format!("case-{seed}-{case}.{ext}"));
                std::fs::write(&file, &bytes).unwrap();
                crashes.push(format!("{} (from {}): {}", file.display(), s.path.display(), why.unwrap_or_default()));
            }
        }
    }
    let _ = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| report(info)));
    println!(
        "fuzz: {cases} cases from seed {seed} over {} seed files in {:.1} s: {loaded} loaded, {} typed errors, {} panics",
        seeds.len(),
        start.elapsed().as_secs_f64(),
        cases - loaded - crashes.len() as u64,
        crashes.len()
    );
    assert!(crashes.is_empty(), "{} panicking inputs:\n{}", crashes.len(), crashes.join("\n"));
}

/// Mutated scenes that load are drawn by the renderer on the suite's device (every light with
/// the technique it asks for, shadow volumes where it asks for none): each frame is a frame or
/// a typed error, and the validation layer stays silent. `UMBRA_FUZZ_RENDERS` (default 100).
#[test]
fn mutated_scenes_that_load_render_validation_clean() {
    let seeds = seeds();
    let renders = env_u64("UMBRA_FUZZ_RENDERS", 100);
    let mut rng = Rng(fuzz_seed() ^ 0x5EED);
    common::with_context(|ctx| {
        let desc = umbra::shadows::RendererDesc::new(64, 48);
        let mut renderer = umbra::shadows::Renderer::new(ctx, desc).expect("renderer");
        let (mut frames, mut refused, mut tries) = (0, Vec::new(), 0);
        while frames + refused.len() < renders as usize && tries < 100_000 {
            tries += 1;
            let s = &seeds[rng.below(seeds.len())];
            let Some(mut scene) = load(s, &mutated(s, &mut rng)) else { continue };
            for light in scene.lights.iter_mut().filter(|l| l.technique == umbra::scene::Technique::Unshadowed) {
                light.technique = umbra::scene::Technique::ShadowVolume;
            }
            match renderer.render(&scene) {
                Ok(_) => frames += 1,
                Err(e) => refused.push(format!("{} (from {}): {e}", scene.name, s.path.display())),
            }
        }
        println!("fuzz renders: {frames} frames, {} typed errors, after {tries} mutations", refused.len());
        for r in &refused {
            println!("  refused: {r}");
        }
        assert!(frames > 0, "no mutated scene rendered");
    });
}
