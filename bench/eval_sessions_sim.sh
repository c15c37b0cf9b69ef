#!/bin/bash
# eval_sessions_sim.sh: the simulated multi-session worlds (config/sessions/*.ini), each
# session mapped against the one before, the change reports scored by `dynamap eval --sessions`.
#
# usage: bench/eval_sessions_sim.sh DYNAMAP OUT
#
# Three times per world: on ground-truth poses, on scan matching and on slam (session 1 from its
# odometry, each later session started at its first true pose with --initial-pose: the start
# search refuses the symmetric worlds' starts, which is right, and is measured on the real logs;
# slam's later sessions are tied to the prior's map).
# The table goes to stdout and OUT/eval-sessions-sim.md.
set -euo pipefail

DYNAMAP=$1
OUT=$2
mkdir -p "$OUT"

# Maps every session of world $1 into $OUT/$1/$2-1, -2, ... with poses $2; prints the scores.
run() {
  local w=$1 poses=$2 d="$OUT/$1" prev="" k=1
  for log in "$d/sim/$w.rawlog" $(ls "$d/sim/$w".s*.rawlog | sort -V); do
    local args=(map --input "$log" --poses "$poses" --no-baseline --out "$d/$poses-$k")
    if [ -n "$prev" ]; then
      args+=(--prior "$prev")
      [ "$poses" = ground_truth ] || args+=(--initial-pose "$(head -1 "${log%.rawlog}.gt.txt" | cut -d' ' -f2-4)")
    fi
    "$DYNAMAP" "${args[@]}" > /dev/null 2>&1
    prev="$d/$poses-$k"
    k=$((k + 1))
  done
  "$DYNAMAP" eval --truth "$d/sim/$w" --sessions $(ls -d "$d/$poses"-* | sort -V) | grep '^session' |
    sed 's/^session \([0-9]*\): \([0-9]*\) changes, \([0-9]*\) found, \([0-9]*\) under a wrong id, \([0-9]*\) misplaced, \([0-9]*\) missed; \([0-9]*\) false changes/| '"$w"' | '"$poses"' | \1 | \2 | \3 | \4 | \5 | \6 | \7 |/'
}

{
  echo "| world | poses | session | changes | found | wrong id | misplaced | missed | false |"
  echo "|---|---|---|---|---|---|---|---|---|"
  for ini in config/sessions/*.ini; do
    w=$(basename "$ini" .ini)
    "$DYNAMAP" simulate --scenario "$ini" --out "$OUT/$w/sim" > /dev/null
    run "$w" ground_truth
    run "$w" scan_matching
    run "$w" slam
  done
} | tee "$OUT/eval-sessions-sim.md"
