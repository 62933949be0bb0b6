#!/usr/bin/env bash
# Installs everything umbra needs to build and test on Debian 12. Idempotent; run as root.
#
#   - Vulkan loader, Mesa lavapipe (llvmpipe), the Khronos validation layer, spirv-tools
#   - cmake, g++, python3 (shaderc's `build-from-source` compiles glslang)
#   - Xvfb, xwd (x11-apps), xdotool and the X libraries winit loads at run time, for the windowed
#     examples' tests
#   - SwiftShader, unpacked from the npm package @sparticuz/chromium into $UMBRA_CACHE
#   - Mesa 25's lavapipe from Debian 12's bookworm-backports, unpacked into $UMBRA_CACHE beside
#     the system's Mesa 22 lavapipe, which it does not replace
#
# Prints one `DRIVER ICD-JSON` line per unpacked driver last (ci/drivers.sh reads them):
#   swiftshader /root/.cache/umbra/swiftshader-143.0.4/vk_swiftshader_icd.json
#   lavapipe-25 /root/.cache/umbra/mesa-25.0.7-2-bpo12-1/lvp_icd.json
set -euo pipefail

SPARTICUZ_VERSION="143.0.4"
# The backports version measured in docs/; setup takes whatever 25.x backports carries when
# this one has left the archive, and says so.
MESA_VERSION="25.0.7-2~bpo12+1"
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

# Mesa 25's lavapipe: `apt-get download` from bookworm-backports through an apt state of its
# own under the cache (the system's sources and package lists stay as they are), `dpkg -x` of
# the package, and an ICD json naming the unpacked libvulkan_lvp.so by absolute path. Only
# the driver is used: every libdrm symbol it imports is in Debian 12's libdrm2 2.4.114 (the
# package asks for 2.4.121 for its GPU drivers), so nothing else is unpacked or preloaded.
mesa_icd=$(ls "$CACHE"/mesa-25.*/lvp_icd.json 2>/dev/null | head -n 1 || true)
if [ -z "$mesa_icd" ]; then
    apt_dir="$CACHE/apt-backports"
    mkdir -p "$apt_dir/lists/partial" "$apt_dir/debs"
    echo "deb http://deb.debian.org/debian bookworm-backports main" > "$apt_dir/sources.list"
    apt_opts=(-o "Dir::Etc::SourceList=$apt_dir/sources.list" -o "Dir::Etc::SourceParts=/dev/null"
              -o "Dir::State::Lists=$apt_dir/lists" -o "APT::Sandbox::User=root")
    echo "setup: fetching Mesa's lavapipe from bookworm-backports" >&2
    apt-get -q "${apt_opts[@]}" update >&2
    version=$(apt-cache "${apt_opts[@]}" madison mesa-vulkan-drivers | awk '{print $3}' | grep "^${MESA_VERSION}$" || true)
    if [ -z "$version" ]; then
        version=$(apt-cache "${apt_opts[@]}" madison mesa-vulkan-drivers | awk '$3 ~ /^25\./ {print $3; exit}')
        [ -n "$version" ] || { echo "setup: no Mesa 25 mesa-vulkan-drivers in bookworm-backports" >&2; exit 1; }
        echo "setup: warning: $MESA_VERSION has left bookworm-backports; using $version (docs/ measured $MESA_VERSION)" >&2
    fi
    (cd "$apt_dir/debs" && rm -f ./*.deb && apt-get -q "${apt_opts[@]}" download "mesa-vulkan-drivers=$version" >&2)
    mesa_dir="$CACHE/mesa-${version//[~+]/-}"
    rm -rf "$mesa_dir.tmp"
    mkdir -p "$mesa_dir.tmp"
    dpkg -x "$apt_dir"/debs/mesa-vulkan-drivers_*.deb "$mesa_dir.tmp/root"
    rm -f "$apt_dir"/debs/*.deb
    rm -rf "$mesa_dir"
    mv "$mesa_dir.tmp" "$mesa_dir"
    lib=$(find "$mesa_dir/root" -name libvulkan_lvp.so | head -n 1)
    [ -n "$lib" ] || { echo "setup: libvulkan_lvp.so not in mesa-vulkan-drivers $version" >&2; exit 1; }
    api=$(sed -n 's/.*"api_version": *"\([0-9.]*\)".*/\1/p' "$mesa_dir/root/usr/share/vulkan/icd.d/lvp_icd.json")
    cat > "$mesa_dir/lvp_icd.json.tmp" <<JSON
{
    "file_format_version": "1.0.0",
    "ICD": {
        "library_path": "$lib",
        "api_version": "${api:-1.4.305}"
    }
}
JSON
    mv "$mesa_dir/lvp_icd.json.tmp" "$mesa_dir/lvp_icd.json"
    mesa_icd="$mesa_dir/lvp_icd.json"
fi

echo "swiftshader $SWS_ICD"
echo "lavapipe-25 $mesa_icd"
