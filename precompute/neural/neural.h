/* precompute/neural: dense multilayer perceptrons, for the CROM encoder and decoder that the
 * adaptive linear ROM builds on (adaptive-linear-rom-grassmann paper, Sec. 3.2 and Sec. 5: encoder
 * 2 x 128 and decoder 8 x 128 hidden units, ELU, Adam, batch 64, MSE loss).
 *
 *   mlp.c        the network: sizes, one contiguous parameter array, seeded initialisation,
 *                ELU, the workspace, the batched forward pass (dgemm)
 *   backward.c   reverse mode: dL/d(params) and dL/d(input) from dL/d(output) (dgemm)
 *   jacobian.c   forward mode: d out / d in[first .. first + k) by k tangents per input
 *   adam.c       Adam and the paper's phased learning rate
 *   train.c      minibatch MSE training, deterministic for a seed
 *
 * A network maps n_0 -> n_1 -> ... -> n_L through L layers; layer l (0 <= l < L) computes
 * z = W_l a + b_l (W_l is n_{l+1} x n_l) and applies ELU on every layer but the last, which is the
 * identity. Batches are row-major: B inputs are B x n_0, one input per row.
 *
 * Parameter layout (params, rk_mlp_params(m) doubles, in layer order):
 *   layer l: W_l at params + offset[l], row-major n_{l+1} x n_l (W_l[o][i] at o n_l + i),
 *            then b_l (n_{l+1} values) at params + offset[l] + n_{l+1} n_l;
 *   offset[0] = 0, offset[l+1] = offset[l] + n_{l+1} n_l + n_{l+1}, offset[L] = the count.
 * Gradients use the same layout, so the array can be written into an asset as it is. */
#ifndef RK_NEURAL_H
#define RK_NEURAL_H

#include "util/util.h"

typedef struct {
    int nlayers;      /* L: layers with weights; sizes has L + 1 entries */
    int *sizes;       /* n_0 (inputs) .. n_L (outputs) */
    long *offset;     /* L + 1: where each layer's W starts in params; offset[L] = the count */
    double *params;   /* the layout above */
} rk_mlp;

/* A network of nsizes - 1 layers with sizes[0..nsizes) units (nsizes >= 2, every size >= 1).
 * Biases start at 0; weights uniform from the project's generator (util.h, splitmix64) seeded
 * with `seed`: in [-sqrt(6 / n_in), sqrt(6 / n_in)] on the hidden layers (He's variance 2 / n_in,
 * for the ELU that follows) and [-sqrt(6 / (n_in + n_out)), ...] on the output layer (Glorot's,
 * which has no activation). The same sizes and seed give the same bits everywhere. */
int rk_mlp_init(rk_mlp *m, int nsizes, const int *sizes, unsigned long long seed, rk_error *err);
void rk_mlp_free(rk_mlp *m);
/* The number of doubles in params (offset[L]). */
long rk_mlp_params(const rk_mlp *m);

/* ELU with alpha = 1: z for z > 0, exp(z) - 1 otherwise; its derivative 1 for z > 0, exp(z)
 * otherwise (1 at 0 from both sides, so ELU is C^1). */
double rk_elu(double z);
double rk_elu_grad(double z);

/* What one forward pass keeps for the backward pass and the Jacobian, allocated once per
 * network shape and batch capacity. Only the activations are stored, not the pre-activations:
 * ELU's derivative follows from its value (1 where a > 0, a + 1 = exp(z) elsewhere). */
typedef struct {
    int nlayers;      /* the shape it was made for (checked on every use) */
    int *sizes;
    int batch;        /* most rows per pass */
    int tangents;     /* most Jacobian columns k per pass (0: no Jacobian buffers) */
    int width;        /* widest layer */
    int rows;         /* rows of the last forward pass (0: none yet) */
    long *aoff;       /* L + 1: layer l's activations at act + aoff[l], rows x n_l */
    double *act;      /* layer 0 holds a copy of the input, layer L the output */
    double *delta[2]; /* batch x width each: the backward pass's ping-pong */
    double *tan[2];   /* batch tangents x width each: the Jacobian's ping-pong */
} rk_mlp_work;

/* A workspace for passes of up to `batch` inputs (>= 1) and Jacobians of up to `tangents`
 * columns (>= 0). */
int rk_mlp_work_init(rk_mlp_work *w, const rk_mlp *m, int batch, int tangents, rk_error *err);
void rk_mlp_work_free(rk_mlp_work *w);

/* Y (B x n_L, or NULL: read w's last layer) = the network on X (B x n_0), 1 <= B <= w->batch.
 * The activations stay in w for rk_mlp_backward. */
int rk_mlp_forward(const rk_mlp *m, rk_mlp_work *w, int B, const double *X, double *Y, rk_error *err);

/* Reverse mode after rk_mlp_forward (on the same w and unchanged params): given dY = dL/dY for
 * the last pass's rows (rows x n_L), ADDS dL/d(params) into dparams (rk_mlp_params(m) values,
 * the params layout; the caller zeroes it) and, when dX is not NULL, WRITES dL/dX (rows x n_0).
 * dY must not overlap dparams or dX. */
int rk_mlp_backward(const rk_mlp *m, rk_mlp_work *w, const double *dY, double *dparams, double *dX, rk_error *err);

