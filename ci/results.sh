#!/usr/bin/env bash
# Regenerates the measurements behind docs/results.md: the umbra-bench sweep on lavapipe and on
# SwiftShader (and on any other device named in UMBRA_RESULTS_DEVICES, e.g. a GPU's name whose
# ICD file UMBRA_EXTRA_ICDS adds), each
# into docs/results/<device>/ (summary.md, results.csv, results.json) with its plots copied to
# docs/images/results/<device>/. The reading in docs/results.md is written from these.
# Installs what it needs first (ci/setup.sh). Builds the dev profile, as the tests do (umbra at
# opt-level 1, its dependencies at 2): the GPU times are the driver's whatever umbra's profile,
# and a release build would add about 15 minutes on 2 cores; the host-side columns (CPU
# silhouette ms, BVH build ms) are the dev profile's.
set -euo pipefail
cd "$(dirname "$0")/.."

# shellcheck source=ci/drivers.sh
source ci/drivers.sh
export VK_ICD_FILENAMES="$VK_ICD_FILENAMES${UMBRA_EXTRA_ICDS:+:$UMBRA_EXTRA_ICDS}"
export VK_DRIVER_FILES="$VK_ICD_FILENAMES"
cargo build --locked -p umbra-bench

# SwiftShader runs about six times slower than lavapipe here: it gets a smaller sweep.
sweep_args() {
    case "$1" in
        swiftshader) echo "--scenes cubes,cage,tree,cylinder,spot.glb,suzanne.glb --sm-sizes 64,512,2048 --filters pcf2x2 --masks depth-bounds --frames 3 --warmup 1" ;;
        *) echo "--scenes cubes,cage,tree,cylinder,spot.glb,suzanne.glb --sm-sizes 64,256,512,1024,2048 --filters nearest,pcf2x2 --masks depth-bounds,stencil,none --frames 5 --warmup 2" ;;
    esac
}

for device in ${UMBRA_RESULTS_DEVICES:-llvmpipe swiftshader}; do
    out="target/results/$device"
    rm -rf "$out"
    # shellcheck disable=SC2046
    UMBRA_DEVICE=$device "$CARGO_TARGET_DIR/debug/umbra-bench" sweep $(sweep_args "$device") \
        --techniques sm,silmap,sv,hybrid,rt,hybrid-rt --size 512x384 --spot-lights --quiet --out "$out"
    mkdir -p "docs/results/$device" "docs/images/results/$device"
    cp "$out/summary.md" "$out/results.csv" "$out/results.json" "docs/results/$device/"
    cp "$out"/*.png "docs/images/results/$device/"
    # The summary sits one folder away from its plots.
    sed -i "s|!\\[\\(.*\\)\\](\\(.*\\.png\\))|![\\1](../../images/results/$device/\\2)|" "docs/results/$device/summary.md"
done
