/*
 * file_io.c — the cache files' shared header (file_io.h).
 */
#include "cache/file_io.h"

#include <errno.h>

FILE *file_open(const char *path, const char *mode, const char *what, char *msg, size_t msg_size)
{
    FILE *f = fopen(path, mode);
    if (!f)
        snprintf(msg, msg_size, "cannot %s the %s file %s: %s", mode[0] == 'w' ? "write" : "read", what, path,
                 strerror(errno));
    return f;
}

phos_status file_finish_write(FILE *f, int ok, const char *path, const char *what, char *msg, size_t msg_size)
{
    if (fclose(f) != 0)
        ok = 0;
    if (ok)
        return PHOS_OK;
    snprintf(msg, msg_size, "could not write all of the %s file %s", what, path);
    return PHOS_ERROR_INVALID_ARGUMENT;
}

phos_status file_finish_read(FILE *f, const char *why, const char *path, const char *what, char *msg,
                             size_t msg_size)
{
    fclose(f);
    if (!why)
        return PHOS_OK;
    snprintf(msg, msg_size, "the %s file %s is not used: %s", what, path, why);
    return PHOS_ERROR_INVALID_ARGUMENT;
}

int file_write_header(FILE *f, const char magic[8], uint32_t version, const scene *s, const uint32_t *settings,
                      uint32_t count)
{
    scene_fingerprint fp = scene_fingerprint_of(s);
    int ok = fwrite(magic, 1, 8, f) == 8 && file_write_u32(f, version) && file_write_u64(f, fp.geometry) &&
             file_write_u64(f, fp.materials) && file_write_u64(f, fp.lights) && file_write_u32(f, count);
    for (uint32_t i = 0; ok && i < count; i++)
        ok = file_write_u32(f, settings[i]);
    return ok;
}

const char *file_check_header(FILE *f, const char magic[8], uint32_t version, const char *what, const scene *s,
                              const uint32_t *settings, const char *const *names, uint32_t count, char *detail,
                              size_t detail_size)
{
    char m[8];
    uint32_t v = 0, n = 0;
    if (fread(m, 1, 8, f) != 8 || memcmp(m, magic, 8) != 0) {
        snprintf(detail, detail_size, "it is not a Phos %s file", what);
        return detail;
    }
    if (!file_read_u32(f, &v) || v != version) {
        snprintf(detail, detail_size, "it is of format version %u, this Phos reads version %u", v, version);
        return detail;
    }
    scene_fingerprint fp = scene_fingerprint_of(s), file;
    if (!file_read_u64(f, &file.geometry) || !file_read_u64(f, &file.materials) || !file_read_u64(f, &file.lights))
        return "it ends in its header";
    if (file.geometry != fp.geometry)
        return "it was made for other geometry (meshes or their placement differ)";
    if (file.materials != fp.materials)
        return "it was made for other materials (closures or images differ)";
    if (file.lights != fp.lights)
        return "it was made for other lights (lamps or the world differ)";
    if (!file_read_u32(f, &n) || n != count)
        return "its settings block does not match this version";
    for (uint32_t i = 0; i < count; i++) {
        uint32_t w;
        if (!file_read_u32(f, &w))
            return "it ends in its header";
        if (w != settings[i]) {
            snprintf(detail, detail_size, "it was made with another %s", names[i]);
            return detail;
        }
    }
    return NULL;
}
