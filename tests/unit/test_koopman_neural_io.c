/* rk_koopman_neural_write / _read: a trained model (without and with a shape code) comes back bit
 * for bit (its parameters, and the operator it gives on a mesh), its training report too; a
 * damaged, truncated, foreign or missing file is refused by name; a failed write leaves nothing. */
#include <unistd.h>

#include "koopman_beam.h"
#include "formats/rombin_read.h"

static int same_operator(const rk_koopman_neural *a, const rk_koopman_neural *b, const beam *m, const double *gamma,
                         rk_error *err)
{
    rk_koopman ka, kb;
    if (rk_koopman_neural_operator(a, m->sim.mesh.X, m->sim.mesh.nv, gamma, &ka, err)) return -1;
    if (rk_koopman_neural_operator(b, m->sim.mesh.X, m->sim.mesh.nv, gamma, &kb, err)) {
        rk_koopman_free(&ka);
        return -1;
    }
    int same = ka.r == kb.r && ka.n == kb.n && !memcmp(ka.lambda_re, kb.lambda_re, sizeof(double) * ka.r) &&
               !memcmp(ka.lambda_im, kb.lambda_im, sizeof(double) * ka.r) &&
               !memcmp(ka.W, kb.W, sizeof(double) * ka.r * ka.r);
    rk_koopman_free(&ka);
    rk_koopman_free(&kb);
    return same ? 0 : rk_fail(err, "the operators differ");
}

static void round_trip(beam *b, int nmesh, const double *gammas, int g, const char *path)
{
    rk_error err;
    rk_koopman_neural_mesh m[2];
    for (int i = 0; i < nmesh; i++) m[i] = beam_mesh(&b[i], g ? gammas + i : NULL);
    rk_koopman_neural_options o;
    rk_koopman_neural_default_options(&o);
    o.rank = 4;
    o.hidden = 8;
    o.depth = 2;
    o.pretrain_epochs = 20;
    o.epochs = 10;
    o.shape_dim = g;
    rk_koopman_neural nk, back;
    rk_koopman_neural_report rep, rep_back;
    CHECK_OK(rk_koopman_neural_train(m, nmesh, &o, &nk, &rep, &err));
    CHECK_OK(rk_koopman_neural_write(&nk, &rep, path, &err));
    CHECK_OK(rk_koopman_neural_read(path, &back, &rep_back, &err));
    printf("# g = %d: rank %d, %ld + %ld parameters, loss %.4g, read back\n", g, nk.r, rk_mlp_params(&nk.net),
           g ? rk_mlp_params(&nk.eignet) : 0L, rep.final_loss);
    long np = rk_mlp_params(&nk.net);
    CHECK(back.r == nk.r && back.g == nk.g && back.window == nk.window && rk_mlp_params(&back.net) == np &&
              !memcmp(back.net.params, nk.net.params, sizeof(double) * np) &&
              !memcmp(back.eig, nk.eig, sizeof(double) * nk.r) && !memcmp(back.block, nk.block, sizeof(int) * nk.r) &&
              back.h == nk.h && back.vscale == nk.vscale && back.scale == nk.scale,
          "g = %d: the model read differs from the one written", g);
    if (g)
        CHECK(rk_mlp_params(&back.eignet) == rk_mlp_params(&nk.eignet) &&
                  !memcmp(back.eignet.params, nk.eignet.params, sizeof(double) * rk_mlp_params(&nk.eignet)) &&
                  back.gamma_lo[0] == nk.gamma_lo[0] && back.gamma_hi[0] == nk.gamma_hi[0],
              "the eigenvalue network or the shape range differ");
    CHECK(rep_back.final_loss == rep.final_loss && rep_back.pretrained_loss == rep.pretrained_loss,
          "report %g %g, saved %g %g", rep_back.final_loss, rep_back.pretrained_loss, rep.final_loss, rep.pretrained_loss);
    double mid = g ? 0.5 * (gammas[0] + gammas[1]) : 0;
    CHECK_OK(same_operator(&nk, &back, &b[0], g ? &mid : NULL, &err));
    rk_koopman_neural_free(&back);
    rk_koopman_neural_free(&nk);
}

