#!/usr/bin/env bash
# Installs the Vulkan loader, Mesa's lavapipe (>= 24.1, with VK_KHR_ray_query), the Khronos
# validation layer, SPIRV-Tools (spirv-val checks the patched any-hit SPIR-V) and Xvfb (the viewer's tests open a window on a virtual X server) on Debian 12. The backports suite is added by copying the machine's own
# first Debian source entry.
set -euo pipefail
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi

have_lavapipe() {
    local icd
    for icd in /usr/share/vulkan/icd.d/lvp_icd*.json; do
        [ -e "$icd" ] || return 1
    done
    local v
    v=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
    [ -n "$v" ] && dpkg --compare-versions "$v" ge 24.1
}

have_validation() {
    [ -e /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json ]
}

have_xvfb() {
    command -v Xvfb >/dev/null
}

have_spirv_val() {
    command -v spirv-val >/dev/null
}

if have_lavapipe && dpkg-query -W libvulkan1 >/dev/null 2>&1 && have_validation && have_xvfb && have_spirv_val; then
    echo "lavapipe $(dpkg-query -W -f='${Version}' mesa-vulkan-drivers) already installed"
    exit 0
fi

src=/etc/apt/sources.list.d/debian.sources
bp=/etc/apt/sources.list.d/raygraph-backports.sources
if [ -f "$src" ] && [ ! -f "$bp" ]; then
    # First deb822 stanza, with its Suites line replaced.
    awk 'BEGIN{RS=""; FS="\n"} NR==1 {print; exit}' "$src" \
        | sed -E 's/^Suites:.*/Suites: bookworm-backports/' | $SUDO tee "$bp" >/dev/null
elif [ ! -f "$src" ] && [ ! -f "$bp" ]; then
    line=$(grep -m1 -E '^deb ' /etc/apt/sources.list)
    echo "$line" | awk '{ $3="bookworm-backports"; print }' | $SUDO tee /etc/apt/sources.list.d/raygraph-backports.list >/dev/null
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq -t bookworm-backports mesa-vulkan-drivers libvulkan1 >/dev/null
$SUDO apt-get install -y -qq vulkan-validationlayers xvfb spirv-tools >/dev/null
echo "installed lavapipe $(dpkg-query -W -f='${Version}' mesa-vulkan-drivers), validation layers $(dpkg-query -W -f='${Version}' vulkan-validationlayers)"
