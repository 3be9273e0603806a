# physics/physics_impl.h is shared with the C99 runtime: it must compile as strict C99 in both
# precisions with nothing beyond <math.h> and <string.h>.
. tests/lib.sh
cat >"$TMP/both.c" <<'C'
#define PHYS_REAL float
#define PHYS_FLOAT 1
#define PHYS_FN(name) f32_##name
#include "physics/physics_impl.h"
#undef PHYS_REAL
#undef PHYS_FLOAT
#undef PHYS_FN
#define PHYS_REAL double
#define PHYS_FN(name) f64_##name
#include "physics/physics_impl.h"
C
if ${CC:-cc} -std=c99 -pedantic -Wall -Wextra -Werror -I. -c "$TMP/both.c" -o "$TMP/both.o" 2>"$TMP/err"; then
    ok physics_compiles_as_c99_in_both_precisions
else
    fail physics_compiles_as_c99_in_both_precisions "$(head -c 600 "$TMP/err")"
fi
if grep -h '#include' physics/physics_impl.h physics/collider_impl.h physics/contact_impl.h physics/contact_ad_impl.h | grep -v -e '<math.h>' -e '<string.h>' -e '"physics/physics.h"' -e '"physics/collider_impl.h"' -e '"physics/contact_impl.h"' -e '"physics/contact_ad_impl.h"' >"$TMP/inc"; then
    fail physics_includes_only_libc_math "$(cat "$TMP/inc")"
else
    ok physics_includes_only_libc_math
fi
