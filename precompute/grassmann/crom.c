/* The CROM decoder (grassmann.h; the paper's Sec. 3.2, Eq. 4 and 7, after Chen et al. 2022): an
 * encoder e(u) from a displacement field (3 nv values) to r latent coordinates and a decoder g(p,
 * X) from the latent code and a rest position to that point's displacement, trained jointly on
 * full-order snapshots, each minibatch a few snapshots at random subsets of their vertices (CROM's
 * discretization-agnostic training). Inputs are normalised: displacements by one scale (the data's
 * largest |u| component), positions to the unit box around the mesh's centre. The online basis is
 * the decoder's Jacobian in p at every vertex (forward mode, rk_mlp_jacobian). */
#include "grassmann/grassmann.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "neural/neural.h"

struct rk_crom {
    int nv, n, r;
    rk_mlp enc, dec;
    double u_scale;            /* displacements are divided by it going in, multiplied coming out */
    double *Xn;                /* 3 nv: the rest positions, normalised */
    rk_mlp_work we, wd;        /* online: the encoder on one field, the decoder on every vertex */
    double *in, *J, *p;        /* nv (r + 3), nv 3 r, r */
};

static void destroy(void *ctx)
{
    rk_crom *c = ctx;
    if (!c) return;
    rk_mlp_free(&c->enc);
    rk_mlp_free(&c->dec);
    rk_mlp_work_free(&c->we);
    rk_mlp_work_free(&c->wd);
    free(c->Xn);
    free(c->in);
    free(c->J);
    free(c->p);
    free(c);
}

/* The decoder's inputs at every vertex for latent code p: rows [p, Xn_v]. */
static void decoder_inputs(const rk_crom *c, const double *p, double *in)
{
    int w = c->r + 3;
    for (int v = 0; v < c->nv; v++) {
        memcpy(in + (size_t)v * w, p, sizeof(double) * (size_t)c->r);
        memcpy(in + (size_t)v * w + c->r, c->Xn + 3 * (size_t)v, 3 * sizeof(double));
    }
}

static int encode(void *ctx, const double *u, double *p, rk_error *err)
{
    rk_crom *c = ctx;
    for (int i = 0; i < c->n; i++) c->in[i] = u[i] / c->u_scale;
    return rk_mlp_forward(&c->enc, &c->we, 1, c->in, p, err);
}

static int decode(void *ctx, const double *p, double *u, rk_error *err)
{
    rk_crom *c = ctx;
    decoder_inputs(c, p, c->in);
    if (rk_mlp_forward(&c->dec, &c->wd, c->nv, c->in, u, err)) return -1;
    for (int i = 0; i < c->n; i++) u[i] *= c->u_scale;
    return 0;
}

static int jacobian(void *ctx, const double *p, double *U, rk_error *err)
{
    rk_crom *c = ctx;
    int r = c->r;
    decoder_inputs(c, p, c->in);
    if (rk_mlp_jacobian(&c->dec, &c->wd, c->nv, c->in, 0, r, NULL, c->J, err)) return -1;
    for (int v = 0; v < c->nv; v++) /* J: vertex v's 3 x r row-major; U: n x r column-major */
        for (int a = 0; a < 3; a++)
            for (int j = 0; j < r; j++) U[(size_t)j * c->n + 3 * v + a] = c->u_scale * c->J[((size_t)v * 3 + a) * r + j];
    return 0;
}

void rk_crom_default_options(rk_crom_options *o)
{
    *o = (rk_crom_options){.encoder_width = 128, .encoder_layers = 2, .decoder_width = 64, .decoder_layers = 4,
                           .epochs = 200, .snapshots_per_batch = 8, .points = 256, .base_lr = 1e-4, .seed = 1};
}

/* Network sizes: in -> width x layers -> out. */
static int make_mlp(rk_mlp *m, int in, int width, int layers, int out, unsigned long long seed, rk_error *err)
{
    int sizes[66];
    if (layers < 1 || layers > 64 || width < 1) return rk_fail(err, "a network needs 1 to 64 hidden layers of >= 1 units");
    sizes[0] = in;
    for (int l = 1; l <= layers; l++) sizes[l] = width;
    sizes[layers + 1] = out;
    return rk_mlp_init(m, layers + 2, sizes, seed, err);
}

