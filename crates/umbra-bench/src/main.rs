//! The `umbra-bench` binary: see the library's documentation (`umbra_bench`) for what each
//! subcommand measures and writes.

fn main() {
    umbra_bench::cli::main();
}
