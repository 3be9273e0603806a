/* Method adaptive_subspace as a module (method.h): its keys, its run beside full order
 * (adaptive_compare.c), no bake (it simulates in the precompute), its report rows. */
#include "pipeline/method_adaptive_subspace.h"

#include <math.h>
#include <string.h>

#include "pipeline/parse_impl.h"

_Static_assert(sizeof(rk_adaptive_subspace_entry) <= RK_METHOD_OWN_BYTES, "options fit the entry's block");
_Static_assert(sizeof(rk_adaptive_subspace_measures) <= RK_COMPARE_OWN_BYTES, "measures fit the result's block");

int rk_adaptive_subspace_compare(rk_compare_ctx *c, const rk_rom_entry *e, rk_compare_method *m, rk_error *err);

/* The adaptive subspace method's keys (adaptive.h; the paper's Table 2 names them). */
static int parse(const rk_json_ctx *c, const cJSON *e, const char *path, double h, rk_rom_entry *o)
{
    rk_adaptive_subspace_entry *own = (rk_adaptive_subspace_entry *)o->own;
    rk_adaptive_options *a = &own->opt;
    rk_adaptive_default_options(a);
    own->initial_size = 0;
    if (cJSON_HasObjectItem(e, "cubature") || cJSON_HasObjectItem(e, "koopman") ||
        cJSON_HasObjectItem(e, "mesh_free") || cJSON_HasObjectItem(e, "tolerance"))
        return rk_json_fail(c, path, "method adaptive_subspace takes a candidate basis by size, with no cubature, "
                            "koopman, mesh_free or tolerance (it integrates every element)");
    const char *hessian = NULL, *units = NULL;
    if (rk_json_number(c, e, path, "eps_g_modal", 0, &a->eps_g_modal) ||
        rk_json_number(c, e, path, "eps_g_nodal", 0, &a->eps_g_nodal) ||
        rk_json_number(c, e, path, "eps_e", 0, &a->eps_e) || rk_json_number(c, e, path, "eps_d", 0, &a->eps_d) ||
        rk_json_whole(c, e, path, "subdomains", 0, 1e7, &a->subdomains) ||
        rk_json_whole(c, e, path, "initial_size", 0, 1e6, &own->initial_size) ||
        rk_json_bool(c, e, path, "downdate", &a->downdate) || rk_json_bool(c, e, path, "modal", &a->modal) ||
        rk_json_bool(c, e, path, "nodal", &a->nodal) || rk_json_number(c, e, path, "pcg_tol", 0, &a->pcg_tol) ||
        rk_json_string(c, e, path, "hessian", 0, &hessian) || rk_json_bool(c, e, path, "residual", &a->residual) ||
        rk_json_whole(c, e, path, "residual_rounds", 0, 1e6, &a->residual_rounds) ||
        rk_json_number(c, e, path, "accuracy", 0, &a->accuracy) ||
        rk_json_number(c, e, path, "full_fraction", 0, &a->full_fraction) ||
        rk_json_string(c, e, path, "eps_g_units", 0, &units))
        return -1;
    if (units && strcmp(units, "tolerance") && strcmp(units, "paper"))
        return rk_json_fail(c, path, "eps_g_units must be \"tolerance\" (its own tolerance's, from accuracy) or \"paper\" (the "
                            "paper's dimensionless G), got \"%s\"", units);
    a->paper_units = units && !strcmp(units, "paper");
    if (a->paper_units) { /* the paper's defaults for what the entry leaves out (its Sec. 4, Table 2) */
        if (!cJSON_HasObjectItem(e, "eps_g_nodal")) a->eps_g_nodal = 0.5;
        if (!cJSON_HasObjectItem(e, "eps_g_modal")) a->eps_g_modal = 0.5;
        if (!cJSON_HasObjectItem(e, "eps_e")) a->eps_e = 1e-4;
    }
    static const char *const positive[4] = {"eps_g_modal", "eps_g_nodal", "eps_d", "pcg_tol"};
    double values[4] = {a->eps_g_modal, a->eps_g_nodal, a->eps_d, a->pcg_tol};
    for (int k = 0; k < 4; k++)
        if (!(values[k] > 0) || !isfinite(values[k]))
            return rk_json_fail(c, path, "%s must be a positive number, got %g", positive[k], values[k]);
    if (!(a->full_fraction > 0 && a->full_fraction <= 1))
        return rk_json_fail(c, path, "full_fraction (the enriched share at which full order finishes a step) must be in "
                            "(0, 1], got %g", a->full_fraction);
    if (a->pcg_tol >= 1) return rk_json_fail(c, path, "pcg_tol must be below 1, got %g", a->pcg_tol);
    if (!isfinite(a->eps_e)) return rk_json_fail(c, path, "eps_e must be finite, got %g", a->eps_e);
    if (hessian && strcmp(hessian, "bfgs") && strcmp(hessian, "exact"))
        return rk_json_fail(c, path, "hessian must be \"bfgs\" or \"exact\", got \"%s\"", hessian);
    a->exact_hessian = hessian && !strcmp(hessian, "exact");
    if (o->basis.size == 0) return rk_json_fail(c, path, "method adaptive_subspace needs size (the candidate basis)");
    return 0;
}


