#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# The stress suite's long run (docs/stress.md), one command:
#
#   scripts/bench/stress.sh [BUILD_DIR] [COUNT] [FIRST]
#
# runs COUNT seeded random scenes (default 3000) from seed FIRST (default 1) with the `talus`
# of BUILD_DIR (default build; build it first with scripts/build.sh, or TALUS_SANITIZE=ON for the
# sanitizers), then the bad-input matrix and the self-test. Scenes run in batches of
# TALUS_STRESS_BATCH (100) per process; a batch that dies (a signal, a sanitizer abort) is reported
# as a "crash" defect naming the seed it was running, and the run goes on from the next seed.
# A sanitizer report ("AddressSanitizer", "runtime error:") is a defect too.
#
# Prints every defect line and "stress: N scenes, M defects"; writes the report to
# scripts/bench/results/stress_<build dir name>.md and into docs/results/stress-results.md between the markers
# <!-- stress-results:<build dir name> --> ... <!-- /stress-results:<build dir name> -->
# (TALUS_STRESS_DOC=0 leaves the doc alone). Exit status 1 if there is a defect.
set -uo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
build=${1:-build}
count=${2:-3000}
first=${3:-1}
batch=${TALUS_STRESS_BATCH:-100}
[[ -x $build/talus ]] || { echo "stress.sh: no $build/talus (build it: TALUS_BUILD_DIR=$build scripts/build.sh)" >&2; exit 2; }
build_abs=$(cd "$build" && pwd)
talus="$build_abs/talus"
export TALUS_PLUGIN_PATH="$build_abs/plugins${TALUS_PLUGIN_PATH:+:$TALUS_PLUGIN_PATH}"
name=$(basename "$build")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
runner="$root/tests/stress/stress.lua"
defects="$work/defects"
: >"$defects"
sanitizer='AddressSanitizer|LeakSanitizer|runtime error:'
start=$(date +%s)
cpu0=$(awk '{print $14 + $15 + $16 + $17}' /proc/$$/stat 2>/dev/null || echo 0)

# One batch of scenes; on a crash, report the seed and go on after it.
seed=$first
last=$((first + count - 1))
stopped=0
warned=0
touch "$work/digests" "$work/groups"
while ((seed <= last)); do
    n=$((last - seed + 1 < batch ? last - seed + 1 : batch))
    out="$work/batch.txt"
    (cd "$work" && "$talus" run "$runner" scenes "$seed" "$n" --progress) >"$out" 2>&1
    rc=$?
    grep '^DEFECT ' "$out" >>"$defects"
    current=$(grep '^# seed ' "$out" | tail -1 | awk '{print $3}')
    if grep -Eq "$sanitizer" "$out"; then
        # The seed running when the report was printed: the last "# seed" line before it.
        bad=$(awk -v re="$sanitizer" '/^# seed /{s=$3} $0 ~ re {print s; exit}' "$out")
        echo "DEFECT seed=$bad sanitizer: $(grep -Em1 "$sanitizer" "$out" | cut -c1-200)" >>"$defects"
    fi
    if ((rc == 126 || rc == 127)); then
        echo "stress.sh: cannot run $talus: $(tail -1 "$out")" >&2
        exit 2
    fi
    if ! grep -q '^stress: [0-9]* scenes' "$out"; then
        # The process died inside scene $current.
        current=${current:-$seed}
        echo "DEFECT seed=$current crash: the runner died (exit status $rc$( ((rc > 128)) && echo ", signal $((rc - 128))")): $(grep -v '^# seed\|^DEFECT' "$out" | tail -1 | cut -c1-200)" >>"$defects"
        seed=$((current + 1))
        continue
    fi
    s=$(sed -n 's/^stress: seeds.* \([0-9]*\) stopped with an error.*/\1/p' "$out")
    w=$(sed -n 's/^stress: seeds.*; \([0-9]*\) warned.*/\1/p' "$out")
    stopped=$((stopped + ${s:-0}))
    warned=$((warned + ${w:-0}))
    grep '^stress: state digest' "$out" >>"$work/digests"
    grep '^stress: groupstats' "$out" >>"$work/groups"
    seed=$((seed + n))
done

# The bad-input matrix and the self-test (one process each).
(cd "$work" && "$talus" run "$runner" badinput --out="$work") >"$work/bad.txt" 2>&1
rc_bad=$?
grep '^DEFECT ' "$work/bad.txt" >>"$defects"
grep -q '^stress: [0-9]* bad-input cases' "$work/bad.txt" ||
    echo "DEFECT badinput crash: the runner died (exit status $rc_bad): $(tail -1 "$work/bad.txt" | cut -c1-200)" >>"$defects"
