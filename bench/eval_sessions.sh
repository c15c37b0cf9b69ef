#!/bin/bash
# eval_sessions.sh: real logs split into two sessions, the second mapped against the first.
#
# usage: bench/eval_sessions.sh DYNAMAP DATASETS OUT
#
# For each corrected CARMEN log of DATASETS/carmen/: the log is cut at its middle laser line
# into session A (everything before) and session B (the file's header lines, then everything
# after). A is mapped on its corrected poses (--poses ground_truth); B is mapped twice on its
# own, as a first session would be, and against A's session.json (--prior). Nothing in these logs
# was moved on purpose between the halves, so every change B's report holds is false or a
# change the building saw while it was logged (a door, a chair, someone who stood). The CPU time
# (user + system) of B with and without the prior gives the cost of a continued session.
# Then B's start is searched for: `dynamap perturb` gives B drifting odometry (seeds 1-3), and
# B is mapped on it against A without --initial-pose; the start found is compared with B's first
# corrected pose (position and heading error), or the search's refusal is shown. Last, B on its
# drifting odometry is mapped with --poses slam against A (tied to A's map; --initial-pose at
# its first corrected pose where the search refuses) and its poses are scored against B's
# corrected poses, paired by timestamp, in A's frame with no alignment (RMSE and worst).
# The tables go to stdout and OUT/eval-sessions.md.
set -euo pipefail

DYNAMAP=$1
DATASETS=$2
OUT=$3
LOGS=${EVAL_SESSIONS_LOGS:-freiburg-079 intel freiburg-campus orebro}
DATA='^(FLASER|ROBOTLASER1|RLASER|RAWLASER[0-9]|ODOM|TRUEPOS|SONAR) '
mkdir -p "$OUT"

# CPU seconds (user + system) of a command, its output discarded; called in $( ), whose
# subshell's children are that command alone (bash's `times`).
cpu() {
  "$@" > /dev/null 2>&1 || true
  times > "$OUT/.times"  # not through a pipe: that would be a subshell of its own
  tail -1 "$OUT/.times" | awk '{ s = 0; for (i = 1; i <= 2; ++i) { split($i, p, /[ms]/); s += p[1] * 60 + p[2] } printf "%.2f", s }'
}
# Position RMSE and worst error [m] of poses.txt $2 against `t x y phi` truth $1, paired by time.
poseError() {
  awk 'NR == FNR { if ($1 !~ /^%/) { x[$1] = $2; y[$1] = $3 } next }
       $1 !~ /^%/ && ($1 in x) { d2 = ($2 - x[$1])^2 + ($3 - y[$1])^2; s += d2; n++; if (d2 > w) w = d2 }
       END { if (n) printf "%.3f / %.3f", sqrt(s / n), sqrt(w); else printf "no pose paired" }' "$1" "$2"
}
# The first `x y phi` of a truth file.
firstPose() { awk '!/^%/ { print $2, $3, $4; exit }' "$1"; }
# The count of one kind of change in a changes.csv.
kind() { awk -F, -v k="$1" '$1 == k { n++ } END { print n + 0 }' "$2"; }

# B on its drifting odometry (seed $2) mapped with --poses slam against A, at --initial-pose $3
# when given (the search refused the start); a row of its pose error and ties.
tied() {
  local d="$OUT/$1" args
  args=(map --input "$d/drift-$2/odometry.rawlog" --poses slam --prior "$d/a" --no-baseline
    --out "$d/slam-$2")
  [ -z "$3" ] || args+=(--initial-pose "$3")
  "$DYNAMAP" "${args[@]}" > /dev/null 2>&1 || true
  local ties
  ties=$(grep -A3 '"prior_map_ties"' "$d/slam-$2/summary.json" 2>/dev/null |
    awk -F'[:,]' '/"accepted"/ { a = $2 } /"searches"/ { s = $2 } END { gsub(/ /, "", a); gsub(/ /, "", s); print a " / " s }')
  echo "| $1 | $2 | $(poseError "$d/drift-$2/gt.txt" "$d/slam-$2/poses.txt" 2>/dev/null) | $ties |"
}

: > "$OUT/.tied"
{
  echo "| log | laser lines A / B | objects moved | new | gone | structure added | removed | CPU of B alone / with prior [s] |"
  echo "|---|---|---|---|---|---|---|---|"
  for log in $LOGS; do
    src="$DATASETS/carmen/$log-corrected.log.gz"
    [ -f "$src" ] || continue
    d="$OUT/$log"
    mkdir -p "$d"
    zcat "$src" > "$d/whole.log"
    n=$(grep -cE "^(FLASER|ROBOTLASER1) " "$d/whole.log")
    cut=$(grep -nE "^(FLASER|ROBOTLASER1) " "$d/whole.log" | sed -n "$((n / 2))p" | cut -d: -f1)
    head -n "$cut" "$d/whole.log" > "$d/a.log"
    { grep -vE "$DATA" "$d/whole.log" || true; tail -n +"$((cut + 1))" "$d/whole.log" | grep -E "$DATA"; } > "$d/b.log"
    "$DYNAMAP" map --input "$d/a.log" --poses ground_truth --out "$d/a" > /dev/null 2>&1 || true
    alone=$(cpu "$DYNAMAP" map --input "$d/b.log" --poses ground_truth --out "$d/b-alone")
    prior=$(cpu "$DYNAMAP" map --input "$d/b.log" --poses ground_truth --prior "$d/a" --out "$d/b")
    c="$d/b/changes.csv"
    echo "| $log | $((n / 2)) / $((n - n / 2)) | $(kind object_moved "$c") | $(kind object_new "$c") | $(kind object_gone "$c") | $(kind structure_added "$c") | $(kind structure_removed "$c") | $alone / $prior |"
    rm -f "$d/whole.log"
  done
  echo
  echo "| log | seed | start found (x y phi) | its first corrected pose | error [m] / [deg] |"
  echo "|---|---|---|---|---|"
  for log in $LOGS; do
    d="$OUT/$log"
    [ -f "$d/b.log" ] || continue
    for seed in 1 2 3; do
      "$DYNAMAP" perturb --input "$d/b.log" --out "$d/drift-$seed" --seed "$seed" > /dev/null 2>&1
      said=$("$DYNAMAP" map --input "$d/drift-$seed/odometry.rawlog" --poses odometry --prior "$d/a" \
        --no-baseline --out "$d/start-$seed" 2>&1 | grep -E "starts at|fit" | head -1 || true)
      truth=$(firstPose "$d/drift-$seed/gt.txt")
      found=$(echo "$said" | sed -n 's/.*starts at \([-0-9.]* [-0-9.]* [-0-9.]*\) .*/\1/p')
      if [ -n "$found" ]; then
        err=$(echo "$found $truth" | awk '{ d = $3 - $6; while (d > 3.14159265) d -= 6.2831853;
          while (d < -3.14159265) d += 6.2831853;
          printf "%.3f / %.2f", sqrt(($1 - $4)^2 + ($2 - $5)^2), (d < 0 ? -d : d) * 57.2957795 }')
        echo "| $log | $seed | $found | $truth | $err |"
      else
        echo "| $log | $seed | refused: ${said#*: } | $truth | |"
      fi
      tied "$log" "$seed" "$([ -n "$found" ] || echo "$truth")" >> "$OUT/.tied"
    done
  done
  echo
  echo "| log | seed | B on slam tied to A: position RMSE / worst [m] | ties accepted / searches |"
  echo "|---|---|---|---|"
  cat "$OUT/.tied"
} | tee "$OUT/eval-sessions.md"
