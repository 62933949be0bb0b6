#!/usr/bin/env bash
# Runs umbra's whole test suite twice: on lavapipe (UMBRA_DEVICE=llvmpipe) and on SwiftShader
# (UMBRA_DEVICE=swiftshader), with the Khronos validation layer on. Fails if either run fails.
# Installs what it needs first (ci/setup.sh; idempotent, needs root the first time).
set -euo pipefail
cd "$(dirname "$0")/.."

if [ "$(id -u)" -eq 0 ]; then
    sws_icd=$(bash ci/setup.sh | tail -n 1)
else
    sws_icd=$(sudo -E bash ci/setup.sh | tail -n 1)
fi
lvp_icd=$(ls /usr/share/vulkan/icd.d/lvp_icd.*.json 2>/dev/null | head -n 1)
[ -f "$lvp_icd" ] || { echo "test: lavapipe ICD not found (mesa-vulkan-drivers)" >&2; exit 1; }
[ -f "$sws_icd" ] || { echo "test: SwiftShader ICD not found ($sws_icd)" >&2; exit 1; }

# A persistent target dir outside the clone: shaderc's C++ build is paid once per machine.
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/umbra/target}"
# Only the two CPU drivers are visible, so UMBRA_DEVICE picks between exactly these.
export VK_ICD_FILENAMES="$lvp_icd:$sws_icd"
export VK_DRIVER_FILES="$VK_ICD_FILENAMES"
export UMBRA_VALIDATION=1
export RUST_BACKTRACE=1

echo "== cargo fmt --check"
cargo fmt --all -- --check

echo "== cargo clippy (warnings are errors, missing rustdoc included)"
cargo clippy --workspace --all-targets --locked -- -D warnings

echo "== rustdoc (warnings are errors)"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --locked

echo "== build"
cargo build --workspace --all-targets --locked

failed=()
for device in llvmpipe swiftshader; do
    echo "== tests on $device (validation on)"
    if ! UMBRA_DEVICE=$device cargo test --workspace --locked --no-fail-fast -- --test-threads=2 --show-output; then
        failed+=("$device")
    fi
done

if [ ${#failed[@]} -gt 0 ]; then
    echo "test: FAILED on ${failed[*]}" >&2
    exit 1
fi
echo "test: all tests passed on llvmpipe and swiftshader"
