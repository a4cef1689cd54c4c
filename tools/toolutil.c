/* toolutil.c - see toolutil.h */
#define _POSIX_C_SOURCE 200809L
#if defined(__APPLE__)
#define _DARWIN_C_SOURCE /* sysconf(_SC_PHYS_PAGES) */
#endif
#include "toolutil.h"
#include <errno.h>
#include <fcntl.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* ---- errors ---------------------------------------------------------------------------------- */

void tool_error_set(tool_error *err, const char *path, int line, const char *fmt, ...) {
    if (!err) return;
    size_t n = sizeof(err->message);
    int k = 0;
    err->line = line > 0 ? line : 0;
    if (path && line > 0) k = snprintf(err->message, n, "%s:%d: ", path, line);
    else if (path) k = snprintf(err->message, n, "%s: ", path);
    else err->message[0] = '\0';
    if (k < 0) k = 0;
    if ((size_t)k >= n) return; /* prefix alone fills the buffer (already NUL-terminated) */
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message + k, n - (size_t)k, fmt, ap);
    va_end(ap);
}

/* ---- files ----------------------------------------------------------------------------------- */

uint32_t tool_get32(const void *p) {
    const uint8_t *b = (const uint8_t *)p;
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

int read_file(const char *path, void **data, size_t *size, tool_error *err) {
    *data = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f) {
        tool_error_set(err, path, 0, "cannot open: %s", strerror(errno));
        return -1;
    }
    size_t cap = 0, len = 0;
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0 &&
        (uint64_t)st.st_size < (uint64_t)SIZE_MAX - 1)
        cap = (size_t)st.st_size + 1; /* +1 so that EOF is seen without a regrow */
    if (cap < 4096) cap = 4096;
    char *buf = (char *)malloc(cap + 1);
    if (!buf) goto oom;
    for (;;) {
        if (len == cap) {
            if (cap > (SIZE_MAX - 1) / 2) goto oom;
            size_t ncap = cap * 2;
            char *nb = (char *)realloc(buf, ncap + 1);
            if (!nb) goto oom;
            buf = nb;
            cap = ncap;
        }
        size_t got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (got == 0) {
            if (ferror(f)) {
                int e = errno;
                tool_error_set(err, path, 0, "cannot read: %s", e ? strerror(e) : "I/O error");
                free(buf);
                fclose(f);
                return -1;
            }
            break; /* EOF */
        }
    }
    fclose(f);
    buf[len] = '\0';
    *data = buf;
    *size = len;
    return 0;
oom:
    free(buf);
    fclose(f);
    tool_error_set(err, path, 0, "out of memory reading the file");
    return -1;
}

/* Runs fn on f and closes f: 0, or the errno of the failure (EIO when fn failed without one). */
static int write_stream_close(FILE *f, int (*fn)(FILE *f, const void *ctx), const void *ctx) {
    errno = 0;
    int bad = fn(f, ctx) != 0;
    if (fflush(f) != 0 || ferror(f)) bad = 1;
    int e = bad ? (errno ? errno : EIO) : 0;
    if (fclose(f) != 0 && !e) e = errno ? errno : EIO;
    return e;
}

int write_stream_atomic(const char *path, int (*fn)(FILE *f, const void *ctx), const void *ctx, tool_error *err) {
    struct stat st;
    int e, exists = stat(path, &st) == 0;
    if (exists && S_ISDIR(st.st_mode)) {
        tool_error_set(err, path, 0, "is a directory");
        return -1;
    }
    if (exists && !S_ISREG(st.st_mode)) { /* /dev/null, a pipe: written in place */
        FILE *f = fopen(path, "wb");
        e = f ? write_stream_close(f, fn, ctx) : errno;
        if (e) tool_error_set(err, path, 0, "%s: %s", f ? "write error" : "cannot open", strerror(e));
        return e ? -1 : 0;
    }
    size_t n = strlen(path) + 32;
    char *tmp = (char *)malloc(n), *buf = (char *)malloc((size_t)1 << 16);
    FILE *f = NULL;
    if (!tmp || !buf) {
        tool_error_set(err, path, 0, "out of memory");
        goto fail;
    }
    snprintf(tmp, n, "%s.tmp.%ld", path, (long)getpid());
    f = fopen(tmp, "wb");
    if (!f) {
        tool_error_set(err, path, 0, "cannot create %s: %s", tmp, strerror(errno));
        goto fail;
    }
    setvbuf(f, buf, _IOFBF, (size_t)1 << 16);
    e = write_stream_close(f, fn, ctx);
    if (e || rename(tmp, path) != 0) {
        tool_error_set(err, path, 0, "%s %s: %s", e ? "cannot write" : "cannot rename", tmp, strerror(e ? e : errno));
        remove(tmp);
        goto fail;
    }
    free(tmp);
    free(buf);
    return 0;
fail:
    free(tmp);
    free(buf);
    return -1;
}

