#!/usr/bin/env bash
# Lint with Debian's clang-format and clang-tidy (version 14; .clang-format,
# .clang-tidy).
#
# 1. clang-format --dry-run -Werror on every tracked *.cpp and *.h (but
#    tests/fixtures/): fails listing the files to reformat, and the command
#    that reformats them.
# 2. clang-tidy, through run-clang-tidy, on the library, the CLI and the
#    Python module (src/**/*.cpp, python/*.cpp), with the compile commands of
#    a configure-only CMake build in a temporary directory, LINT_JOBS files at
#    a time (default 2). Findings in the headers of include/fss/ and src/ are
#    reported too, once however many sources include them. tests/ and bench/
#    are left out for time: clang-tidy spends 10 to 65 s of CPU on a test
#    source against about 10 s on one of src/, so the test sources (about as
#    many) would add some 20 minutes on two cores to the 7 to 8 minutes (15
#    minutes of CPU) of src/ and python/, in a CI run with about 7 to spare.
#    Each finding is normalised to "path:check:message" (path relative to the
#    repository, no line or column, every number in the message written N so
#    that a function growing by a line does not make a new finding) and the
#    sorted list is compared, as a multiset, with .clang-tidy-baseline: a
#    finding not in the baseline fails the run and is printed in full, with
#    its line; a baseline entry no longer found is reported as fixed, without
#    failing. Compiler errors (clang-diagnostic-error) are never baselined:
#    they always fail.
#
# Usage: scripts/lint.sh                    both checks; exit 1 on a failure
#        scripts/lint.sh --update-baseline  rewrites .clang-tidy-baseline from
#                                           the current findings (no format
#                                           check); exit 1 if a source does not
#                                           compile
# Environment: LINT_JOBS (default 2), CLANG_FORMAT (default clang-format-14),
#              CLANG_TIDY (default clang-tidy-14).
set -euo pipefail
export LC_ALL=C
cd "$(dirname "$0")/.."
root=$(pwd -P)
baseline=.clang-tidy-baseline
jobs=${LINT_JOBS:-2}
clang_format=${CLANG_FORMAT:-clang-format-14}
clang_tidy=${CLANG_TIDY:-clang-tidy-14}
run_clang_tidy=run-clang-tidy-14

update=0
for argument in "$@"; do
  case "$argument" in
    --update-baseline) update=1 ;;
    *) echo "lint: unknown argument '$argument' (expected --update-baseline)" >&2; exit 2 ;;
  esac
done
for tool in "$clang_format" "$clang_tidy" "$run_clang_tidy"; do
  command -v "$tool" >/dev/null || {
    echo "lint: $tool not found (scripts/install-deps.sh installs clang-format and clang-tidy)" >&2
    exit 1
  }
done

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0

