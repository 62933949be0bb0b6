#!/usr/bin/env bash
# The results sweep on a real GPU, in under 8 minutes (a GPU machine may be lent for minutes
# only). Writes docs/results/<device>/ (summary.md, results.csv, results.json, the plots and the
# poster), named after the device as Vulkan reports it.
#
#   bash ci/gpu-results.sh                 # on the GPU machine, in the repository's root
#
# What it needs, and how it gets it:
#   - the Vulkan loader (libvulkan.so.1): found, else `apt-get install libvulkan1` (as root, when
#     apt can reach Debian's packages), else unpacked from .gl/*.deb if those were carried in;
#   - the GPU's ICD: the system's, or NVIDIA's container path (/usr/local/nvidia/...);
#   - umbra-bench: $UMBRA_BENCH, else target/release/umbra-bench carried in (built elsewhere
#     with `cargo build --release -p umbra-bench`), else built here with cargo.
# UMBRA_DEVICE picks the device (default: the best type Vulkan offers, refused if that is a CPU
# driver);
# UMBRA_GPU_SWEEP_ARGS replaces the sweep's flags (e.g. for a quick check on lavapipe);
# UMBRA_GPU_BUDGET_S bounds the sweep's time (default 420 s; the poster runs after it).
set -euo pipefail
cd "$(dirname "$0")/.."

if ! ldconfig -p 2>/dev/null | grep -q 'libvulkan.so.1'; then
    if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null && apt-get install -y -q libvulkan1 >/dev/null 2>&1; then
        echo "gpu-results: installed libvulkan1"
    elif compgen -G ".gl/*.deb" >/dev/null; then
        for f in .gl/*.deb; do dpkg -x "$f" /; done
        ldconfig
        echo "gpu-results: unpacked the Vulkan loader from .gl/"
    else
        echo "gpu-results: no Vulkan loader (libvulkan.so.1) and no way to install one" >&2
        exit 1
    fi
fi
nvidia_icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if [ -z "${VK_DRIVER_FILES:-}" ] && [ -f "$nvidia_icd" ] && ! ls /usr/share/vulkan/icd.d/nvidia* >/dev/null 2>&1; then
    export VK_DRIVER_FILES="$nvidia_icd" VK_ICD_FILENAMES="$nvidia_icd"
fi

bench="${UMBRA_BENCH:-}"
if [ -z "$bench" ]; then
    for candidate in target/release/umbra-bench "${CARGO_TARGET_DIR:-/nonexistent}/release/umbra-bench"; do
        [ -x "$candidate" ] && bench="$candidate" && break
    done
fi
if [ -z "$bench" ]; then
    command -v cargo >/dev/null || { echo "gpu-results: no umbra-bench binary and no cargo to build one" >&2; exit 1; }
    cargo build --release --locked -p umbra-bench
    bench="${CARGO_TARGET_DIR:-target}/release/umbra-bench"
fi

# The poster first (seconds): it names the device Vulkan picked (UMBRA_DEVICE, else the best
# type: a discrete GPU before an integrated one before a CPU driver).
tmp="target/results/gpu-results-$$"
rm -rf "$tmp"
started=$(date +%s)
"$bench" poster --size 512x384 --spot-lights --out "$tmp/poster"
device=$(sed -n 's/^  "device": "\(.*\)",$/\1/p' "$tmp/poster/poster.json" | head -n 1)
if [ -z "${UMBRA_GPU_SWEEP_ARGS:-}" ] && echo "$device" | grep -q -i -E 'llvmpipe|swiftshader'; then
    echo "gpu-results: the device is $device, a CPU driver: no GPU here (ci/results.sh is for CPU drivers)" >&2
    exit 1
fi
slug=$(echo "$device" | tr '[:upper:]' '[:lower:]' | tr -c 'a-z0-9\n' '-' | sed 's/--*/-/g; s/^-//; s/-$//')
out="$tmp/sweep"
dest="docs/results/$slug"
echo "gpu-results: $device → $dest (bench: $bench)"

# Full size, every technique and option the CPU drivers' sweep has, 20 timed frames.
default_args="--scenes cubes,cage,tree,cylinder,spot.glb --techniques sm,silmap,sv,hybrid \
--sm-sizes 512,1024,2048,4096 --filters nearest,pcf2x2 --masks depth-bounds,stencil,none \
--size 1024x768 --frames 20 --warmup 3 --spot-lights"
# shellcheck disable=SC2086
timeout "${UMBRA_GPU_BUDGET_S:-420}" "$bench" sweep ${UMBRA_GPU_SWEEP_ARGS:-$default_args} --quiet --out "$out"
echo "gpu-results: poster and sweep took $(( $(date +%s) - started )) s"

rm -rf "$dest"
mkdir -p "$dest"
cp "$out"/summary.md "$out"/results.csv "$out"/results.json "$out"/*.png "$dest/"
cp "$tmp/poster/poster.png" "$tmp/poster/poster.json" "$dest/"
echo "gpu-results: wrote $(ls "$dest" | wc -l) files to $dest"
