#!/usr/bin/env bash
# Regenerates the seed-paper report, docs/seed_paper.md, in one command:
#   1. builds examples/seed_paper.cpp with exactly the compiler flags of tests/problems/test_seed_paper.cpp (taken from
#      the build's compile_commands.json), so that the test recomputes the same bits;
#   2. runs it: the tables (markdown) and the plot data (CSV) go to BUILD_DIR/seed_paper_data/;
#   3. splices every <!-- table:NAME --> block into docs/seed_paper.md and copies the tables to
#      docs/seed_paper/results.md;
#   4. draws docs/seed_paper/*.png with matplotlib (Debian's python3-matplotlib, under /usr/bin/python3);
#   5. builds and runs the test that checks the report against the program (SeedReport.*).
# When matplotlib is missing and cannot be installed (no root, no sudo), steps 1-3 and 5 still run: the
# numbers are regenerated and checked, the plots are left as they are, and the script says so and exits
# with status 2.
#
#   scripts/seed_report.sh [BUILD_DIR]        (default: build)
#   LGI_SEED_PYTHON="python3 -S" scripts/seed_report.sh   another interpreter (e.g. one without matplotlib)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=$(realpath -m "${1:-$root/build}")
# Debian's matplotlib imports only under the system interpreter (NUMERICS.md, traps).
read -r -a py <<< "${LGI_SEED_PYTHON:-/usr/bin/python3}"

LGI_DEPS_EXTRA="python3-matplotlib" "$root/scripts/install-deps.sh" ||
  echo "seed_report: install-deps failed (see above); continuing with what is installed" >&2
plots=yes
if ! "${py[@]}" -c "import matplotlib" 2> /dev/null; then
  plots=no
  echo "seed_report: matplotlib cannot be imported by ${py[*]} (Debian: apt-get install python3-matplotlib);" \
       "the tables will be regenerated, the plots will NOT be redrawn" >&2
fi
cmake -S "$root" -B "$build" > /dev/null

# 1. The test's compile command, with its source and object replaced.
flags=$("${py[@]}" - "$build/compile_commands.json" <<'EOF'
import json, shlex, sys
for entry in json.load(open(sys.argv[1])):
    if entry["file"].endswith("tests/problems/test_seed_paper.cpp"):
        args = shlex.split(entry["command"])
        out, skip = [], False
        for a in args[1:]:
            if skip:
                skip = False
                continue
            if a in ("-o", "-c"):
                skip = True
                continue
            out.append(a)
        print(shlex.join([args[0]] + out))
        break
else:
    sys.exit("seed_report: no compile command for tests/problems/test_seed_paper.cpp in " + sys.argv[1])
EOF
)
echo "seed_report: building examples/seed_paper.cpp" >&2
eval "$flags" "$root/examples/seed_paper.cpp" -o "$build/seed_paper"

# 2. Run.
data="$build/seed_paper_data"
mkdir -p "$data" "$root/docs/seed_paper"
echo "seed_report: running the reproduction" >&2
"$build/seed_paper" "$data" > /dev/null
cp "$data/results.md" "$root/docs/seed_paper/results.md"

# 3. Splice the tables into the report.
"${py[@]}" - "$data/results.md" "$root/docs/seed_paper.md" <<'EOF'
import re, sys
results, doc_path = open(sys.argv[1]).read(), sys.argv[2]
doc = open(doc_path).read()
pattern = re.compile(r"<!-- table:(\w+) -->\n.*?<!-- /table:\1 -->\n", re.S)
blocks = {m.group(1): m.group(0) for m in pattern.finditer(results)}
missing = [name for name in blocks if f"<!-- table:{name} -->" not in doc]
if missing:
    sys.exit("seed_report: docs/seed_paper.md has no place for the tables " + ", ".join(missing))
doc = pattern.sub(lambda m: blocks.get(m.group(1), m.group(0)), doc)
open(doc_path, "w").write(doc)
EOF

# 4. Plots.
if [[ $plots == yes ]]; then
echo "seed_report: drawing docs/seed_paper/*.png" >&2
"${py[@]}" - "$data" "$root/docs/seed_paper" <<'EOF'
import csv, math, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

data, out = sys.argv[1], sys.argv[2]

def load(name):
    with open(f"{data}/{name}") as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}

def floor(values, eps=1e-17):
    return [max(v, eps) if not math.isnan(v) else float("nan") for v in values]

plt.rcParams.update({"font.size": 9, "figure.dpi": 110})

