#!/usr/bin/env bash
# Fuzzes WireFur's input readers for a bounded time (the ctest tests cad_fuzz, scene_fuzz and
# mesh_fuzz, LABELS fuzz; each runs this script on its own targets).
#
#   run_fuzz.sh BUILD_DIR [CLANGXX] [CMAKE]
#
# Targets (WF_FUZZ_TARGETS):
#   step iges brep fcstd   the CAD reader (vtk_filters/cad), one per format: fuzz_cad_<format>;
#                          only where OpenCASCADE, libzip and pugixml are found
#   scene                  the scene loader (apps/scene_*.cpp), then a small render: fuzz_scene
#   mesh                   the mesh / polyline readers (apps/mesh_io.cpp): fuzz_mesh
#
# 1. Configures tests/fuzz/standalone with clang (libFuzzer, AddressSanitizer,
#    UndefinedBehaviorSanitizer) into BUILD_DIR and builds the targets asked for (incremental on
#    a re-run; the CAD and the apps targets share the build folder).
# 2. Writes the seed corpus at run time: make_cad_seeds (OpenCASCADE + libzip) for the CAD
#    formats; make_app_seeds (VTK's writers) for mesh, and for scene the committed scenes of
#    data/scenes plus a few that name mesh files and images. Lists what each target makes of
#    each seed (one that does not read is noted, not failed).
# 3. Runs each target for WF_FUZZ_SECONDS on a fresh copy of the seeds, with
#    -rss_limit_mb=2048 -timeout=10. libFuzzer stops at a crash; it is started again on the
#    grown corpus with the time left, so every target gets its full time and every crash,
#    timeout and OOM is kept with its own report (BUILD_DIR/artifacts/<target>/, .log beside).
# 4. Groups the failing inputs by where they fail and writes BUILD_DIR/findings-<name>.txt: per
#    group a reproducer, the stack, and whether the faulting frame is in WireFur's code (src/,
#    apps/, vtk_filters/, the harnesses' contract checks: [ours]) or in a library (OpenCASCADE,
#    libzip, pugixml, VTK, libpng: [library]).
#
# Exit status: 0 nothing found; 1 findings (see the findings file); 2 the build failed; 77
# skipped (no clang++, no libFuzzer, or none of the targets asked for can be built here: ctest
# reports the test as skipped).
#
# Environment:
#   WF_FUZZ_NAME=fuzz           the name in messages and of the findings file (the ctest test's)
#   WF_FUZZ_SECONDS=20          fuzzing time per target
#   WF_FUZZ_TARGETS="step iges brep fcstd scene mesh"
#                               targets that cannot be built here (no OpenCASCADE) are skipped
#   WF_FUZZ_JOBS=2              build parallelism
#   WF_FUZZ_TIMEOUT=10          libFuzzer's -timeout (seconds per input)
#   WF_FUZZ_STOP_AT_FIRST=0     1: stop each target at its first failing input
#   WF_FUZZ_KEEP_CORPUS=0       1: keep the working corpus between runs (grows coverage; the
#                               initial pass over a large corpus is not bounded by the time)
#   WF_FUZZ_CORPUS_DIR=BUILD_DIR/corpus
#                               where the working corpus lives (<dir>/<target>); scripts/fuzz.sh
#                               keeps its own, apart from the ctest runs'. The committed corpus,
#                               tests/fuzz/corpus/<target> (small inputs that reached something
#                               new: hand-written legacy .vtk variants, kept finds), joins the
#                               seeds of every run
#   WF_FUZZ_RSS_MB=2048         libFuzzer's -rss_limit_mb (and, in fork mode, -malloc_limit_mb is
#                               a quarter of it: a reader asked for gigabytes fails at the ask)
#   WF_FUZZ_FORK=0              N >= 1: libFuzzer's fork mode, N jobs at a time (cores), with
#                               -ignore_crashes / _timeouts / _ooms:
#                               one run for the whole time that keeps going past failing inputs
#                               (for long runs: the failures of VTK's legacy reader come every few
#                               seconds); each failing input is run again afterwards for its report
#   WF_FUZZ_FAIL_ON=all         ours: findings whose faulting frame is inside a library are
#                               listed but do not fail the run
#
# Reproduce one input: BUILD_DIR/fuzz_cad_step BUILD_DIR/artifacts/step/crash-...,
# BUILD_DIR/fuzz_scene BUILD_DIR/artifacts/scene/crash-... (WF_FUZZ_VERBOSE=1: what the code
# under test made of it). A scene input is a scene file (save it as x.json in a folder holding
# BUILD_DIR/seeds/assets/* and run the g++ build's `wirefur render x.json`); a mesh input is one
# format byte (0 vtp, 1 vtk, 2 stl, 3 obj, 4 ply) and then the file (tail -c +2 INPUT > x.vtp).
#
# Leak checking is off (-detect_leaks=0): OpenCASCADE's data exchange initialises global
# registries lazily (Interface_Static, IFSelect_Editor, TPrsStd_DriverTable), which
# LeakSanitizer reports as direct leaks, and with OpenCASCADE uninstrumented (no frame
# pointers) the stacks stop inside Standard_MMgrRaw::Allocate, so they cannot be told apart
# from a leak per input. A leak per input shows as growing memory instead: run a kept input
# with -runs=1000 and watch rss in libFuzzer's output.
set -u

