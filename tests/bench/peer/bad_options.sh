#!/bin/sh
# Bad options to a benchmark driver: each must end at once with exit status 2 and one line on
# stderr, before any rendering. Usage: bad_options.sh BINARY 'OPTIONS' ...
bin=$1
shift
err=$(mktemp)
trap 'rm -f "$err"' EXIT
for opts in "$@"; do
  # shellcheck disable=SC2086  # each argument is a list of options
  "$bin" $opts --no-vtk >/dev/null 2>"$err"
  rc=$?
  lines=$(wc -l <"$err")
  if [ "$rc" -ne 2 ] || [ "$lines" -ne 1 ]; then
    echo "bad_options: '$opts' gave exit $rc and $lines lines:"
    cat "$err"
    exit 1
  fi
  echo "ok: '$opts' -> $(cat "$err")"
done