int write_file_atomic(const char *path, const void *data, size_t size, tool_error *err) {
    size_t plen = strlen(path);
    char *tmp = (char *)malloc(plen + 32);
    if (!tmp) {
        tool_error_set(err, path, 0, "out of memory");
        return -1;
    }
    snprintf(tmp, plen + 32, "%s.tmp.%ld", path, (long)getpid());
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (fd < 0) {
        tool_error_set(err, path, 0, "cannot create %s: %s", tmp, strerror(errno));
        free(tmp);
        return -1;
    }
    const char *p = (const char *)data;
    size_t left = size;
    while (left > 0) {
        size_t chunk = left > ((size_t)1 << 30) ? ((size_t)1 << 30) : left;
        ssize_t w = write(fd, p, chunk);
        if (w < 0) {
            if (errno == EINTR) continue;
            tool_error_set(err, path, 0, "cannot write %s: %s", tmp, strerror(errno));
            goto fail;
        }
        if (w == 0) {
            tool_error_set(err, path, 0, "cannot write %s: no progress", tmp);
            goto fail;
        }
        p += w;
        left -= (size_t)w;
    }
    if (fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
        tool_error_set(err, path, 0, "cannot sync %s: %s", tmp, strerror(errno));
        goto fail;
    }
    if (close(fd) != 0) {
        fd = -1;
        tool_error_set(err, path, 0, "cannot close %s: %s", tmp, strerror(errno));
        goto fail;
    }
    fd = -1;
    if (rename(tmp, path) != 0) {
        tool_error_set(err, path, 0, "cannot rename %s: %s", tmp, strerror(errno));
        goto fail;
    }
    free(tmp);
    return 0;
fail:
    if (fd >= 0) close(fd);
    unlink(tmp);
    free(tmp);
    return -1;
}

/* ---- progress -------------------------------------------------------------------------------- */

static double progress__now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void progress__duration(char *buf, size_t n, double s) {
    if (s < 0) s = 0;
    if (s < 10) snprintf(buf, n, "%.1fs", s);
    else if (s < 100) snprintf(buf, n, "%.0fs", s);
    else if (s < 3600) snprintf(buf, n, "%dm%02ds", (int)(s / 60), (int)s % 60);
    else if (s < 1e7) snprintf(buf, n, "%dh%02dm", (int)(s / 3600), ((int)s / 60) % 60);
    else snprintf(buf, n, "a long time");
}

/* Called with the mutex held. final: the closing draw. */
static void progress__draw(progress *p, double now, int final) {
    char line[256], t[32];
    int k;
    double elapsed = now - p->start;
    if (p->total > 0) {
        uint64_t done = p->done > p->total ? p->total : p->done;
        int percent = (int)(done * 100 / p->total);
        char bar[31];
        int fill = (int)(done * 30 / p->total);
        for (int i = 0; i < 30; ++i) bar[i] = i < fill ? '#' : '.';
        bar[30] = '\0';
        k = snprintf(line, sizeof(line), "%s [%s] %3d%% %llu/%llu", p->label, bar, percent,
                     (unsigned long long)done, (unsigned long long)p->total);
        if (final) {
            progress__duration(t, sizeof(t), elapsed);
            snprintf(line + k, sizeof(line) - (size_t)k, " in %s", t);
        } else if (done > 0 && done < p->total) {
            progress__duration(t, sizeof(t), elapsed * (double)(p->total - done) / (double)done);
            snprintf(line + k, sizeof(line) - (size_t)k, " ETA %s", t);
        }
        p->last_percent = percent;
        p->last_decile = percent / 10;
    } else {
        progress__duration(t, sizeof(t), elapsed);
        snprintf(line, sizeof(line), "%s %llu %s%s", p->label, (unsigned long long)p->done,
                 final ? "in " : "", t);
    }
    if (p->tty) fprintf(p->out, "\r%s\033[K%s", line, final ? "\n" : "");
    else fprintf(p->out, "%s\n", line);
    fflush(p->out);
    p->last_draw = now;
    p->drawn = 1;
}

