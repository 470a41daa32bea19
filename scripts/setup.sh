#!/usr/bin/env bash
# Installs every Debian 12 package sva needs to build, test and run. Idempotent; run as root.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
packages=(
  build-essential cmake ninja-build pkg-config git
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools
  libglm-dev libembree-dev libtinygltf-dev libstb-dev nlohmann-json3-dev
  libusb-1.0-0-dev catch2 libtbb-dev
  patchelf  # scripts/bundle.sh: $ORIGIN run paths in the relocatable bundle for a GPU machine
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update
  $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi
