# Sanitizer and fuzzing builds (the second build of the test command, tools/bootstrap.sh test).
#
# BLENDBENCH_SANITIZE=ON: AddressSanitizer (with LeakSanitizer) and UndefinedBehaviorSanitizer on
# every target, -O1 -g with frame pointers so reports carry useful stacks; undefined behaviour
# aborts (-fno-sanitize-recover), so a finding fails the test that hit it. Use it with
# CMAKE_BUILD_TYPE=Debug so assertions stay on (no NDEBUG).
# BLENDBENCH_FUZZ=ON (clang only): tests/fuzz builds the libFuzzer harnesses, with the readers
# they exercise compiled once more with libFuzzer's coverage instrumentation; the rest of the
# build goes without it (it makes the sanitizer suite about 2.4x slower: ik_test 1.5 s -> 3.5 s).
# The sanitizers' run-time options and the suppressions of system libraries' own findings
# (tests/sanitizers/) are set on every test by tests/CMakeLists.txt.
option(BLENDBENCH_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(BLENDBENCH_FUZZ "Build the libFuzzer harnesses in tests/fuzz (clang; implies BLENDBENCH_SANITIZE)" OFF)

if(BLENDBENCH_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "BLENDBENCH_FUZZ needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++")
  endif()
  set(BLENDBENCH_SANITIZE ON CACHE BOOL "" FORCE)
endif()

set(BLENDBENCH_SANITIZER_LINK_FLAGS "")
if(BLENDBENCH_SANITIZE)
  set(BLENDBENCH_SANITIZER_LINK_FLAGS -fsanitize=address,undefined)
  add_compile_options(-O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined)
  # debug information and assertion messages name files relative to the source tree, so an
  # installed build carries no path of it (tests/install_consumer.sh checks)
  add_compile_options(-ffile-prefix-map=${PROJECT_SOURCE_DIR}/=)
  add_link_options(${BLENDBENCH_SANITIZER_LINK_FLAGS})
endif()