if [[ $# -lt 1 ]]; then
  echo "usage: $0 BUILD_DIR [CLANGXX] [CMAKE]" >&2
  exit 2
fi
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
BUILD=$1
CXX_IN=${2:-}
CMAKE=${3:-cmake}
SECONDS_PER_TARGET=${WF_FUZZ_SECONDS:-20}
TARGETS=${WF_FUZZ_TARGETS:-step iges brep fcstd scene mesh}
NAME=${WF_FUZZ_NAME:-fuzz}
JOBS=${WF_FUZZ_JOBS:-2}
TIMEOUT=${WF_FUZZ_TIMEOUT:-10}
STOP_AT_FIRST=${WF_FUZZ_STOP_AT_FIRST:-0}
FUZZER_FAILED=0
KEEP_CORPUS=${WF_FUZZ_KEEP_CORPUS:-0}
FAIL_ON=${WF_FUZZ_FAIL_ON:-all}
CORPUS_DIR=${WF_FUZZ_CORPUS_DIR:-$BUILD/corpus}
FORK=${WF_FUZZ_FORK:-0}
if ! [[ "$FORK" =~ ^[0-9]+$ ]]; then
  echo "run_fuzz.sh: WF_FUZZ_FORK must be a whole number (got '$FORK')" >&2
  exit 2
fi
NOT_REPRODUCED=0
RSS_MB=${WF_FUZZ_RSS_MB:-2048}

skip() {
  echo "$NAME: SKIPPED: $*"
  exit 77
}

# --- clang and libFuzzer ---------------------------------------------------------------------
CLANGXX=""
for c in "$CXX_IN" clang++ clang++-16 clang++-15 clang++-14; do
  [[ -n "$c" && "$c" != *NOTFOUND* ]] || continue
  if command -v "$c" > /dev/null 2>&1; then
    CLANGXX=$(command -v "$c")
    break
  fi
done
[[ -n "$CLANGXX" ]] || skip "no clang++ (Debian: apt install clang libclang-rt-dev)"
mkdir -p "$BUILD" || exit 2
BUILD=$(cd "$BUILD" && pwd)
probe="$BUILD/probe"
mkdir -p "$probe"
printf '#include <cstddef>\n#include <cstdint>\nextern "C" int LLVMFuzzerTestOneInput(const uint8_t*, size_t) { return 0; }\n' > "$probe/probe.cpp"
if ! "$CLANGXX" -fsanitize=fuzzer,address,undefined "$probe/probe.cpp" -o "$probe/probe" > "$probe/probe.log" 2>&1; then
  cat "$probe/probe.log"
  skip "$CLANGXX cannot link -fsanitize=fuzzer,address,undefined (Debian: apt install libclang-rt-14-dev)"
fi
echo "$NAME: clang: $CLANGXX ($("$CLANGXX" --version | head -n 1))"

# --- build -----------------------------------------------------------------------------------
t0=$(date +%s)
gen=()
if [[ ! -f "$BUILD/CMakeCache.txt" ]] && command -v ninja > /dev/null 2>&1; then gen=(-G Ninja); fi
if ! "$CMAKE" -S "$HERE/standalone" -B "$BUILD" "${gen[@]}" -DCMAKE_CXX_COMPILER="$CLANGXX" > "$BUILD/configure.log" 2>&1; then
  cat "$BUILD/configure.log"
  echo "$NAME: FAILED: configuring $HERE/standalone"
  exit 2
fi
# What this configuration can build (standalone/CMakeLists.txt writes it: the CAD targets only
# with OpenCASCADE); targets asked for that it cannot are left out with a note.
available=" $(cat "$BUILD/available_targets.txt" 2> /dev/null) "
exe_of() { case "$1" in step | iges | brep | fcstd) echo "fuzz_cad_$1" ;; *) echo "fuzz_$1" ;; esac; }
wanted=""
build_targets=()
need_cad_seeds=0
need_app_seeds=0
for t in $TARGETS; do
  if [[ "$available" != *" $t "* ]]; then
    echo "$NAME: note: target $t cannot be built here (see $BUILD/configure.log), left out"
    continue
  fi
  wanted="$wanted $t"
  build_targets+=(--target "$(exe_of "$t")")
  case "$t" in
    step | iges | brep | fcstd) need_cad_seeds=1 ;;
    *) need_app_seeds=1 ;;
  esac
