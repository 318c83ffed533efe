#!/usr/bin/env bash
# Writes the lockstep alogs of the alpha, delta, survey and dive missions with the coug binary
# of a given commit (default: HEAD), so a refactoring can be checked to leave them byte for byte
# unchanged:
#
#   tools/alog-baseline.sh <commit> <out-dir>       # e.g. the commit before the change
#   tools/alog-baseline.sh HEAD <out-dir2>
#   diff -r <out-dir> <out-dir2>                    # no output: identical
#
# The commit is built in a throwaway worktree under target/; ../shared must sit beside the
# repository (the alpha and delta missions come from its corpus).
set -euo pipefail
commit=${1:?usage: tools/alog-baseline.sh <commit> <out-dir>}
out=${2:?usage: tools/alog-baseline.sh <commit> <out-dir>}
repo=$(cd "$(dirname "$0")/.." && pwd)
corpus=$repo/../shared/corpus/moos-ivp-missions
[ -d "$corpus" ] || { echo "alog-baseline: $corpus is missing" >&2; exit 1; }

wt=$repo/target/alog-baseline-$(git -C "$repo" rev-parse --short "$commit")
if [ ! -d "$wt" ]; then
  git -C "$repo" worktree add -q --detach "$wt" "$commit"
fi
CARGO_TARGET_DIR=$repo/target/alog-baseline-build cargo build -q --release --manifest-path "$wt/Cargo.toml"
coug=$repo/target/alog-baseline-build/release/coug

mkdir -p "$out"
out=$(cd "$out" && pwd)
run() { # name mission args...
  local name=$1 mission=$2; shift 2
  local d; d=$(mktemp -d)
  (cd "$d" && "$coug" run "$mission" --lockstep --log-dir logs "$@" >/dev/null 2>"$d/stderr") \
    || { cat "$d/stderr" >&2; exit 1; }
  find "$d/logs" -name '*.alog' -exec cp {} "$out/$name.alog" \;
  rm -rf "$d"
}
run alpha "$corpus/s1_alpha/alpha.moos" --deploy --until "MISSION = complete" --max-time 1500
run delta "$corpus/s4_delta/delta.moos" --deploy --poke SURVEY=true@300 --poke RETURN=true@1200 \
  --until "DEPLOY = false" --max-time 3000
run survey "$repo/missions/surface_survey/survey.moos" --deploy --until "MISSION = complete" --max-time 900
run dive "$repo/missions/dive/dive.moos" --deploy --until "MISSION = complete" --max-time 1200
git -C "$repo" worktree remove --force "$wt"
ls -l "$out"
