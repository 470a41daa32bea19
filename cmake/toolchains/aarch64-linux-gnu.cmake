# Cross build for aarch64 (a Jetson-class or other arm64 robot computer) on a Debian 12 x86-64 machine: Debian's
# cross compiler (g++-aarch64-linux-gnu) and the arm64 multiarch packages (libembree-dev:arm64, libvulkan-dev:arm64,
# ...: scripts/setup.sh --aarch64 installs them). The build's tools that run here (glslangValidator for the shaders)
# stay x86-64; what it builds runs under qemu-aarch64 (scripts/aarch64-check.sh) or on the robot.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# Debian's multiarch layout: arm64 libraries in /usr/lib/aarch64-linux-gnu, headers shared in /usr/include.
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)  # glslangValidator, pkg-config: the build machine's
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig")
# Run what the build itself runs (none today) and ctest's tests under emulation.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /usr/aarch64-linux-gnu)
