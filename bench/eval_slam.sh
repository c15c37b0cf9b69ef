#!/bin/bash
# eval_slam.sh: --poses slam on real logs made to drift, one table of every log x seed.
#
# usage: [EVAL_SLAM_LOGS="intel orebro"] [EVAL_SLAM_CONFIG=my.ini] \
#          bench/eval_slam.sh DYNAMAP DATASETS OUT [SEEDS] [MAP_ARGS]
#
# For each corrected CARMEN log of DATASETS/carmen/ and each seed of SEEDS ("0 1 2 3 4 5 6"):
#   dynamap perturb (the default noise: 3 %/m translation, 3 %/rad + 0.005 rad/m heading,
#   0.002 rad/m heading bias) writes the drifting odometry and the known poses once (kept in OUT
#   between runs: the same log and seed give the same bytes);
#   dynamap map --poses slam MAP_ARGS maps it, timed (CPU of both passes, user + system);
#   dynamap eval --trajectory scores the raw odometry and slam's poses against the known poses
#   (position RMSE after the best rigid alignment, mean relative error over 1 m of path), and
#   dynamap eval --input their global consistency beside the known poses' own (the known poses
#   are themselves a SLAM result: a lower figure than theirs lays the scans more consistently).
# Seed 0 is no noise at all: the corrected poses given as odometry, and slam not allowed to keep
# them ([slam] keep_better_odometry = false). Its ATE is how far slam's own matches and loop
# closures pull the trajectory from the reference when odometry is perfect: the part of every
# other seed's error that no odometry model can remove.
# Each log is also mapped once on its corrected poses (--poses odometry reads them from the laser
# lines), for the object count a drifting run is compared with.
# The table goes to stdout and OUT/eval-slam.md; the loop closures of every run (proposed,
# accepted, dropped as ambiguous, rejected by the optimiser's gate) are in the table too.
set -euo pipefail

DYNAMAP=$1
DATASETS=$2
OUT=$3
SEEDS=${4:-0 1 2 3 4 5 6}
MAP_ARGS=${5:-}
# The environment may narrow the logs or change the configuration (experiments).
LOGS=${EVAL_SLAM_LOGS:-freiburg-079 intel freiburg-campus orebro}
CONFIG=${EVAL_SLAM_CONFIG:-config/default.ini}

mkdir -p "$OUT"
# Seed 0's configuration: the one given, slam never keeping the odometry.
NO_KEEP="$OUT/no-keep.ini"
sed 's/^keep_better_odometry *=.*/keep_better_odometry = false/' "$CONFIG" > "$NO_KEEP"
grep -q '^keep_better_odometry = false' "$NO_KEEP" || printf '[slam]\nkeep_better_odometry = false\n' >> "$NO_KEEP"

# The number after `key` in a one-line summary of dynamap eval.
field() { sed -n "s/.*$1 \([0-9.]*\) .*/\1/p" | head -1; }
# A count from summary.json: the first `"key": n` line.
count() { sed -n "s/.*\"$1\": \([0-9]*\).*/\1/p" "$2" | head -1; }
# Global consistency (mm) of the log's scans at a trajectory.
global_mm() { "$DYNAMAP" eval --input "$1" --trajectory "$2" | sed -n 's/.*global \([0-9.]*\) mm.*/\1/p' | head -1; }
# The objects of a result (objects.csv less its header).
objects() { [ -f "$1/objects.csv" ] && echo $(($(wc -l < "$1/objects.csv") - 1)) || echo "n/a"; }

table="$OUT/eval-slam.md"
{
  echo "| log | seed | scans | odometry aligned ATE [m] | slam aligned ATE [m] | slam RE 1 m [m] | slam RE 1 m [deg] | consistency slam / known poses [mm] | closures proposed / accepted / ambiguous / gate-rejected | objects slam / known poses | CPU [s] |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|"
} > "$table"
cat "$table"

for log in $LOGS; do
  input="$DATASETS/carmen/$log-corrected.log.gz"
  if [ ! -f "$input" ]; then
    echo "eval_slam: $input not found, skipped" >&2
    continue
  fi
  ref="$OUT/$log-known"
  if [ ! -f "$ref/objects.csv" ]; then
    "$DYNAMAP" map --config config/default.ini --poses odometry --input "$input" --out "$ref" \
      > "$OUT/$log-known.log" 2>&1
  fi
  for seed in $SEEDS; do
    run="$OUT/$log-s$seed"
    drift="$run/perturbed"
    noise=() cfg="$CONFIG"
    if [ "$seed" = 0 ]; then
      noise=(--trans-noise 0 --rot-noise 0 --rot-per-m 0 --heading-bias 0) cfg="$NO_KEEP"
    fi
    if [ ! -f "$drift/odometry.txt" ]; then
      "$DYNAMAP" perturb --input "$input" --out "$drift" --seed "$seed" "${noise[@]}" > /dev/null
    fi
    [ -f "$drift/known_global_mm" ] || global_mm "$input" "$drift/gt.txt" > "$drift/known_global_mm"
    # bash's own timer: the CPU time of the child, user + system.
    TIMEFORMAT="%U %S"
    { time "$DYNAMAP" map --config "$cfg" --poses slam $MAP_ARGS \
        --input "$drift/odometry.rawlog" --out "$run/slam" > "$run/map.log" 2>&1; } 2> "$run/time"
    cpu=$(awk '{ printf "%.1f", $1 + $2 }' "$run/time")
    odo=$("$DYNAMAP" eval --truth "$drift/gt.txt" --trajectory "$drift/odometry.txt" |
      field "position RMSE")
    ev=$("$DYNAMAP" eval --truth "$drift/gt.txt" --trajectory "$run/slam/poses.txt")
    ate=$(echo "$ev" | field "position RMSE")
    re=$(echo "$ev" | field "over 1 m of path")
    re_deg=$(echo "$ev" | sed -n 's/.*over 1 m of path [0-9.]* m, \([0-9.]*\) deg.*/\1/p')
    cons="$(global_mm "$drift/odometry.rawlog" "$run/slam/poses.txt") / $(cat "$drift/known_global_mm")"
    js="$run/slam/summary.json"
    loops="$(count proposed "$js") / $(count accepted "$js") / $(count rejected_ambiguous "$js")"
    loops="$loops / $(($(count rejected "$js") - $(count rejected_ambiguous "$js")))"
    scans=$(wc -l < "$drift/gt.txt")
    echo "| $log | $seed | $scans | $odo | $ate | $re | $re_deg | $cons | $loops | $(objects "$run/slam") / $(objects "$ref") | $cpu |" |
      tee -a "$table"
  done
done