void progress_begin_ex(progress *p, const char *label, uint64_t total, unsigned flags, FILE *out) {
    memset(p, 0, sizeof(*p));
    pthread_mutex_init(&p->mutex, NULL);
    p->out = out ? out : stderr;
    snprintf(p->label, sizeof(p->label), "%s", label ? label : "");
    p->total = total;
    p->quiet = (flags & PROGRESS_QUIET) != 0;
    if (flags & PROGRESS_TTY) p->tty = 1;
    else if (flags & PROGRESS_PLAIN) p->tty = 0;
    else p->tty = isatty(fileno(p->out));
    p->start = p->last_draw = progress__now();
    p->last_percent = -1;
    p->last_decile = 0;
    if (!p->quiet && p->tty) progress__draw(p, p->start, 0);
}

void progress_begin(progress *p, const char *label, uint64_t total) {
    progress_begin_ex(p, label, total, 0, NULL);
}

static void progress__maybe_draw(progress *p) {
    if (p->quiet || p->ended) return;
    double now = progress__now();
    if (p->tty) {
        int percent = p->total ? (int)((p->done > p->total ? p->total : p->done) * 100 / p->total) : -2;
        if (percent != p->last_percent || now - p->last_draw >= 0.5) progress__draw(p, now, 0);
    } else {
        int decile = p->total ? (int)((p->done > p->total ? p->total : p->done) * 10 / p->total) : 0;
        if ((p->total && decile > p->last_decile && decile < 10) || now - p->last_draw >= 2.0)
            progress__draw(p, now, 0);
    }
}

void progress_update(progress *p, uint64_t done) {
    pthread_mutex_lock(&p->mutex);
    if (done > p->done) {
        p->done = done;
        progress__maybe_draw(p);
    }
    pthread_mutex_unlock(&p->mutex);
}

void progress_add(progress *p, uint64_t n) {
    pthread_mutex_lock(&p->mutex);
    p->done += n;
    progress__maybe_draw(p);
    pthread_mutex_unlock(&p->mutex);
}

void progress_end(progress *p) {
    pthread_mutex_lock(&p->mutex);
    if (!p->quiet && !p->ended) progress__draw(p, progress__now(), 1);
    p->ended = 1;
    pthread_mutex_unlock(&p->mutex);
    pthread_mutex_destroy(&p->mutex);
}

/* ---- threads --------------------------------------------------------------------------------- */

uint32_t cpu_count(void) {
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    if (n < 1) return 1;
    if (n > 1024) return 1024;
    return (uint32_t)n;
}

double memory_bytes(void) {
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGESIZE)
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    if (pages > 0 && size > 0) return (double)pages * (double)size;
#endif
    return 0.0;
}

typedef struct pf__shared {
    pthread_mutex_t mutex;
    uint32_t next, count;
    void (*fn)(void *user, uint32_t index, uint32_t thread);
    void *user;
} pf__shared;

typedef struct pf__worker {
    pf__shared *shared;
    uint32_t thread;
    pthread_t handle;
} pf__worker;

static void pf__run(pf__shared *s, uint32_t thread) {
    for (;;) {
        pthread_mutex_lock(&s->mutex);
        uint32_t i = s->next;
        if (i < s->count) s->next = i + 1;
        pthread_mutex_unlock(&s->mutex);
        if (i >= s->count) return;
        s->fn(s->user, i, thread);
    }
}

