# Test tiers (tests/tiers, issue 31): every line names a test of tests/unit once, with a tier that
# exists (a test not listed is a unit test), and tests/run.sh runs exactly the tiers TIERS asks for,
# checked on stand-in executables in a scratch build folder: a listed validation test (and its
# _double build), an unlisted one, and one whose source is gone (a stale build: never run).
. tests/lib.sh
bad=
for line in $(awk '$1 !~ /^#/ && NF {print $1 ":" $2 ":" NF}' tests/tiers); do
    tier=${line%%:*}; rest=${line#*:}; name=${rest%%:*}; fields=${rest#*:}
    case $tier in validation | experiment) ;; *) bad="$bad $name (tier '$tier': validation or experiment)" ;; esac
    [ "$fields" = 2 ] || bad="$bad $name ($fields fields, want TIER NAME)"
    [ -f "tests/unit/$name.c" ] || bad="$bad $name (no tests/unit/$name.c)"
done
dups=$(awk '$1 !~ /^#/ && NF {print $2}' tests/tiers | sort | uniq -d | tr '\n' ' ')
[ -z "$dups" ] || bad="$bad listed twice: $dups"
if [ -z "$bad" ]; then ok tiers_list_names_tests_once; else fail tiers_list_names_tests_once "tests/tiers:$bad"; fi

B="$TMP/build"
mkdir -p "$B/tests"
for t in test_pipeline_cantilever test_pipeline_cantilever_double test_util_npy test_zz_gone; do
    printf '#!/bin/sh\necho "ok ran_%s"\n' "$t" >"$B/tests/$t"
    chmod +x "$B/tests/$t"
done
# ran TIERS: the stand-ins run.sh ran with that TIERS, sorted, on one line
ran() { BUILD="$B" SUITES=unit TIERS="$1" sh tests/run.sh 2>&1 | sed -n 's/^ok ran_//p' | sort | tr '\n' ' '; }
got=$(ran unit)
if [ "$got" = "test_util_npy " ]; then ok tiers_unit_runs_only_unlisted_tests
else fail tiers_unit_runs_only_unlisted_tests "TIERS=unit ran: '$got'"; fi
got=$(ran validation)
if [ "$got" = "test_pipeline_cantilever test_pipeline_cantilever_double " ]; then ok tiers_validation_runs_listed_tests
else fail tiers_validation_runs_listed_tests "TIERS=validation ran: '$got'"; fi
got=$(ran "unit validation")
if [ "$got" = "test_pipeline_cantilever test_pipeline_cantilever_double test_util_npy " ]; then ok tiers_make_test_runs_both
else fail tiers_make_test_runs_both "TIERS='unit validation' ran: '$got'"; fi
