/* A plan's files (plan.h): plan.json, the Makefile, and the Slurm scripts. All are made in memory
 * first and then written, each atomically; a failing write removes what was written, so a plan is
 * written whole or not at all. */
#include "plan/plan.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct {
    char *s;
    size_t n, cap;
    int failed;
} text;

static void put(text *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int need = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (t->failed || need < 0) {
        t->failed = 1;
        return;
    }
    if (t->n + (size_t)need + 1 > t->cap) {
        size_t cap = 2 * (t->n + (size_t)need + 1);
        char *grown = realloc(t->s, cap);
        if (!grown) {
            t->failed = 1;
            return;
        }
        t->s = grown;
        t->cap = cap;
    }
    va_start(ap, fmt);
    vsnprintf(t->s + t->n, t->cap - t->n, fmt, ap);
    va_end(ap);
    t->n += (size_t)need;
}

/* A step's command line; ROMKIT is the Makefile's $(ROMKIT) or the scripts' "$ROMKIT". */
static void command(text *t, const rk_plan_step *s, const char *romkit)
{
    put(t, "%s", romkit);
    for (int i = 0; i < s->nargs; i++) put(t, " %s", s->args[i]);
}

static cJSON *plan_json(const rk_plan *p, const char *dir, const char *romkit)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "scene", p->scene);
    cJSON_AddNumberToObject(j, "entry", p->entry);
    cJSON_AddStringToObject(j, "name", p->entry_name);
    cJSON_AddStringToObject(j, "method", p->method);
    cJSON_AddBoolToObject(j, "split", p->split);
    if (!p->split) cJSON_AddStringToObject(j, "one_step_because", p->whole_reason);
    cJSON_AddStringToObject(j, "dir", dir);
    cJSON_AddStringToObject(j, "romkit", romkit);
    cJSON_AddNumberToObject(j, "threads", p->threads);
    cJSON_AddStringToObject(j, "asset", p->steps[p->nsteps - 1].output);
    cJSON *steps = cJSON_AddArrayToObject(j, "steps");
    for (int k = 0; k < p->nsteps; k++) {
        const rk_plan_step *s = &p->steps[k];
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "id", s->id);
        cJSON *c = cJSON_AddArrayToObject(o, "command");
        cJSON_AddItemToArray(c, cJSON_CreateString("romkit"));
        for (int i = 0; i < s->nargs; i++) cJSON_AddItemToArray(c, cJSON_CreateString(s->args[i]));
        cJSON *in = cJSON_AddArrayToObject(o, "inputs");
        for (int i = 0; i < s->ninputs; i++) cJSON_AddItemToArray(in, cJSON_CreateString(s->inputs[i]));
        cJSON *out = cJSON_AddArrayToObject(o, "outputs");
        cJSON_AddItemToArray(out, cJSON_CreateString(s->output));
        cJSON *after = cJSON_AddArrayToObject(o, "after");
        for (int i = 0; i < s->nafter; i++) cJSON_AddItemToArray(after, cJSON_CreateString(p->steps[s->after[i]].id));
        if (k < p->ntrain) cJSON_AddNumberToObject(o, "array_index", k);
        cJSON_AddItemToArray(steps, o);
    }
    return j;
}

/* make -C DIR -j: one rule per step, its output from its inputs. .DELETE_ON_ERROR and the atomic
 * writes of every romkit output mean a failed or killed step leaves nothing that looks done, so a
 * rerun (the retry) redoes exactly the missing and the out-of-date. */
static void makefile(text *t, const rk_plan *p, const char *romkit)
{
    put(t, "# romkit plan: %s, rom entry %d (%s). make -j2 runs it; a rerun redoes only what is missing\n"
           "# or older than its inputs. The same steps as plan.json; the asset is %s.\n",
        p->scene, p->entry, p->entry_name, p->steps[p->nsteps - 1].output);
    put(t, "ROMKIT ?= %s\n# every step at one thread count: the asset's bits follow it (romkit build at the same)\n"
           "export ROMKIT_THREADS := %d\n.DELETE_ON_ERROR:\n.PHONY: all\nall: %s\n",
        romkit, p->threads, p->steps[p->nsteps - 1].output);
    for (int k = 0; k < p->nsteps; k++) {
        const rk_plan_step *s = &p->steps[k];
        put(t, "\n# %s\n%s:", s->id, s->output);
        for (int i = 0; i < s->ninputs; i++) put(t, " %s", s->inputs[i]);
        put(t, "\n\t");
        command(t, s, "$(ROMKIT)");
        put(t, "\n");
    }
}

