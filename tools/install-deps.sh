#!/usr/bin/env bash
# Installs the Debian 12 packages that aeroflock needs and that are missing, with apt-get (as
# root, or through sudo). Does nothing at all when every package is already installed.
set -euo pipefail

packages=(
  # Build tools.
  build-essential cmake ninja-build pkg-config git ca-certificates
  # Libraries of the engine, the tools and the tests.
  libglm-dev libcli11-dev libtomlplusplus-dev nlohmann-json3-dev libgtest-dev googletest libstb-dev
  # Vulkan: loader, software driver (lavapipe), shader compiler, validation and tools.
  libvulkan-dev mesa-vulkan-drivers glslang-tools spirv-tools vulkan-validationlayers vulkan-tools
  # Windows, VTK export and headless display.
  libglfw3-dev libvtk9-dev python3 python3-vtk9 xvfb xauth
  # Many ranks (engine/dist): OpenMPI, its compiler wrappers and mpirun.
  openmpi-bin libopenmpi-dev
  # Plots of `aeroflock bench --plot`; videos of `run --video` (ffmpeg, ffprobe).
  gnuplot-nox ffmpeg
  # The fuzz preset: clang, its libFuzzer and sanitizer runtimes (not pulled in without
  # recommends) and its OpenMP runtime.
  clang libclang-rt-14-dev libomp-dev
  # The sources' formatting check (tools/check_format.sh): Debian 12's clang-format, version 14.
  clang-format
)

installed() {
  dpkg-query -W -f='${db:Status-Status}\n' "$1" 2>/dev/null | grep -qx installed
}

missing=()
for package in "${packages[@]}"; do
  installed "$package" || missing+=("$package")
done
if ((${#missing[@]} == 0)); then
  exit 0
fi

if ((EUID == 0)); then
  as_root=()
elif command -v sudo >/dev/null 2>&1; then
  as_root=(sudo)
else
  echo "install-deps: missing packages: ${missing[*]}" >&2
  echo "install-deps: run this script as root (sudo is not installed)" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}" >&2
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
  apt-get install -y --no-install-recommends "${missing[@]}"
