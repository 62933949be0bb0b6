#!/usr/bin/env bash
# Installs everything umbra needs to build and test on Debian 12. Idempotent; run as root.
#
#   - Vulkan loader, Mesa lavapipe (llvmpipe), the Khronos validation layer, spirv-tools
#   - cmake, g++, python3 (shaderc's `build-from-source` compiles glslang)
#   - Xvfb, xwd (x11-apps), xdotool and the X libraries winit loads at run time, for the windowed
#     examples' tests
#   - SwiftShader, unpacked from the npm package @sparticuz/chromium into $UMBRA_CACHE
#
# Prints the path of the SwiftShader ICD json on its last line (ci/test.sh reads it).
set -euo pipefail

SPARTICUZ_VERSION="143.0.4"
CACHE="${UMBRA_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/umbra}"
SWS_DIR="$CACHE/swiftshader-$SPARTICUZ_VERSION"
SWS_ICD="$SWS_DIR/vk_swiftshader_icd.json"

need_pkgs=()
for p in libvulkan1 libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools \
         spirv-tools cmake g++ python3 brotli pkg-config fonts-dejavu-core \
         xvfb x11-apps xdotool libx11-6 libx11-xcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need_pkgs+=("$p")
done
# npm may come from Node's own distribution rather than Debian's: only install it when absent.
command -v npm >/dev/null 2>&1 || need_pkgs+=(npm)
if [ ${#need_pkgs[@]} -gt 0 ]; then
    echo "setup: installing ${need_pkgs[*]}" >&2
    if [ "$(id -u)" -ne 0 ]; then
        echo "setup: missing packages and not root; run ci/setup.sh as root" >&2
        exit 1
    fi
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -q >&2
    apt-get install -y -q --no-install-recommends "${need_pkgs[@]}" >&2
fi

if [ ! -f "$SWS_ICD" ]; then
    echo "setup: fetching SwiftShader from npm @sparticuz/chromium@$SPARTICUZ_VERSION" >&2
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    (cd "$tmp" && npm pack --silent "@sparticuz/chromium@$SPARTICUZ_VERSION" >/dev/null)
    tar -xzf "$tmp"/sparticuz-chromium-*.tgz -C "$tmp" package/bin/swiftshader.tar.br
    brotli -d -c "$tmp/package/bin/swiftshader.tar.br" > "$tmp/swiftshader.tar"
    mkdir -p "$tmp/sws"
    tar -xf "$tmp/swiftshader.tar" -C "$tmp/sws"
    lib=$(find "$tmp/sws" -name libvk_swiftshader.so | head -n 1)
    [ -n "$lib" ] || { echo "setup: libvk_swiftshader.so not in the archive" >&2; exit 1; }
    mkdir -p "$SWS_DIR"
    cp "$lib" "$SWS_DIR/libvk_swiftshader.so"
    cat > "$SWS_ICD.tmp" <<JSON
{
    "file_format_version": "1.0.0",
    "ICD": {
        "library_path": "$SWS_DIR/libvk_swiftshader.so",
        "api_version": "1.3.0"
    }
}
JSON
    mv "$SWS_ICD.tmp" "$SWS_ICD"
fi
echo "$SWS_ICD"