static const char *kind_name(rk_step_kind k)
{
    return k == RK_STEP_TRAIN ? "train" : k == RK_STEP_BASIS ? "basis" : k == RK_STEP_CUBATURE ? "cubature" : "bake";
}

static void sbatch_head(text *t, const rk_plan *p, const char *dir, const char *romkit, const char *name, int array)
{
    put(t, "#!/bin/sh\n# romkit plan: step %s of %s, rom entry %d (submit.sh submits it)\n", name, p->scene, p->entry);
    put(t, "#SBATCH --job-name=romkit-%s\n#SBATCH --chdir=%s\n#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=%d\n", name,
        dir, p->threads);
    if (array) put(t, "#SBATCH --array=0-%d\n#SBATCH --output=%s/logs/%s-%%A_%%a.out\n", p->ntrain - 1, dir, name);
    else put(t, "#SBATCH --output=%s/logs/%s-%%j.out\n", dir, name);
    put(t, "set -u\nROMKIT=\"${ROMKIT:-%s}\"\nexport ROMKIT_THREADS=%d\ncd %s || exit 1\n", romkit, p->threads, dir);
}

/* The step's command, skipped when make says its output is up to date (a resubmission resumes). */
static void sbatch_step(text *t, const rk_plan_step *s, const char *indent)
{
    put(t, "%sif command -v make >/dev/null 2>&1 && make -q %s 2>/dev/null; then echo \"%s: %s is up to date\"; exit 0; fi\n",
        indent, s->output, s->id, s->output);
    put(t, "%secho \"%s: ", indent, s->id);
    command(t, s, "romkit");
    put(t, "\"\n%s", indent);
    command(t, s, "\"$ROMKIT\"");
    put(t, "\n%src=$?; echo \"%s: exit $rc\"; exit $rc\n", indent, s->id);
}

static void submit(text *t, const rk_plan *p)
{
    put(t, "#!/bin/sh\n# romkit plan: submits the bake of %s, rom entry %d, to Slurm: the training runs as one job\n"
           "# array, then each step with --dependency=afterok on the jobs it needs. Prints the job ids.\n"
           "set -eu\ncd \"$(dirname \"$0\")\"\nmkdir -p logs\nid() { echo \"${1%%%%;*}\"; }\n",
        p->scene, p->entry);
    if (p->ntrain) put(t, "train=$(id \"$(sbatch --parsable slurm/train.sbatch)\")\necho \"train $train (array 0-%d)\"\n",
                       p->ntrain - 1);
    for (int k = p->ntrain; k < p->nsteps; k++) {
        const rk_plan_step *s = &p->steps[k];
        const char *name = kind_name(s->kind);
        char dep[512] = "";
        int train = 0;
        for (int i = 0; i < s->nafter; i++) /* the array's one id covers every task */
            if (s->after[i] < p->ntrain && !train++) strcat(dep, ":$train");
        for (int i = 0; i < s->nafter; i++)
            if (s->after[i] >= p->ntrain) {
                strcat(dep, ":$");
                strcat(dep, kind_name(p->steps[s->after[i]].kind));
            }
        if (dep[0]) put(t, "%s=$(id \"$(sbatch --parsable --dependency=afterok%s slurm/%s.sbatch)\")\n", name, dep, name);
        else put(t, "%s=$(id \"$(sbatch --parsable slurm/%s.sbatch)\")\n", name, name);
        put(t, "echo \"%s $%s%s%s\"\n", name, name, dep[0] ? " afterok" : "", dep);
    }
}