int rk_crom_train(const double *D, int T, const double *X, int nv, int r, const rk_crom_options *o, rk_decoder *out,
                  rk_crom_report *report, rk_error *err)
{
    memset(out, 0, sizeof *out);
    int n = 3 * nv;
    if (r < 1) return rk_fail(err, "CROM needs r >= 1 latent coordinates, got %d", r);
    if (T < r) return rk_fail(err, "CROM: %d snapshots cannot train %d latent coordinates (need at least r)", T, r);
    if (o->epochs < 1 || o->snapshots_per_batch < 1 || o->points < 1 || !(o->base_lr > 0))
        return rk_fail(err, "CROM: epochs, snapshots_per_batch and points must be >= 1 and base_lr > 0");
    double scale = 0;
    for (size_t k = 0; k < (size_t)n * T; k++) {
        if (!isfinite(D[k]))
            return rk_fail(err, "CROM: snapshot %zu, vertex %zu, component %zu is not finite", k / n, (k % n) / 3, k % 3);
        scale = fmax(scale, fabs(D[k]));
    }
    if (!(scale > 0)) return rk_fail(err, "CROM: every snapshot is the rest shape: nothing to train on");
    double t0 = rk_now();
    rk_crom *c = rk_calloc(1, sizeof *c, err);
    if (!c) return -1;
    c->nv = nv;
    c->n = n;
    c->r = r;
    c->u_scale = scale;
    int S = o->snapshots_per_batch < T ? o->snapshots_per_batch : T, P = o->points < nv ? o->points : nv, rc = -1;
    int w = r + 3;
    double *Ein = NULL, *Eout = NULL, *Din = NULL, *Dout = NULL, *dY = NULL, *dX = NULL, *dP = NULL;
    double *genc = NULL, *gdec = NULL;
    int *order = NULL, *pts = NULL;
    rk_adam ae = {0}, ad = {0};
    rk_mlp_work te = {0}, td = {0};
    if (make_mlp(&c->enc, n, o->encoder_width, o->encoder_layers, r, o->seed, err) ||
        make_mlp(&c->dec, w, o->decoder_width, o->decoder_layers, 3, o->seed + 1, err))
        goto out;
    c->Xn = malloc(sizeof(double) * (size_t)n);
    c->in = malloc(sizeof(double) * ((size_t)nv * w > (size_t)n ? (size_t)nv * w : (size_t)n));
    c->J = malloc(sizeof(double) * (size_t)nv * 3 * r);
    c->p = malloc(sizeof(double) * (size_t)r);
    Ein = malloc(sizeof(double) * (size_t)S * n);
    Eout = malloc(sizeof(double) * (size_t)S * r);
    Din = malloc(sizeof(double) * (size_t)S * P * w);
    Dout = malloc(sizeof(double) * (size_t)S * P * 3);
    dY = malloc(sizeof(double) * (size_t)S * P * 3);
    dX = malloc(sizeof(double) * (size_t)S * P * w);
    dP = malloc(sizeof(double) * (size_t)S * r);
    genc = malloc(sizeof(double) * (size_t)rk_mlp_params(&c->enc));
    gdec = malloc(sizeof(double) * (size_t)rk_mlp_params(&c->dec));
    order = malloc(sizeof(int) * (size_t)T);
    pts = malloc(sizeof(int) * (size_t)nv);
    if (!c->Xn || !c->in || !c->J || !c->p || !Ein || !Eout || !Din || !Dout || !dY || !dX || !dP || !genc || !gdec ||
        !order || !pts) {
        rk_fail(err, "out of memory for CROM training (%d snapshots of %d vertices)", T, nv);
        goto out;
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, ext = 0;
    for (int v = 0; v < nv; v++)
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], X[3 * v + a]);
            hi[a] = fmax(hi[a], X[3 * v + a]);
        }
    for (int a = 0; a < 3; a++) ext = fmax(ext, hi[a] - lo[a]);
    for (int v = 0; v < nv; v++)
        for (int a = 0; a < 3; a++) c->Xn[3 * v + a] = 2 * (X[3 * v + a] - 0.5 * (lo[a] + hi[a])) / ext;
    if (rk_adam_init(&ae, rk_mlp_params(&c->enc), err) || rk_adam_init(&ad, rk_mlp_params(&c->dec), err) ||
        rk_mlp_work_init(&te, &c->enc, S, 0, err) || rk_mlp_work_init(&td, &c->dec, S * P, 0, err) ||
        rk_mlp_work_init(&c->we, &c->enc, 1, 0, err) || rk_mlp_work_init(&c->wd, &c->dec, nv, r, err))
        goto out;
    int blas = rk_threads_blas(1); /* the same weights on any thread count */
    uint64_t state = o->seed * 0x9E3779B97F4A7C15ull + 7;
    for (int i = 0; i < T; i++) order[i] = i;
    for (int v = 0; v < nv; v++) pts[v] = v;
    double loss = 0;
    long steps = 0;
    for (int epoch = 0; epoch < o->epochs && rc == -1; epoch++) {
        double lr = rk_lr_phased(o->base_lr, epoch, o->epochs), sum = 0;
        long count = 0;
        for (int i = T - 1; i > 0; i--) { /* Fisher-Yates: the snapshots' order this epoch */
            int j = (int)(rk_splitmix64(&state) % (uint64_t)(i + 1)), t = order[i];
            order[i] = order[j];
            order[j] = t;
        }
        for (int first = 0; first < T; first += S) {
            int s_n = T - first < S ? T - first : S;
            for (int s = 0; s < s_n; s++) {
                const double *u = D + (size_t)order[first + s] * n;
                for (int i = 0; i < n; i++) Ein[(size_t)s * n + i] = u[i] / scale;
            }
            if (rk_mlp_forward(&c->enc, &te, s_n, Ein, Eout, err)) goto stop;
            for (int s = 0; s < s_n; s++) {
                for (int k = 0; k < P; k++) { /* a random subset of the vertices (partial Fisher-Yates) */
                    int j = k + (int)(rk_splitmix64(&state) % (uint64_t)(nv - k)), t = pts[k];
                    pts[k] = pts[j];
                    pts[j] = t;
                    double *row = Din + ((size_t)s * P + k) * w;
                    memcpy(row, Eout + (size_t)s * r, sizeof(double) * (size_t)r);
                    memcpy(row + r, c->Xn + 3 * (size_t)pts[k], 3 * sizeof(double));
                    memcpy(dY + ((size_t)s * P + k) * 3, Ein + (size_t)s * n + 3 * (size_t)pts[k], 3 * sizeof(double));
                }
            }
            int rows = s_n * P;
            if (rk_mlp_forward(&c->dec, &td, rows, Din, Dout, err)) goto stop;
            double batch_loss = 0, norm = 2.0 / (3.0 * rows);
            for (int k = 0; k < 3 * rows; k++) { /* the MSE and its gradient (dY held the targets) */
                double e = Dout[k] - dY[k];
                batch_loss += e * e;
                dY[k] = norm * e;
            }
            sum += batch_loss;
            count += 3 * rows;
            memset(gdec, 0, sizeof(double) * (size_t)rk_mlp_params(&c->dec));
            memset(genc, 0, sizeof(double) * (size_t)rk_mlp_params(&c->enc));
            if (rk_mlp_backward(&c->dec, &td, dY, gdec, dX, err)) goto stop;
            memset(dP, 0, sizeof(double) * (size_t)s_n * r); /* each snapshot's code feeds its P rows */
            for (int s = 0; s < s_n; s++)
                for (int k = 0; k < P; k++)
                    for (int j = 0; j < r; j++) dP[(size_t)s * r + j] += dX[((size_t)s * P + k) * w + j];
            if (rk_mlp_backward(&c->enc, &te, dP, genc, NULL, err) || rk_adam_step(&ad, c->dec.params, gdec, lr, err) ||
                rk_adam_step(&ae, c->enc.params, genc, lr, err))
                goto stop;
            steps++;
        }
        loss = sum / count;
        if (!isfinite(loss)) {
            rk_fail(err, "CROM training diverged at epoch %d (loss %g): lower base_lr", epoch, loss);
            goto stop;
        }
        if (report && epoch == 0) report->first_loss = loss;
    }
    rc = 0;
