#!/usr/bin/env bash
# Regenerates docs/hard-cases.md, docs/images/hard-cases/ and docs/results/hard-cases.json:
# the hard-case conformance suite on lavapipe and SwiftShader, validation layer on.
set -euo pipefail
cd "$(dirname "$0")/.."
source ci/drivers.sh
cargo run --release -p umbra-bench -- hard-cases --devices llvmpipe,swiftshader --out docs
