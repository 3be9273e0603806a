#include "mesh/text_reader_impl.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int rk_reader_open(rk_reader *r, const char *path, char comment, rk_error *err)
{
    memset(r, 0, sizeof *r);
    r->path = path;
    r->comment = comment;
    r->line = 1;
    r->err = err;
    FILE *fp = fopen(path, "rb");
    if (!fp) return rk_fail(err, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    long size = -1;
    /* a directory opens too, and seeks to a nonsense end (a glTF buffer's uri may name one) */
    if (fstat(fileno(fp), &st) == 0 && S_ISREG(st.st_mode) && fseek(fp, 0, SEEK_END) == 0) size = ftell(fp);
    if (size < 0 || fseek(fp, 0, SEEK_SET) != 0) {
        fclose(fp);
        return rk_fail(err, "%s: cannot read (not a regular file?)", path);
    }
    r->buf = rk_calloc((size_t)size + 1, 1, err);
    if (!r->buf) {
        fclose(fp);
        return rk_error_prefix(err, "%s", path);
    }
    size_t got = fread(r->buf, 1, (size_t)size, fp);
    int bad = ferror(fp);
    fclose(fp);
    if (bad || got != (size_t)size) {
        rk_reader_close(r);
        return rk_fail(err, "%s: read error", path);
    }
    r->len = got;
    return 0;
}

void rk_reader_close(rk_reader *r)
{
    free(r->buf);
    r->buf = NULL;
    r->len = r->pos = 0;
}

int rk_reader_fail(rk_reader *r, const char *fmt, ...)
{
    char msg[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (r->binary) return rk_fail(r->err, "%s: byte %zu: %s", r->path, r->pos, msg);
    return rk_fail(r->err, "%s:%ld: %s", r->path, r->tok_line > 0 ? r->tok_line : r->line, msg);
}

static int is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

/* Skips blanks (and newlines when cross_lines) and comments. */
static void skip_blank(rk_reader *r, int cross_lines)
{
    while (r->pos < r->len) {
        char c = r->buf[r->pos];
        if (c == '\n') {
            if (!cross_lines) return;
            r->line++;
            r->pos++;
        } else if (is_space(c)) {
            r->pos++;
        } else if (r->comment && c == r->comment) {
            while (r->pos < r->len && r->buf[r->pos] != '\n') r->pos++;
        } else {
            return;
        }
    }
}

static int take_token(rk_reader *r, rk_token *tok)
{
    if (r->pos >= r->len) return 0;
    if (r->buf[r->pos] == '\n') return 0;
    size_t start = r->pos;
    while (r->pos < r->len && !is_space(r->buf[r->pos])) r->pos++;
    tok->s = r->buf + start;
    tok->len = r->pos - start;
    r->tok_line = r->line;
    return 1;
}

int rk_next_token(rk_reader *r, rk_token *tok)
{
    skip_blank(r, 1);
    return take_token(r, tok);
}

int rk_next_token_on_line(rk_reader *r, rk_token *tok)
{
    skip_blank(r, 0);
    return take_token(r, tok);
}

void rk_skip_line(rk_reader *r)
{
    while (r->pos < r->len && r->buf[r->pos] != '\n') r->pos++;
    if (r->pos < r->len) {
        r->pos++;
        r->line++;
    }
}

void rk_read_line(rk_reader *r, char *out, size_t cap)
{
    size_t start = r->pos;
    while (r->pos < r->len && r->buf[r->pos] != '\n') r->pos++;
    size_t n = r->pos - start;
    if (n > 0 && r->buf[start + n - 1] == '\r') n--;
    if (cap > 0) {
        if (n > cap - 1) n = cap - 1;
        memcpy(out, r->buf + start, n);
        out[n] = '\0';
    }
    r->tok_line = r->line;
    rk_skip_line(r);
}

int rk_peek_token(rk_reader *r, rk_token *tok)
{
    size_t pos = r->pos;
    long line = r->line, tok_line = r->tok_line;
    int got = rk_next_token(r, tok);
    r->pos = pos;
    r->line = line;
    r->tok_line = tok_line;
    return got;
}

int rk_token_is(rk_token tok, const char *word)
{
    size_t n = strlen(word);
    return tok.len == n && memcmp(tok.s, word, n) == 0;
}

int rk_token_is_nocase(rk_token tok, const char *word)
{
    size_t n = strlen(word);
    if (tok.len != n) return 0;
    for (size_t i = 0; i < n; i++) {
        char a = tok.s[i], b = word[i];
        if (a >= 'A' && a <= 'Z') a = (char)(a - 'A' + 'a');
        if (b >= 'A' && b <= 'Z') b = (char)(b - 'A' + 'a');
        if (a != b) return 0;
    }
    return 1;
}

const char *rk_token_str(rk_token tok, char *buf, size_t cap)
{
    size_t n = tok.len;
    if (n > cap - 1) n = cap - 1;
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)tok.s[i];
        buf[i] = (c >= 32 && c < 127) ? (char)c : '?';
    }
    buf[n] = '\0';
    if (tok.len > cap - 1 && cap > 4) memcpy(buf + cap - 4, "...", 4);
    return buf;
}

