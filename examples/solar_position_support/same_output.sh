#!/bin/bash
# Byte comparison of two solar_position binaries: the same stdout and exit
# code for every algorithm, both float types, refraction and
# --allow-out-of-range, on the given inputs and on small edge files
# (empty input, header only, BOM only, blank lines before the header, no
# usable column, a quote never closed).
#
#   examples/solar_position_support/same_output.sh OLD_BINARY NEW_BINARY INPUT.csv...
#
# Inputs: make_rows.py's benchmark rows and its --edge rows. Prints one line
# per case and `pass=N fail=M`; exits 1 on any difference.
set -u
old=$1 new=$2
shift 2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
pass=0 fail=0
one() { # name input args...
  local name=$1 input=$2 ro rn
  shift 2
  "$old" "$@" < "$input" > "$work/old.out" 2> /dev/null; ro=$?
  "$new" "$@" < "$input" > "$work/new.out" 2> /dev/null; rn=$?
  if [ "$ro" = "$rn" ] && cmp -s "$work/old.out" "$work/new.out"; then
    pass=$((pass + 1))
    echo "same  $name [$*] exit $ro, $(grep -c '' "$work/new.out") lines"
  else
    fail=$((fail + 1))
    echo "DIFF  $name [$*] exit $ro / $rn: $(cmp "$work/old.out" "$work/new.out" 2>&1 | head -1)"
  fi
}
printf '' > "$work/empty.csv"
printf 'utc,latitude,longitude\n' > "$work/header_only.csv"
printf 'utc,latitude,longitude' > "$work/header_no_line_end.csv"
printf '\xef\xbb\xbf' > "$work/bom_only.csv"
printf '\n\n  \n""\nutc,lat,lon\n2030-06-01T12:00:00Z,45,0\n' > "$work/no_usable_column.csv"
printf '\r\n\n utc , LATITUDE,longitude\r\n2030-06-01T12:00:00Z,45,0' > "$work/blank_lines_first.csv"
printf 'utc,latitude,longitude,note\n2030-06-01T12:00:00Z,45,0,"never closed\n2030-06-01T12:00:00Z,45,0,x\n' \
  > "$work/open_quote.csv"
for f in empty header_only header_no_line_end bom_only no_usable_column blank_lines_first open_quote; do
  one "$f" "$work/$f.csv" --algorithm psa-2020 --float f64
done
for input in "$@"; do
  name=$(basename "$input")
  for alg in psa-2001 psa-2020 psa-modified psa-modified-printed michalsky grena-2008 \
    grena-2012-1 grena-2012-3 grena-2012-5 spa textbook; do
    for float in f64 f32; do
      one "$name" "$input" --algorithm "$alg" --float "$float"
    done
  done
  one "$name" "$input" --algorithm spa --float f64 --pressure 1010 --temperature 12.5
  one "$name" "$input" --algorithm psa-2020 --float f32 --pressure 700 --temperature -30 --allow-out-of-range
  one "$name" "$input" --algorithm grena-2012-3 --float f64 --allow-out-of-range
done
echo "pass=$pass fail=$fail"
[ "$fail" = 0 ]
