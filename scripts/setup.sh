# scripts/setup.sh -- sourced by scripts/run and scripts/test: install what is
# missing (Debian packages via apt-get) and configure + build mpgm.
#   mpgm_setup BUILD_DIR [extra cmake args...]
set -euo pipefail

MPGM_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
MPGM_PACKAGES=(
  build-essential cmake pkg-config
  libsuitesparse-dev libgsl-dev libcjson-dev
  zlib1g-dev             # CRC-32 of checkpoint sections (base/blob.c)
  libopenblas0-pthread   # fast BLAS for SuiteSparse (Debian's default is the reference BLAS)
  petsc-dev              # solver.linear "petsc": PETSc 3.18 with hypre, MUMPS and Open MPI
  # tests read our VTK files with VTK's own reader, as ParaView does; python3-paraview
  # gives `import vtk` too, and conflicts with python3-vtk9 (installing one removes the other)
  python3 python3-paraview paraview  # tests/scripts/paraview.sh opens the series under pvbatch3.11
  libnanoflann-dev       # header-only, used only by bench/kdtree
  gnuplot-nox            # mpgm plot and mpgm render draw with it (docs/studies.md)
  xvfb                   # bench/pictures: Debian's pvbatch needs an X display, even offscreen
  clang libclang-rt-14-dev  # libFuzzer: scripts/fuzz (docs/architecture.md, Tests)
)

mpgm_install_missing() {
  local missing=()
  for p in "${MPGM_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "mpgm: installing missing Debian packages: ${missing[*]}" >&2
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null 2>&1 || { echo "mpgm: need root (or sudo) to install: ${missing[*]}" >&2; exit 3; }
    sudo="sudo"
  fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

mpgm_setup() {
  local build="$1"; shift
  mpgm_install_missing
  cmake -S "$MPGM_ROOT" -B "$build" "$@" >/dev/null
  cmake --build "$build" -j"$(nproc)" 2>&1 | grep -E "error|warning|Error" >&2 || true
  # grep hides cmake's progress lines; the build's own status decides
  cmake --build "$build" -j"$(nproc)" >/dev/null
}
