# Helpers for integration scripts (sourced). Each check prints "ok NAME" or "FAIL NAME: why".
# ROMKIT points at the built command; TMP is a scratch folder removed on exit.
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
ok() { echo "ok $1"; }
fail() { echo "FAIL $1: $2"; }
# expect_fail NAME PATTERN CMD...: the command must exit non-zero and print PATTERN on stderr.
expect_fail() {
    name=$1; pattern=$2; shift 2
    if "$@" >"$TMP/out" 2>"$TMP/err"; then fail "$name" "succeeded but should have failed"
    elif grep -q -- "$pattern" "$TMP/err"; then ok "$name"
    else fail "$name" "error did not mention '$pattern': $(head -c 300 "$TMP/err")"; fi
}

# JSON reports are read parsed, through jsonq (tests/tools/jsonq.c), never as grepped text.
# PATH is jsonq's: keys joined by dots, array elements by [i] (methods[2].cubature.elements).
JSONQ=${JSONQ:-${ROMKIT_BUILD:-build}/jsonq}
# json_doc PATH VALUE: a JSON document holding VALUE (JSON text) at PATH, and nulls before it in arrays.
json_doc() {
    jq_doc=$2; jq_rest=$1
    while [ -n "$jq_rest" ]; do
        jq_seg=${jq_rest##*.}
        case $jq_rest in *.*) jq_rest=${jq_rest%.*} ;; *) jq_rest= ;; esac
        while :; do
            case $jq_seg in *\]) ;; *) break ;; esac
            jq_i=${jq_seg##*\[}; jq_i=${jq_i%\]}; jq_seg=${jq_seg%\[*}; jq_pad=
            while [ "$jq_i" -gt 0 ]; do jq_pad="null,$jq_pad"; jq_i=$((jq_i - 1)); done
            jq_doc="[$jq_pad$jq_doc]"
        done
        [ -n "$jq_seg" ] && jq_doc="{\"$jq_seg\":$jq_doc}"
    done
    printf '%s\n' "$jq_doc"
}
# json_is FILE PATH VALUE: FILE has VALUE (JSON text: 12, "modes", null) at PATH, of the same type
# and, for a number, exactly equal (jsonq same, tolerance 0).
json_is() {
    json_doc "$2" "$3" >"$TMP/json_want.json" && "$JSONQ" same "$TMP/json_want.json" "$1" 0 "$2" >/dev/null 2>&1
}
# json_num FILE PATH: prints the number at PATH; prints nothing and fails when PATH is missing or
# holds anything but a number. (jsonq same against 0 with relative tolerance 1 holds for every
# number, |x - 0| <= max(|x|, 0), and for nothing else: a string or null never equals a number.)
json_num() {
    json_doc "$2" 0 >"$TMP/json_want.json" && "$JSONQ" same "$TMP/json_want.json" "$1" 1 "$2" >/dev/null 2>&1 &&
        "$JSONQ" get "$1" "$2"
}
# json_checks NAME FILE CHECK...: "ok NAME" when every CHECK holds in FILE, else "FAIL NAME" naming
# those that do not. CHECK: PATH (there, any value; PATH[0] for a non-empty array, PATH.KEY for an
# object) or PATH=VALUE (json_is: that JSON value, same type, exactly).
json_checks() {
    jq_name=$1; jq_file=$2; shift 2; jq_bad=
    for jq_c in "$@"; do
        case $jq_c in
            *=*) json_is "$jq_file" "${jq_c%%=*}" "${jq_c#*=}" ||
                     jq_bad="$jq_bad $jq_c (is $("$JSONQ" get "$jq_file" "${jq_c%%=*}" 2>/dev/null || echo missing))" ;;
            *) "$JSONQ" has "$jq_file" "$jq_c" 2>/dev/null || jq_bad="$jq_bad $jq_c (missing)" ;;
        esac
    done
    if [ -z "$jq_bad" ]; then ok "$jq_name"; else fail "$jq_name" "$jq_file:$jq_bad"; fi
}
# .npy files (format version 1, little-endian float64, as romkit writes them): the header is 10
# bytes plus the length stored in bytes 8-9, a Python dict text holding 'shape': (...).
npy_header_bytes() { set -- $(od -A n -t u1 -j 8 -N 2 "$1"); echo $(($1 + 256 * $2 + 10)); }
npy_shape() { head -c "$(npy_header_bytes "$1")" "$1" | LC_ALL=C sed -n "s/.*'shape': (\([0-9, ]*\)).*/\1/p"; }
# npy_values FILE: every value, one per line, in file order (od prints doubles round-trip exact).
npy_values() { od -A n -v -t f8 -j "$(npy_header_bytes "$1")" "$1" | tr -s ' ' '\n' | sed '/^$/d'; }
# below A B: A is a number (not empty, not text that awk would read as 0) and A < B.
below() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a ~ /^[-+]?[0-9.]+([eE][-+]?[0-9]+)?$/ && a + 0 < b + 0) }'; }

# cantilever FILE CELLS_X GRAVITY_Y ROM_JSON: the small neo-Hookean cantilever several scripts bake
# (1 x 0.2 x 0.2 m, CELLS_X x 2 x 2 cells, clamped at x = 0), 0.2 s under gravity GRAVITY_Y (m/s^2),
# its rom section ROM_JSON.
cantilever() {
    cat >"$1" <<JSON
{
  "objects": [{
    "mesh": {"box": {"size": [1, 0.2, 0.2], "cells": [$2, 2, 2]}},
    "material": {"model": "neohookean", "young": 2e6, "poisson": 0.4, "density": 1000},
    "fixed": [{"box": [[-1, -1, -1], [0.01, 1, 1]]}]
  }],
  "gravity": [0, $3, 0],
  "time": {"step": 0.01, "duration": 0.2},
  "rom": $4
}
JSON
}