TEST(models_come_back_bit_for_bit)
{
    rk_error err;
    beam b[2];
    double thick[2] = {0.18, 0.22};
    CHECK_OK(beam_open_thick(&b[0], thick[0], 4, 1, 1, 0.2, &err));
    CHECK_OK(beam_open_thick(&b[1], thick[1], 4, 1, 1, 0.2, &err));
    char path[512];
    snprintf(path, sizeof path, "%s/romkit_ndmd_XXXXXX", tl_tmpdir());
    int fd = mkstemp(path);
    CHECK(fd >= 0, "mkstemp");
    close(fd);
    round_trip(b, 1, thick, 0, path);
    round_trip(b, 2, thick, 1, path);

    /* damage: one byte flipped in the parameters, the tail cut, another file, no file */
    FILE *fp = fopen(path, "rb");
    fseek(fp, 0, SEEK_END);
    long size = ftell(fp);
    unsigned char *data = malloc((size_t)size);
    fseek(fp, 0, SEEK_SET);
    CHECK(fread(data, 1, (size_t)size, fp) == (size_t)size, "read back");
    fclose(fp);
    rk_koopman_neural nk;
    const struct { long at, len; unsigned char flip; const char *want; } cases[] = {
        {size / 2, size, 0x40, "checksum mismatch"}, {0, size - 9, 0, "checksum mismatch"},
        {0, size, 'X', "no RKNDMD header"}, {7, size, 0x03, "format version"}, {0, 6, 0, "no RKNDMD header"}};
    for (int k = 0; k < 5; k++) {
        unsigned char *d = malloc((size_t)size);
        memcpy(d, data, (size_t)size);
        d[cases[k].at] ^= cases[k].flip;
        fp = fopen(path, "wb");
        fwrite(d, 1, (size_t)cases[k].len, fp);
        fclose(fp);
        free(d);
        int rc = rk_koopman_neural_read(path, &nk, NULL, &err);
        printf("# damage %d: %s\n", k, rc ? err.msg : "(read)");
        CHECK(rc != 0 && strstr(err.msg, cases[k].want) && strstr(err.msg, path), "case %d: %s", k, rc ? err.msg : "read");
    }
    /* every single-byte change with the checksum made right again: read or refused, never past
     * the buffer (the semantic checks behind the CRC; run under the sanitizers too) */
    int refused = 0, accepted = 0;
    unsigned seed = 11;
    for (int k = 0; k < 400; k++) {
        unsigned char *d = malloc((size_t)size);
        memcpy(d, data, (size_t)size);
        seed = seed * 1103515245u + 12345u;
        long span = k % 2 ? size - 12 : 160; /* half in the counts, sizes and blocks up front */
        long at = 8 + (long)((seed >> 8) % (unsigned)span);
        d[at] ^= (unsigned char)(1u << (seed % 8));
        uint32_t crc = rombin_crc32(0, d, (size_t)size - 4);
        memcpy(d + size - 4, &crc, 4);
        fp = fopen(path, "wb");
        fwrite(d, 1, (size_t)size, fp);
        fclose(fp);
        free(d);
        if (rk_koopman_neural_read(path, &nk, NULL, &err)) {
            refused++;
            CHECK(strstr(err.msg, path) != NULL, "message without the path: %s", err.msg);
        } else {
            accepted++;
            rk_koopman_neural_free(&nk);
        }
    }
    printf("# 400 bit flips with a valid checksum, half in the first 168 bytes: %d refused, %d read (a flipped parameter bit is a model)\n", refused,
           accepted);
    CHECK(refused > 0, "no flip refused");
    free(data);
    unlink(path);
    CHECK(rk_koopman_neural_read(path, &nk, NULL, &err) != 0 && strstr(err.msg, "cannot open"), "%s", err.msg);
    beam_close(&b[0]);
    beam_close(&b[1]);
}

int main(void)
{
    RUN(models_come_back_bit_for_bit);
    return test_finish();
}
