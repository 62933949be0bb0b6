#!/usr/bin/env bash
# Regenerates the measurements behind docs/results.md and the README's poster, on the three CPU
# drivers of ci/drivers.sh (Mesa 25's lavapipe first, then Debian 12's Mesa 22 lavapipe and
# SwiftShader; UMBRA_RESULTS_DEVICES names others, e.g. a GPU whose ICD file UMBRA_EXTRA_ICDS
# adds). Per device, one after the other on one machine:
#   - the poster (`umbra-bench poster` with the demo's defaults: cage, its point lights, 512×384)
#     into docs/results/<device>/; the first device's is also docs/images/poster.png, the README's picture
#   - the umbra-bench sweep into docs/results/<device>/ (summary.md, results.csv, results.json)
#     with its plots in docs/images/results/<device>/
# and then docs/results/drivers.md, the sweeps side by side (`umbra-bench compare`).
# The reading in docs/results.md is written from these. Installs what it needs first
# (ci/setup.sh). Builds the dev profile, as the tests do (umbra at opt-level 1, its dependencies
# at 2): the GPU times are the driver's whatever umbra's profile, and a release build would add
# about 15 minutes on 2 cores; the host-side columns (CPU silhouette ms, BVH build ms) are the
# dev profile's.
set -euo pipefail
cd "$(dirname "$0")/.."

# shellcheck source=ci/drivers.sh
source ci/drivers.sh
export VK_ICD_FILENAMES="$VK_ICD_FILENAMES${UMBRA_EXTRA_ICDS:+:$UMBRA_EXTRA_ICDS}"
export VK_DRIVER_FILES="$VK_ICD_FILENAMES"
cargo build --locked -p umbra-bench
bench="$CARGO_TARGET_DIR/debug/umbra-bench"

# SwiftShader runs about six times slower than lavapipe here: it gets a smaller sweep.
sweep_args() {
    case "$1" in
        swiftshader) echo "--scenes cubes,cage,tree,cylinder,spot.glb,suzanne.glb --sm-sizes 64,512,2048 --filters pcf2x2 --masks depth-bounds --frames 3 --warmup 1" ;;
        *) echo "--scenes cubes,cage,tree,cylinder,spot.glb,suzanne.glb --sm-sizes 64,256,512,1024,2048 --filters nearest,pcf2x2 --masks depth-bounds,stencil,none --frames 5 --warmup 2" ;;
    esac
}

first=""
compared=()
for device in ${UMBRA_RESULTS_DEVICES:-$UMBRA_DRIVERS}; do
    out="target/results/$device"
    rm -rf "$out"
    started=$(date +%s)
    UMBRA_DEVICE=$device "$bench" poster --out "$out/poster"
    # shellcheck disable=SC2046
    UMBRA_DEVICE=$device "$bench" sweep $(sweep_args "$device") \
        --size 512x384 --spot-lights --quiet --out "$out"
    echo "results: $device took $(( $(date +%s) - started )) s"
    rm -rf "docs/results/$device" "docs/images/results/$device"
    mkdir -p "docs/results/$device" "docs/images/results/$device"
    cp "$out/summary.md" "$out/results.csv" "$out/results.json" "$out/poster/poster.png" "$out/poster/poster.json" \
        "docs/results/$device/"
    cp "$out"/*.png "docs/images/results/$device/"
    # The summary sits one folder away from its plots.
    sed -i "s|!\\[\\(.*\\)\\](\\(.*\\.png\\))|![\\1](../../images/results/$device/\\2)|" "docs/results/$device/summary.md"
    compared+=("docs/results/$device/results.json")
    if [ -z "$first" ]; then
        first=$device
        cp "$out/poster/poster.png" docs/images/poster.png
    fi
done
"$bench" compare --results "$(IFS=,; echo "${compared[*]}")" --out docs/results/drivers.md
echo "results: docs/images/poster.png is $first's"
