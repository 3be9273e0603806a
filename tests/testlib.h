/* A minimal test harness. Each tests/unit/test_<stage>_<name>.c is one executable:
 *
 *   TEST(reads_a_box) { CHECK(x == 1, "x was %d", x); }
 *   int main(void) { RUN(reads_a_box); return test_finish(); }
 *
 * Every test prints one line, "ok <name>" or "FAIL <name>: file:line: message";
 * tests/run.sh counts those lines across all executables and prints "N passed, N failed". */
#ifndef RK_TESTLIB_H
#define RK_TESTLIB_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int tl_failed_here;
static int tl_failures;
static int tl_count;

#define TEST(name) static void name(void)

#define RUN(name)                                                       \
    do {                                                                \
        tl_failed_here = 0;                                             \
        tl_count++;                                                     \
        name();                                                         \
        if (!tl_failed_here) printf("ok %s\n", #name);                  \
        else tl_failures++;                                             \
        fflush(stdout);                                                 \
    } while (0)

/* Records a failure (with a printf message) and leaves the test. */
#define CHECK(cond, ...)                                                         \
    do {                                                                         \
        if (!(cond)) {                                                           \
            printf("FAIL %s: %s:%d: ", __func__, __FILE__, __LINE__);            \
            printf(__VA_ARGS__);                                                 \
            printf("\n");                                                        \
            tl_failed_here = 1;                                                  \
            return;                                                              \
        }                                                                        \
    } while (0)

/* |a - b| <= tol * max(1, |b|) */
#define CHECK_CLOSE(a, b, tol)                                                        \
    CHECK(fabs((double)(a) - (double)(b)) <= (tol) * fmax(1.0, fabs((double)(b))),   \
          "%s = %.12g, expected %.12g (tol %g)", #a, (double)(a), (double)(b), (double)(tol))

/* Calls an rk_* function that returns 0 on success and fills `err` otherwise. */
#define CHECK_OK(call) CHECK((call) == 0, "%s failed: %s", #call, err.msg)

/* Locates test data: ROMKIT_TEST_DATA or tests/data relative to the repository root. */
static inline const char *test_data(const char *rel)
{
    static char buf[4][1024];
    static int slot;
    const char *root = getenv("ROMKIT_TEST_DATA");
    char *out = buf[slot++ & 3];
    snprintf(out, 1024, "%s/%s", root ? root : "tests/data", rel);
    return out;
}

/* Euclidean norm of n entries. */
static inline double test_norm(const double *x, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++) s += x[i] * x[i];
    return sqrt(s);
}

/* The folder for scratch files: $TMPDIR, or /tmp when it is unset or empty. */
static inline const char *tl_tmpdir(void)
{
    const char *dir = getenv("TMPDIR");
    return dir && *dir ? dir : "/tmp";
}

/* A scratch file's path of this process's own: $TMPDIR (or /tmp)/romkit_<pid>_<name>. Two tests,
 * the float and double build of one, or two checkouts testing at once never share a file. */
static inline const char *tl_scratch(char *out, size_t cap, const char *name)
{
    snprintf(out, cap, "%s/romkit_%ld_%s", tl_tmpdir(), (long)getpid(), name);
    return out;
}

static inline int test_finish(void) { return tl_failures ? 1 : 0; }

#endif
