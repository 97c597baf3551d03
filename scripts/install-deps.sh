#!/usr/bin/env bash
# Makes a fresh Debian 12 machine ready to build and test suturesim.
# Idempotent: when every package is already installed it returns in about a second.
set -euo pipefail

packages=(
  build-essential cmake git ccache pkg-config
  libdeal.ii-dev          # deal.II 9.4.1 with PETSc 3.18, SUNDIALS 6.4, p4est, MPI, muparser
  libeigen3-dev           # realtime path and rod solver
  nlohmann-json3-dev      # summary.json
  zlib1g-dev              # the realtime tissue's compressed .vtu files (also a deal.II dependency)
  libgtest-dev googletest libbenchmark-dev
  gmsh                    # .geo -> .msh at run time
  util-linux              # prlimit: gmsh run under Mesh/Gmsh memory limit
  libgmsh-dev             # gmsh API: tetrahedral meshes for the realtime path
  openmpi-bin             # mpirun for the parallel regression test
  numdiff
  libopenblas0-pthread    # optimised BLAS/LAPACK: MUMPS spends its time in dense BLAS-3
  python3-matplotlib python3-numpy   # postprocess/
  snakemake               # suturesim study --export snakemake: a study as a workflow (tested)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
