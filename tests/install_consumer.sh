#!/usr/bin/env bash
# install_consumer.sh CMAKE BUILD_DIR SOURCE_DIR WITH_CLI [SANITIZED]
#
# Installs BUILD_DIR into a fresh prefix and uses it the way another project would:
#   1. examples/consumer, copied out of the source tree, is configured with only
#      CMAKE_PREFIX_PATH=<prefix> and with MuJoCo, yaml-cpp, urdfdom, nlohmann-json and CLI11
#      unfindable, built (no include path of the source tree on its compile lines)
#      and run: the blended, timed two-line program must report a positive cycle time, a
#      path shorter than the 200 mm programmed, and a corner deviation within its tolerance;
#   2. WITH_CLI=1 (built with BLENDBENCH_SIM=ON): a project finding every component
#      configures; no installed file names the source tree; the installed program, started
#      from a folder outside the source tree with BLENDBENCH_DATA_DIR unset, reads its data from
#      <prefix>/share/blendbench (path, run with and without a scenario, check against the
#      installed baseline, reproduce), and a copy of it with no data beside it fails naming
#      the places it tried.
# The consumer is configured with the generator and compiler in CMAKE_GENERATOR and CXX (ctest
# sets them to the build's). SANITIZED=1 (an ASan/UBSan build): the compiled files are left out
# of the source-tree check, as the sanitizers record each object's source file as it was given
# to the compiler (absolute, from CMake) for their reports, which -ffile-prefix-map does not
# reach in clang 14; everything else is checked, and the Release build checks them all.
set -euo pipefail

cmake_command=$1
build=$2
source=$(cd "$3" && pwd)
with_cli=$4
sanitized=${5:-0}

work=$(mktemp -d "${TMPDIR:-/tmp}/blendbench-install-XXXXXX")
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
fail() { echo "install_consumer: FAILED: $*" >&2; exit 1; }

echo "== install into $prefix"
"$cmake_command" --install "$build" --prefix "$prefix" > "$work/install.log"
test -f "$prefix/lib/cmake/blendbench/blendbenchConfig.cmake" || fail "no package config installed"
test -f "$prefix/lib/cmake/blendbench/blendbenchConfigVersion.cmake" || fail "no package version file installed"
test -f "$prefix/include/blendbench/timing/timing.hpp" || fail "planner headers not installed"

echo "== examples/consumer against the prefix"
cp -r "$source/examples/consumer" "$work/consumer-src"
# the planner component needs Eigen alone: the edges' dependencies are made unfindable
no_edges=()
for package in mujoco yaml-cpp urdfdom nlohmann_json CLI11; do no_edges+=("-DCMAKE_DISABLE_FIND_PACKAGE_$package=ON"); done
"$cmake_command" -S "$work/consumer-src" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$prefix" "${no_edges[@]}" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_EXPORT_COMPILE_COMMANDS=ON > "$work/consumer-configure.log" \
  || { cat "$work/consumer-configure.log"; fail "the consumer does not configure"; }
"$cmake_command" --build "$work/consumer" > "$work/consumer-build.log" \
  || { cat "$work/consumer-build.log"; fail "the consumer does not build"; }
if grep -qF "$source" "$work/consumer/compile_commands.json"; then
  fail "the consumer's compile lines name the source tree $source"
fi
(cd "$work" && "$work/consumer/consumer") > "$work/consumer.out"
cat "$work/consumer.out"
awk '
  { value[$1] = $2 }
  END {
    ok = value["cycle_time_s"] > 0 && value["path_length_mm"] > 190 && value["path_length_mm"] < 200 &&
         value["corner_deviation_mm"] > 0 && value["corner_deviation_mm"] <= value["tolerance_mm"] * (1 + 1e-6)
    exit ok ? 0 : 1
  }' "$work/consumer.out" || fail "the consumer's figures are not sane"

if [ "$with_cli" != 1 ]; then
  echo "install_consumer: passed (planner only: built with BLENDBENCH_SIM=OFF)"
  exit 0
fi

echo "== a project finding every component"
mkdir -p "$work/all-src"
cat > "$work/all-src/CMakeLists.txt" <<'EOF'
cmake_minimum_required(VERSION 3.25)
project(blendbench_all LANGUAGES CXX)
find_package(blendbench CONFIG REQUIRED)
foreach(t planner core geometry program corner timing robot io sim report papers app)
  if(NOT TARGET blendbench::${t})
    message(FATAL_ERROR "blendbench::${t} is not imported")
  endif()
endforeach()
EOF
"$cmake_command" -S "$work/all-src" -B "$work/all" -DCMAKE_PREFIX_PATH="$prefix" > "$work/all.log" \
  || { cat "$work/all.log"; fail "find_package(blendbench) with every component fails"; }

echo "== no installed file names the source tree"
named=()
while IFS= read -r -d '' f; do
  if [ "$sanitized" = 1 ] && { [ "$(head -c 4 "$f" | od -An -c | tr -d ' ')" = '177ELF' ] || [ "$(head -c 7 "$f")" = '!<arch>' ]; }; then
    continue
  fi
  if grep -qF "$source" "$f"; then named+=("$f"); fi
done < <(find "$prefix" -type f -print0)
if [ ${#named[@]} -gt 0 ]; then printf '%s\n' "${named[@]}"; fail "the files above name the source tree $source"; fi

echo "== the installed program on its installed data"
bin="$prefix/bin/blendbench"
data="$prefix/share/blendbench"
mkdir -p "$work/cwd"
cd "$work/cwd"
unset BLENDBENCH_DATA_DIR
"$bin" path "$data/scenarios/default.yaml" --csv x.csv > path.log || { cat path.log; fail "path on an installed scenario"; }
head -1 x.csv | grep -qx 's,x,y,z,tx,ty,tz,kappa' || fail "path wrote no path CSV"
"$bin" run "$data/scenarios/cases/biclothoid_line_line.yaml" --no-video --no-plots --out small > small.log \
  || { cat small.log; fail "run of an installed scenario"; }
test -f small/summary.json || fail "run of a small scenario wrote no summary"
"$bin" run --no-video --no-plots > default.log || { cat default.log; fail "run without a scenario"; }
grep -qF "($data/scenarios/default.yaml)" default.log || fail "run without a scenario did not read $data/scenarios/default.yaml"
"$bin" check results/runs/default > check.log || { cat check.log; fail "check of the default run"; }
grep -qF "check passed against $data/results/baselines/default.json" check.log || fail "check did not use the installed baseline"
"$bin" reproduce all --no-plots --out papers > reproduce.log || { cat reproduce.log; fail "reproduce on the installed data"; }
test -f papers/004/results.json && test -f papers/000/results.json || fail "reproduce wrote no results"

echo "== a program with no data beside it names what it tried"
mkdir -p "$work/lone/bin"
cp "$bin" "$work/lone/bin/"
if "$work/lone/bin/blendbench" run --no-video --no-plots > lone.log 2>&1; then fail "a program without data ran"; fi
cat lone.log
grep -qF "$work/lone/share/blendbench (no such folder)" lone.log || fail "the error does not name the install layout tried"
grep -qF "BLENDBENCH_DATA_DIR" lone.log || fail "the error does not name BLENDBENCH_DATA_DIR"
BLENDBENCH_DATA_DIR="$data" "$work/lone/bin/blendbench" path "$data/scenarios/default.yaml" --csv y.csv > /dev/null \
  || fail "BLENDBENCH_DATA_DIR does not point the program at its data"

echo "install_consumer: passed"
