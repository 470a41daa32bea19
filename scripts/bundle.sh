#!/usr/bin/env bash
# Makes a relocatable folder that runs the sva test suite and the speed
# benchmark on a GPU machine with no build tools (docs/vulkan-backend.md,
# "Running on a GPU machine"):
#
#   scripts/bundle.sh [--arch x86_64|aarch64] OUT_DIR
#                                      BUILD_DIR=build-ci (default): reused when built,
#                                      else configured and built with PRESET (ci: the
#                                      default preset builds the command line only)
#                                      --arch aarch64: the aarch64 preset's cross build
#                                      (build-aarch64; scripts/setup.sh --aarch64), for a
#                                      Jetson-class machine; its libraries found under qemu
#
# OUT_DIR/  sva, tests/sva_tests_<area>, bench/estimate_speed, filter_speed and batch_speed (where built), assets/ (scenes and objects), lib/ (every
#           shared library they load but the C library and the Vulkan drivers),
#           run-tests.sh, run-bench.sh, env.sh, README.txt
# The binaries get the run path $ORIGIN/lib (patchelf), so they run from any folder;
# the shaders are embedded in them (shaders/CMakeLists.txt). The scripts set
# SVA_BIN and SVA_ASSETS, so the build and source paths compiled into the tests
# (tests/main.cpp) are never used.
set -euo pipefail
usage() { echo "usage: [BUILD_DIR=build-ci] [PRESET=ci] scripts/bundle.sh [--arch x86_64|aarch64] OUT_DIR" >&2; exit 2; }
arch=x86_64
if [[ ${1:-} == --arch ]]; then
  [[ $# -ge 2 ]] || usage
  arch=$2
  shift 2
fi
[[ $arch == x86_64 || $arch == aarch64 ]] || { echo "bundle: --arch must be x86_64 or aarch64, not '$arch'" >&2; exit 2; }
[[ $# -eq 1 && -n $1 ]] || usage
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out=$1
preset=${PRESET:-ci}
[[ $arch == aarch64 ]] && preset=${PRESET:-aarch64}
# The presets' binary folders: build/ for default, build-<preset>/ for the others.
default_build=$root/build
[[ $preset == default ]] || default_build=$root/build-$preset
build=${BUILD_DIR:-$default_build}
# What differs by architecture: how a binary's libraries are listed (ldd runs the binary's own loader, so a foreign
# one runs under qemu), where a library the binaries do not link is found, and the strip tool.
if [[ $arch == aarch64 ]]; then
  command -v qemu-aarch64 >/dev/null || { echo "bundle: qemu-aarch64 not found (scripts/setup.sh installs it)" >&2; exit 1; }
  list_libs() { qemu-aarch64 -L / /lib/ld-linux-aarch64.so.1 --list "$1"; }  # executables and libraries alike
  run_target() { qemu-aarch64 -L / "$@"; }
  # The arm64 packages' multiarch folder (an x86-64 machine's linker cache does not list it).
  system_lib() { ls /usr/lib/aarch64-linux-gnu/"$1" /lib/aarch64-linux-gnu/"$1" 2>/dev/null | head -n 1; }
  strip_tool=aarch64-linux-gnu-strip
else
  list_libs() { ldd "$1"; }
  run_target() { "$@"; }
  system_lib() { { ldconfig -p 2>/dev/null || /sbin/ldconfig -p; } | awk -v so="$1" '$1 == so && /x86-64/ { print $NF; exit }'; }
  strip_tool=strip
fi
command -v patchelf >/dev/null || { echo "bundle: patchelf not found (scripts/setup.sh installs it)" >&2; exit 1; }

if [[ $arch == aarch64 && ! -x $build/tests/sva_tests_vulkan ]]; then
  # The aarch64 preset's own build makes the CPU-only suites that run under qemu; a GPU machine runs them all.
  [[ -z ${BUILD_DIR:-} ]] || { echo "bundle: no aarch64 Vulkan suite in BUILD_DIR=$build (build every target)" >&2; exit 1; }
  echo "== no whole aarch64 build in $build: cmake --preset $preset, cmake --build --preset aarch64-bundle"
  (cd "$root" && cmake --preset "$preset" && cmake --build --preset aarch64-bundle)
elif [[ ! -x $build/sva ]]; then
  [[ -z ${BUILD_DIR:-} ]] || { echo "bundle: no sva in BUILD_DIR=$build" >&2; exit 1; }
  echo "== no build in $build: cmake --preset $preset"
  (cd "$root" && cmake --preset "$preset" && cmake --build --preset "$preset")
fi
build=$(cd "$build" && pwd)
mapfile -t tests < <(find "$build/tests" -maxdepth 1 -type f -name 'sva_tests_*' -perm -u+x | sort)
[[ ${#tests[@]} -gt 0 ]] || { echo "bundle: no test executables in $build/tests (build them first)" >&2; exit 1; }

# Never delete a folder that is not a bundle.
if [[ -e $out ]]; then
  if [[ -d $out && ( -z $(ls -A "$out") || -f $out/.sva-bundle ) ]]; then rm -rf "$out"
  else echo "bundle: $out exists and is not a bundle; not overwriting it" >&2; exit 1; fi
fi
mkdir -p "$out/lib" "$out/tests" "$out/assets"
out=$(cd "$out" && pwd)
case $out/ in "$build"/* | "$root"/*)
  echo "note: $out is inside the source or build tree; move it elsewhere to use it" ;;
esac
touch "$out/.sva-bundle"
echo "== bundle $build -> $out"

cp "$build/sva" "$out/sva"
cp "${tests[@]}" "$out/tests/"
# The estimate's stages timed, with one session's critical path (bench/speed/estimate_speed.cpp), where the build made
# it: the device check compares a many-core host's measured latency with the model.
# The same for one session's update (bench/speed/filter_speed.cpp): its span on the host's threads; and for a batch of
# 64 sessions (bench/speed/batch_speed.cpp).
benches=()
for b in estimate_speed filter_speed batch_speed; do
  [[ -x $build/bench/$b ]] || continue
  mkdir -p "$out/bench"
  cp "$build/bench/$b" "$out/bench/"
  benches+=("$out/bench/$b")
done
# The built-in scenes and objects, loaded at run time through SVA_ASSETS (the
# generator's source stays behind).
cp -r "$root/assets/scenes" "$root/assets/objects" "$root/assets/view" "$out/assets/"
# The parsers' fuzz corpus (the io tests read it beside the assets: assets/../tests/fuzz/corpus).
mkdir -p "$out/tests/fuzz"
cp -r "$root/tests/fuzz/corpus" "$out/tests/fuzz/"
# three.js for `sva view` (Debian's libjs-three, laid out as Debian's; env.sh sets SVA_THREE_JS).
three=${SVA_THREE_JS:-/usr/share/javascript/three}
[[ -f $three/three.min.js && -f $three/examples/js/controls/OrbitControls.js ]] ||
  { echo "bundle: three.js not found in $three (scripts/setup.sh installs libjs-three)" >&2; exit 1; }
mkdir -p "$out/three/examples/js/controls"
cp -L "$three/three.min.js" "$out/three/"
cp -L "$three/examples/js/controls/OrbitControls.js" "$out/three/examples/js/controls/"
for f in env.sh run-tests.sh run-bench.sh run-device-check.sh README.txt; do cp "$root/scripts/bundle/$f" "$out/$f"; done
chmod +x "$out/run-tests.sh" "$out/run-bench.sh" "$out/run-device-check.sh"

# The shared-library closure (ldd is recursive), but the C library: glibc's parts
# must match the target's ld.so, which a newer machine provides. libstdc++ and
# libgcc_s are bundled (env.sh prefers the machine's own when newer). The Vulkan
# loader is bundled; the drivers (ICDs) it opens at run time are the machine's.
glibc_re='^(linux-vdso|ld-linux|libc|libm|libmvec|libpthread|libdl|librt|libresolv|libutil|libanl|libnsl|libBrokenLocale|libthread_db)\.so'
declare -A libs=()
for bin in "$out/sva" "$out"/tests/sva_tests_* "${benches[@]}"; do
  while read -r name _ path _; do
    [[ $name =~ $glibc_re ]] && continue
    [[ $path == /* ]] || { echo "bundle: $bin needs $name, which is not found" >&2; exit 1; }
    libs[$name]=$path
  done < <(list_libs "$bin" | awk '$2 == "=>" { print $1, $2, $3 }')
done
# Loaded with dlopen, so ldd does not see it: TBB's scalable allocator (Embree's
# task scheduler uses it when present).
if [[ -n ${libs[libtbb.so.12]:-} && -f $(dirname "${libs[libtbb.so.12]}")/libtbbmalloc.so.2 ]]; then
  libs[libtbbmalloc.so.2]=$(dirname "${libs[libtbb.so.12]}")/libtbbmalloc.so.2
fi
for name in "${!libs[@]}"; do cp -L "${libs[$name]}" "$out/lib/$name"; done
chmod u+w "$out"/lib/*
# libglvnd's EGL and dispatch libraries, for a GPU machine that lacks them: NVIDIA's Vulkan driver
# (libGLX_nvidia.so.0, named by the container's ICD file) opens libEGL.so.1, which needs libGLdispatch.so.0, and
# without them the loader finds no driver ("Could not get 'vkCreateInstance'"; the fifth GPU run,
# docs/vulkan-backend.md). Not in lib/: env.sh puts this folder on LD_LIBRARY_PATH only when the machine has no
# libEGL.so.1, since the driver opens them at run time and the binaries' run path does not reach them.
mkdir -p "$out/glvnd"
for name in libEGL.so.1 libGLdispatch.so.0; do
  path=$(system_lib "$name")
  [[ -n $path ]] || { echo "bundle: $name ($arch) not found (scripts/setup.sh installs libegl1 and libglvnd0)" >&2; exit 1; }
  cp -L "$path" "$out/glvnd/$name"
done

# The figures' font (cairo through fontconfig): a GPU machine may have no fonts at all, and a figure without
# glyphs fails its test. env.sh points fontconfig at this folder's configuration.
mkdir -p "$out/fonts"
cp -L /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf "$out/fonts/"
cat >"$out/fonts/fonts.conf" <<'CONF'
<?xml version="1.0"?>
<!DOCTYPE fontconfig SYSTEM "fonts.dtd">
<fontconfig><dir prefix="relative">.</dir><cachedir prefix="relative">cache</cachedir></fontconfig>
CONF

# Debug information stays in the build tree; the bundle is for running.
if command -v "$strip_tool" >/dev/null && [[ ${STRIP:-1} != 0 ]]; then
  "$strip_tool" --strip-debug "$out/sva" "$out"/tests/sva_tests_* "${benches[@]}" "$out"/lib/*
fi
patchelf --set-rpath '$ORIGIN/lib' "$out/sva"
for t in "$out"/tests/sva_tests_* "${benches[@]}"; do patchelf --set-rpath '$ORIGIN/../lib' "$t"; done
for l in "$out"/lib/*; do patchelf --set-rpath '$ORIGIN' "$l"; done

# Check: every library resolves inside the bundle or to the C library, with no
# help from LD_LIBRARY_PATH.
bad=0
for bin in "$out/sva" "$out"/tests/sva_tests_* "${benches[@]}" "$out"/lib/*; do
  while read -r name _ path _; do
    [[ $name =~ $glibc_re || $(realpath -m "$path") == "$out/lib/"* ]] && continue
    echo "bundle: $bin loads $name from $path, outside the bundle" >&2; bad=1
  done < <(unset LD_LIBRARY_PATH; list_libs "$bin" | awk '$2 == "=>" { print $1, $2, $3 }')
done
[[ $bad -eq 0 ]] || exit 1
(unset LD_LIBRARY_PATH; SVA_ASSETS="$out/assets" run_target "$out/sva" --version >/dev/null)

{
  run_target "$out/sva" --version 2>/dev/null | head -n 1
  echo "architecture: $arch"
  # The oldest C library it runs on: the newest glibc symbol version anything here asks for.
  echo "needs glibc >= $(cat "$out/sva" "$out"/tests/sva_tests_* "$out"/lib/* | grep -aoE 'GLIBC_2\.[0-9]+' | sort -uV | tail -n 1 | cut -c7-)"
  echo "built from $(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown) on $(uname -n), $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "tests: $(cd "$out/tests" && ls -d sva_tests_* | tr '\n' ' ')"
  echo "libraries: $(cd "$out/lib" && ls | tr '\n' ' ')"
} >"$out/BUILD-INFO.txt"
echo "== bundle ready: $out ($(du -sh "$out" | cut -f1)); see $out/README.txt"