static void default_name(const rk_rom_entry *e, char *name, size_t size)
{
    snprintf(name, size, "adaptive_subspace-%d", e->basis.size);
}

static int bake(const rk_scene *scene, const rk_rom_entry *e, const rk_bake_request *req, const rk_asset_options *ao,
                rk_baked *out, rk_error *err)
{
    return rk_fail(err, "%s: method adaptive_subspace simulates in the precompute (full-order quality, every "
                   "element); it has no runtime asset to bake: romkit compare runs it", e->path);
}

static void report(const rk_compare_method *m, cJSON *j)
{
    const rk_adaptive_subspace_measures *am = (const void *)m->own;
    cJSON *a = cJSON_AddObjectToObject(j, "adaptive");
    cJSON_AddNumberToObject(a, "mean_modes", am->mean_modes);
    cJSON_AddNumberToObject(a, "max_modes", am->max_modes);
    cJSON_AddNumberToObject(a, "mean_enriched_vertices", am->mean_nodes);
    cJSON_AddNumberToObject(a, "max_enriched_vertices", am->max_nodes);
    cJSON_AddNumberToObject(a, "enriched_share", am->enriched_share);
    cJSON_AddNumberToObject(a, "subdomains", am->subdomains);
    cJSON_AddNumberToObject(a, "pcg_iterations_per_solve", am->pcg_per_solve);
    cJSON_AddNumberToObject(a, "newton_iterations_per_step", am->newton_per_step);
    cJSON_AddNumberToObject(a, "steps_full", am->steps_full);
    cJSON *sh = cJSON_AddObjectToObject(a, "shares");
    cJSON_AddNumberToObject(sh, "potential", am->share_potential);
    cJSON_AddNumberToObject(sh, "oracle", am->share_oracle);
    cJSON_AddNumberToObject(sh, "subspace_hessian", am->share_hessian);
    cJSON_AddNumberToObject(sh, "enriched_rows", am->share_system);
    cJSON_AddNumberToObject(sh, "pcg", am->share_pcg);
    cJSON_AddNumberToObject(sh, "line_search", am->share_line_search);
    rk_adaptive_residual_report(a, am);
}

static void print(const rk_compare_method *m, FILE *f)
{
    const rk_adaptive_subspace_measures *am = (const void *)m->own;
    fprintf(f, "  %s: %.1f modes (max %d), %.1f enriched vertices (%.1f%%, max %d) of %d subdomains; %d steps by "
            "full order; %.1f Newton iterations a step, %.1f PCG iterations a solve; time: potential %.0f%%, oracle %.0f%%, subspace "
            "Hessian %.0f%%, enriched rows %.0f%%, PCG %.0f%%, line search %.0f%%\n",
            m->name, am->mean_modes, am->max_modes, am->mean_nodes, 100 * am->enriched_share, am->max_nodes, am->subdomains,
            am->steps_full,
            am->newton_per_step, am->pcg_per_solve, 100 * am->share_potential, 100 * am->share_oracle,
            100 * am->share_hessian, 100 * am->share_system, 100 * am->share_pcg, 100 * am->share_line_search);
    if (am->residual)
        fprintf(f, "  %s: full-space residual |d|_inf/h: mean %.3g, max %.3g m/s (its tolerance %.3g), %d steps "
                "over it; %d enrichment rounds for it (%d vertices)\n",
                m->name, am->residual_mean, am->residual_max, am->residual_tolerance, am->residual_over,
                am->residual_rounds, am->residual_nodes_added);
}

static const char *const keys[] = {"eps_g_modal", "eps_g_nodal", "eps_e", "eps_d", "subdomains", "initial_size",
                                   "downdate", "modal", "nodal", "hessian", "pcg_tol", "eps_g_units", "residual",
                                   "residual_rounds", "accuracy", "full_fraction", NULL};

const rk_method rk_method_adaptive_subspace = {
    .name = "adaptive_subspace",
    .kind = "adaptive_subspace",
    .keys = keys,
    .measures_contact = 1,
    .parse = parse,
    .default_name = default_name,
    .compare = rk_adaptive_subspace_compare,
    .bake = bake,
    .report = report,
    .print = print,
};

const rk_adaptive_subspace_entry *rk_adaptive_subspace_of(const rk_rom_entry *e)
{
    return rk_method_options(e, &rk_method_adaptive_subspace);
}