/* Replaces non-printable bytes (binary garbage) for messages. */
static const char *printable(char *s)
{
    for (char *c = s; *c; c++)
        if ((unsigned char)*c < 32 || (unsigned char)*c >= 127) *c = '?';
    return s;
}

/* Next token copied into a NUL-terminated buffer for strtod/strtoll. */
static int number_token(rk_reader *r, char *buf, size_t cap, const char *what)
{
    rk_token tok;
    if (!rk_next_token(r, &tok)) return rk_reader_fail(r, "expected %s, found end of file", what);
    if (tok.len >= cap) {
        char shown[40];
        return rk_reader_fail(r, "expected %s, got '%s'", what, rk_token_str(tok, shown, sizeof shown));
    }
    memcpy(buf, tok.s, tok.len);
    buf[tok.len] = '\0';
    return 0;
}

int rk_text_int64(rk_reader *r, int64_t *v, const char *what)
{
    char buf[64], *end;
    if (number_token(r, buf, sizeof buf, what)) return -1;
    errno = 0;
    long long x = strtoll(buf, &end, 10);
    if (end == buf || *end != '\0' || errno == ERANGE)
        return rk_reader_fail(r, "expected %s (an integer), got '%s'", what, printable(buf));
    *v = (int64_t)x;
    return 0;
}

int rk_text_double(rk_reader *r, double *v, const char *what)
{
    char buf[64], *end;
    if (number_token(r, buf, sizeof buf, what)) return -1;
    double x = strtod(buf, &end);
    if (end == buf || *end != '\0') return rk_reader_fail(r, "expected %s (a number), got '%s'", what, printable(buf));
    *v = x;
    return 0;
}

int rk_text_int(rk_reader *r, int lo, int hi, int *v, const char *what)
{
    int64_t x;
    if (rk_text_int64(r, &x, what)) return -1;
    if (x < lo || x > hi)
        return rk_reader_fail(r, "%s %" PRId64 " is out of range [%d, %d]", what, x, lo, hi);
    *v = (int)x;
    return 0;
}

int rk_line_int64s(rk_reader *r, int64_t *v, int max, int *n, const char *what)
{
    skip_blank(r, 1);
    rk_token tok;
    *n = 0;
    while (rk_next_token_on_line(r, &tok)) {
        if (*n == max) return rk_reader_fail(r, "more than %d numbers on one line in %s", max, what);
        char buf[64], *end;
        if (tok.len >= sizeof buf) return rk_reader_fail(r, "expected integers in %s, got a %zu-character token", what, tok.len);
        memcpy(buf, tok.s, tok.len);
        buf[tok.len] = '\0';
        errno = 0;
        long long x = strtoll(buf, &end, 10);
        if (end == buf || *end != '\0' || errno == ERANGE)
            return rk_reader_fail(r, "expected integers in %s, got '%s'", what, printable(buf));
        v[(*n)++] = (int64_t)x;
    }
    if (*n == 0) return rk_reader_fail(r, "expected %s, found end of file", what);
    rk_skip_line(r);
    return 0;
}

int rk_expect_word(rk_reader *r, const char *word, int nocase)
{
    rk_token tok;
    if (!rk_next_token(r, &tok)) return rk_reader_fail(r, "expected '%s', found end of file", word);
    if (nocase ? rk_token_is_nocase(tok, word) : rk_token_is(tok, word)) return 0;
    char shown[40];
    return rk_reader_fail(r, "expected '%s', got '%s'", word, rk_token_str(tok, shown, sizeof shown));
}

int rk_skip_past(rk_reader *r, const char *marker)
{
    size_t n = strlen(marker);
    for (size_t i = r->pos; i + n <= r->len; i++) {
        if (r->buf[i] == marker[0] && memcmp(r->buf + i, marker, n) == 0) {
            for (size_t j = r->pos; j < i + n; j++)
                if (r->buf[j] == '\n') r->line++;
            r->pos = i + n;
            return 0;
        }
    }
    char shown[80];
    snprintf(shown, sizeof shown, "%s", marker);
    return rk_reader_fail(r, "no %s found (file truncated?)", printable(shown));
}

int rk_check_count(rk_reader *r, int64_t count, int64_t max_count, int tokens, size_t bytes,
                   const char *what)
{
    if (count < 0) return rk_reader_fail(r, "negative %s count %" PRId64, what, count);
    if (count > max_count)
        return rk_reader_fail(r, "%s count %" PRId64 " is too large (at most %" PRId64 ")", what, count,
                              max_count);
    size_t remaining = r->len - r->pos;
    if (r->binary) {
        if (bytes > 0 && (uint64_t)count > remaining / bytes)
            return rk_reader_fail(r,
                                  "%s count %" PRId64 " needs %" PRIu64 " bytes but only %zu remain "
                                  "(file truncated or corrupt)",
                                  what, count, (uint64_t)count * bytes, remaining);
    } else {
        uint64_t per = 2 * (uint64_t)(tokens > 0 ? tokens : 1);
        if ((uint64_t)count > (remaining + 1) / per)
            return rk_reader_fail(r,
                                  "%s count %" PRId64 " is more than the rest of the file can hold "
                                  "(file truncated or corrupt)",
                                  what, count);
    }
    return 0;
}
