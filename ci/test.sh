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
logs="${CARGO_TARGET_DIR}/test-logs"
mkdir -p "$logs"
rm -f "$logs"/*.log
for device in $UMBRA_DRIVERS; do
    echo "== tests on $device (validation on)"
    log="$logs/$device.log"
    if UMBRA_DEVICE=$device cargo test --workspace --locked --no-fail-fast -- --test-threads=2 --show-output 2>&1 |
        tee "$log"; then
        continue
    fi
    # A test binary that died of a signal (the process, not an assertion) is run once more,
    # and said so: drivers and the validation layer have crashed a test process
    # intermittently. A failed assertion, or a second crash, fails the suite.
    if ! bash ci/rerun-crashed.sh "$device" "$log"; then
        failed+=("$device")
    fi
done

if [ ${#failed[@]} -gt 0 ]; then
    # The log's tail is what a CI summary shows: what failed, after everything else.
    for device in "${failed[@]}"; do
        echo "== what failed on $device (whole log: $logs/$device.log)"
        bash ci/failures.sh "$logs/$device.log"
    done
    echo "test: FAILED on ${failed[*]}" >&2
    exit 1
fi
# A crash that passed when run again is not hidden: the last lines say so.
grep -h "when run again, after a crash" "$logs"/*.log || true
echo "test: all tests passed on $UMBRA_DRIVERS"
