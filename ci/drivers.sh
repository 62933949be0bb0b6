# Sourced by ci/test.sh and ci/results.sh: installs what umbra needs (ci/setup.sh; idempotent,
# root the first time), finds the lavapipe and SwiftShader ICDs, and exports the persistent
# CARGO_TARGET_DIR (shaderc's C++ build is paid once per machine) and VK_ICD_FILENAMES with
# exactly those two drivers, so UMBRA_DEVICE picks between them.
if [ "$(id -u)" -eq 0 ]; then
    sws_icd=$(bash ci/setup.sh | tail -n 1)
else
    sws_icd=$(sudo -E bash ci/setup.sh | tail -n 1)
fi
lvp_icd=$(ls /usr/share/vulkan/icd.d/lvp_icd.*.json 2>/dev/null | head -n 1)
[ -f "$lvp_icd" ] || { echo "ci: lavapipe ICD not found (mesa-vulkan-drivers)" >&2; exit 1; }
[ -f "$sws_icd" ] || { echo "ci: SwiftShader ICD not found ($sws_icd)" >&2; exit 1; }
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/umbra/target}"
export VK_ICD_FILENAMES="$lvp_icd:$sws_icd"
export VK_DRIVER_FILES="$VK_ICD_FILENAMES"