# Nutation: U(t) by the quadrature and by integration, scenario B.
n = load("nutation_B.csv")
fig, (a, b) = plt.subplots(2, 1, figsize=(7, 4.5), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
a.plot(n["t"], n["U_quadrature"], lw=1.2, label="U(t), quadrature: u1 + (u2 - u1) sn²(λt + τ0, k)")
a.plot(n["t"][::80], n["U_integration"][::80], "o", ms=3, label="U = k·(R e3), RKMK4 on SO(3), h = 2.5e-4")
a.set_ylabel("U = cos(axis, k)")
a.set_ylim(min(n["U_quadrature"]) - 0.02, max(n["U_quadrature"]) + 0.16)
a.legend(loc="upper right", fontsize=8, ncol=1)
b.semilogy(n["t"], floor(n["error"]), lw=0.8)
b.set_ylabel("|difference|")
b.set_xlabel("t")
fig.suptitle("Scenario B: the nutation coordinate U(t)")
fig.tight_layout()
fig.savefig(f"{out}/nutation.png")

# Agreement of the formulations, scenario B.
g = load("agreement_B.csv")
fig, a = plt.subplots(figsize=(7, 3.2))
a.semilogy(g["t"], floor(g["euler_vs_so3"]), lw=0.8, label="Euler angles (RK4) vs SO(3) (RKMK4), h = 1e-3")
a.semilogy(g["t"], floor(g["so3_vs_quadrature"]), lw=0.8, label="SO(3) (RKMK4) vs quadrature")
a.semilogy(g["t"], floor(g["euler_vs_quadrature"]), lw=0.8, label="Euler angles (RK4) vs quadrature")
a.set_xlabel("t")
a.set_ylabel("‖ΔR‖_F")
a.legend(fontsize=8)
a.set_title("Scenario B: three formulations of the paper's top")
fig.tight_layout()
fig.savefig(f"{out}/agreement.png")

# The two laboratory frames, scenario B.
f = load("frames_B.csv")
fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.8))
a.plot(f["paper_x"], f["paper_y"], lw=2.5, alpha=0.5, label="(s7), paper's frame")
a.plot(f["textbook_x"], f["textbook_y"], "--", lw=1, label="(s7.1), frame e3 = k, mapped back by Qᵀ")
a.plot(f["naive_x"], f["naive_y"], ":", lw=1, label="(s7.1) fed the same angle values (mapped back)")
a.set_aspect("equal")
a.set_xlabel("x (paper's frame)")
a.set_ylabel("y")
a.set_title("symmetry axis R e3, projected", fontsize=9)
a.legend(fontsize=7, loc="lower left")
b.semilogy(f["t"], floor(f["distance"]), lw=0.8)
b.set_xlabel("t")
b.set_ylabel("|axis(s7) − Qᵀ axis(s7.1)|")
b.set_title("same physical initial state", fontsize=9)
fig.tight_layout()
fig.savefig(f"{out}/frames.png")

# The coordinate singularity, scenario A.
s = load("singularity_A.csv")
fig, (a, b) = plt.subplots(2, 1, figsize=(7, 4.5), sharex=True)
a.plot(s["t"], s["sin_theta_paper"], lw=1, label="sin θ, paper's frame (k = (0, 0.6, 0.8))")
a.plot(s["t"], s["sin_theta_textbook"], lw=1, label="sin θ_k, textbook frame (e3 = k)")
a.axhline(0.05, color="gray", lw=0.6, ls="--", label="min_sin_theta = 0.05")
a.set_ylabel("sin θ")
a.legend(fontsize=8)
b.semilogy(s["t"], floor(s["euler_error"]), lw=0.8)
b.set_ylabel("Euler angles vs SO(3), ‖ΔR‖_F")
b.set_xlabel("t")
fig.suptitle("Scenario A, R(0) = 1: the Euler angles start on their singularity and come back near it")
fig.tight_layout()
fig.savefig(f"{out}/singularity.png")
EOF
fi

# 5. The report carries the program's numbers.
cmake --build "$build" -j2 --target test_seed_paper > /dev/null
"$build/tests/test_seed_paper" --gtest_filter='SeedReport.*' --gtest_brief=1
if [[ $plots == no ]]; then
  echo "seed_report: docs/seed_paper.md regenerated and checked; plots NOT redrawn (no matplotlib)" >&2
  exit 2
fi
echo "seed_report: docs/seed_paper.md and docs/seed_paper/*.png regenerated" >&2
