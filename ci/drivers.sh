# Sourced by ci/test.sh, ci/results.sh and ci/hard-cases.sh: installs what umbra needs
# (ci/setup.sh; idempotent, root the first time), finds the three CPU drivers' ICDs and exports
# the persistent CARGO_TARGET_DIR (shaderc's C++ build is paid once per machine),
# VK_ICD_FILENAMES with exactly those three drivers, so that UMBRA_DEVICE picks among them, and
# UMBRA_DRIVERS, their UMBRA_DEVICE names, the current driver first:
#   llvmpipe-mesa-25  Mesa 25's lavapipe, unpacked from bookworm-backports into umbra's cache
#   llvmpipe-mesa-22  Debian 12's own lavapipe (mesa-vulkan-drivers 22.3.6)
#   swiftshader       SwiftShader, unpacked from npm into umbra's cache
if [ "$(id -u)" -eq 0 ]; then
    setup_out=$(bash ci/setup.sh)
else
    setup_out=$(sudo -E bash ci/setup.sh)
fi
sws_icd=$(sed -n 's/^swiftshader //p' <<<"$setup_out")
lvp25_icd=$(sed -n 's/^lavapipe-25 //p' <<<"$setup_out")
lvp22_icd=$(ls /usr/share/vulkan/icd.d/lvp_icd.*.json 2>/dev/null | head -n 1)
[ -f "$lvp22_icd" ] || { echo "ci: lavapipe ICD not found (mesa-vulkan-drivers)" >&2; exit 1; }
[ -f "$lvp25_icd" ] || { echo "ci: Mesa 25 lavapipe ICD not found ($lvp25_icd)" >&2; exit 1; }
[ -f "$sws_icd" ] || { echo "ci: SwiftShader ICD not found ($sws_icd)" >&2; exit 1; }
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/umbra/target}"
export VK_ICD_FILENAMES="$lvp25_icd:$lvp22_icd:$sws_icd"
export VK_DRIVER_FILES="$VK_ICD_FILENAMES"
export UMBRA_DRIVERS="llvmpipe-mesa-25 llvmpipe-mesa-22 swiftshader"
