#!/usr/bin/env bash
# Every `dynamap` command of the README's ```sh blocks runs as written on the bundled data and
# exits 0. The commands run in README order (an `eval` reads the `map` before it) in a temporary
# directory that links the repository's rawlogs/, config/ and fuzz/, so the outputs land there;
# `dynamap` is the program under test.
#
#   readme_commands_test.sh SOURCE_DIR DYNAMAP [README]
#
# A command whose input (--input, --scenario, --config, --truth, --trajectory, --result, or an
# import's positional log) the clone lacks is skipped and named; an input under rawlogs/,
# config/ or fuzz/ that does not exist is a failure (the README names a bundled file wrongly).
set -u
src=$(cd "$1" && pwd)
exe=$(cd "$(dirname "$2")" && pwd)/$(basename "$2")
readme=${3:-$src/README.md}
[ -x "$exe" ] || { echo "readme_commands: $exe is not an executable"; exit 1; }
[ -f "$readme" ] || { echo "readme_commands: no $readme"; exit 1; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for d in rawlogs config fuzz; do ln -s "$src/$d" "$tmp/$d"; done
cd "$tmp" || exit 1

# The lines of ```sh blocks that start with `dynamap `, comments cut off.
commands=$(awk '/^```sh[[:space:]]*$/ { inside = 1; next } /^```/ { inside = 0 }
                inside && /^dynamap / { sub(/[[:space:]]+#.*$/, ""); print }' "$readme")

# The inputs a command reads, one per line.
inputs() {
  local prev="" first_positional=1 a
  for a in "$@"; do
    case "$prev" in
      --input | -i | --scenario | --config | -c | --truth | --trajectory | --result | --people-bag) echo "$a" ;;
    esac
    if [ "$first_positional" = 1 ] && [ "$prev" != "" ] && [ "${a#-}" = "$a" ] &&
       [ "${prev#-}" = "$prev" ] && { [ "$prev" = import-bag ] || [ "$prev" = import-carmen ]; }; then
      echo "$a"; first_positional=0
    fi
    prev=$a
  done
}

passed=0 failed=0 skipped=0 n=0
while IFS= read -r line; do
  [ -n "$line" ] || continue
  n=$((n + 1))
  args=${line#dynamap }
  eval "set -- ${args%%[<>|]*}"  # the words, without a redirection
  missing=""
  while IFS= read -r f; do
    [ -n "$f" ] || continue
    # --truth takes a file prefix as well as a file or directory.
    if [ ! -e "$f" ] && ! compgen -G "$f.*" > /dev/null; then missing="$missing $f"; fi
  done < <(inputs "$@")
  if [ -n "$missing" ]; then
    case "$missing" in
      *" rawlogs/"* | *" config/"* | *" fuzz/"*)
        echo "FAIL: $line"; echo "      bundled input missing:$missing"
        failed=$((failed + 1)) ;;
      *) echo "skip: $line (input not in the clone:$missing)"; skipped=$((skipped + 1)) ;;
    esac
    continue
  fi
  # Redirections in the README (`> my.ini`) are kept: the command runs through the shell.
  if eval "\"\$exe\" ${line#dynamap }" > "cmd$n.log" 2>&1; then
    echo "ok:   $line"; passed=$((passed + 1))
  else
    rc=$?
    echo "FAIL: $line (exit $rc)"; sed 's/^/      /' "cmd$n.log" | tail -20
    failed=$((failed + 1))
  fi
done <<< "$commands"

if [ "$n" = 0 ]; then echo "readme_commands: no dynamap command in $readme"; exit 1; fi
echo "$passed passed, $failed failed, $skipped skipped"
[ "$failed" = 0 ]
