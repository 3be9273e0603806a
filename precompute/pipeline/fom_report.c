/* A built scene's full-order run measured and reported (fom_report.h): what romkit fom writes. */
#include "pipeline/fom_report.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/util.h"

static rk_iteration_stat stat_of(const double *v, long n)
{
    rk_iteration_stat st = {0, 0, 0};
    double *t = n > 0 ? malloc(sizeof(double) * (size_t)n) : NULL;
    if (!t) return st;
    memcpy(t, v, sizeof(double) * (size_t)n);
    st.median = rk_median(t, (int)n); /* sorts t */
    st.min = t[0];
    st.max = t[n - 1];
    free(t);
    return st;
}

typedef struct {
    const rk_scene_sim *sim;
    rk_fom_measure *m;
    rk_frame_fn frame;
    void *ctx;
} measure_ctx;

static int on_frame(void *ctx, int step, rk_fom *fom, double seconds, rk_error *err)
{
    measure_ctx *c = ctx;
    rk_fom_measure *m = c->m;
    const rk_scene_sim *sim = c->sim;
    int nv = sim->mesh.nv;
    memcpy(m->x, fom->x, sizeof(double) * 3 * (size_t)nv);
    double min_J, closest;
    int inverted = rk_fem_inverted(&sim->fem, fom->x, &min_J), crossings;
    if (inverted > m->max_inverted) m->max_inverted = inverted;
    if (m->contact) {
        if (rk_fom_contact_measure(fom, &crossings, &closest, err)) return -1;
        rk_contact_tally_add(&m->tally, crossings, closest);
    }
    if (step == m->steps) {
        const double *it, *fa;
        long n = rk_fom_iterations(fom, &it, &fa);
        m->iteration = stat_of(it, n);
        m->factorization = stat_of(fa, n);
        double max_disp = 0;
        for (int v = 0; v < nv; v++) {
            double d2 = 0;
            for (int i = 0; i < 3; i++) d2 += pow(fom->x[3 * v + i] - sim->mesh.X[3 * v + i], 2);
            max_disp = fmax(max_disp, sqrt(d2));
        }
        m->time = fom->t;
        m->inverted = inverted;
        m->min_det_F = min_J;
        m->max_displacement = max_disp;
        m->kinetic_energy = rk_fom_kinetic_energy(fom);
        m->elastic_energy = rk_fem_energy(&sim->fem, fom->x);
        if (m->contact && rk_fom_contact_stats(fom)) m->contact_stats = *rk_fom_contact_stats(fom);
    }
    return c->frame ? c->frame(c->ctx, step, fom, seconds, err) : 0;
}

int rk_scene_fom_measure(const rk_scene_sim *sim, rk_frame_fn frame, void *ctx, rk_fom_measure *out, rk_error *err)
{
    memset(out, 0, sizeof *out);
    rk_contact_tally_init(&out->tally);
    out->contact = sim->options.nobstacles > 0 || sim->options.nobjects > 1 || sim->options.contact.self;
    out->steps = sim->options.is_static ? 1 : sim->steps;
    if (!(out->x = rk_calloc(3 * (size_t)sim->mesh.nv, sizeof(double), err))) return -1;
    measure_ctx c = {sim, out, frame, ctx};
    if (rk_scene_fom_run(sim, NULL, "full-order run", on_frame, &c, &out->stats, err)) {
        rk_fom_measure_free(out);
        return -1;
    }
    return 0;
}

void rk_fom_measure_free(rk_fom_measure *m)
{
    free(m->x);
    m->x = NULL;
}

/* seconds.X and shares.X (of seconds.simulate) */
static void add_part(cJSON *sec, cJSON *shares, const char *name, double seconds, double simulate)
{
    cJSON_AddNumberToObject(sec, name, seconds);
    cJSON_AddNumberToObject(shares, name, simulate > 0 ? seconds / simulate : 0);
}

