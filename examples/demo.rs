//! umbra in one picture: one scene rendered with every technique (shadow map, silhouette map,
//! shadow volumes, hybrid, ray traced) on the same frame, each scored against the exact ray-traced
//! reference (`umbra-reference`), written as `out/poster.png` (per technique its image, its
//! error image and a caption with GPU ms and wrong pixels) and `out/poster.json`, with a table
//! on stdout. The same as `umbra-bench poster`; `poster.json` names the `umbra-bench sweep`
//! command that measures the same configurations.
//!
//! ```text
//! cargo run --release --example demo -- --scene cage --size 512x384 --sm-size 1024
//! ```

use clap::Parser;

#[derive(Parser, Debug)]
#[command(about = "Every umbra technique on one frame, scored against the exact reference, as one poster")]
struct Args {
    #[command(flatten)]
    poster: umbra_bench::poster::PosterArgs,
}

fn main() -> anyhow::Result<()> {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info")).init();
    let args = Args::parse();
    umbra_bench::poster::run_cli(&args.poster)?;
    Ok(())
}
