#!/usr/bin/env bash
# The hostile-input corpus (tests/corpus/): every file is run through `validate`, `path`, `plan`
# and `run --no-video --no-plots` (G-code files: the first three; `run` reads scenarios), each
# in a fresh empty folder with its outputs pointed into it, and must
#   - exit 2 (bad input), within kSeconds;
#   - print the refusal its second line announces:
#       # expect: [FILE] LINE:COLUMN 'KEY' WORDS      (';' instead of '#' in G-code)
#     i.e. "FILE:LINE:COLUMN: 'KEY': " followed somewhere by WORDS (FILE defaults to the file
#     itself; KEY '' means a refusal before any key, which prints no key);
#   - write nothing (the folder stays empty).
# A third line "# commands: plan run" names the commands that must refuse when not all do (a
# plan too long to sample is refused by planning, not by loading or blending).
# Then inputs that cannot be committed are made here: a file over the size limit (sparse), a
# FIFO, /dev/zero, and a path spacing of 1e-300 mm.
#   tests/corpus.sh BLENDBENCH CORPUS_DIR WORK_DIR
set -uo pipefail
binary=$(realpath "$1")
corpus=$(realpath "$2")
work=$(realpath -m "$3")
kSeconds=5

rm -rf "$work"
mkdir -p "$work"
failures=0
checks=0

fail() {
  echo "FAIL: $*"
  failures=$((failures + 1))
}

# run_case NAME LOCATION WORDS COMMAND...: one command in a fresh folder; exit 2, the location
# and the words in its output, nothing written
run_case() {
  local name=$1 location=$2 words=$3
  shift 3
  local dir="$work/$name"
  mkdir -p "$dir"
  local start end output status
  start=$(date +%s.%N)
  output=$(cd "$dir" && timeout 30 "$@" 2>&1)
  status=$?
  end=$(date +%s.%N)
  checks=$((checks + 1))
  if [ "$status" -ne 2 ]; then
    fail "$name: exit $status, expected 2: $output"
  elif [[ "$output" != *"$location"* || "$output" != *"$words"* ]]; then
    fail "$name: expected '$location' and '$words' in: $output"
  fi
  if awk -v a="$start" -v b="$end" -v s="$kSeconds" 'BEGIN { exit !(b - a > s) }'; then
    fail "$name: took more than $kSeconds s"
  fi
  if [ -n "$(ls -A "$dir")" ]; then
    fail "$name: wrote $(cd "$dir" && find . -mindepth 1 | head -5 | tr '\n' ' ')"
  fi
  if [ -n "$(find "$corpus" -newer "$work" -mindepth 1 2>/dev/null | head -1)" ]; then
    fail "$name: wrote into the corpus folder"
  fi
}

for file in "$corpus"/*.yaml "$corpus"/*.ngc; do
  base=$(basename "$file")
  header=$(sed -n 2p "$file")
  # "# expect: [FILE] LINE:COLUMN 'KEY' WORDS"
  if [[ ! "$header" =~ ^[\#\;]\ expect:\ (([^ ]+)\ )?([0-9]+):([0-9]+)\ \'([^\']*)\'\ (.*)$ ]]; then
    fail "$base: no '# expect: LINE:COLUMN 'KEY' WORDS' header on line 2"
    continue
  fi
  where=${BASH_REMATCH[2]:-$base}
  [ "$where" = "$base" ] && where=$file || where="$corpus/$where"
  key=${BASH_REMATCH[5]}
  location="$where:${BASH_REMATCH[3]}:${BASH_REMATCH[4]}: "
  [ -n "$key" ] && location+="'$key': "
  words=${BASH_REMATCH[6]}
  commands="validate path plan run"
  [[ "$file" == *.ngc ]] && commands="validate path plan"
  third=$(sed -n 3p "$file")
  [[ "$third" =~ ^[\#\;]\ commands:\ (.*)$ ]] && commands=${BASH_REMATCH[1]}
  for command in $commands; do
    case "$command" in
      validate) run_case "$base.validate" "$location" "$words" "$binary" validate "$file" ;;
      path) run_case "$base.path" "$location" "$words" "$binary" path "$file" --csv out/path.csv --report out/report.json ;;
      plan) run_case "$base.plan" "$location" "$words" "$binary" plan "$file" --csv out/plan.csv --summary out/summary.json ;;
      run) run_case "$base.run" "$location" "$words" "$binary" run "$file" --out out/run --no-video --no-plots ;;
      *) fail "$base: unknown command '$command' on line 3" ;;
    esac
  done
done

# made here: a file over the size limit (sparse, so no disk is used), a FIFO, a device
truncate -s 65M "$work/oversize.yaml"
mkfifo "$work/fifo.yaml"
for input in "$work/oversize.yaml:the scenario file is 65 MiB; the limit is 64 MiB" \
             "$work/fifo.yaml:the scenario file is a FIFO (named pipe), not a regular file" \
             "/dev/zero:the scenario file is a character device, not a regular file"; do
  file=${input%%:*}
  words=${input#*:}
  name=$(basename "$file")
  run_case "$name.validate" "$file: " "$words" "$binary" validate "$file"
  run_case "$name.path" "$file: " "$words" "$binary" path "$file" --csv out/path.csv
  run_case "$name.plan" "$file: " "$words" "$binary" plan "$file" --csv out/plan.csv --summary out/summary.json
  run_case "$name.run" "$file: " "$words" "$binary" run "$file" --out out/run --no-video --no-plots
done
# a sample spacing that would overflow a row count
run_case "ds_tiny.path" "'--ds': " "sampling the 120 mm path every 1e-300 mm would write" \
  "$binary" path "$corpus/../data/tiny.yaml" --ds 1e-300 --csv out/path.csv

rm -f "$work/fifo.yaml" "$work/oversize.yaml"
echo "corpus: $checks commands checked, $failures failures"
[ "$failures" -eq 0 ]
