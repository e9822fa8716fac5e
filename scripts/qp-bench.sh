#!/usr/bin/env bash
# The QP comparison of docs/qp.md: pwsim's dual active set against R's quadprog on the outside
# MPC benchmark (bench/qp_bench), and the MPC's worst case over the shipped scenes
# (bench/qp_mpc_worst_case), as markdown tables with the commit and the machine they ran on.
#   scripts/qp-bench.sh [--write] [DATA_DIR] [BUILD_DIR]
# DATA_DIR defaults to ../shared/data/qp-mpc beside the source tree, BUILD_DIR to build/ (both
# bench targets are built there if missing). Prints the markdown; with --write it also replaces
# the part of docs/qp.md between the lines "<!-- qp-bench:begin -->" and "<!-- qp-bench:end -->".
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
write=0
if [ "${1:-}" = "--write" ]; then write=1; shift; fi
data=${1:-$root/../shared/data/qp-mpc}
build=${2:-$root/build}
if [ ! -d "$data" ]; then
  echo "qp-bench: no benchmark directory $data (the qpsolvers/mpc_qpbenchmark problems as JSON)" >&2
  exit 2
fi
for target in qp_bench qp_mpc_worst_case; do
  if [ ! -x "$build/bench/$target" ]; then cmake --build "$build" --target "$target" -j2; fi
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$build/bench/qp_bench" "$(cd "$data" && pwd)" > "$work/qp.txt"
"$build/bench/qp_mpc_worst_case" --repeats 3 > "$work/mpc.txt"

commit=$(git -C "$root" rev-parse --short HEAD)
if ! git -C "$root" diff --quiet HEAD -- mca/qp_active_set.h mca/qp_active_set.cc mca/qp_problem.h \
    mca/qp_problem.cc bench/qp_bench.cc bench/qp_mpc_worst_case.cc scripts/qp-quadprog.R; then
  commit="$commit + uncommitted changes to the solver or the benchmark"
fi
cpu=$(grep -m1 "model name" /proc/cpuinfo | sed 's/.*: //')
machine="$cpu, $(nproc) cores, $(uname -sr), load average $(cut -d' ' -f1-3 /proc/loadavg) at the start"
compiler=$(grep -m1 CMAKE_CXX_COMPILER: "$build/CMakeCache.txt" | sed 's/.*=//')
flags=$(grep -m1 "^CMAKE_CXX_FLAGS_RELEASE" "$build/CMakeCache.txt" | sed 's/.*=//')

python=python3
if [ -x /usr/bin/python3 ]; then python=/usr/bin/python3; fi
"$python" - "$work/qp.txt" "$work/mpc.txt" "$commit" "$machine" "$(date -u +%Y-%m-%d)" \
  "$("$compiler" --version | head -1) $flags" > "$work/table.md" <<'PY'
import re
import sys

qp_file, mpc_file, commit, machine, day, compiler = sys.argv[1:]
section, ours, theirs, detail, summary, about = None, {}, {}, {}, [], {}
for line in open(qp_file):
    line = line.rstrip("\n")
    if line.startswith("# pwsim"):
        section, about["pwsim"] = "pwsim", line[2:]
    elif line.startswith("# quadprog"):
        section, about["quadprog"] = "quadprog", line[2:]
    elif line.startswith("# SECONDS"):
        about["seconds"] = line[2:]
    elif line.startswith("#"):
        section = None
    elif line.startswith("detail "):
        _, name, n, m, steps, iters = line.split()
        detail[name] = (n, m, steps, iters)
    elif line.startswith("summary "):
        summary.append(line[len("summary "):])
    elif section:
        name, status, objective, seconds = line.split()
        (ours if section == "pwsim" else theirs)[name] = (status, float(objective), float(seconds))


def natural(name):
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", name)]


print(f"Measured {day} at commit {commit} on {machine}; {compiler}.")
print(f"{about.get('seconds', '')}. {about.get('pwsim', '')}. {about.get('quadprog', 'quadprog: not run (Rscript or the package missing)')}.")
print()
print("| problem | n × m | pwsim | objective | µs | steps | quadprog | objective | µs | iterations | quadprog / pwsim time |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for name in sorted(ours, key=natural):
    n, m, steps, iters = detail[name]
    s, f, t = ours[name]
    if name in theirs:
        s2, f2, t2 = theirs[name]
        ref = f"{s2} | {f2:.12g} | {t2 * 1e6:.1f} | {iters} | {t2 / t:.2f}"
    else:
        ref = "– | – | – | – | –"
    print(f"| {name} | {n} × {m} | {s} | {f:.12g} | {t * 1e6:.1f} | {steps} | {ref} |")
print()
for line in summary:
    print(f"- {line}")
print()
print("The MPC's QP over the shipped scenes (`pwsim run SCENE --mca mpc`: held input, the scene's platform "
      "and settings; steps per solve, thread CPU time of a solving tick, minimum over 3 repeats per solve, "
      "then p50 / p99 / max over the solves; wall max: any repeat, interference included):")
print()
print("| scene | platform | solves | fallbacks | steps max (at) | steps mean | CPU µs p50 | p99 | max | wall µs max |")
print("|---|---|---|---|---|---|---|---|---|---|")
worst = []
for line in open(mpc_file):
    if line.startswith("#"):
        continue
    if line.startswith("worst "):
        worst.append(line.strip()[len("worst "):])
        continue
    f = line.split()
    if "skipped:" in f:
        print(f"| {f[0]} | skipped: {' '.join(f[2:])} |||||||||")
        continue
    kv = dict(x.split("=", 1) for x in f if "=" in x)
    at = re.search(r"\(at t=([0-9.]+) s\)", line).group(1)
    print(f"| {f[0]} | {f[1]} | {kv['solves']} | {kv['fallbacks']} | {kv['steps_max']} ({at} s) | {kv['steps_mean']} | "
          f"{kv['p50']} | {kv['p99']} | {kv['max']} | {kv['wall_us_max']} |")
print()
for line in worst:
    print(f"- worst {line}")
PY

cat "$work/table.md"
if [ $write -eq 1 ]; then
  doc="$root/docs/qp.md"
  "$python" - "$doc" "$work/table.md" <<'PY'
import sys
doc, table = sys.argv[1:]
text = open(doc).read()
begin, end = "<!-- qp-bench:begin -->", "<!-- qp-bench:end -->"
if begin not in text or end not in text:
    sys.exit(f"qp-bench: {doc} lacks the lines {begin} and {end}")
head, rest = text.split(begin, 1)
_, tail = rest.split(end, 1)
open(doc, "w").write(head + begin + "\n" + open(table).read() + end + tail)
PY
  echo "qp-bench: wrote the tables into $doc" >&2
fi