done
TARGETS=${wanted# }
[[ -n "$TARGETS" ]] || skip "none of the targets asked for (${WF_FUZZ_TARGETS:-default}) can be built here"
[[ $need_cad_seeds == 1 ]] && build_targets+=(--target make_cad_seeds)
[[ $need_app_seeds == 1 ]] && build_targets+=(--target make_app_seeds)
if ! "$CMAKE" --build "$BUILD" -j "$JOBS" "${build_targets[@]}" > "$BUILD/build.log" 2>&1; then
  tail -n 60 "$BUILD/build.log"
  echo "$NAME: FAILED: building the fuzz targets"
  exit 2
fi
echo "$NAME: built $TARGETS in $(($(date +%s) - t0)) s (log: $BUILD/build.log)"

# --- seeds -----------------------------------------------------------------------------------
ROOT=$(cd "$HERE/../.." && pwd)
for t in $TARGETS; do rm -rf "$BUILD/seeds/$t"; done
if [[ $need_cad_seeds == 1 ]] && ! "$BUILD/make_cad_seeds" "$BUILD/seeds"; then
  echo "$NAME: FAILED: make_cad_seeds"
  exit 2
fi
if [[ $need_app_seeds == 1 ]]; then
  rm -rf "$BUILD/seeds/assets"
  if ! "$BUILD/make_app_seeds" "$BUILD/seeds"; then
    echo "$NAME: FAILED: make_app_seeds"
    exit 2
  fi
  cp "$ROOT"/data/scenes/*.json "$BUILD/seeds/scene/"
fi
for t in $TARGETS; do
  if [[ -d "$HERE/corpus/$t" ]]; then
    mkdir -p "$BUILD/seeds/$t"
    cp "$HERE/corpus/$t"/* "$BUILD/seeds/$t"/ 2> /dev/null
  fi
done

export ASAN_OPTIONS="detect_leaks=0:handle_abort=1:symbolize=1:${WF_FUZZ_ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${WF_FUZZ_UBSAN_OPTIONS:-}"

# Every seed should read: one that does not is listed (a note, not a failure: the seeds are made
# by this OpenCASCADE or VTK, or are the committed scenes, so a seed that fails is a bug of its
# own, as the binary BREP was).
seed_problems=0
for t in $TARGETS; do
  # (Its own artifact folder: libFuzzer writes a seed slower than 10 s as slow-unit-* there, by
  # default into the folder the script was started from.)
  mkdir -p "$BUILD/seed-check/$t"
  while IFS= read -r line; do
    echo "$NAME: seed $t: $line"
    case "$line" in
      *error:*) seed_problems=$((seed_problems + 1)) ;;
    esac
  done < <(WF_FUZZ_VERBOSE=1 "$BUILD/$(exe_of "$t")" -runs=0 -artifact_prefix="$BUILD/seed-check/$t/" "$BUILD/seeds/$t" 2>&1 | grep '^WF_FUZZ: [1-9]' | sort -u | sed 's/^WF_FUZZ: //')
done

# --- findings --------------------------------------------------------------------------------
# A finding's signature: the harness's FINDING line; or the sanitizer's kind and faulting
# function; or, for a timeout / OOM, the library call WireFur made that never came back. Ours
# when the faulting frame (the innermost outside libFuzzer, the sanitizers and the C/C++
# runtimes) is in WireFur's sources, or the harness found a broken contract.
fname() { sed -E 's/^ +#[0-9]+ 0x[0-9a-f]+ in //; s/\(.*//; s/ .*//' | cut -c1-120; }
signature_of() {  # log -> "owner|signature"
  local log=$1 sig stack frames owner="library" entry callee kind
  stack=$(awk '/^ +#[0-9]+ 0x/ { s = 1; print; next } s { exit }' "$log")
  frames=$(echo "$stack" | grep -vE ' in (fuzzer::|__sanitizer|__asan|__ubsan|__interceptor|__libc|_start|main |__GI_|abort|raise|std::terminate|__cxxabiv1|__cxa_|__dynamic_cast|__gnu_cxx::__verbose)|libc\.so|libstdc\+\+|compiler-rt| \(<unknown module>\)|^ +#[0-9]+ 0x[0-9a-f]+ +\(' |
           grep -vE '/fuzz_[a-z_]+\+0x' || true)
  if grep -qE 'WIREFUR-(CAD-)?FUZZ== FINDING' "$log"; then
    sig=$(grep -m1 'FINDING:' "$log" | sed -E 's/.*FINDING: //; s/[0-9]+(\.[0-9]+)?/N/g' | cut -c1-160)
    owner="ours"
  elif grep -q 'ERROR: libFuzzer: ' "$log"; then
    kind=$(grep -m1 'ERROR: libFuzzer: ' "$log" | sed -E 's/.*ERROR: libFuzzer: //; s/ (after|\().*//')
    entry=$(echo "$frames" | grep -n -m1 -F "$ROOT/" | cut -d: -f1)
    if [[ -n "$entry" && "$entry" -gt 1 ]]; then
      callee=$(echo "$frames" | sed -n "$((entry - 1))p" | fname)
      sig="$kind in $callee (called from $(echo "$frames" | sed -n "${entry}p" | fname))"
    else
      sig="$kind in $(echo "$frames" | head -n 1 | fname)"
    fi
  elif grep -q '^SUMMARY: ' "$log"; then
    sig=$(grep -m1 '^SUMMARY: ' "$log" | sed -E 's/^SUMMARY: [A-Za-z]+Sanitizer: //; s/ \(BuildId: [0-9a-f]+\)//; s/\(\/[^)]*\+0x[0-9a-f]+\)//; s/ +/ /g' | cut -c1-200)
  else
    sig="$(grep -m1 -E 'ERROR|deadly signal' "$log" | cut -c1-120) (no report)"
  fi
  if echo "$frames" | head -n 1 | grep -qF "$ROOT/"; then owner="ours"; fi
  echo "$owner|$sig"
}

# --- fuzz ------------------------------------------------------------------------------------
# libFuzzer stops at the first crash; it is started again on the grown corpus with the time
# left, so that every target gets its full time and every crash is kept with its own report.
declare -A EXECS RATE KEPT RUNS COVERAGE GROUP_COUNT GROUP_EXAMPLE GROUP_OWNER GROUP_TARGET GROUP_LOG
# One failing input of target $1 ($2, its report $3) into the group of its signature.
add_finding() {
  local r owner sig
  r=$(signature_of "$3")
  owner=${r%%|*}
  sig="$1: ${r#*|}"
  if [[ -z "${GROUP_COUNT[$sig]:-}" ]]; then
    GROUP_COUNT[$sig]=0
    GROUP_EXAMPLE[$sig]=$2
    GROUP_OWNER[$sig]=$owner
    GROUP_TARGET[$sig]=$1
  fi
  GROUP_COUNT[$sig]=$((GROUP_COUNT[$sig] + 1))
}
for t in $TARGETS; do
  corpus="$CORPUS_DIR/$t"
  art="$BUILD/artifacts/$t"
  logs="$BUILD/logs/$t"
  [[ "$KEEP_CORPUS" == 1 ]] || rm -rf "$corpus"
  rm -rf "$art" "$logs"
  mkdir -p "$corpus" "$art" "$logs"
  cp -n "$BUILD/seeds/$t"/* "$corpus"/ 2> /dev/null
  dict=()
  [[ -f "$HERE/$t.dict" ]] && dict=(-dict="$HERE/$t.dict")
  echo "$NAME: fuzzing $t for ${SECONDS_PER_TARGET} s ..."
  start=$(date +%s.%N)
  deadline=$(($(date +%s) + SECONDS_PER_TARGET))
  n=0
  k=0
  if ((FORK >= 1)); then
    k=1
    log="$logs/run-1.log"
    timeout --signal=KILL $((SECONDS_PER_TARGET * 2 + 120)) "$BUILD/$(exe_of "$t")" -fork="$FORK" -ignore_crashes=1 -ignore_timeouts=1 \
      -ignore_ooms=1 -max_total_time="$SECONDS_PER_TARGET" -rss_limit_mb="$RSS_MB" -malloc_limit_mb=$((RSS_MB / 4)) \
      -timeout="$TIMEOUT" -close_fd_mask=1 \
      -detect_leaks=0 "${dict[@]}" -artifact_prefix="$art/" "$corpus" > "$log" 2>&1
    # Fork mode's progress lines: "#N: cov: C ft: F corp: K exec/s R oom/timeout/crash: ..."
    rc=$?
    n=$(grep -E '^#[0-9]+: cov:' "$log" | tail -n 1 | sed -E 's/^#([0-9]+):.*/\1/')
    if [[ -z "$n" || $rc -eq 124 || $rc -eq 137 ]]; then
      echo "$NAME: $t: libFuzzer's fork mode exited with $rc without finishing (log $log):"
      tail -n 20 "$log"
      FUZZER_FAILED=1
    fi
    n=${n:-0}
    sed -nE 's/^#[0-9]+: cov: ([0-9]+) ft: ([0-9]+) .*/#0 DONE cov: \1 ft: \2 corp: 0/p' "$log" > "$logs/run-1-coverage.log"
    # Each failing input run once more for its report (bounded: at most WF_FUZZ_RERUNS=200 of
    # them, each within the per-input limit; the rest are kept, counted, not grouped).
    reruns=0
    for unit in $(find "$art" -maxdepth 1 -type f ! -name '*.log' ! -name 'slow-unit-*' ! -name 'unreproduced-*' | sort); do
      reruns=$((reruns + 1))
      if [[ $reruns -gt ${WF_FUZZ_RERUNS:-200} ]]; then
        echo "$NAME: $t: more than ${WF_FUZZ_RERUNS:-200} failing inputs; the rest are kept in $art, not grouped"
        break
      fi
      # (The fork run's limits: an input that failed there on -malloc_limit_mb fails here too.)
      if timeout --signal=KILL $((TIMEOUT * 3 + 30)) "$BUILD/$(exe_of "$t")" -rss_limit_mb="$RSS_MB" \
        -malloc_limit_mb=$((RSS_MB / 4)) -timeout="$TIMEOUT" -detect_leaks=0 "$unit" > "$unit.log" 2>&1; then
        # Not failing again (a timeout or OOM of a loaded machine): kept and counted, not a finding.
        NOT_REPRODUCED=$((NOT_REPRODUCED + 1))
        mv "$unit" "$art/unreproduced-$(basename "$unit")" 2> /dev/null
        rm -f "$unit.log"
        continue
      fi
      add_finding "$t" "$unit" "$unit.log"
    done
  fi
  while ((FORK == 0)); do
    left=$((deadline - $(date +%s)))
    [[ $left -ge 1 ]] || break
    k=$((k + 1))
    log="$logs/run-$k.log"
    # A hard stop well past the time asked for: the initial pass over the corpus is not bounded.
    timeout --signal=KILL $((left * 2 + 60)) "$BUILD/$(exe_of "$t")" -max_total_time="$left" -rss_limit_mb="$RSS_MB" -timeout="$TIMEOUT" \
      -close_fd_mask=1 -detect_leaks=0 -print_final_stats=1 "${dict[@]}" -artifact_prefix="$art/" "$corpus" > "$log" 2>&1
    rc=$?
    e=$(grep -E '^stat::number_of_executed_units:' "$log" | tail -n 1 | awk '{print $2}')
    n=$((n + ${e:-0}))
    # Slow units (-report_slow_units) are kept by libFuzzer but are not failures: left out.
    unit=$(grep -oE 'Test unit written to [^ ]+' "$log" | grep -v '/slow-unit-' | head -n 1 | sed 's/Test unit written to //')
    if [[ -n "$unit" && -f "$unit" ]]; then
      cp "$log" "$unit.log"
      add_finding "$t" "$unit" "$log"
      [[ "$STOP_AT_FIRST" == 1 ]] && break
    elif [[ $rc -ne 0 ]]; then
      echo "$NAME: $t: libFuzzer exited with $rc and kept no input (log $log):"
      tail -n 20 "$log"
      FUZZER_FAILED=1
      break
    fi
  done
  elapsed=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  EXECS[$t]=$n
  RUNS[$t]=$k
  RATE[$t]=$(awk -v n="$n" -v s="$elapsed" 'BEGIN { printf "%.1f", (s > 0 ? n / s : 0) }')
  # Coverage reached: the most edges ("cov") and features ("ft") any of its libFuzzer runs saw.
  COVERAGE[$t]=$(grep -hE '^#[0-9]+[[:space:]]+(DONE|INITED|NEW|REDUCE|pulse)' "$logs"/run-*.log 2> /dev/null |
    sed -nE 's/.* cov: ([0-9]+) ft: ([0-9]+) .*/\1 \2/p' | sort -n -k1,1 -k2,2 | tail -n 1 | awk '{print $1 " edges, " $2 " features"}')
  KEPT[$t]=$(find "$art" -maxdepth 1 -type f ! -name '*.log' ! -name 'slow-unit-*' ! -name 'unreproduced-*' | wc -l)
  echo "$NAME: $t: ${EXECS[$t]} executions in ${elapsed} s (${RATE[$t]}/s), ${RUNS[$t]} libFuzzer runs, coverage ${COVERAGE[$t]:-unknown}, $(ls "$corpus" | wc -l) corpus inputs, ${KEPT[$t]} failing inputs kept"
done

findings="$BUILD/findings-$NAME.txt"
: > "$findings"
ours_total=0
libs_total=0
for sig in "${!GROUP_COUNT[@]}"; do
  ex=${GROUP_EXAMPLE[$sig]}
  {
    echo "=== [${GROUP_OWNER[$sig]}] $sig"
    echo "    inputs: ${GROUP_COUNT[$sig]}; reproducer: $ex ($(stat -c %s "$ex") bytes)"
    echo "    reproduce: $BUILD/$(exe_of "${GROUP_TARGET[$sig]}") $ex"
    grep -E 'FINDING|^==[0-9]+==ERROR|^==[0-9]+== ERROR|runtime error' "$ex.log" | head -n 2 | sed 's/^/    /'
    awk '/^ +#[0-9]+ 0x/ { s = 1; print; next } s { exit }' "$ex.log" | head -n 16 | sed -E 's/ \(BuildId: [0-9a-f]+\)//; s/^ +/      /' | cut -c1-220
    echo
  } >> "$findings"
  if [[ ${GROUP_OWNER[$sig]} == ours ]]; then ours_total=$((ours_total + 1)); else libs_total=$((libs_total + 1)); fi
done

# --- summary ---------------------------------------------------------------------------------
echo
echo "$NAME: summary (${SECONDS_PER_TARGET} s per target, -timeout=${TIMEOUT})"
for t in $TARGETS; do
  echo "  $t: ${EXECS[$t]} executions, ${RATE[$t]}/s, ${RUNS[$t]} libFuzzer runs, coverage ${COVERAGE[$t]:-unknown}, ${KEPT[$t]} failing inputs (logs $BUILD/logs/$t)"
done
if [[ -s "$findings" ]]; then
  echo
  echo "$NAME: $((ours_total + libs_total)) distinct findings ($ours_total in WireFur's code, $libs_total in libraries); $findings:"
  echo
  cat "$findings"
fi
[[ $NOT_REPRODUCED -gt 0 ]] && echo "$NAME: note: $NOT_REPRODUCED failing input(s) of the fork run did not fail again alone (kept as unreproduced-*)"
[[ $seed_problems -gt 0 ]] && echo "$NAME: note: $seed_problems seed(s) did not read (see the seed lines above)"
if [[ $ours_total -gt 0 || $FUZZER_FAILED -ne 0 ]]; then exit 1; fi
if [[ $libs_total -gt 0 && "$FAIL_ON" != ours ]]; then exit 1; fi
if [[ $libs_total -gt 0 ]]; then echo "$NAME: no findings in WireFur's code ($libs_total in libraries, listed above)"
else echo "$NAME: no findings"; fi
exit 0
