/* Private to precompute/mesh: a whole file in memory, read as whitespace-separated tokens.
 *
 * Every reader (ASCII or binary) starts from an rk_reader: the file's bytes, a position and
 * the line number of that position. ASCII formats walk it with the tokenizer below; binary
 * formats switch to the bounds-checked cursor of binary_reader_impl.h on the same buffer (formats
 * like Gmsh, VTK and PLY mix a text header with binary blocks). rk_reader_fail names the file
 * and the line (text mode) or the byte offset (binary mode), so every message says where. */
#ifndef RK_MESH_TEXT_READER_H
#define RK_MESH_TEXT_READER_H

#include <stddef.h>
#include <stdint.h>

#include "util/util.h"

typedef struct {
    const char *path;   /* for messages */
    char *buf;          /* the file, NUL-terminated */
    size_t len;
    size_t pos;
    long line;          /* line of `pos`, 1-based */
    long tok_line;      /* line of the last token read */
    char comment;       /* comment character skipped to end of line ('#'), 0 for none */
    int binary;         /* numbers are raw bytes (binary_reader_impl.h), not tokens */
    int big_endian;     /* byte order of binary numbers */
    rk_error *err;
} rk_reader;

/* A token: a pointer into the buffer and a length (not NUL-terminated). */
typedef struct {
    const char *s;
    size_t len;
} rk_token;

/* Reads the whole file. Fails (naming the file) if it cannot be read. */
int rk_reader_open(rk_reader *r, const char *path, char comment, rk_error *err);
void rk_reader_close(rk_reader *r);

/* Fills r->err with "path:LINE: message" (text mode) or "path: byte OFFSET: message"
 * (binary mode). Returns -1. */
int rk_reader_fail(rk_reader *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Next token, crossing line ends and skipping comments. Returns 1, or 0 at end of file. */
int rk_next_token(rk_reader *r, rk_token *tok);
/* Next token on the current line only. Returns 1, or 0 at the end of the line (the newline
 * itself is not consumed) or of the file. */
int rk_next_token_on_line(rk_reader *r, rk_token *tok);
/* Consumes everything up to and including the next newline. */
void rk_skip_line(rk_reader *r);
/* Copies the rest of the current line (without the newline and a trailing '\r') to out,
 * truncated to cap - 1 characters, and consumes the newline. */
void rk_read_line(rk_reader *r, char *out, size_t cap);
/* The next token without consuming it (0 at end of file). */
int rk_peek_token(rk_reader *r, rk_token *tok);

int rk_token_is(rk_token tok, const char *word);        /* exact */
int rk_token_is_nocase(rk_token tok, const char *word); /* ASCII case-insensitive */
/* Copies a token for messages (shortened with "..." when long). */
const char *rk_token_str(rk_token tok, char *buf, size_t cap);

/* Next token as a number; on failure "expected <what>, got '...'" or "... found end of file". */
int rk_text_int64(rk_reader *r, int64_t *v, const char *what);
int rk_text_double(rk_reader *r, double *v, const char *what);
/* An int in [lo, hi]. */
int rk_text_int(rk_reader *r, int lo, int hi, int *v, const char *what);
/* The next token must be `word` (case-insensitive when nocase). */
int rk_expect_word(rk_reader *r, const char *word, int nocase);

/* All integers on the next non-blank line (at most max of them; more is an error), then
 * consumes that line. For line-structured ASCII records whose length varies (Gmsh elements). */
int rk_line_int64s(rk_reader *r, int64_t *v, int max, int *n, const char *what);

/* Skips forward to just after the next occurrence of `marker` (line numbers stay right).
 * Fails with "no <marker> found" when there is none. */
int rk_skip_past(rk_reader *r, const char *marker);

/* Guards an allocation by a count read from the file: the count must be >= 0, at most
 * max_count, and the rest of the file must be able to hold it, each item taking at least
 * `tokens` tokens (text mode, 2 bytes each counting the separator) or `bytes` bytes (binary).
 * A corrupt header therefore fails here instead of allocating gigabytes. */
int rk_check_count(rk_reader *r, int64_t count, int64_t max_count, int tokens, size_t bytes,
                   const char *what);

#endif
