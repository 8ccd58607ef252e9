# Cross build for 64-bit Arm Linux with Debian's cross compiler (g++-aarch64-linux-gnu) and Debian's
# arm64 libraries installed side by side with the host's (multiarch: libenet-dev:arm64 and the others
# in scripts/packages-aarch64.txt). The programs run on an x86-64 machine under qemu-user:
#   qemu-aarch64 -L /usr/aarch64-linux-gnu build-aarch64/bin/rattle-trace
# Use: cmake -S . -B build-aarch64 -DCMAKE_TOOLCHAIN_FILE=cmake/aarch64-linux-gnu.cmake
# The project's own flags (-ffp-contract=off above all: aarch64 g++ fuses a*b+c into an fma by default)
# come from the top-level CMakeLists.txt as for any other compiler.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
# Multiarch: the arm64 libraries are in /usr/lib/aarch64-linux-gnu, their headers in /usr/include (shared
# with the host's, identical across architectures) or /usr/include/aarch64-linux-gnu.
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
# Multiarch needs no sysroot: with the library architecture set, CMake and pkg-config look in the
# aarch64 directories (/usr/lib/aarch64-linux-gnu) and never in the host's (/usr/lib/x86_64-linux-gnu).
# Programs found (pkg-config) are the host's.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
# pkgconf's cross wrapper looks in /usr/lib/aarch64-linux-gnu/pkgconfig and /usr/share/pkgconfig only.
set(PKG_CONFIG_EXECUTABLE aarch64-linux-gnu-pkg-config CACHE FILEPATH "pkg-config for aarch64")
# try_run and the tests' discovery run target programs through qemu-user.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /usr/aarch64-linux-gnu)