/* The report's "contact" object: what the run came to and what contact cost. */
static void add_contact(cJSON *r, const rk_fom_measure *m)
{
    const rk_contact_stats *cs = &m->contact_stats;
    cJSON *c = cJSON_AddObjectToObject(r, "contact");
    rk_contact_tally_report(c, &m->tally);
    cJSON_AddNumberToObject(c, "mean_pairs", cs->gathers ? (double)cs->pairs / cs->gathers : 0);
    cJSON_AddNumberToObject(c, "max_pairs", (double)cs->max_pairs);
    cJSON_AddNumberToObject(c, "ccd_calls", (double)cs->ccd_calls);
    cJSON *sec = cJSON_AddObjectToObject(c, "seconds");
    cJSON_AddNumberToObject(sec, "broad_phase", cs->seconds_broad);
    cJSON_AddNumberToObject(sec, "ccd", cs->seconds_ccd);
    cJSON_AddNumberToObject(sec, "barrier", cs->seconds_potential);
}

cJSON *rk_fom_report(const rk_scene_sim *sim, const rk_fom_measure *m, double seconds_total)
{
    const rk_fom_stats *st = &m->stats;
    int steps = m->steps;
    cJSON *r = cJSON_CreateObject();
    cJSON_AddNumberToObject(r, "vertices", sim->mesh.nv);
    cJSON_AddNumberToObject(r, "tets", sim->mesh.nt);
    cJSON_AddNumberToObject(r, "steps", steps);
    cJSON_AddNumberToObject(r, "h", sim->options.h);
    cJSON_AddStringToObject(r, "integrator", sim->options.is_static ? "static"
                                             : sim->options.integrator == RK_BDF2 ? "bdf2"
                                                                                   : "backward_euler");
    cJSON_AddNumberToObject(r, "seconds_per_step", steps > 0 ? st->seconds_total / steps : st->seconds_total);
    cJSON_AddNumberToObject(r, "newton_iterations", (double)st->newton_iterations);
    cJSON_AddNumberToObject(r, "unconverged_steps", (double)st->unconverged_steps);
    /* Where the simulation's time went: disjoint parts of seconds.simulate, each with its share
     * (shares.*): CHOLMOD's analyses in steps (contact changing the pattern), numeric
     * factorizations and solves; the Newton iterations' potential with gradient and Newton matrix
     * (assembly; the elastic Hessians with their PSD projection are seconds.hessian, a part of
     * it), the line search's potential values, the contact stage; other: the rest (predictor,
     * prescribed motion, checks). seconds.analysis_init: the analysis before the first step. */
    double sim_s = st->seconds_total;
    double other = sim_s - st->seconds_analyze - st->seconds_factor - st->seconds_solve - st->seconds_assemble -
                   st->seconds_line_search - st->seconds_contact;
    cJSON *sec = cJSON_AddObjectToObject(r, "seconds");
    cJSON *shares = cJSON_CreateObject();
    cJSON_AddNumberToObject(sec, "total", seconds_total);
    cJSON_AddNumberToObject(sec, "simulate", sim_s);
    cJSON_AddNumberToObject(sec, "analysis_init", st->seconds_analyze_init);
    add_part(sec, shares, "analysis", st->seconds_analyze, sim_s);
    add_part(sec, shares, "factorization", st->seconds_factor, sim_s);
    add_part(sec, shares, "solve", st->seconds_solve, sim_s);
    add_part(sec, shares, "assembly", st->seconds_assemble, sim_s);
    add_part(sec, shares, "hessian", st->seconds_hessian, sim_s);
    add_part(sec, shares, "line_search", st->seconds_line_search, sim_s);
    add_part(sec, shares, "contact", st->seconds_contact, sim_s);
    add_part(sec, shares, "other", other > 0 ? other : 0, sim_s);
    cJSON_AddItemToObject(r, "shares", shares);
    cJSON_AddNumberToObject(r, "factorization_share", sim_s > 0 ? st->seconds_factor / sim_s : 0);
    /* Per Newton iteration (median over the run's iterations, with the fastest and slowest):
     * its seconds (potential, factorization, solve, line search) against its numeric
     * factorization's alone. */
    const rk_iteration_stat *it = &m->iteration, *fa = &m->factorization;
    cJSON *nw = cJSON_AddObjectToObject(r, "newton");
    cJSON_AddNumberToObject(nw, "iterations", (double)st->newton_iterations);
    cJSON_AddNumberToObject(nw, "line_search_halvings", (double)st->line_search_halvings);
    cJSON_AddNumberToObject(nw, "analyses", (double)st->analyses);
    cJSON_AddNumberToObject(nw, "projected_hessians", (double)st->projected_hessians);
    cJSON_AddNumberToObject(nw, "seconds_per_iteration", it->median);
    cJSON_AddNumberToObject(nw, "seconds_per_iteration_min", it->min);
    cJSON_AddNumberToObject(nw, "seconds_per_iteration_max", it->max);
    cJSON_AddNumberToObject(nw, "factorization_seconds", fa->median);
    cJSON_AddNumberToObject(nw, "factorization_seconds_min", fa->min);
    cJSON_AddNumberToObject(nw, "factorization_seconds_max", fa->max);
    cJSON_AddNumberToObject(nw, "iteration_per_factorization", fa->median > 0 ? it->median / fa->median : 0);
    cJSON_AddNumberToObject(r, "threads", rk_threads());
    cJSON *mesh = cJSON_AddObjectToObject(r, "mesh");
    cJSON_AddNumberToObject(mesh, "components", sim->mesh_report.components);
    cJSON_AddNumberToObject(mesh, "reoriented", sim->mesh_report.reoriented);
    cJSON_AddNumberToObject(mesh, "min_quality", sim->mesh_report.min_quality);
    /* Slivers simulated (kept: thicker than rounding) and flat tets dropped, with the vertices only
     * they used (each named in a warning on stderr when the scene was built). */
    cJSON_AddNumberToObject(mesh, "slivers", sim->mesh_report.slivers);
    cJSON_AddNumberToObject(mesh, "flat_dropped", sim->mesh_report.flat_dropped);
    cJSON_AddNumberToObject(mesh, "flat_inside", sim->mesh_report.ghosts); /* kept as ghosts (mesh.h) */
    cJSON_AddNumberToObject(mesh, "orphans_removed", sim->mesh_report.orphans_removed);
    cJSON *fin = cJSON_AddObjectToObject(r, "final");
    cJSON_AddNumberToObject(fin, "time", m->time);
    cJSON_AddNumberToObject(fin, "inverted_elements", m->inverted);
    cJSON_AddNumberToObject(fin, "min_det_F", m->min_det_F);
    cJSON_AddNumberToObject(fin, "max_displacement", m->max_displacement);
    cJSON_AddNumberToObject(fin, "kinetic_energy", m->kinetic_energy);
    cJSON_AddNumberToObject(fin, "elastic_energy", m->elastic_energy);
    cJSON_AddNumberToObject(r, "max_inverted_elements", m->max_inverted);
    if (m->contact) add_contact(r, m);
    if (sim->body_points) { /* point clouds run on their bodies (rk_scene_build_full_order) */
        cJSON *b = cJSON_AddObjectToObject(r, "cloud_body");
        cJSON_AddNumberToObject(b, "points", sim->body_points);
        cJSON_AddNumberToObject(b, "points_outside", sim->body_outside);
        cJSON_AddNumberToObject(b, "worst_distance", sim->body_worst_distance);
        cJSON_AddNumberToObject(b, "surface_outside", sim->body_surface_outside);
        cJSON_AddNumberToObject(b, "backed_off", sim->body_backed_off);
        cJSON_AddNumberToObject(b, "min_volume_ratio", sim->body_min_volume_ratio);
        cJSON_AddNumberToObject(b, "mass_scale", sim->body_mass_scale);
        cJSON_AddNumberToObject(b, "volume", sim->body_volume);
        cJSON_AddNumberToObject(b, "mass", sim->body_mass);
        cJSON_AddNumberToObject(b, "scene_vertices", sim->layout.nv);
    }
    return r;
}

void rk_unconverged_warn(FILE *f, const char *who, long unconverged, long steps)
{
    if (unconverged <= 0) return;
    fprintf(f, "warning: %s: %ld of %ld steps stopped short of the Newton tolerance (at the iteration limit, or "
            "where the line search found no decrease): their answer is not converged (unconverged_steps in the "
            "report; newton.max_iterations raises the limit)\n", who, unconverged, steps);
}