/* Forward mode: for each of the B inputs X (B x n_0), the n_L x k Jacobian of the outputs with
 * respect to inputs first .. first + k - 1 only (a decoder g(p, x) differentiated in its latent p
 * alone), in J (B x n_L x k: input b's matrix row-major at J + b n_L k). k tangents are pushed
 * through the layers, J_l = diag(act'(z_l)) W_l J_{l-1}, for all B inputs by one dgemm per layer.
 * Needs B <= w->batch and k <= w->tangents; Y (B x n_L, or NULL) gets the outputs, and w's
 * activations are those of this pass (rk_mlp_backward may follow). */
int rk_mlp_jacobian(const rk_mlp *m, rk_mlp_work *w, int B, const double *X, int first, int k, double *Y, double *J,
                    rk_error *err);

/* Adam (Kingma & Ba 2015) with bias correction: per parameter
 *   m <- beta1 m + (1 - beta1) g,  v <- beta2 v + (1 - beta2) g^2,
 *   p <- p - lr (m / (1 - beta1^t)) / (sqrt(v / (1 - beta2^t)) + eps)
 * at step t = 1, 2, ...; beta1 0.9, beta2 0.999, eps 1e-8 (PyTorch's defaults). */
typedef struct {
    long n;
    double *m, *v;
    long step;
    double beta1, beta2, eps;
} rk_adam;

int rk_adam_init(rk_adam *a, long n, rk_error *err);
void rk_adam_free(rk_adam *a);
/* One step on params (a->n values) from grad, in place; refuses a non-finite gradient (naming
 * its index) or lr <= 0 and then leaves params and the moments as they were. */
int rk_adam_step(rk_adam *a, double *params, const double *grad, double lr, rk_error *err);

/* The paper's schedule, "starts at 5 and decreases to 2, 1, and 0.5 over four phases of 100
 * epochs each" (Sec. 5). A learning rate of 5 would make Adam's steps 5 per parameter, so the
 * numbers are read as multiples of a base rate (the paper gives no unit; default base 1e-4, i.e.
 * 5e-4, 2e-4, 1e-4, 5e-5): base x {5, 2, 1, 0.5} in phase floor(4 epoch / epochs_total), epoch
 * counted from 0 (four equal phases when 4 divides epochs_total, otherwise each has the floor or
 * the ceiling of epochs_total / 4 epochs; an epoch past the end stays in the last phase). */
double rk_lr_phased(double base, int epoch, int epochs_total);

#define RK_LR_BASE_DEFAULT 1e-4

/* An objective for rk_lbfgs_minimize: *f and its gradient g (n values) at x; nonzero fails. */
typedef int (*rk_objective)(void *ctx, const double *x, double *f, double *g, rk_error *err);

typedef struct {
    int iterations;        /* >= 0: accepted steps at most */
    int memory;            /* >= 1: stored (s, y) pairs */
    double tolerance;      /* >= 0: stop at |g| <= tolerance */
} rk_lbfgs_options;

typedef struct {
    double initial, final; /* the objective at the start and at the end */
    int iterations;        /* accepted steps */
    long evaluations;      /* objective calls in the line searches */
} rk_lbfgs_report;

/* Minimizes f from x (n values, overwritten by the best point found) by L-BFGS (Nocedal & Wright,
 * Alg. 7.4-7.5) with backtracking Armijo steps (c = 1e-4, halving): a deterministic full-batch
 * optimizer for where a loss and its exact gradient are cheap (the neural DMD's polish after
 * Adam). Stops after o->iterations steps, at |g| <= o->tolerance, or when no step along the
 * direction decreases f (round-off). o NULL: 100 iterations, memory 10, tolerance 0. Fails on
 * bad options, an objective that fails, or a non-finite objective at the start. */
int rk_lbfgs_minimize(long n, double *x, rk_objective f, void *ctx, const rk_lbfgs_options *o, rk_lbfgs_report *rep,
                      rk_error *err);

typedef struct {
    int epochs;            /* >= 1 (paper: 400) */
    int batch;             /* >= 1 (paper: 64); a batch above N trains on all N at once */
    double base_lr;        /* > 0: rk_lr_phased's base */
    unsigned long long seed; /* the shuffles' generator */
} rk_mlp_train_options;

/* epochs 400, batch 64, base_lr RK_LR_BASE_DEFAULT, seed 1. */
void rk_mlp_train_default_options(rk_mlp_train_options *o);

typedef struct {
    double initial_loss;   /* the MSE over all N pairs before training */
    double final_loss;     /* the MSE over all N pairs after the last epoch */
    double seconds;        /* wall clock */
    long steps;            /* Adam steps taken */
} rk_mlp_train_report;

/* Trains m in place on N pairs (X: N x n_0, Y: N x n_L, row-major) to minimise the mean squared
 * error (1 / (B n_L)) sum |net(x) - y|^2 over each minibatch: every epoch draws a new permutation
 * of the rows (Fisher-Yates from the seed), takes minibatches of `batch` rows in that order (the
 * last one shorter when batch does not divide N) and takes one Adam step on each, the learning
 * rate rk_lr_phased(base_lr, epoch, epochs). OpenBLAS runs on one thread throughout, so the same
 * m, data and options give bit-identical params on any ROMKIT_THREADS (on one machine: OpenBLAS
 * picks its kernels by CPU). o NULL: the defaults. Refuses N < 1, a non-finite
 * value in X or Y (naming the row and column), bad options, and a loss that turns non-finite
 * (naming the epoch: a learning rate too high); on any failure m keeps the parameters it came
 * with. report may be NULL. */
int rk_mlp_train(rk_mlp *m, const double *X, const double *Y, int N, const rk_mlp_train_options *o,
                 rk_mlp_train_report *report, rk_error *err);

#endif
