#!/usr/bin/env bash
# Installs the Debian 12 packages flexsens needs; quiet and quick when all are present.
set -euo pipefail
PACKAGES=(
  g++ cmake ninja-build              # toolchain
  ccache                             # rebuilds of unchanged sources are cache hits
  libeigen3-dev                      # dense/sparse linear algebra
  libsuitesparse-dev                 # KLU sparse LU, CHOLMOD sparse Cholesky
  libopenblas0-serial                # BLAS of CHOLMOD's supernodes (faster than the reference BLAS)
  libmumps-seq-dev                   # MUMPS' sparse LDL^T (sequential): Newton matrices of constrained continua
  libsundials-dev                    # IDAS (+ nvecserial, sunmatrixsparse, sunlinsolklu)
  libgmsh-dev                        # Gmsh SDK (geometry -> node chains)
  libseccomp-dev                     # system-call filter of the sandboxed Gmsh child
  libvtk9-dev                        # VTK XML writers (.vtu)
  libyaml-cpp-dev                    # scene files
  libnlopt-cxx-dev                   # NLopt (C++ API): MMA, SLSQP, L-BFGS of flexsens optimize
  libcli11-dev                       # command line
  libgtest-dev                       # tests
  libopenmpi-dev openmpi-bin         # MPI: sweep, run and study over the ranks of mpirun (docs/sweeps.md)
  python3-matplotlib                 # PNG plots of the results
  python3-yaml                       # scene fuzzer (scripts/fuzz_scenes.py)
  pybind11-dev python3-dev           # the Python module flexsens (python/): bindings, Python headers
  python3-numpy                      # its arrays (Result.q, .dq, ...)
  python3-pytest                     # its tests (tests/python, run by CTest)
  python3-scipy                      # the design-fit example (examples/python/design_fit.py)
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "flexsens: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
