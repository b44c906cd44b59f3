#!/usr/bin/env bash
# Installs the Debian packages Bouguer needs to build, test and render.
# Idempotent: packages already present are skipped, and `apt-get update` runs only
# when something is missing. Runs as root, or through sudo when that is available.
# `install-deps.sh --fuzz` adds what `make fuzz` needs: clang and its libFuzzer/sanitizer runtimes.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config make
  libembree-dev        # BVH and ray queries (Embree 3)
  libtbb-dev           # threads (oneTBB)
  libopenexr-dev       # EXR read/write
  libpng-dev           # PNG write
  libopenimageio-dev   # texture images (PNG, JPEG, EXR, TIFF, HDR), io/texture_image.cpp only
  nlohmann-json3-dev   # scene files, --json output
  libcli11-dev         # command line
  libfmt-dev           # formatting
  libtinyobjloader-dev # OBJ meshes
  libgtest-dev         # tests
  libbenchmark-dev     # micro-benchmarks
  libopenvdb-dev       # voxel grids (the grid concentration field)
  libboost-iostreams-dev # OpenVDB's FindOpenVDB.cmake needs it; libopenvdb-dev does not pull it in without recommends
  libcairo2-dev        # plots (bouguer material --plot): SVG, PNG and PDF from one drawing
  chromium             # the report page is checked in a real browser (headless) by the tests
  fonts-dejavu-core    # a font for plot labels and the report screenshot
  libopenmpi-dev       # distributed rendering (mpirun -np N bouguer render); optional at configure time
  openmpi-bin          # mpirun, for the distributed tests
  libtinygltf-dev      # glTF 2.0 assets (header only)
  libdraco-dev         # Draco-compressed glTF meshes (KHR_draco_mesh_compression)
  pybind11-dev         # the Python module (import bouguer); optional at configure time
  python3-dev          # its headers
  python3-numpy        # its arrays
  python3-pytest       # its tests (tests/python)
  python3-matplotlib   # the Python examples (examples/python), run by the tests
  blender              # the Blender add-on (blender/): its tests render in Blender against Cycles
)
if [ "${1:-}" = "--fuzz" ]; then
  packages+=(clang libclang-rt-14-dev)  # libFuzzer, ASan, UBSan (make fuzz only)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then sudo_cmd=(sudo); else
    echo "install-deps: missing packages (${missing[*]}) and not root; install them or run as root" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
