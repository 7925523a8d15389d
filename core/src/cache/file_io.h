/*
 * file_io.h — the little-endian words and the header every cache file of
 * Phos shares (docs/cache_files.md): magic, version, the scene's
 * fingerprint, then the settings the cache depends on, each compared on
 * reading so that a refusal can name what differs.
 */
#ifndef PHOS_FILE_IO_H
#define PHOS_FILE_IO_H

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "cache/fingerprint.h"
#include "phos.h"

static inline int file_write_u32(FILE *f, uint32_t v)
{
    unsigned char b[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16),
                          (unsigned char)(v >> 24)};
    return fwrite(b, 1, 4, f) == 4;
}

static inline int file_read_u32(FILE *f, uint32_t *v)
{
    unsigned char b[4];
    if (fread(b, 1, 4, f) != 4)
        return 0;
    *v = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    return 1;
}

static inline int file_write_u64(FILE *f, uint64_t v)
{
    return file_write_u32(f, (uint32_t)v) && file_write_u32(f, (uint32_t)(v >> 32));
}

static inline int file_read_u64(FILE *f, uint64_t *v)
{
    uint32_t lo, hi;
    if (!file_read_u32(f, &lo) || !file_read_u32(f, &hi))
        return 0;
    *v = (uint64_t)hi << 32 | lo;
    return 1;
}

static inline uint32_t file_float_bits(float x)
{
    uint32_t v;
    memcpy(&v, &x, 4);
    return v;
}

static inline float file_bits_float(uint32_t v)
{
    float x;
    memcpy(&x, &v, 4);
    return x;
}

/* Opens `path` ("wb" or "rb"); NULL with a message ("cannot write the
 * photon map file …: No such file or directory") on failure. `what`
 * names the file's kind. */
FILE *file_open(const char *path, const char *mode, const char *what, char *msg, size_t msg_size);

/* Closes a file written with ok = every write succeeded; PHOS_OK, or an
 * error with a message. */
phos_status file_finish_write(FILE *f, int ok, const char *path, const char *what, char *msg, size_t msg_size);

/* Closes a file read; why is NULL if it was read whole and used, else the
 * reason it is not, put in the message. */
phos_status file_finish_read(FILE *f, const char *why, const char *path, const char *what, char *msg,
                             size_t msg_size);

/* The header: magic (8 bytes), version, fingerprint, then `count` setting
 * words. 1 when written whole. */
int file_write_header(FILE *f, const char magic[8], uint32_t version, const scene *s, const uint32_t *settings,
                      uint32_t count);

/* Reads and checks a header written by file_write_header: NULL if it
 * matches, else why not ("it was made for other lights", "it was made
 * with another seed"), naming setting i by names[i]; detail holds the
 * text where it is composed. */
const char *file_check_header(FILE *f, const char magic[8], uint32_t version, const char *what, const scene *s,
                              const uint32_t *settings, const char *const *names, uint32_t count, char *detail,
                              size_t detail_size);

#endif /* PHOS_FILE_IO_H */