grep -Eq "$sanitizer" "$work/bad.txt" && echo "DEFECT badinput sanitizer: $(grep -Em1 "$sanitizer" "$work/bad.txt" | cut -c1-200)" >>"$defects"
(cd "$work" && "$talus" run "$runner" selftest) >"$work/self.txt" 2>&1 ||
    grep -v '^stress:' "$work/self.txt" | grep MISSED | sed 's/^/DEFECT /' >>"$defects"

ndef=$(wc -l <"$defects")
elapsed=$(($(date +%s) - start))
classes=$(sed -n 's/^stress: bad-input classes: //p' "$work/bad.txt")
ncases=$(sed -n 's/^stress: \([0-9]*\) bad-input cases.*/\1/p' "$work/bad.txt")
# Clump and group scenes, and the worst group residuals over all batches (stress.lua's summary).
groups_line=$(awk '{
    for (i = 3; i <= NF; i++) { split($i, kv, "="); v[kv[1]] = kv[2] }
    c += v["clumps"]; g += v["groups"]; p += v["partitions"]
    if (v["own"] + 0 > own) { own = v["own"] + 0; os = v["own_seed"] }
    if (v["whole"] + 0 > whole) { whole = v["whole"] + 0; ws = v["whole_seed"] }
    if (v["sum"] + 0 > sum) { sum = v["sum"] + 0; ss = v["sum_seed"] }
} END { printf "%d scenes with clumps, %d with groups (%d partitions); worst group residual %.3g of the model throughput (seed %s; %.3g of its own, seed %s, not a criterion); worst partition sum %.3g of the throughput (seed %s)", c, g, p, whole, ws, own, os, sum, ss }' "$work/groups")
by_check=$(sed -E 's/^DEFECT (badinput [^:]*: ([a-z-]+):|seed=[0-9]+ [^]]*\] ([a-z-]+):|seed=[0-9]+ ([a-z-]+):).*/\2\3\4/' "$defects" |
    sort | uniq -c | awk '{printf "%s%s %d", (NR > 1 ? ", " : ""), $2, $1}')

report="$work/report.md"
doc_report="$work/doc_report.md"
{
    echo "Run of $(date -u +%Y-%m-%d) with \`scripts/bench/stress.sh $build $count $first\` ($(git rev-parse --short HEAD 2>/dev/null || echo '?')$(git diff --quiet 2>/dev/null || echo ' + local changes'), $elapsed s wall on $(nproc) cores):"
    echo
    echo "- scenes: $count (seeds $first-$last); $stopped stopped with a clear error, $warned warned"
    echo "- clumps and groups: $groups_line"
    echo "- bad-input cases: ${ncases:-?} (${classes:-no result})"
    echo "- defects: $ndef${by_check:+ ($by_check)}"
    echo "- state digest: $(md5sum <"$work/digests" | cut -c1-16) (md5 of the batches' FNV-1a digests of every final state; equal between builds = bit-identical results)"
    echo
} >"$report"
cp "$report" "$doc_report"
if ((ndef > 0)); then
    { echo '```'; cut -c1-240 "$defects"; echo '```'; } >>"$report"
    # The doc keeps the first 60 lines; the results file has them all.
    {
        echo '```'
        head -60 "$defects" | cut -c1-240
        ((ndef > 60)) && echo "... $((ndef - 60)) more in scripts/bench/results/stress_$name.md"
        echo '```'
    } >>"$doc_report"
fi
mkdir -p scripts/bench/results
cp "$report" "scripts/bench/results/stress_$name.md"

if [[ ${TALUS_STRESS_DOC:-1} != 0 && -f docs/results/stress-results.md ]]; then
    python3 - "$name" "$doc_report" <<'PY'
import sys, re
name, report = sys.argv[1], open(sys.argv[2]).read()
path = "docs/results/stress-results.md"
doc = open(path).read()
begin, end = f"<!-- stress-results:{name} -->", f"<!-- /stress-results:{name} -->"
block = f"{begin}\n{report.rstrip()}\n{end}"
if begin in doc and end in doc:
    doc = re.sub(re.escape(begin) + ".*?" + re.escape(end), lambda m: block, doc, flags=re.S)
else:
    doc = doc.rstrip() + "\n\n" + block + "\n"
open(path, "w").write(doc)
PY
fi

cat "$defects" | cut -c1-300
echo "stress: state digest $(md5sum <"$work/digests" | cut -c1-16)"
echo "stress: bad-input: ${ncases:-?} cases (${classes:-no result})"
echo "stress: $count scenes, $ndef defects"
((ndef == 0))
