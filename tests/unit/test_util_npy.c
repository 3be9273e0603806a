#include "testlib.h"
#include "util/util.h"

#include <unistd.h>

TEST(npy_round_trip)
{
    rk_error err;
    double a[6] = {1, 2, 3, 4.5, -5, 1e300};
    long shape[2] = {2, 3};
    char path[512];
    snprintf(path, sizeof path, "%s/rk_npy_XXXXXX", tl_tmpdir());
    int fd = mkstemp(path);
    close(fd);
    CHECK_OK(rk_npy_write(path, a, 2, shape, &err));
    double *b;
    int ndim;
    long sh[4];
    CHECK_OK(rk_npy_read(path, &b, &ndim, sh, &err));
    remove(path);
    CHECK(ndim == 2 && sh[0] == 2 && sh[1] == 3, "shape %d (%ld, %ld)", ndim, sh[0], sh[1]);
    for (int i = 0; i < 6; i++) CHECK(a[i] == b[i], "value %d differs", i);
    free(b);
}

TEST(npy_header_is_aligned_to_64_bytes)
{
    rk_error err;
    double a[1] = {0};
    long shape[1] = {1};
    char path[512];
    snprintf(path, sizeof path, "%s/rk_npy_XXXXXX", tl_tmpdir());
    close(mkstemp(path));
    CHECK_OK(rk_npy_write(path, a, 1, shape, &err));
    FILE *fp = fopen(path, "rb");
    fseek(fp, 0, SEEK_END);
    long size = ftell(fp);
    fclose(fp);
    remove(path);
    CHECK((size - 8) % 64 == 0, "file size %ld: header not padded to 64", size);
}

TEST(npy_rejects_garbage)
{
    rk_error err;
    char path[512];
    snprintf(path, sizeof path, "%s/rk_npy_XXXXXX", tl_tmpdir());
    int fd = mkstemp(path);
    CHECK(write(fd, "hello world, not numpy", 22) == 22, "write");
    close(fd);
    double *b;
    int ndim;
    long sh[4];
    CHECK(rk_npy_read(path, &b, &ndim, sh, &err) != 0, "garbage accepted");
    remove(path);
    CHECK(strstr(err.msg, "not a .npy") != NULL, "message: %s", err.msg);
}

int main(void)
{
    RUN(npy_round_trip);
    RUN(npy_header_is_aligned_to_64_bytes);
    RUN(npy_rejects_garbage);
    return test_finish();
}