stop:
    rk_threads_blas(blas);
    if (!rc && report) {
        report->final_loss = loss * scale * scale; /* in m^2 per component */
        report->first_loss *= scale * scale;
        report->seconds = rk_now() - t0;
        report->steps = steps;
        report->encoder_params = rk_mlp_params(&c->enc);
        report->decoder_params = rk_mlp_params(&c->dec);
    }
out:
    rk_adam_free(&ae);
    rk_adam_free(&ad);
    rk_mlp_work_free(&te);
    rk_mlp_work_free(&td);
    free(Ein);
    free(Eout);
    free(Din);
    free(Dout);
    free(dY);
    free(dX);
    free(dP);
    free(genc);
    free(gdec);
    free(order);
    free(pts);
    if (rc) {
        destroy(c);
        return -1;
    }
    *out = (rk_decoder){.n = n, .r = r, .ctx = c, .encode = encode, .jacobian = jacobian, .decode = decode,
                        .destroy = destroy};
    return 0;
}

int rk_crom_parts_of(const rk_decoder *dec, rk_crom_parts *out)
{
    if (!dec || dec->encode != encode) return -1;
    const rk_crom *c = dec->ctx;
    *out = (rk_crom_parts){c->enc.nlayers, c->dec.nlayers, c->enc.sizes, c->dec.sizes, c->enc.params, c->dec.params,
                           rk_mlp_params(&c->enc), rk_mlp_params(&c->dec), c->u_scale, c->Xn};
    return 0;
}