static void *pf__main(void *arg) {
    pf__worker *w = (pf__worker *)arg;
    pf__run(w->shared, w->thread);
    return NULL;
}

int parallel_for(uint32_t threads, uint32_t count, void (*fn)(void *user, uint32_t index, uint32_t thread),
                 void *user) {
    if (count == 0) return 0;
    if (threads == 0) threads = cpu_count();
    if (threads > count) threads = count;
    if (threads <= 1) {
        for (uint32_t i = 0; i < count; ++i) fn(user, i, 0);
        return 0;
    }
    pf__shared s;
    pthread_mutex_init(&s.mutex, NULL);
    s.next = 0;
    s.count = count;
    s.fn = fn;
    s.user = user;
    pf__worker *workers = (pf__worker *)calloc(threads, sizeof(pf__worker));
    uint32_t started = 0;
    if (workers) {
        for (uint32_t t = 1; t < threads; ++t) {
            workers[t].shared = &s;
            workers[t].thread = t;
            if (pthread_create(&workers[t].handle, NULL, pf__main, &workers[t]) != 0) break;
            started = t;
        }
    }
    pf__run(&s, 0);
    for (uint32_t t = 1; t <= started; ++t) pthread_join(workers[t].handle, NULL);
    free(workers);
    pthread_mutex_destroy(&s.mutex);
    return 0;
}

/* ---- option parsing -------------------------------------------------------------------------- */

int parse_threads(const char *s, uint32_t *out) {
    if (!s || !*s) return -1;
    uint32_t v = 0;
    for (const char *c = s; *c; ++c) {
        if (*c < '0' || *c > '9') return -1;
        v = v * 10 + (uint32_t)(*c - '0');
        if (v > 1024) return -1;
    }
    *out = v;
    return 0;
}

int parse_float(const char *s, float *out) {
    if (!s) return -1;
    /* Grammar: [+-] (digits [. digits*] | . digits) [(e|E) [+-] digits] - no hex, nan, inf, spaces. */
    const char *c = s;
    if (*c == '+' || *c == '-') ++c;
    int digits = 0;
    while (*c >= '0' && *c <= '9') ++c, ++digits;
    if (*c == '.') {
        ++c;
        while (*c >= '0' && *c <= '9') ++c, ++digits;
    }
    if (!digits) return -1;
    if (*c == 'e' || *c == 'E') {
        ++c;
        if (*c == '+' || *c == '-') ++c;
        if (*c < '0' || *c > '9') return -1;
        while (*c >= '0' && *c <= '9') ++c;
    }
    if (*c) return -1;
    char *end = NULL;
    double d = strtod(s, &end);
    if (end != c) return -1; /* e.g. a locale with ',' as the decimal point */
    float f = (float)d;
    if (!isfinite(d) || !isfinite(f)) return -1;
    *out = f;
    return 0;
}

int parse_floats(char **argv, int at, int argc, int n, float *out) {
    int k;
    if (at < 0 || n < 0 || at + n > argc) return -1;
    for (k = 0; k < n; ++k)
        if (parse_float(argv[at + k], out + k)) return -1;
    return 0;
}

int tool_usage_error(const char *tool, const char *fmt, ...) {
    va_list ap;
    fprintf(stderr, "%s: ", tool);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\n(see %s --help)\n", tool);
    return 2;
}

/* ---- PNG ------------------------------------------------------------------------------------- */

