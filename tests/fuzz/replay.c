/* replay: runs inputs through the runtime without libFuzzer, for gcc + sanitizer builds.
 *
 *   replay FILE|DIR...                 LLVMFuzzerTestOneInput on each file (a crash is the failure)
 *   replay --expect-error FILE|DIR...  each must be refused: "ok rejects NAME: STATUS: MESSAGE"
 *   replay --expect-ok FILE|DIR...     each must open and take 3 steps: "ok opens NAME"
 *
 * A directory stands for the files under it, in name order. Exit status 1 if any line is FAIL. */
#define _POSIX_C_SOURCE 200809L /* dirent, stat, posix_memalign */

#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "runtime/romrt.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

enum { MODE_FUZZ, MODE_EXPECT_ERROR, MODE_EXPECT_OK };

/* The whole file, 16-byte aligned as an application would hold an asset; NULL if unreadable. */
static unsigned char *read_file(const char *path, size_t *size)
{
    FILE *fp = fopen(path, "rb");
    long n;
    void *p = NULL;
    if (!fp) return NULL;
    if (fseek(fp, 0, SEEK_END) != 0 || (n = ftell(fp)) < 0 || fseek(fp, 0, SEEK_SET) != 0 ||
        posix_memalign(&p, 16, (size_t)n + 1) != 0 || fread(p, 1, (size_t)n, fp) != (size_t)n) {
        free(p);
        fclose(fp);
        return NULL;
    }
    fclose(fp);
    *size = (size_t)n;
    return p;
}

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

/* Arena size, open, then `steps` steps of one model (kind -1: romrt_open's default); the first
 * failing call's status and error. */
static romrt_status open_and_step_kind(const unsigned char *asset, size_t size, int kind, int steps, romrt_error *err)
{
    size_t bytes = 0;
    void *arena = NULL;
    romrt_model *m;
    romrt_status st;
    int i;
    memset(err, 0, sizeof *err);
    st = kind < 0 ? romrt_arena_size(asset, size, &bytes, err)
                  : romrt_arena_size_kind(asset, size, (romrt_kind)kind, &bytes, err);
    if (st != ROMRT_OK) return st;
    if (posix_memalign(&arena, 16, bytes ? bytes : 1) != 0) {
        fprintf(stderr, "replay: cannot allocate an arena of %lu bytes\n", (unsigned long)bytes);
        exit(2);
    }
    st = kind < 0 ? romrt_open(asset, size, arena, bytes, &m, err)
                  : romrt_open_kind(asset, size, (romrt_kind)kind, arena, bytes, &m, err);
    for (i = 0; st == ROMRT_OK && i < steps; i++) st = romrt_step(m, err);
    free(arena);
    return st;
}

/* Every model the asset holds: the default one, then its Koopman operator if it has one beside a
 * reduced model (damage there must be refused too). */
static romrt_status open_and_step(const unsigned char *asset, size_t size, int steps, romrt_error *err)
{
    romrt_status st = open_and_step_kind(asset, size, -1, steps, err);
    romrt_error k;
    if (st != ROMRT_OK) return st;
    st = open_and_step_kind(asset, size, ROMRT_KIND_KOOPMAN, steps, &k);
    if (st == ROMRT_E_UNSUPPORTED && strstr(k.message, "has no Koopman operator")) return ROMRT_OK; /* none */
    *err = k;
    return st;
}

/* Runs one file; returns 1 if it failed its expectation. */
static int run_file(const char *path, int mode)
{
    size_t size = 0;
    unsigned char *data = read_file(path, &size);
    romrt_error err;
    romrt_status st;
    int failed = 0;
    if (!data) {
        printf("FAIL %s %s: cannot read the file\n", mode == MODE_EXPECT_OK ? "opens" : "rejects", base_name(path));
        return 1;
    }
    if (mode == MODE_FUZZ) {
        LLVMFuzzerTestOneInput(data, size);
    } else if (mode == MODE_EXPECT_ERROR) {
        st = open_and_step(data, size, 1, &err);
        if (st == ROMRT_OK) {
            printf("FAIL rejects %s: opened and stepped without an error\n", base_name(path));
            failed = 1;
        } else if (err.message[0] == 0) {
            printf("FAIL rejects %s: %s: (empty message)\n", base_name(path), romrt_status_string(st));
            failed = 1;
        } else {
            printf("ok rejects %s: %s: %s\n", base_name(path), romrt_status_string(st), err.message);
        }
    } else {
        st = open_and_step(data, size, 3, &err);
        if (st == ROMRT_OK) {
            printf("ok opens %s\n", base_name(path));
        } else {
            printf("FAIL opens %s: %s: %s\n", base_name(path), romrt_status_string(st), err.message);
            failed = 1;
        }
    }
    free(data);
    return failed;
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* A file, or every file under a directory in name order; returns the FAIL count. */
static int run_path(const char *path, int mode, int *files)
{
    struct stat s;
    DIR *d;
    struct dirent *de;
    char **names = NULL;
    size_t n = 0, cap = 0, i;
    int failed = 0;
    if (stat(path, &s) != 0 || !S_ISDIR(s.st_mode)) {
        (*files)++;
        return run_file(path, mode);
    }
    d = opendir(path);
    if (!d) {
        printf("FAIL %s: cannot open the directory\n", path);
        return 1;
    }
    while ((de = readdir(d)) != NULL) {
        char *full;
        if (de->d_name[0] == '.') continue;
        full = malloc(strlen(path) + strlen(de->d_name) + 2);
        if (!full) exit(2);
        sprintf(full, "%s/%s", path, de->d_name);
        if (stat(full, &s) != 0 || !(S_ISREG(s.st_mode) || S_ISDIR(s.st_mode))) {
            free(full);
            continue;
        }
        if (n == cap) {
            char **grown = realloc(names, (cap = cap ? 2 * cap : 64) * sizeof *names);
            if (!grown) exit(2);
            names = grown;
        }
        names[n++] = full;
    }
    closedir(d);
    if (n) qsort(names, n, sizeof *names, by_name);
    for (i = 0; i < n; i++) {
        failed += run_path(names[i], mode, files);
        free(names[i]);
    }
    free(names);
    return failed;
}

int main(int argc, char **argv)
{
    int mode = MODE_FUZZ, first = 1, i, failed = 0, files = 0;
    if (argc > 1 && strcmp(argv[1], "--expect-error") == 0) mode = MODE_EXPECT_ERROR, first = 2;
    else if (argc > 1 && strcmp(argv[1], "--expect-ok") == 0) mode = MODE_EXPECT_OK, first = 2;
    if (first >= argc || argv[first][0] == '-') {
        fprintf(stderr, "usage: replay [--expect-error | --expect-ok] FILE|DIR...\n");
        return 2;
    }
    for (i = first; i < argc; i++) failed += run_path(argv[i], mode, &files);
    if (mode == MODE_FUZZ) printf("replayed %d input%s\n", files, files == 1 ? "" : "s");
    return failed ? 1 : 0;
}
