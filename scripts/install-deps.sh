#!/usr/bin/env bash
# Installs the Debian 12 packages tvid needs to build and test. Idempotent, non-interactive.
#   scripts/install-deps.sh            everything: build, tests, plots, sanitizers, fuzzing, MPI, benchmarks
#   scripts/install-deps.sh --minimal  only what building and running the tvid tool needs
set -euo pipefail

minimal=0
case "${1:-}" in
  "") ;;
  --minimal) minimal=1 ;;
  *) echo "install-deps: unknown option '$1' (use --minimal, or nothing)" >&2; exit 2 ;;
esac

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev          # Eigen 3.4: dense linear algebra
  libboost-dev           # Boost 1.74 headers: Odeint, Math (root finding)
  libnlopt-cxx-dev       # NLopt 2.7 with its C++ API
  libyaml-cpp-dev        # yaml-cpp 0.7: experiment files
  libcli11-dev           # CLI11 2.1: command line
  nlohmann-json3-dev     # nlohmann-json 3.11: report files
  libssl-dev             # OpenSSL: SHA-256 of config and data in the report
)
[ "$minimal" -eq 1 ] || packages+=(
  catch2                 # Catch2 2.13: tests
  python3                # data generation and test helpers (standard library only)
  python3-matplotlib     # scripts/plot_report.py: figures of a report directory
  python3-numpy          # scripts/fir_reference.py: the black-box reference of a measured bench
  clang libclang-rt-14-dev libomp-dev  # the asan preset and the libFuzzer targets (scripts/fuzz.sh)
  libopenmpi-dev openmpi-bin           # Open MPI: the mpi preset (tvid fit / batch under mpirun)
  universal-ctags        # scripts/long_functions.py: each function's first and last line (the layers test)
  libpagmo-dev           # pagmo2 2.18: bench/pagmo_cvt.cpp, the yardstick of the paper's swarm
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
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: installed ${missing[*]}"
