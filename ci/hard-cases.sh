#!/usr/bin/env bash
# Regenerates docs/hard-cases.md, docs/images/hard-cases/ and docs/results/hard-cases.json:
# the hard-case conformance suite on the three CPU drivers of ci/drivers.sh (Mesa 25's lavapipe,
# whose images the page shows, Debian 12's Mesa 22 lavapipe and SwiftShader), validation on.
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=ci/drivers.sh
source ci/drivers.sh
cargo run --release -p umbra-bench -- hard-cases --devices "${UMBRA_DRIVERS// /,}" --out docs
