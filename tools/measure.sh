#!/usr/bin/env bash
# Allocation and instruction figures of lockstep runs (for the closing notes of optimisation
# work): heaptrack's allocation count for the surface survey (per simulated second) and
# callgrind's instruction count for the alpha mission. Needs heaptrack and valgrind; builds
# the release binary of the working tree. ../shared must sit beside the repository.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
cargo build -q --release --manifest-path "$repo/Cargo.toml"
coug=$repo/target/release/coug
corpus=$repo/../shared/corpus/moos-ivp-missions
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

survey=(run "$repo/missions/surface_survey/survey.moos" --lockstep --deploy --until "MISSION = complete"
        --max-time 900 --log-dir logs)
heaptrack -o "$work/survey" "$coug" "${survey[@]}" >/dev/null 2>&1
sim=$(find logs -name '*.alog' -exec tail -n 1 {} \; | awk '{print $1}')
heaptrack_print "$work"/survey.*.zst 2>/dev/null >"$work/heap.txt" || heaptrack_print "$work"/survey.* >"$work/heap.txt"
calls=$(grep -m1 '^calls to allocation functions' "$work/heap.txt" | awk '{print $5}')
peak=$(grep -m1 '^peak heap memory consumption' "$work/heap.txt" | awk '{print $5}')
echo "survey: ${sim} simulated s, ${calls} allocations ($(awk -v c="$calls" -v s="$sim" 'BEGIN{printf "%.0f", c/s}') per simulated s), peak heap ${peak}"

rm -rf logs
alpha=(run "$corpus/s1_alpha/alpha.moos" --lockstep --deploy --until "MISSION = complete" --max-time 1500
       --log-dir logs)
valgrind --tool=callgrind --callgrind-out-file="$work/cg.out" "$coug" "${alpha[@]}" >/dev/null 2>"$work/cg.err"
ir=$(grep -m1 '^summary:' "$work/cg.out" | awk '{print $2}')
echo "alpha: ${ir} instructions (callgrind)"
