#!/bin/sh
# Builds one libFuzzer target of hardware/ with clang (-fsanitize=fuzzer,address,undefined) and
# runs it for a few seconds. Usage: run_fuzzers.sh SOURCE_DIR WORK_DIR NAME SECONDS
# Exit 77 (CTest skip) when clang or its fuzzer runtime is missing.
set -eu
src=$1; work=$2; name=$3; seconds=$4
CXX=${PWSIM_FUZZ_CXX:-clang++}
if ! command -v "$CXX" >/dev/null 2>&1; then
  echo "SKIP: $CXX not found (libFuzzer targets need clang)"; exit 77
fi
mkdir -p "$work/obj" "$work/corpus/$name"
flags="-std=c++20 -O1 -g -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -I$src $(pkg-config --cflags eigen3 2>/dev/null)"
# Shared library code, compiled once (guarded against parallel ctest runs).
(
  flock 9
  rm -f "$work/obj/session.o"  # hardware/session.cc was split into session_*.cc
  for unit in can_frame candump_log canopen cia402_master safety_supervisor hmd_protocol \
      session_config session_core session_replay session_report session_text link_auth; do
    o="$work/obj/$unit.o"
    # Any newer header recompiles (a unit includes more than its own header).
    if [ ! -f "$o" ] || [ "$src/hardware/$unit.cc" -nt "$o" ] ||
       [ -n "$(find "$src/hardware" "$src/engine" -name '*.h' -newer "$o" | head -1)" ]; then
      $CXX $flags -c "$src/hardware/$unit.cc" -o "$o"
    fi
  done
  # The platform's mechanism (the session's kinematics and its default car platform).
  for unit in mechanism platform; do
    o="$work/obj/mca_$unit.o"
    if [ ! -f "$o" ] || [ "$src/mca/$unit.cc" -nt "$o" ] ||
       [ -n "$(find "$src/mca" "$src/engine" -name '*.h' -newer "$o" | head -1)" ]; then
      $CXX $flags -c "$src/mca/$unit.cc" -o "$o"
    fi
  done
  # The engine units the parsers use (linear interpolation; the key file's InputError; the
  # platform files' YAML reader).
  for unit in interpolate input_error yaml_reader; do
    o="$work/obj/engine_$unit.o"
    if [ ! -f "$o" ] || [ "$src/engine/$unit.cc" -nt "$o" ] || [ "$src/engine/$unit.h" -nt "$o" ]; then
      $CXX $flags -c "$src/engine/$unit.cc" -o "$o"
    fi
  done
  exe="$work/$name"
  if [ ! -x "$exe" ] || [ "$src/hardware/fuzz/$name.cc" -nt "$exe" ] || [ -n "$(find "$work/obj" -newer "$exe" -name '*.o')" ]; then
    if ! echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long){return 0;}' |
         $CXX -fsanitize=fuzzer -x c++ - -o "$work/.probe" 2>/dev/null; then
      echo "SKIP: $CXX cannot link -fsanitize=fuzzer (install libclang-rt-14-dev)"; exit 77
    fi
    $CXX $flags -fsanitize=fuzzer "$src/hardware/fuzz/$name.cc" "$work"/obj/*.o -lsodium -lyaml-cpp -o "$exe"
  fi
) 9>"$work/.lock"
# Seeds from the checked-in corpus, findings written under WORK_DIR.
seeds="$src/hardware/fuzz/corpus/$name"
[ -d "$seeds" ] || seeds=""
exec "$work/$name" -max_total_time="$seconds" -timeout=5 -rss_limit_mb=1024 \
  -artifact_prefix="$work/crash-$name-" "$work/corpus/$name" $seeds