# --- 1. clang-format -------------------------------------------------------
if [ "$update" = 0 ]; then
  sources=()
  while IFS= read -r -d '' file; do
    # A file deleted from the working tree but still in the index is skipped.
    [ -f "$file" ] && sources+=("$file")
  done < <(git ls-files -z -- '*.cpp' '*.h' ':!:tests/fixtures/**')
  # --dry-run -Werror prints "FILE:LINE:COL: error: code should be
  # clang-formatted [-Wclang-format-violations]" for each difference.
  "$clang_format" --dry-run -Werror "${sources[@]}" > "$work/format.log" 2>&1 || true
  unformatted=()
  while IFS= read -r file; do unformatted+=("$file"); done < <(
    sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: error: .*\[-Wclang-format-violations\]$/\1/p' \
      "$work/format.log" | sort -u)
  if [ "${#unformatted[@]}" -gt 0 ]; then
    status=1
    echo "lint: ${#unformatted[@]} file(s) not formatted as .clang-format says:"
    printf '  %s\n' "${unformatted[@]}"
    echo "lint: to reformat them, run:"
    echo "  $clang_format -i ${unformatted[*]}"
  elif grep -q 'error' "$work/format.log"; then
    # An error of clang-format itself (a file it cannot read, a bad .clang-format).
    status=1
    cat "$work/format.log"
  else
    echo "lint: clang-format: ${#sources[@]} files formatted"
  fi
fi

# --- 2. clang-tidy ---------------------------------------------------------
# Configure only: the one generated source (the built-in codes, FSS_CODES_CPP,
# made at build time) is not among the files linted and no linted file
# includes a generated header. Debug keeps the assertions, which the static
# analyzer takes as facts. FSS_BUILD_PYTHON=ON fails the configure if pybind11
# or the Python headers are missing instead of leaving python/ out.
cmake -S . -B "$work/build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
  -DFSS_BUILD_TESTS=OFF -DFSS_BUILD_BENCH=OFF -DFSS_BUILD_PYTHON=ON > "$work/configure.log" 2>&1 || {
  cat "$work/configure.log" >&2
  echo "lint: the CMake configure failed" >&2
  exit 1
}
quoted_root=$(printf '%s' "$root" | sed 's/[][\.*^$+?(){}|]/\\&/g')
file_regexes=("^$quoted_root/src/.*\\.cpp\$" "^$quoted_root/python/[^/]*\\.cpp\$")
count=$(grep -cE "\"file\": \"($quoted_root/src/.*\\.cpp|$quoted_root/python/[^/]*\\.cpp)\"" \
  "$work/build/compile_commands.json" || true)
if [ "$count" -eq 0 ]; then
  echo "lint: no source of src/ or python/ in $work/build/compile_commands.json" >&2
  exit 1
fi
echo "lint: clang-tidy on $count files, $jobs at a time"
# run-clang-tidy exits 1 when clang-tidy fails on a file: a compiler error
# (a finding below, clang-diagnostic-error) or a crash.
tidy_status=0
"$run_clang_tidy" -clang-tidy-binary "$(command -v "$clang_tidy")" -p "$work/build" -j "$jobs" \
  -quiet -header-filter="^$quoted_root/(include/fss|src)/" "${file_regexes[@]}" \
  > "$work/tidy.log" 2> "$work/tidy.err" || tidy_status=$?

# One line a diagnostic, "KEY<TAB>FINDING": FINDING as clang-tidy prints it,
# path relative and without "dir/../"; KEY the normalised form. A finding in
# a header, printed once for each source including it, is kept once.
# run-clang-tidy asks for colours (--use-color): the escapes are removed.
sed 's/\x1b\[[0-9;]*m//g' "$work/tidy.log" > "$work/tidy.txt"
awk -v root="$root/" '
  /^\/[^:]+:[0-9]+:[0-9]+: (warning|error|fatal error): .* \[[^]]+\]$/ {
    split($0, part, ":")
    path = part[1]
    while (sub(/\/[^\/]+\/\.\.\//, "/", path)) {}
    if (index(path, root) == 1) path = substr(path, length(root) + 1)
    print path substr($0, length(part[1]) + 1)
  }' "$work/tidy.txt" | sort -u > "$work/findings"
sed -E 's/^([^:]+):[0-9]+:[0-9]+: (warning|error|fatal error): (.*) \[([^]]+)\]$/\1:\4:\3/;
        s/(^|[^[:alnum:]_])[0-9]+([.][0-9]+)?/\1N/g' "$work/findings" > "$work/keys"
paste "$work/keys" "$work/findings" > "$work/keyed"
grep -v '^[^:]*:clang-diagnostic-error:' "$work/keys" | sort > "$work/current" || true
if [ "$tidy_status" != 0 ] || grep -q '^[^:]*:clang-diagnostic-error:' "$work/keys"; then
  # A source that does not compile (never baselined), or clang-tidy itself
  # failing (a crash, a missing file): its errors, with and without a place,
  # and what run-clang-tidy printed on stderr but the counts of warnings.
  status=1
  echo "lint: clang-tidy failed:"
  {
    awk -F'\t' '$1 ~ /^[^:]*:clang-diagnostic-error:/ { print $2 }' "$work/keyed"
    grep '^error: ' "$work/tidy.txt" || true
    grep -v 'generated\.$\|^Suppressed [0-9]* warnings\|^Use -header-filter\|^Use -system-headers' \
      "$work/tidy.err" || true
  } | sed 's/^/  /'
fi

if [ "$update" = 1 ]; then
  cp "$work/current" "$baseline"
  echo "lint: $baseline rewritten: $(wc -l < "$baseline") findings"
  awk -F: '{ print $2 }' "$baseline" | sort | uniq -c | sort -rn | sed 's/^/  /'
  exit "$status"
fi

if [ -f "$baseline" ]; then
  grep -v '^#' "$baseline" | sort > "$work/baseline" || true
else
  : > "$work/baseline"
fi
comm -13 "$work/baseline" "$work/current" | sort -u > "$work/new"
comm -23 "$work/baseline" "$work/current" > "$work/fixed"
if [ -s "$work/fixed" ]; then
  echo "lint: clang-tidy: $(wc -l < "$work/fixed") finding(s) fixed, remove from the baseline" \
    "(scripts/lint.sh --update-baseline):"
  sed 's/^/  /' "$work/fixed"
fi
if [ -s "$work/new" ]; then
  status=1
  echo "lint: clang-tidy: new finding(s), not in $baseline:"
  # Where a file has more findings of one key than the baseline, all of that
  # key are printed: the line numbers do not say which one is new.
  awk -F'\t' 'NR == FNR { new[$0] = 1; next } ($1 in new) { print "  " $2 }' \
    "$work/new" "$work/keyed"
  echo "lint: fix them, or if a finding is to be kept, add it to the baseline" \
    "(scripts/lint.sh --update-baseline)"
else
  echo "lint: clang-tidy: no finding beyond the $(wc -l < "$work/baseline") of $baseline"
fi
exit "$status"
