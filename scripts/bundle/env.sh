# Sourced by run-tests.sh and run-bench.sh in a bundle made by scripts/bundle.sh:
# sets BUNDLE (the bundle's folder) and the environment the tests and the
# benchmark run in, so nothing compiled in from the build machine is used.
BUNDLE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"

# The tests' main() defaults these to the build and source trees of the build
# machine (tests/main.cpp); the bundle's own copies replace them. sva finds its
# scenes and objects through SVA_ASSETS too.
export SVA_BIN="$BUNDLE/sva"
export SVA_ASSETS="$BUNDLE/assets"
# The Khronos validation layer is a development tool, usually absent on a GPU
# machine; the caller may still ask for it.
export SVA_VK_VALIDATION="${SVA_VK_VALIDATION:-0}"
# VK_DRIVER_FILES is left as the caller set it (e.g. the NVIDIA ICD of a
# container); unset, the Vulkan loader searches the machine's usual ICD folders.

# The binaries find their libraries in $BUNDLE/lib through their run path
# ($ORIGIN/lib), libstdc++ and libgcc_s included, so an older machine works.
# A Vulkan driver loaded at run time (Mesa's, built against LLVM) may need a
# newer libstdc++ than the bundled one: when the machine's own is newer, it is
# preloaded instead (only one libstdc++ can live in a process).
sva_glibcxx() { grep -aoE 'GLIBCXX_3\.4\.[0-9]+' "$1" 2>/dev/null | sort -uV | tail -n 1; }
sva_system_lib() {
  # The first copy of a soname for this machine's architecture in the dynamic linker's cache (a bundle is made for
  # x86-64 or aarch64: scripts/bundle.sh --arch).
  local arch=x86-64
  [[ $(uname -m) == aarch64 ]] && arch=AArch64
  { ldconfig -p 2>/dev/null || /sbin/ldconfig -p 2>/dev/null; } |
    awk -v so="$1" -v a="$arch" '$1 == so && index($0, "," a ")") { print $NF; exit }'
}
if [[ -f $BUNDLE/lib/libstdc++.so.6 && -z ${SVA_BUNDLE_NO_PRELOAD:-} ]]; then
  sys_cxx=$(sva_system_lib libstdc++.so.6)
  sys_gcc=$(sva_system_lib libgcc_s.so.1)
  if [[ -n $sys_cxx && -n $sys_gcc ]]; then
    mine=$(sva_glibcxx "$BUNDLE/lib/libstdc++.so.6")
    theirs=$(sva_glibcxx "$sys_cxx")
    if [[ -n $theirs && $mine != "$theirs" && $(printf '%s\n%s\n' "$mine" "$theirs" | sort -V | tail -n 1) == "$theirs" ]]; then
      export LD_PRELOAD="$sys_gcc:$sys_cxx${LD_PRELOAD:+:$LD_PRELOAD}"
      echo "note: using the machine's newer libstdc++ ($theirs > bundled $mine): $sys_cxx"
    fi
  fi
  unset sys_cxx sys_gcc mine theirs
fi

# NVIDIA's Vulkan driver opens libglvnd's libEGL.so.1 (which needs libGLdispatch.so.0), and a bare NVIDIA container
# may lack both: the bundle's copies then (scripts/bundle.sh), reached through LD_LIBRARY_PATH since the driver
# opens them at run time.
if [[ -f $BUNDLE/glvnd/libEGL.so.1 && -z $(sva_system_lib libEGL.so.1) ]]; then
  export LD_LIBRARY_PATH="$BUNDLE/glvnd${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
fi

# three.js for `sva view`'s pages (scripts/bundle.sh copies Debian's libjs-three).
export SVA_THREE_JS="${SVA_THREE_JS:-$BUNDLE/three}"

# The figures' font: the bundle's own fontconfig configuration and DejaVu Sans (scripts/bundle.sh).
export FONTCONFIG_FILE="$BUNDLE/fonts/fonts.conf"

# All cores for the thread pools (sva simulate/train/bench, CPU backend).
SVA_NPROC=$(nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)
export SVA_THREADS="${SVA_THREADS:-$SVA_NPROC}"
