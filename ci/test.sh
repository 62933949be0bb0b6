#!/usr/bin/env bash
# Runs umbra's whole test suite on three Vulkan drivers, with the Khronos validation layer on:
# Mesa 25's lavapipe (UMBRA_DEVICE=llvmpipe-mesa-25), Debian 12's Mesa 22 lavapipe
# (llvmpipe-mesa-22) and SwiftShader (swiftshader). Fails if any run fails. Installs what it
# needs first (ci/setup.sh; idempotent, needs root the first time).
set -euo pipefail
cd "$(dirname "$0")/.."

# shellcheck source=ci/drivers.sh
source ci/drivers.sh
export UMBRA_VALIDATION=1
export RUST_BACKTRACE=1

echo "== cargo fmt --check"
cargo fmt --all -- --check

echo "== cargo clippy (warnings are errors, missing rustdoc included)"
cargo clippy --workspace --all-targets --locked -- -D warnings

echo "== rustdoc (warnings are errors)"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --locked

echo "== cargo package (every crate packages on its own: its files, licences and GLSL inside it)"
cargo package --workspace --no-verify --locked --allow-dirty --quiet
ls "${CARGO_TARGET_DIR}"/package/*.crate | sed 's|.*/|  packaged |'
# umbra-shaders' build.rs compiles the GLSL inside its own package: every file must be there.
shipped=$(tar -tzf "${CARGO_TARGET_DIR}"/package/umbra-shaders-*.crate | sed -n 's|^umbra-shaders-[^/]*/shaders-glsl/||p' | sort)
missing=$(cd shaders-glsl && find . -type f | sed 's|^\./||' | sort | comm -23 - <(echo "$shipped"))
[ -z "$missing" ] || { echo "umbra-shaders' package lacks: $missing" >&2; exit 1; }

echo "== build"
cargo build --workspace --all-targets --locked

failed=()
for device in $UMBRA_DRIVERS; do
    echo "== tests on $device (validation on)"
    if ! UMBRA_DEVICE=$device cargo test --workspace --locked --no-fail-fast -- --test-threads=2 --show-output; then
        failed+=("$device")
    fi
done

if [ ${#failed[@]} -gt 0 ]; then
    echo "test: FAILED on ${failed[*]}" >&2
    exit 1
fi
echo "test: all tests passed on $UMBRA_DRIVERS"
