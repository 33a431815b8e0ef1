#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer build in build-asan/ (its own directory, -O1,
# debug info) and the fast tests under it, leak check included. Gmsh's own allocations that
# outlive gmsh::finalize are suppressed (scripts/lsan.supp); everything else is a failure.
#
#   bash scripts/run-sanitizers.sh                 # the default subset below
#   bash scripts/run-sanitizers.sh 'Gmsh*:Pim*'    # a gtest filter of your own
#   JOBS=1 bash scripts/run-sanitizers.sh          # fewer parallel compiles
#
# The flexsens processes the tests start (bad scenes, interrupts, full disk) are the
# sanitized binary too, so the CLI paths are covered. Slow: the build alone takes ~15 min on
# 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
FILTER="${1:-TimeGrid.*:Interrupts.*:RunIntegrity.*:BadScenes/*:BadScenes.*:CliErrors.*:PimErrors.*:Gmsh*:GeoScan.*:Outputs*:Rigidization*}"
# EIGEN_MALLOC_ALREADY_ALIGNED=1: under ASan, Eigen switches to its own offset-pointer
# allocator (Memory.h: !__SANITIZE_ADDRESS__), while libgmsh (not instrumented) frees the
# matrices of the Eigen templates it shares with us with plain free(): a "bad-free" that is an
# artefact of mixing the two. glibc's and ASan's malloc are 16-byte aligned, which is all
# Eigen needs without AVX (its assert, on in this -O1 build, would say otherwise).
SAN="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined -DEIGEN_MALLOC_ALREADY_ALIGNED=1"
# Configured every time (cheap), so that a change of these flags reaches an existing build-asan/.
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DCMAKE_CXX_FLAGS="$SAN" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build build-asan -j "${JOBS:-$(nproc)}"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd build-asan
./flexsens_tests --gtest_filter="$FILTER" --gtest_brief=1
# The sandboxed Gmsh path (fork, seccomp, limits, the mesh back over the pipe) on meshed
# bodies and beam geometry: a shell, a solid, a meshed link and the satellite's curves.
for scene in shell/panel.yaml solid/pendulum3d.yaml fivebar/meshed_link.yaml satellite/satellite.yaml; do
  ./flexsens check "../examples/$scene" >/dev/null
done
T=$(mktemp -d)
./flexsens run ../examples/shell/panel.yaml --t-end 0.004 --out "$T/panel" >/dev/null
rm -rf "$T"
# Every tenth mutant puts a hostile command into a meshed body's .geo (SystemCall, Printf >,
# Include /dev/zero, endless loop, ...); meshed bodies are reached (mesh: paths made absolute).
python3 ../scripts/fuzz_scenes.py --exe ./flexsens --count 60 --seed 7 --time-limit 120
echo "sanitizers: clean ($FILTER, 4 meshed examples, 60 fuzz mutants)"
