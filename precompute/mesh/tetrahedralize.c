/* rk_tetrahedralize: runs the tetgen command on the surface in a private temporary
 * directory: surface.off in, surface.1.node/.ele out (read with the TetGen reader), then
 * the directory is emptied and removed. The program is $ROMKIT_TETGEN, else "tetgen" on
 * PATH. It is started with fork/exec (no shell, so no quoting issues); its output goes to
 * a log whose last lines end up in the error message when it fails. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "mesh/mesh_impl.h"

#define EXEC_FAILED_MARK "romkit: cannot execute "

static void remove_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (d) {
        struct dirent *e;
        char path[4200];
        while ((e = readdir(d)) != NULL) {
            if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            unlink(path);
        }
        closedir(d);
    }
    rmdir(dir);
}

/* The end of the log, on one line, for error messages. */
static void log_tail(const char *log_path, char *out, size_t cap)
{
    out[0] = '\0';
    FILE *fp = fopen(log_path, "rb");
    if (!fp) return;
    char buf[400];
    long size = fseek(fp, 0, SEEK_END) == 0 ? ftell(fp) : -1;
    long start = size > (long)sizeof buf - 1 ? size - (long)sizeof buf + 1 : 0;
    size_t n = 0;
    if (size >= 0 && fseek(fp, start, SEEK_SET) == 0) n = fread(buf, 1, sizeof buf - 1, fp);
    fclose(fp);
    buf[n] = '\0';
    for (size_t i = 0; i < n; i++)
        if (buf[i] == '\n' || buf[i] == '\r') buf[i] = ' ';
    while (n > 0 && buf[n - 1] == ' ') buf[--n] = '\0';
    snprintf(out, cap, "%s", buf);
}

static int run_tetgen(const char *program, const char *switches, const char *input, const char *log_path,
                      rk_error *err)
{
    /* The child only calls async-signal-safe functions: its message is formatted here. */
    char exec_failed[600];
    int exec_failed_len = snprintf(exec_failed, sizeof exec_failed, EXEC_FAILED_MARK "%s\n", program);
    if (exec_failed_len < 0 || exec_failed_len >= (int)sizeof exec_failed) exec_failed_len = (int)strlen(EXEC_FAILED_MARK);
    pid_t pid = fork();
    if (pid < 0) return rk_fail(err, "tetgen: cannot fork: %s", strerror(errno));
    if (pid == 0) {
        int fd = open(log_path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
            close(fd);
        }
        char *argv[] = {(char *)program, (char *)switches, (char *)input, NULL};
        execvp(program, argv);
        if (write(2, exec_failed, (size_t)exec_failed_len) < 0) _exit(127);
        _exit(127);
    }
    int status;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return rk_fail(err, "tetgen: waitpid failed: %s", strerror(errno));
    char tail[400];
    log_tail(log_path, tail, sizeof tail);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return 0;
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127 && strstr(tail, EXEC_FAILED_MARK))
        return rk_fail(err, "tetgen is not installed or not runnable: cannot execute '%s' (install tetgen, or set "
                            "ROMKIT_TETGEN to its path)",
                       program);
    if (WIFEXITED(status))
        return rk_fail(err, "tetgen failed with exit status %d: %s", WEXITSTATUS(status), tail[0] ? tail : "(no output)");
    return rk_fail(err,
                   "tetgen was killed by signal %d (it aborts on input it cannot mesh, e.g. a self-intersecting "
                   "surface): %s",
                   WIFSIGNALED(status) ? WTERMSIG(status) : -1, tail[0] ? tail : "(no output)");
}

int rk_tetrahedralize(const rk_surface *s, double max_radius_edge, double max_volume, rk_mesh *out, rk_error *err)
{
    *out = (rk_mesh){0};
    if (max_radius_edge <= 0) max_radius_edge = 1.4;
    if (!isfinite(max_radius_edge) || max_radius_edge < 1.0)
        return rk_fail(err, "tetrahedralize: radius-edge bound %g is below 1.0 (tetgen may not terminate)", max_radius_edge);
    if (!isfinite(max_volume)) return rk_fail(err, "tetrahedralize: max volume %g is not finite", max_volume);
    if (rk_surface_check(s, "surface to tetrahedralize", err)) return -1;

    char switches[128];
    if (max_volume > 0) snprintf(switches, sizeof switches, "-pq%.6ga%.6gQ", max_radius_edge, max_volume);
    else snprintf(switches, sizeof switches, "-pq%.6gQ", max_radius_edge);

    const char *tmp = getenv("TMPDIR");
    char dir[4096], input[4200], node[4200], log_path[4200];
    snprintf(dir, sizeof dir, "%s/romkit-tetgen-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
    if (!mkdtemp(dir)) return rk_fail(err, "tetrahedralize: cannot create a temporary directory in %s: %s",
                                      tmp && tmp[0] ? tmp : "/tmp", strerror(errno));
    snprintf(input, sizeof input, "%s/surface.off", dir);
    snprintf(node, sizeof node, "%s/surface.1.node", dir);
    snprintf(log_path, sizeof log_path, "%s/tetgen.log", dir);
    const char *program = getenv("ROMKIT_TETGEN");
    if (!program || !program[0]) program = "tetgen";

    int rc = rk_surface_write(input, s, err);
    if (rc == 0) rc = run_tetgen(program, switches, input, log_path, err);
    if (rc == 0 && rk_read_tetgen(node, out, err)) rc = rk_error_prefix(err, "reading tetgen's output");
    if (rc == 0) rc = rk_mesh_check(out, "tetgen output", RK_MESH_KEEP_FLAT, NULL, err);
    if (rc) rk_mesh_free(out);
    remove_dir(dir);
    return rc;
}
