#!/usr/bin/env bash
# Installs the Debian packages lgi needs, only those that are missing.
# Idempotent and silent when everything is present; safe to run before every build.
#
#   scripts/install-deps.sh            build + test dependencies
#   LGI_DEPS_EXTRA="pkg ..." scripts/install-deps.sh   also install extra packages
set -euo pipefail

packages=(
  build-essential       # g++ 12, make
  cmake                 # >= 3.25
  libeigen3-dev         # Eigen 3.4: the core's only dependency
  libceres-dev          # Ceres 2.1: ceres::Jet in tests, fitting
  libgtest-dev libgmock-dev
  libbenchmark-dev      # Google Benchmark
  nlohmann-json3-dev    # scene files
  libboost-dev          # Boost.Math: elliptic functions for exact solutions (header-only)
  libcli11-dev          # command line
  valgrind              # callgrind instruction counts (benchmarks)
  libgsl-dev            # benchmarks: GSL odeiv2 (rk8pd, rk4imp, msadams), a peer in work_precision
  libsundials-dev       # benchmarks: SUNDIALS 6.4 CVODE Adams and ARKODE ERK, peers in work_precision
  python3-matplotlib    # benchmarks: scripts/bench_report.py plots (Debian's /usr/bin/python3)
  clang libclang-rt-14-dev  # scene fuzzer (fuzz/): clang-14 only Recommends the libFuzzer/ASan runtimes (rt-14-dev)
  libopenmpi-dev openmpi-bin  # lgi_sweep_mpi (optional, apps/sweep_mpi.cpp): Open MPI, and mpirun for its test
  doxygen               # the API reference (docs target) and its api_reference test (docs/Doxyfile.in)
  pybind11-dev python3-dev python3-numpy python3-pytest  # the Python package (python/) and its tests
  libjs-three           # lgi view: three.js r111, inlined into the pages it writes (apps/view.hpp)
  chromium              # lgi view's browser test (tests/viewer): Debian's Chromium, headless
)
# shellcheck disable=SC2206
packages+=(${LGI_DEPS_EXTRA:-})

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
((${#missing[@]} == 0)) && exit 0

echo "install-deps: installing ${missing[*]}" >&2
as_root=(env DEBIAN_FRONTEND=noninteractive)  # through env: sudo's env_reset would drop an export
if ((EUID != 0)); then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  # -n: fail at once rather than wait for a password nobody will type (CI); a terminal may prompt.
  if [[ -t 0 ]]; then as_root=(sudo "${as_root[@]}"); else as_root=(sudo -n "${as_root[@]}"); fi
fi
"${as_root[@]}" apt-get update -qq >&2
"${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