typedef struct {
    char path[4200];
    text t;
    int mode;
} file_out;

/* Whether path holds exactly these bytes already (then it is left alone: its time stays, and make
 * redoes nothing for a plan made again unchanged). */
static int unchanged(const char *path, const text *t)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return 0;
    int same = 1;
    size_t i = 0;
    for (int c; same && (c = fgetc(fp)) != EOF; i++) same = i < t->n && (unsigned char)t->s[i] == (unsigned char)c;
    fclose(fp);
    return same && i == t->n;
}

static int write_all(file_out *f, int n, rk_error *err)
{
    for (int i = 0; i < n; i++) {
        rk_atomic_file a;
        if (f[i].t.failed) return rk_fail(err, "%s: out of memory", f[i].path);
        if (unchanged(f[i].path, &f[i].t)) continue;
        if (rk_atomic_open(&a, f[i].path, err)) goto undo;
        fwrite(f[i].t.s, 1, f[i].t.n, a.fp);
        if (rk_atomic_commit(&a, err)) goto undo;
        if (chmod(f[i].path, (mode_t)f[i].mode) != 0) {
            rk_fail(err, "%s: chmod: %s", f[i].path, strerror(errno));
            i++;
            goto undo;
        }
        continue;
    undo:
        while (i-- > 0) unlink(f[i].path);
        return -1;
    }
    return 0;
}

int rk_plan_write(const rk_plan *p, const char *dir, const char *romkit, int slurm, rk_error *err)
{
    file_out f[8];
    int n = 0, rc = -1;
    memset(f, 0, sizeof f);
    cJSON *j = plan_json(p, dir, romkit);
    char *json = cJSON_Print(j);
    cJSON_Delete(j);
    snprintf(f[n].path, sizeof f[n].path, "%s/plan.json", dir);
    f[n].mode = 0644;
    if (json) put(&f[n].t, "%s\n", json);
    else f[n].t.failed = 1;
    free(json);
    n++;
    snprintf(f[n].path, sizeof f[n].path, "%s/Makefile", dir);
    f[n].mode = 0644;
    makefile(&f[n++].t, p, romkit);
    char sdir[4200];
    snprintf(sdir, sizeof sdir, "%s/slurm", dir);
    int made_sdir = 0;
    if (slurm) {
        if (p->ntrain) {
            snprintf(f[n].path, sizeof f[n].path, "%s/train.sbatch", sdir);
            f[n].mode = 0755;
            text *t = &f[n++].t;
            sbatch_head(t, p, dir, romkit, "train", 1);
            put(t, "case \"${SLURM_ARRAY_TASK_ID:-}\" in\n");
            for (int k = 0; k < p->ntrain; k++) {
                put(t, "%d)\n", k);
                sbatch_step(t, &p->steps[k], "    ");
                put(t, "    ;;\n");
            }
            put(t, "*) echo \"no training run '${SLURM_ARRAY_TASK_ID:-}' (0-%d)\" >&2; exit 2 ;;\nesac\n", p->ntrain - 1);
        }
        for (int k = p->ntrain; k < p->nsteps; k++) {
            const char *name = kind_name(p->steps[k].kind);
            snprintf(f[n].path, sizeof f[n].path, "%s/%s.sbatch", sdir, name);
            f[n].mode = 0755;
            sbatch_head(&f[n].t, p, dir, romkit, name, 0);
            sbatch_step(&f[n++].t, &p->steps[k], "");
        }
        snprintf(f[n].path, sizeof f[n].path, "%s/submit.sh", dir);
        f[n].mode = 0755;
        submit(&f[n++].t, p);
        if (mkdir(sdir, 0755) == 0) made_sdir = 1;
        else if (errno != EEXIST) {
            rk_fail(err, "%s: cannot create: %s", sdir, strerror(errno));
            goto out;
        }
    }
    rc = write_all(f, n, err);
    if (rc && made_sdir) rmdir(sdir);
out:
    for (int i = 0; i < n; i++) free(f[i].t.s);
    return rc;
}
