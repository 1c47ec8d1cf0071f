#!/usr/bin/env bash
# Fuzzes WireFur's input readers for longer than CI does, with a corpus kept between runs.
#
#   scripts/fuzz.sh --minutes N [--targets "mesh scene step iges brep fcstd"] [--jobs J] [--update-corpus]
#
# Runs each target for N minutes (tests/fuzz/run_fuzz.sh: clang, libFuzzer, AddressSanitizer and
# UndefinedBehaviorSanitizer; J cores per target, --jobs, default 1; one target after another;
# libFuzzer's fork mode, which goes on past failing inputs and keeps them) in build/fuzz-build,
# the ctest fuzz tests' build folder (-rss_limit_mb 1024, -malloc_limit_mb 256: VTK's readers
# asked for gigabytes by a corrupt count fail fast), on a working corpus kept in build/fuzz-corpus/<target>: each
# run starts where the last one stopped. The seeds are those CI uses plus the committed corpus
# (tests/fuzz/corpus/<target>). Prints per target the executions, the executions per second, the
# coverage reached (edges and features) and the failing inputs, grouped by where they fail
# (build/fuzz-build/findings-fuzz.txt: ours or a library's), and the totals.
#
# --update-corpus merges what the run found into tests/fuzz/corpus (libFuzzer's -merge=1: only
# inputs of at most 4 KiB that reach something the committed corpus does not), to be reviewed
# and committed.
#
# Exit status as run_fuzz.sh's: 0 nothing found, 1 findings, 2 the build failed, 77 skipped.
set -u
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
MINUTES=""
TARGETS="mesh scene step iges brep fcstd"
UPDATE=0
JOBS=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --minutes | --targets | --jobs)
      if [[ $# -lt 2 ]]; then echo "fuzz.sh: $1 needs a value" >&2; exit 2; fi
      case "$1" in
        --minutes) MINUTES=$2 ;;
        --targets) TARGETS=$2 ;;
        --jobs) JOBS=$2 ;;
      esac
      shift 2 ;;
    --update-corpus) UPDATE=1; shift ;;
    -h | --help) sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "fuzz.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
if ! [[ "$MINUTES" =~ ^[0-9]+([.][0-9]+)?$ ]] || [[ $(awk -v m="$MINUTES" 'BEGIN { print (m > 0) }') != 1 ]]; then
  echo "fuzz.sh: --minutes N (N > 0, per target) is required" >&2
  exit 2
fi
BUILD=$ROOT/build/fuzz-build
CORPUS=$ROOT/build/fuzz-corpus
mkdir -p "$BUILD" "$CORPUS"
CXX=$(command -v clang++ || command -v clang++-14 || true)
if ! [[ "$JOBS" =~ ^[1-9][0-9]*$ ]]; then
  echo "fuzz.sh: --jobs J (a whole number, at least 1) was '$JOBS'" >&2
  exit 2
fi
seconds=$(awk -v m="$MINUTES" 'BEGIN { s = int(m * 60); printf "%d", (s < 1 ? 1 : s) }')
log=$BUILD/fuzz-$(date +%Y%m%d-%H%M%S).log
echo "fuzz.sh: $TARGETS, $MINUTES min each; the whole report in $log"
WF_FUZZ_NAME=fuzz WF_FUZZ_SECONDS=$seconds WF_FUZZ_TARGETS="$TARGETS" WF_FUZZ_KEEP_CORPUS=1 WF_FUZZ_FORK=$JOBS WF_FUZZ_RSS_MB=${WF_FUZZ_RSS_MB:-1024} WF_FUZZ_CORPUS_DIR=$CORPUS \
  bash "$ROOT/tests/fuzz/run_fuzz.sh" "$BUILD" "$CXX" 2>&1 | tee "$log"
rc=${PIPESTATUS[0]}
total=$(sed -nE 's/^fuzz: [a-z]+: ([0-9]+) executions in .*/\1/p' "$log" | awk '{ s += $1 } END { print s + 0 }')
echo "fuzz.sh: $total executions in all (log $log)"
# Every run's report stays in build/fuzz-build: the executions of all of them, by target.
sed -nE 's/^fuzz: ([a-z]+): ([0-9]+) executions in .*/\1 \2/p' "$BUILD"/fuzz-*.log 2> /dev/null |
  awk '{ n[$1] += $2; s += $2 } END { printf "fuzz.sh: all runs kept in build/fuzz-build so far: %d executions (", s;
        first = 1; for (t in n) { printf "%s%s %d", (first ? "" : ", "), t, n[t]; first = 0 } print ")" }'
if [[ $UPDATE == 1 && ( $rc == 0 || $rc == 1 ) ]]; then
  for t in $TARGETS; do
    exe=$BUILD/fuzz_$t
    [[ -x $exe ]] || exe=$BUILD/fuzz_cad_$t
    [[ -x $exe && -d $CORPUS/$t ]] || continue
    mkdir -p "$ROOT/tests/fuzz/corpus/$t"
    before=$(ls "$ROOT/tests/fuzz/corpus/$t" | wc -l)
    # Only inputs of at most 4 KiB are offered (-max_len would cut larger ones, not skip them).
    small=$BUILD/merge-small-$t
    rm -rf "$small" && mkdir -p "$small"
    find "$CORPUS/$t" -maxdepth 1 -type f -size -4097c -exec cp {} "$small"/ \;
    "$exe" -merge=1 -detect_leaks=0 "$ROOT/tests/fuzz/corpus/$t" "$small" > "$BUILD/merge-$t.log" 2>&1
    rm -rf "$small"
    echo "fuzz.sh: $t: the committed corpus went from $before to $(ls "$ROOT/tests/fuzz/corpus/$t" | wc -l) inputs"
  done
fi
exit "$rc"
