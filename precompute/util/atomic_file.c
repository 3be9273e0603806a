#include "util/util.h"

#include <errno.h>
#include <string.h>
#include <unistd.h>

int rk_atomic_open(rk_atomic_file *f, const char *path, rk_error *err)
{
    memset(f, 0, sizeof *f);
    if (strlen(path) >= sizeof f->final_path) return rk_fail(err, "%s: path too long", path);
    strcpy(f->final_path, path);
    snprintf(f->tmp_path, sizeof f->tmp_path, "%s.tmp.%ld", path, (long)getpid());
    f->fp = fopen(f->tmp_path, "wb");
    if (!f->fp) return rk_fail(err, "%s: cannot write: %s", path, strerror(errno));
    return 0;
}

int rk_atomic_commit(rk_atomic_file *f, rk_error *err)
{
    int bad = ferror(f->fp);
    if (fclose(f->fp) != 0) bad = 1;
    f->fp = NULL;
    if (bad) {
        remove(f->tmp_path);
        return rk_fail(err, "%s: write failed (disk full?)", f->final_path);
    }
    if (rename(f->tmp_path, f->final_path) != 0) {
        int e = errno;
        remove(f->tmp_path);
        return rk_fail(err, "%s: cannot rename into place: %s", f->final_path, strerror(e));
    }
    return 0;
}

void rk_atomic_abort(rk_atomic_file *f)
{
    if (f->fp) fclose(f->fp);
    f->fp = NULL;
    if (f->tmp_path[0]) remove(f->tmp_path);
}
