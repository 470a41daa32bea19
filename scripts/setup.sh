#!/usr/bin/env bash
# Installs every Debian 12 package sva needs to build, test and run. Idempotent; run as root.
#   scripts/setup.sh              # the x86-64 build, its tests and the Python package
#   scripts/setup.sh --aarch64    # and the cross build for aarch64 (the aarch64 preset; scripts/aarch64-check.sh)
#   scripts/setup.sh --no-python  # without the Python package's virtual environment: the sva command line needs
#                                 # none (the README's first command: 25 s of downloads and installs saved)
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
aarch64=0 python=1
for arg in "$@"; do
  case "$arg" in
    --aarch64) aarch64=1 ;;
    --no-python) python=0 ;;
    -h | --help) sed -n '2,6p' "$0"; exit 0 ;;
    *) echo "setup.sh: unknown option $arg (see --help)" >&2; exit 2 ;;
  esac
done
packages=(
  build-essential cmake ninja-build pkg-config git ccache
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools
  libglm-dev libembree-dev libtinygltf-dev libstb-dev nlohmann-json3-dev
  libusb-1.0-0-dev catch2 libtbb-dev
  qemu-user  # tests/determinism: the same binary run as other x86-64 CPUs (qemu-x86_64 -cpu Nehalem)
  patchelf libegl1 libglvnd0  # scripts/bundle.sh: $ORIGIN run paths in the relocatable bundle for a GPU machine, and
                              # libglvnd's EGL for one whose NVIDIA Vulkan driver lacks it
  clang-14 libclang-rt-14-dev  # scripts/fuzz.sh: libFuzzer (libclang_rt.fuzzer) and the sanitizer runtimes
  python3 python3-venv python3-dev python3-pip  # the Python package (python/, docs/python.md)
  libcairo2-dev fonts-dejavu-core  # the figures (host/eval/src/plot: cairo, PNG and SVG, DejaVu Sans)
  libjs-three chromium  # sva view's pages (three.js inlined) and their browser test (tests/view, headless)
)
if [ "$aarch64" = 1 ]; then
  # Debian's cross compiler and the arm64 builds of the libraries sva links (multiarch: beside the x86-64 ones).
  packages+=(g++-aarch64-linux-gnu libembree-dev:arm64 libvulkan-dev:arm64 libtinygltf-dev:arm64 libtbb-dev:arm64
    libusb-1.0-0-dev:arm64 libcairo2-dev:arm64 mesa-vulkan-drivers:arm64 libegl1:arm64 libglvnd0:arm64)
  if ! dpkg --print-foreign-architectures | grep -qx arm64; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO dpkg --add-architecture arm64
    force_update=1
  fi
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ] || [ "${force_update:-0}" = 1 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update
  $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi

[ "$python" = 1 ] || exit 0

# The Python package's build and test tools, in a virtual environment at .venv made with Debian's python3 (not
# whatever python3 comes first on PATH): nanobind and scikit-build-core to build, NumPy, pytest, matplotlib and
# Dask distributed to run and test (python/requirements.txt, pinned).
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ ! -x "$repo/.venv/bin/python" ] || ! "$repo/.venv/bin/python" -c 'import sys; sys.exit(sys.base_prefix != "/usr")'; then
  rm -rf "$repo/.venv"
  /usr/bin/python3 -m venv "$repo/.venv"
fi
pins_installed() {  # every pin of python/requirements.txt installed at its version
  "$repo/.venv/bin/python" - "$repo/python/requirements.txt" <<'PY'
import sys
from importlib.metadata import PackageNotFoundError, version
for line in open(sys.argv[1]):
    line = line.split("#")[0].strip()
    if line:
        name, want = line.split("==")
        try:
            if version(name) != want:
                sys.exit(1)
        except PackageNotFoundError:
            sys.exit(1)
PY
}
if ! pins_installed; then
  # --no-compile: Python compiles a module's bytecode when it is first imported instead, which saves a quarter of
  # this step (7 of 26 s on 2 cores) for modules that the first command never imports.
  "$repo/.venv/bin/python" -m pip install --disable-pip-version-check --no-compile -q -r "$repo/python/requirements.txt"
fi
