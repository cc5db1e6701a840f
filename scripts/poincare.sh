#!/usr/bin/env bash
# Regenerates the Poincare section of an asymmetric heavy top in one command:
#   1. builds the lgi command (BUILD_DIR, default build/);
#   2. runs the sweep examples/sweep/heavy_top_poincare.json on all cores (2000 orbits of 50000 LGVI steps with a
#      Lyapunov shadow each, ~15 s of CPU): BUILD_DIR/heavy_top_poincare.csv (one row per orbit) and
#      BUILD_DIR/heavy_top_poincare.crossings.csv (one row per crossing of the section gamma1 = 0, ~97000);
#   3. scripts/poincare.py draws docs/img/heavy_top_poincare.png and splices its summary into docs/sweep.md.
# When matplotlib is missing (Debian: python3-matplotlib, under /usr/bin/python3) the summary is still regenerated;
# the figure is left as it is, the script says so and exits with status 2.
#
#   scripts/poincare.sh [BUILD_DIR]
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=$(realpath -m "${1:-$root/build}")
[ -f "$build/CMakeCache.txt" ] || cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$build" -j"$(nproc)" --target lgi_exe
"$build/lgi" sweep "$root/examples/sweep/heavy_top_poincare.json" -o "$build/heavy_top_poincare.csv" --threads 0
mkdir -p "$root/docs/img"
/usr/bin/python3 "$root/scripts/poincare.py" "$build/heavy_top_poincare.csv" \
  --png "$root/docs/img/heavy_top_poincare.png" --doc "$root/docs/sweep.md"
