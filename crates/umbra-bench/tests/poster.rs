//! `umbra-bench poster` through the real CLI: a poster PNG with every technique, a JSON with one
//! record per technique (the hybrids at the map size the renderer picks), and wrong-pixel counts
//! equal to those of the `umbra-bench sweep` command it names (run here too), configuration by
//! configuration.

use serde_json::Value;
use std::path::Path;
use std::process::Command;

fn bench(args: &[&str], out: &Path) {
    let status = Command::new(env!("CARGO_BIN_EXE_umbra-bench"))
        .args(args)
        .arg("--out")
        .arg(out)
        .status()
        .expect("umbra-bench runs");
    assert!(status.success(), "umbra-bench {args:?} exited with {status}");
}

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("JSON file")).expect("JSON")
}

#[test]
fn the_poster_shows_every_technique_and_agrees_with_the_sweep() {
    let dir = std::env::temp_dir().join(format!("umbra-poster-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let args =
        ["poster", "--scene", "cubes", "--size", "256x192", "--sm-size", "512", "--frames", "3", "--warmup", "1"];
    bench(&args, &dir.join("poster"));
    let poster = json(&dir.join("poster/poster.json"));
    let records = poster["records"].as_array().expect("records");
    let techniques: Vec<&str> = records.iter().filter_map(|r| r["technique"].as_str()).collect();
    let every: Vec<&str> = umbra_scene::Technique::SHADOWING.iter().map(|t| t.short()).collect();
    assert_eq!(techniques, every, "{poster}");
    let png = image::open(dir.join("poster/poster.png")).expect("poster.png decodes");
    assert!(png.width() > 4 * 256 && png.height() > 2 * 192, "{}x{}", png.width(), png.height());

    // The hybrids take the map size the renderer picks (none named), and say which it was.
    for r in records {
        let technique = r["technique"].as_str().unwrap_or_default();
        let named = r["sm_size"].as_u64();
        let picked = r["map_resolution"].as_u64();
        match technique {
            "sv" | "rt" => assert_eq!((named, picked), (None, None), "{technique}"),
            "hybrid" | "hybrid-rt" => assert!(named.is_none() && picked.is_some(), "{technique}: {named:?} {picked:?}"),
            _ => assert_eq!((named, picked), (Some(512), Some(512)), "{technique}"),
        }
    }

    // The sweep the poster names measures the same configurations (and the other size of
    // each map technique): same wrong pixels.
    let command = poster["bench_command"].as_str().expect("bench_command");
    assert!(command.contains("--sm-sizes 512,default"), "{command}");
    let sweep_args: Vec<&str> = command.split_whitespace().skip(1).chain(["--quiet"]).collect();
    bench(&sweep_args, &dir.join("sweep"));
    let sweep = json(&dir.join("sweep/results.json"));
    let swept = sweep["records"].as_array().expect("records");
    assert!(swept.len() > records.len(), "{command}");
    for r in records {
        let key = |r: &Value| [&r["technique"], &r["sm_size"], &r["filter"], &r["mask"]].map(Value::to_string);
        let twin = swept.iter().find(|s| key(s) == key(r)).unwrap_or_else(|| panic!("no sweep record for {r}"));
        println!(
            "{}: poster {} wrong of {}, sweep {} wrong of {}; GPU ms median poster {} sweep {} (p25–p75 {}–{})",
            key(r).join(" "),
            r["accuracy"]["all"]["wrong"],
            r["accuracy"]["all"]["compared"],
            twin["accuracy"]["all"]["wrong"],
            twin["accuracy"]["all"]["compared"],
            r["gpu_ms"]["median"],
            twin["gpu_ms"]["median"],
            twin["gpu_ms"]["p25"],
            twin["gpu_ms"]["p75"],
        );
        assert_eq!(r["accuracy"]["all"], twin["accuracy"]["all"], "{}", key(r).join(" "));
        // Every technique is scored against the reference (its visibility image, or its
        // classification where nothing shadowed the light).
        assert!(r["accuracy"]["all"]["compared"].as_u64() > Some(1000), "{} was not scored", key(r).join(" "));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