uint32_t tool_crc32(uint32_t crc, const void *data, size_t size) {
    const uint8_t *p = (const uint8_t *)data;
    crc = ~crc;
    for (size_t i = 0; i < size; ++i) {
        crc ^= p[i];
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

uint32_t tool_adler32(uint32_t adler, const void *data, size_t size) {
    const uint8_t *p = (const uint8_t *)data;
    uint32_t a = adler & 0xffff, b = adler >> 16;
    while (size > 0) {
        size_t n = size < 5552 ? size : 5552;
        size -= n;
        while (n--) {
            a += *p++;
            b += a;
        }
        a %= 65521;
        b %= 65521;
    }
    return (b << 16) | a;
}

typedef struct png__bits {
    uint8_t *out;
    size_t len;
    uint64_t buf;
    int count;
} png__bits;

static void png__put(png__bits *b, uint32_t value, int nbits) { /* LSB-first, as deflate packs */
    b->buf |= (uint64_t)value << b->count;
    b->count += nbits;
    while (b->count >= 8) {
        b->out[b->len++] = (uint8_t)b->buf;
        b->buf >>= 8;
        b->count -= 8;
    }
}

static void png__put_huff(png__bits *b, uint32_t code, int nbits) { /* Huffman codes go MSB-first */
    uint32_t r = 0;
    for (int i = 0; i < nbits; ++i) r |= ((code >> i) & 1u) << (nbits - 1 - i);
    png__put(b, r, nbits);
}

static void png__literal(png__bits *b, uint32_t sym) {
    if (sym < 144) png__put_huff(b, 0x30 + sym, 8);
    else if (sym < 256) png__put_huff(b, 0x190 + sym - 144, 9);
    else if (sym < 280) png__put_huff(b, sym - 256, 7);
    else png__put_huff(b, 0xC0 + sym - 280, 8);
}

static const uint16_t png__len_base[29] = {3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27,
                                           31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
static const uint8_t png__len_extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                           2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
static const uint16_t png__dist_base[30] = {1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129,
                                            193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097,
                                            6145, 8193, 12289, 16385, 24577};
static const uint8_t png__dist_extra[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6,
                                            6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

static void png__match(png__bits *b, uint32_t len, uint32_t dist) {
    int lc = 28;
    while (png__len_base[lc] > len) --lc;
    png__literal(b, 257 + (uint32_t)lc);
    png__put(b, len - png__len_base[lc], png__len_extra[lc]);
    int dc = 29;
    while (png__dist_base[dc] > dist) --dc;
    png__put_huff(b, (uint32_t)dc, 5);
    png__put(b, dist - png__dist_base[dc], png__dist_extra[dc]);
}

#define PNG__HASH_BITS 15
#define PNG__WINDOW 32768u

static uint32_t png__hash(const uint8_t *p) {
    uint32_t v = (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16);
    return (v * 2654435761u) >> (32 - PNG__HASH_BITS);
}

/* Deflate `raw` as one fixed-Huffman block (or stored blocks) into out (capacity checked by caller).
   Match candidates: the hash head of the next 3 bytes, the previous pixel and the row above. */
static int png__deflate(const uint8_t *raw, size_t n, size_t stride, int stored, uint8_t *out, size_t *outlen) {
    png__bits b = {out, 0, 0, 0};
    if (stored) {
        size_t pos = 0;
        do {
            size_t chunk = n - pos > 65535 ? 65535 : n - pos;
            int last = pos + chunk == n;
            png__put(&b, last ? 1u : 0u, 1);
            png__put(&b, 0, 2);
            if (b.count) png__put(&b, 0, 8 - b.count);
            png__put(&b, (uint32_t)chunk, 16);
            png__put(&b, (uint32_t)chunk ^ 0xffffu, 16);
            memcpy(b.out + b.len, raw + pos, chunk);
            b.len += chunk;
            pos += chunk;
        } while (pos < n);
        *outlen = b.len;
        return 0;
    }
    int32_t *head = (int32_t *)malloc(sizeof(int32_t) << PNG__HASH_BITS);
    if (!head) return -1;
    for (size_t i = 0; i < ((size_t)1 << PNG__HASH_BITS); ++i) head[i] = -1;
    png__put(&b, 1, 1); /* BFINAL */
    png__put(&b, 1, 2); /* BTYPE = fixed Huffman */
    size_t pos = 0;
    while (pos < n) {
        uint32_t best_len = 0, best_dist = 0;
        if (n - pos >= 3) {
            size_t maxlen = n - pos < 258 ? n - pos : 258;
            size_t cand[3];
            int nc = 0;
            uint32_t h = png__hash(raw + pos);
            if (head[h] >= 0) cand[nc++] = (size_t)head[h];
            if (pos >= 4) cand[nc++] = pos - 4;
            if (stride <= PNG__WINDOW && pos >= stride) cand[nc++] = pos - stride;
            for (int c = 0; c < nc; ++c) {
                size_t from = cand[c];
                if (from >= pos || pos - from > PNG__WINDOW) continue;
                size_t l = 0;
                while (l < maxlen && raw[from + l] == raw[pos + l]) ++l;
                if (l >= 3 && l > best_len) {
                    best_len = (uint32_t)l;
                    best_dist = (uint32_t)(pos - from);
                }
            }
            head[h] = (int32_t)pos;
        }
        if (best_len >= 3) {
            png__match(&b, best_len, best_dist);
            /* Index a few positions inside the match so later data can refer to it. */
            size_t end = pos + best_len;
            for (size_t q = pos + 1; q < end && q + 3 <= n; q += (best_len > 32 ? 16 : 1))
                head[png__hash(raw + q)] = (int32_t)q;
            pos = end;
        } else {
            png__literal(&b, raw[pos]);
            ++pos;
        }
    }
    png__literal(&b, 256); /* end of block */
    if (b.count) png__put(&b, 0, 8 - b.count);
    free(head);
    *outlen = b.len;
    return 0;
}

static void png__be32(uint8_t *p, uint32_t v) {
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

/* Appends a chunk (length, type, data, CRC) at out. Returns bytes written. */
static size_t png__chunk(uint8_t *out, const char *type, const uint8_t *data, uint32_t len) {
    png__be32(out, len);
    memcpy(out + 4, type, 4);
    if (len) memmove(out + 8, data, len);
    png__be32(out + 8 + len, tool_crc32(0, out + 4, (size_t)len + 4));
    return (size_t)len + 12;
}

/* Filtered value (0..255) of byte i of row cur (previous row up, NULL on the first row). */
static int png__filter_byte(int type, const uint8_t *cur, const uint8_t *up, size_t i) {
    int a = i >= 4 ? cur[i - 4] : 0, b = up ? up[i] : 0, c = up && i >= 4 ? up[i - 4] : 0, pred = 0;
    switch (type) {
    case 1: pred = a; break;
    case 2: pred = b; break;
    case 3: pred = (a + b) / 2; break;
    case 4: {
        int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
        pred = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
        break;
    }
    default: break;
    }
    return (cur[i] - pred) & 0xff;
}

int png_encode(const uint8_t *rgba, uint32_t w, uint32_t h, int stored, uint8_t **png, size_t *size) {
    *png = NULL;
    *size = 0;
    if (w == 0 || h == 0 || w > 0x7fffffffu || h > 0x7fffffffu) return -1;
    uint64_t stride = 1 + 4 * (uint64_t)w, rawsize = stride * h;
    if (rawsize > (uint64_t)(SIZE_MAX / 2) - 65536) return -1;
    size_t n = (size_t)rawsize;
    uint8_t *raw = (uint8_t *)malloc(n);
    if (!raw) return -1;
    /* Per row, the filter (none, sub, up, average, paeth) with the smallest sum of |signed bytes|
       (the usual heuristic); the stored variant keeps filter 0 so the bytes stay readable. */
    size_t rb = (size_t)4 * w;
    for (uint32_t y = 0; y < h; ++y) {
        const uint8_t *cur = rgba + (size_t)y * rb, *up = y ? cur - rb : NULL;
        uint8_t *dst = raw + (size_t)y * stride;
        uint64_t best_cost = UINT64_MAX;
        int nfilters = stored ? 1 : 5;
        for (int ft = 0; ft < nfilters; ++ft) {
            uint64_t cost = 0;
            for (size_t i = 0; i < rb && cost < best_cost; ++i) {
                int v = png__filter_byte(ft, cur, up, i);
                cost += (uint64_t)(v < 128 ? v : 256 - v);
            }
            if (cost < best_cost) {
                best_cost = cost;
                dst[0] = (uint8_t)ft;
            }
        }
        for (size_t i = 0; i < rb; ++i) dst[1 + i] = (uint8_t)png__filter_byte(dst[0], cur, up, i);
    }
    /* Worst cases: fixed Huffman <= 9 bits per byte; stored adds 5 bytes per 65535. */
    size_t zcap = n + n / 8 + 5 * (n / 65535 + 1) + 64;
    size_t idat_max = (size_t)1 << 30; /* split IDAT into chunks of at most 1 GiB */
    size_t chunks = zcap / idat_max + 1;
    size_t cap = 8 + 25 + zcap + 12 * chunks + 12 + 8;
    uint8_t *out = (uint8_t *)malloc(cap);
    if (!out) {
        free(raw);
        return -1;
    }
    /* Compress into the tail area, then move into chunks (chunk headers are inserted before). */
    uint8_t *z = out + cap - zcap - 8; /* leave room; chunks are built front-to-back with memmove */
    z[0] = 0x78; /* CMF: deflate, 32K window */
    z[1] = 0x01; /* FLG: check bits, fastest */
    size_t zlen = 0;
    if (png__deflate(raw, n, (size_t)stride, stored, z + 2, &zlen)) {
        free(raw);
        free(out);
        return -1;
    }
    zlen += 2;
    png__be32(z + zlen, tool_adler32(1, raw, n));
    zlen += 4;
    free(raw);
    static const uint8_t sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    size_t o = 0;
    memcpy(out, sig, 8);
    o += 8;
    uint8_t ihdr[13];
    png__be32(ihdr, w);
    png__be32(ihdr + 4, h);
    ihdr[8] = 8;  /* bit depth */
    ihdr[9] = 6;  /* RGBA */
    ihdr[10] = 0; /* deflate */
    ihdr[11] = 0; /* adaptive filtering */
    ihdr[12] = 0; /* no interlace */
    o += png__chunk(out + o, "IHDR", ihdr, 13);
    /* The zlib data sits after the write position with a gap of at least 8 + 12*chunks bytes, so
       moving it forward chunk by chunk never overwrites unread data. */
    size_t zpos = 0;
    while (zpos < zlen) {
        size_t len = zlen - zpos > idat_max ? idat_max : zlen - zpos;
        o += png__chunk(out + o, "IDAT", z + zpos, (uint32_t)len);
        zpos += len;
    }
    o += png__chunk(out + o, "IEND", NULL, 0);
    *png = out;
    *size = o;
    return 0;
}

int png_write(const char *path, const uint8_t *rgba, uint32_t w, uint32_t h, tool_error *err) {
    uint8_t *png;
    size_t size;
    if (png_encode(rgba, w, h, 0, &png, &size)) {
        tool_error_set(err, path, 0, "cannot encode a %ux%u PNG (empty, too large or out of memory)", w, h);
        return -1;
    }
    int r = write_file_atomic(path, png, size, err);
    free(png);
    return r;
}

/* ---- text ------------------------------------------------------------------------------------ */

/* 5x7 glyphs for ' '..'`' and '{'..'~'; one byte per row, bit 4 = leftmost column. */
static const uint8_t font__upper[65][7] = {
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}, /*   */
    {0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x04}, /* ! */
    {0x0A, 0x0A, 0x0A, 0x00, 0x00, 0x00, 0x00}, /* " */
    {0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A}, /* # */
    {0x04, 0x0F, 0x14, 0x0E, 0x05, 0x1E, 0x04}, /* $ */
    {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}, /* % */
    {0x0C, 0x12, 0x14, 0x08, 0x15, 0x12, 0x0D}, /* & */
    {0x0C, 0x04, 0x08, 0x00, 0x00, 0x00, 0x00}, /* ' */
    {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}, /* ( */
    {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}, /* ) */
    {0x00, 0x04, 0x15, 0x0E, 0x15, 0x04, 0x00}, /* * */
    {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}, /* + */
    {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}, /* , */
    {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}, /* - */
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}, /* . */
    {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}, /* / */
    {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}, /* 0 */
    {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}, /* 1 */
    {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}, /* 2 */
    {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}, /* 3 */
    {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}, /* 4 */
    {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}, /* 5 */
    {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}, /* 6 */
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}, /* 7 */
    {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}, /* 8 */
    {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}, /* 9 */
    {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}, /* : */
    {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x04, 0x08}, /* ; */
    {0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02}, /* < */
    {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}, /* = */
    {0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08}, /* > */
    {0x0E, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04}, /* ? */
    {0x0E, 0x11, 0x01, 0x0D, 0x15, 0x15, 0x0E}, /* @ */
    {0x0E, 0x11, 0x11, 0x11, 0x1F, 0x11, 0x11}, /* A */
    {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}, /* B */
    {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}, /* C */
    {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}, /* D */
    {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}, /* E */
    {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}, /* F */
    {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}, /* G */
    {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}, /* H */
    {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}, /* I */
    {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}, /* J */
    {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}, /* K */
    {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}, /* L */
    {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}, /* M */
    {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}, /* N */
    {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}, /* O */
    {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}, /* P */
    {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}, /* Q */
    {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}, /* R */
    {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}, /* S */
    {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}, /* T */
    {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}, /* U */
    {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}, /* V */
    {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}, /* W */
    {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}, /* X */
    {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}, /* Y */
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}, /* Z */
    {0x0E, 0x08, 0x08, 0x08, 0x08, 0x08, 0x0E}, /* [ */
    {0x00, 0x10, 0x08, 0x04, 0x02, 0x01, 0x00}, /* \ */
    {0x0E, 0x02, 0x02, 0x02, 0x02, 0x02, 0x0E}, /* ] */
    {0x04, 0x0A, 0x11, 0x00, 0x00, 0x00, 0x00}, /* ^ */
    {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}, /* _ */
    {0x08, 0x04, 0x02, 0x00, 0x00, 0x00, 0x00}, /* ` */
};
static const uint8_t font__braces[4][7] = {
    {0x02, 0x04, 0x04, 0x08, 0x04, 0x04, 0x02}, /* { */
    {0x04, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}, /* | */
    {0x08, 0x04, 0x04, 0x02, 0x04, 0x04, 0x08}, /* } */
    {0x00, 0x00, 0x08, 0x15, 0x02, 0x00, 0x00}, /* ~ */
};

static const uint8_t *font__glyph(unsigned char c) {
    if (c >= 'a' && c <= 'z') c = (unsigned char)(c - 'a' + 'A');
    if (c >= ' ' && c <= '`') return font__upper[c - ' '];
    if (c >= '{' && c <= '~') return font__braces[c - '{'];
    return font__upper['?' - ' '];
}

int draw_text_scaled(uint8_t *rgba, uint32_t w, uint32_t h, int x, int y, const char *text, uint32_t color,
                     int scale) {
    if (scale < 1) scale = 1;
    uint8_t col[4] = {(uint8_t)(color >> 24), (uint8_t)(color >> 16), (uint8_t)(color >> 8), (uint8_t)color};
    int cx = x, cy = y, widest = 0;
    for (const unsigned char *s = (const unsigned char *)text; *s; ++s) {
        if (*s == '\n') {
            cx = x;
            cy += 9 * scale;
            continue;
        }
        const uint8_t *g = font__glyph(*s);
        for (int row = 0; row < 7; ++row)
            for (int colm = 0; colm < 5; ++colm) {
                if (!(g[row] & (0x10 >> colm))) continue;
                for (int dy = 0; dy < scale; ++dy)
                    for (int dx = 0; dx < scale; ++dx) {
                        long px = (long)cx + (long)(colm * scale + dx), py = (long)cy + (long)(row * scale + dy);
                        if (px < 0 || py < 0 || px >= (long)w || py >= (long)h) continue;
                        memcpy(rgba + ((size_t)py * w + (size_t)px) * 4, col, 4);
                    }
            }
        cx += 6 * scale;
        if (cx - x > widest) widest = cx - x;
    }
    return widest;
}

int draw_text(uint8_t *rgba, uint32_t w, uint32_t h, int x, int y, const char *text, uint32_t color) {
    return draw_text_scaled(rgba, w, h, x, y, text, color, 1);
}
