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
