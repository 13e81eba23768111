/* test_read_file.c -- base/read.c and io/overwrite.c: a file of exactly its
 * bound is read and one byte more is refused, binary content keeps its
 * length, a /proc file (size 0 to stat) is read to its end, a FIFO is
 * refused without waiting for a writer, and mpgm_refuse_overwrite finds an
 * input under another name (.., a symbolic link, a hard link, inside a
 * folder output, as an atomic output's temporary) and lets pass what is
 * not one. */
#define _XOPEN_SOURCE 700
#include "mpgm_file.h"
#include "mpgm_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[64];

static void path_of(char *buf, size_t cap, const char *name) { snprintf(buf, cap, "%s/%s", dir, name); }

static void write_bytes(const char *p, const char *b, size_t n) {
  FILE *f = fopen(p, "wb");
  if (f) {
    fwrite(b, 1, n, f);
    fclose(f);
  }
}

static void bounds(void) {
  char p[128], buf[1000];
  for (size_t i = 0; i < sizeof buf; i++) buf[i] = (char)(i % 7 == 3 ? '\0' : 'a' + i % 26);
  path_of(p, sizeof p, "bytes.bin");
  write_bytes(p, buf, sizeof buf);
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  char *t = NULL;
  size_t n = 0;
  int err = mpgm_read_file(&ctx, p, sizeof buf, &t, &n);
  mpgm_test(err == 0 && n == sizeof buf && t && t[n] == '\0' && memcmp(t, buf, n) == 0,
            "a file of exactly its bound (1000 bytes, NULs inside) is read whole: %d, %zu", err, n);
  free(t);
  mpgm_ctx_init(&ctx);
  err = mpgm_read_file(&ctx, p, sizeof buf - 1, &t, &n);
  mpgm_test(err == MPGM_ERR_INPUT && !t && strstr(ctx.msg, "larger than 999 bytes"),
            "one byte over its bound: refused (%s)", ctx.msg);
  mpgm_ctx_init(&ctx);
  err = mpgm_err_too_large(&ctx, "x", (size_t)64 << 20);
  mpgm_test(err == MPGM_ERR_INPUT && strstr(ctx.msg, "x: larger than 64 MiB"), "bounds are named in MiB (%s)",
            ctx.msg);
  mpgm_ctx_init(&ctx);
  err = mpgm_read_file(&ctx, "/proc/self/status", 1 << 20, &t, &n);
  mpgm_test(err == 0 && n > 0 && strstr(t, "Name:"), "/proc/self/status (size 0 to stat) read to its end: %zu bytes", n);
  free(t);
}

static void special(void) {
  char p[128];
  path_of(p, sizeof p, "fifo");
  mkfifo(p, 0600);
  alarm(10); /* a wait for a writer fails the test instead of hanging it */
  mpgm_ctx ctx;
  mpgm_ctx_init(&ctx);
  char *t = NULL;
  int err = mpgm_read_file(&ctx, p, 100, &t, NULL);
  mpgm_test(err == MPGM_ERR_INPUT && strstr(ctx.msg, "is a pipe or FIFO, not a regular file"), "a FIFO: %s",
            ctx.msg);
  mpgm_ctx_init(&ctx);
  FILE *f = NULL;
  err = mpgm_fopen_regular(&ctx, dir, 100, &f, NULL);
  mpgm_test(err == MPGM_ERR_INPUT && !f && strstr(ctx.msg, "is a folder"), "a folder: %s", ctx.msg);
  mpgm_ctx_init(&ctx);
  int fd = -1;
  err = mpgm_open_regular(&ctx, "/dev/null", 100, &fd, NULL);
  mpgm_test(err == MPGM_ERR_INPUT && fd < 0 && strstr(ctx.msg, "a character device"), "/dev/null: %s", ctx.msg);
  mpgm_ctx_init(&ctx);
  path_of(p, sizeof p, "missing");
  err = mpgm_open_regular(&ctx, p, 100, &fd, NULL);
  mpgm_test(err == MPGM_ERR_IO && strstr(ctx.msg, "cannot open"), "a missing file: I/O error (%s)", ctx.msg);
  alarm(0);
}

/* mpgm_refuse_overwrite of one output against one input: its code. */
static int refuse(const char *out, int kind, const char *in, mpgm_ctx *ctx) {
  mpgm_ctx_init(ctx);
  const mpgm_write_path w = {out, kind};
  return mpgm_refuse_overwrite(ctx, &w, 1, &in, 1);
}

static void overwrite(void) {
  char in[128], p[192];
  path_of(in, sizeof in, "in.json");
  write_bytes(in, "{}", 2);
  mpgm_ctx ctx;
  path_of(p, sizeof p, "sub");
  mkdir(p, 0700);
  snprintf(p, sizeof p, "%s/sub/../in.json", dir);
  mpgm_test(refuse(p, MPGM_WRITE_FILE, in, &ctx) == MPGM_ERR_INPUT && strstr(ctx.msg, "would overwrite the input"),
            "the input through ..: %s", ctx.msg);
  path_of(p, sizeof p, "soft.csv");
  mpgm_test(symlink("in.json", p) == 0 && refuse(p, MPGM_WRITE_FILE, in, &ctx) == MPGM_ERR_INPUT,
            "a symbolic link to the input: %s", ctx.msg);
  path_of(p, sizeof p, "hard.csv");
  mpgm_test(link(in, p) == 0 && refuse(p, MPGM_WRITE_FILE, in, &ctx) == MPGM_ERR_INPUT &&
                strstr(ctx.msg, "is a hard link of the input"),
            "a hard link of the input: %s", ctx.msg);
  mpgm_test(refuse(dir, MPGM_WRITE_FOLDER, in, &ctx) == MPGM_ERR_INPUT && strstr(ctx.msg, "holds the input"),
            "a folder output that holds the input: %s", ctx.msg);
  mpgm_test(refuse(dir, MPGM_WRITE_FILE, in, &ctx) == 0, "a folder made or kept (only its name compared): passes");
  path_of(p, sizeof p, "in");
  mpgm_test(refuse(p, MPGM_WRITE_FILE, in, &ctx) == 0, "\"in\" beside \"in.json\": passes");
  char tmp[200];
  snprintf(tmp, sizeof tmp, "%s.tmp", p);
  rename(in, tmp);
  mpgm_test(refuse(p, MPGM_WRITE_ATOMIC, tmp, &ctx) == MPGM_ERR_INPUT && strstr(ctx.msg, "temporary"),
            "the input where an atomic output's temporary goes: %s", ctx.msg);
  mpgm_test(refuse(p, MPGM_WRITE_FILE, tmp, &ctx) == 0, "... a file written in place has none: passes");
  path_of(p, sizeof p, "nowhere/out.csv");
  mpgm_test(refuse(p, MPGM_WRITE_FILE, tmp, &ctx) == 0, "an output in a folder not there yet: passes");
  path_of(p, sizeof p, "gone.json");
  mpgm_test(refuse(p, MPGM_WRITE_FILE, p, &ctx) == 0, "an input that does not exist is passed over (its reader says so)");
  mpgm_test(refuse(NULL, MPGM_WRITE_FILE, tmp, &ctx) == 0, "no output (NULL): passes");
}

int main(void) {
  snprintf(dir, sizeof dir, "/tmp/mpgm_test_read_XXXXXX");
  if (!mkdtemp(dir)) return 1;
  bounds();
  special();
  overwrite();
  char cmd[128];
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  if (system(cmd) != 0) fprintf(stderr, "cannot remove %s\n", dir);
  return mpgm_test_summary();
}
