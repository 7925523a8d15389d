// bench_kdtree — Phos's photon-map kd-tree (core/src/photons/kdtree.c)
// against nanoflann's KDTreeSingleIndexAdaptor on the same photons, in the
// same run, on one thread.
//
// Reports build time, k-nearest queries per second (k = 50 and 500 with a
// maximum radius, the photon map's radiance-estimate query), the ratio,
// bytes per photon, and the peak memory a build adds (measured in a forked
// child, from its VmHWM over its VmRSS at the start). The two searches must return the same number of photons and
// the same final radius² for every query (both accept d² < r² strictly and
// compute d² in the same float order); the count of agreeing queries is
// printed. Times are the best of 3 runs; nothing is asserted about them.
//
// The queries are timed in two orders. In random order each query finds
// the tree cold in cache, so memory latency dominates, and how much of one
// structure stays cached across the 3 runs depends on the query count. In
// a render's order (sorted along a Morton curve, as a tile's pixels are
// near each other) consecutive queries share their cells, so the figure
// is the search's own work.
//
//   bench_kdtree [--photons N] [--queries Q] [--k K] [--input FILE]... [--csv FILE]
//
// --input reads raw 20-byte photon records (bench_core dump FILE N: the
// Cornell box's global map), queried at stored photons' positions; without
// it, synthetic photons on a box and on a room with two spheres.
//
// C++ only because nanoflann is a C++ header; Phos itself is C11.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <nanoflann.hpp>

#include "photons/kdtree.h"
#include "photons/photon.h"
#include "sampling/sampler.h"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0)
{
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Rng {
    uint32_t state;
    float next()
    {
        state = hash_u32(state + 0x9e3779b9U);
        return u32_to_unit_float(state);
    }
};

// ---- photon sets ----------------------------------------------------------

// A point on the six faces of the unit cube: where photons land in a room.
vec3 on_box(Rng &r)
{
    int face = std::min(5, (int)(r.next() * 6.0f));
    float u = r.next(), v = r.next(), w = (face & 1) ? 1.0f : 0.0f;
    return face < 2 ? v3(w, u, v) : face < 4 ? v3(u, w, v) : v3(u, v, w);
}

// The Cornell-like room: the box's faces plus two spheres standing in it
// (one photon in three on the spheres).
vec3 on_room(Rng &r)
{
    if (r.next() < 2.0f / 3.0f)
        return on_box(r);
    float z = 1.0f - 2.0f * r.next(), phi = 2.0f * PHOS_PI * r.next();
    float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
    vec3 d = v3(s * std::cos(phi), s * std::sin(phi), z);
    return r.next() < 0.5f ? v3_madd(v3(0.3f, 0.35f, 0.2f), d, 0.2f) : v3_madd(v3(0.7f, 0.6f, 0.25f), d, 0.25f);
}

struct Scenario {
    const char *name;
    vec3 (*point)(Rng &);
};

std::vector<photon> make_photons(const Scenario &sc, size_t n, uint32_t seed)
{
    std::vector<photon> p(n);
    Rng r{seed};
    for (size_t i = 0; i < n; i++) {
        vec3 pos = sc.point(r);
        vec3 power = v3(r.next(), r.next(), r.next());
        p[i] = photon_make(pos, v3_scale(power, 1e-6f), v3(0.0f, 0.0f, -1.0f), v3(0.0f, 0.0f, 1.0f), 0);
    }
    return p;
}

std::vector<photon> read_photons(const char *path)
{
    std::vector<photon> p;
    FILE *f = std::fopen(path, "rb");
    if (!f) {
        std::fprintf(stderr, "bench_kdtree: cannot read %s\n", path);
        std::exit(1);
    }
    photon rec;
    while (std::fread(&rec, sizeof rec, 1, f) == 1)
        p.push_back(rec);
    std::fclose(f);
    return p;
}

// kB from a /proc/self/status line ("VmRSS:", "VmHWM:").
long status_kb(const char *key)
{
    FILE *f = std::fopen("/proc/self/status", "r");
    char line[256];
    long kb = -1;
    while (f && std::fgets(line, sizeof line, f))
        if (std::strncmp(line, key, std::strlen(key)) == 0)
            kb = std::strtol(line + std::strlen(key), nullptr, 10);
    if (f)
        std::fclose(f);
    return kb;
}

// Bytes of memory the build f adds at its peak, in a forked child so that
// the two structures' peaks are measured apart (−1 if it cannot fork).
template <class F> long peak_bytes(F f)
{
    int fds[2];
    if (pipe(fds) != 0)
        return -1;
    pid_t pid = fork();
    if (pid == 0) {
        long before = status_kb("VmRSS:");
        f();
        long peak = status_kb("VmHWM:");
        long delta = (peak - before) * 1024;
        ssize_t w = write(fds[1], &delta, sizeof delta);
        (void)w;
        _exit(0);
    }
    long delta = -1;
    if (pid > 0) {
        ssize_t r = read(fds[0], &delta, sizeof delta);
        if (r != (ssize_t)sizeof delta)
            delta = -1;
        waitpid(pid, nullptr, 0);
    }
    close(fds[0]);
    close(fds[1]);
    return delta;
}

// ---- nanoflann ------------------------------------------------------------

// Positions only, 12 bytes per point: what nanoflann indexes.
struct Cloud {
    std::vector<float> xyz;
    size_t kdtree_get_point_count() const { return xyz.size() / 3; }
    float kdtree_get_pt(size_t i, size_t d) const { return xyz[3 * i + d]; }
    template <class Box> bool kdtree_get_bbox(Box &) const { return false; }
};

using NanoTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud, 3, uint32_t>;

// KNNResultSet with a maximum radius: its worst distance starts at r²
// instead of +max, so only photons with d² < r² are taken, as in Phos.
struct KnnWithin : nanoflann::KNNResultSet<float, uint32_t, uint32_t> {
    KnnWithin(uint32_t k, uint32_t *index, float *dist2, float r2) : KNNResultSet(k)
    {
        init(index, dist2);
        dist2[k - 1] = r2;
    }
};

// ---- measurements ---------------------------------------------------------

struct Result {
    double build_s;
    double build_all_cores_s; // Phos only: photon_map_build_many on every core
    double qps;
    size_t bytes;
    long peak;
    std::vector<uint32_t> found;
    std::vector<float> radius2;
};

template <class F> double best_of(int reps, F f)
{
    double best = 1e30;
    for (int i = 0; i < reps; i++)
        best = std::min(best, f());
    return best;
}

// Queries per second of search(x, q) (best of 3), each query's count and
// final radius² kept for the comparison with nanoflann.
template <class Search>
void time_queries(const std::vector<vec3> &queries, uint32_t k, Result &res, Search search)
{
    kdtree_query q;
    kdtree_query_init(&q, k);
    res.found.resize(queries.size());
    res.radius2.resize(queries.size());
    double t = best_of(3, [&] {
        auto t0 = Clock::now();
        for (size_t i = 0; i < queries.size(); i++) {
            res.found[i] = search(queries[i], &q);
            res.radius2[i] = q.radius2;
        }
        return seconds_since(t0);
    });
    res.qps = (double)queries.size() / t;
    kdtree_query_free(&q);
}

// A photon map over `photons` (its build timed, best of 3) and its
// unfiltered k-nearest search.
void run_map(const std::vector<photon> &photons, const std::vector<vec3> &queries, uint32_t k, float r2,
             Result &res)
{
    photon_map map;
    photon_map_init(&map);
    res.build_s = best_of(3, [&] {
        photon_map_free(&map);
        photon_map_init(&map);
        photon_map_reserve(&map, (uint32_t)photons.size());
        photon_map_append(&map, photons.data(), (uint32_t)photons.size());
        auto t0 = Clock::now();
        photon_map_build(&map, NULL);
        return seconds_since(t0);
    });
    res.build_all_cores_s = best_of(3, [&] {
        photon_map_free(&map);
        photon_map_init(&map);
        photon_map_reserve(&map, (uint32_t)photons.size());
        photon_map_append(&map, photons.data(), (uint32_t)photons.size());
        photon_map *const maps[1] = {&map};
        auto t0 = Clock::now();
        photon_map_build_many(maps, 1, 0, NULL);
        return seconds_since(t0);
    });
    res.bytes = photon_map_memory(&map);
    res.peak = peak_bytes([&] {
        photon_map m2;
        photon_map_init(&m2);
        photon_map_reserve(&m2, (uint32_t)photons.size());
        photon_map_append(&m2, photons.data(), (uint32_t)photons.size());
        photon_map_build(&m2, NULL);
    });

    time_queries(queries, k, res, [&](vec3 x, kdtree_query *q) { return photon_map_knn(&map, x, r2, q); });
    photon_map_free(&map);
}

// The photons as they are: a map sorts them into its classes (facing and
// flags, photon.h), and its root splits by class.
void run_phos(const std::vector<photon> &photons, const std::vector<vec3> &queries, uint32_t k, float r2,
              Result &res)
{
    run_map(photons, queries, k, r2, res);
}

// The same positions as photons of one class (normal +z, no flags), so the
// map is one spatial tree: the structure nanoflann is compared with.
void run_tree(const std::vector<photon> &photons, const std::vector<vec3> &queries, uint32_t k, float r2,
              Result &res)
{
    std::vector<photon> one_class = photons;
    uint16_t up = (uint16_t)(normal_encode(v3(0.0f, 0.0f, 1.0f)) << PHOTON_NORMAL_SHIFT);
    for (photon &p : one_class)
        p.flags = up;
    run_map(one_class, queries, k, r2, res);
}

void run_nanoflann(const std::vector<photon> &photons, const std::vector<vec3> &queries, uint32_t k, float r2,
                   Result &res)
{
    Cloud cloud;
    cloud.xyz.resize(photons.size() * 3);
    for (size_t i = 0; i < photons.size(); i++)
        std::memcpy(&cloud.xyz[3 * i], photons[i].position, sizeof(float) * 3);

    NanoTree *tree = nullptr;
    res.build_s = best_of(3, [&] {
        delete tree;
        auto t0 = Clock::now();
        tree = new NanoTree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
        return seconds_since(t0);
    });
    res.bytes = tree->usedMemory(*tree) + cloud.xyz.size() * sizeof(float);
    res.peak = peak_bytes([&] {
        Cloud c2;
        c2.xyz.resize(photons.size() * 3);
        for (size_t i = 0; i < photons.size(); i++)
            std::memcpy(&c2.xyz[3 * i], photons[i].position, sizeof(float) * 3);
        NanoTree t2(3, c2, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    });

    std::vector<uint32_t> index(k);
    std::vector<float> dist2(k);
    res.found.resize(queries.size());
    res.radius2.resize(queries.size());
    nanoflann::SearchParams params(32, 0.0f, false); // exact, unsorted like Phos
    double t = best_of(3, [&] {
        auto t0 = Clock::now();
        for (size_t i = 0; i < queries.size(); i++) {
            KnnWithin set(k, index.data(), dist2.data(), r2);
            const float x[3] = {queries[i].x, queries[i].y, queries[i].z};
            tree->findNeighbors(set, x, params);
            res.found[i] = set.size();
            res.radius2[i] = set.worstDist();
        }
        return seconds_since(t0);
    });
    res.qps = (double)queries.size() / t;
    delete tree;
}

// The queries sorted along a Morton (Z-order) curve over their bounding
// box, 21 bits per axis: neighbours in the list are neighbours in space,
// as a render's consecutive searches are.
std::vector<vec3> in_render_order(std::vector<vec3> queries)
{
    vec3 lo = queries[0], hi = queries[0];
    for (vec3 q : queries) {
        lo = v3(std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z));
        hi = v3(std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z));
    }
    auto cell = [](float v, float a, float b) {
        float t = b > a ? (v - a) / (b - a) : 0.0f;
        return (uint64_t)std::min(2097151.0f, std::max(0.0f, t * 2097152.0f));
    };
    auto morton = [&](vec3 v) {
        uint64_t x = cell(v.x, lo.x, hi.x), y = cell(v.y, lo.y, hi.y), z = cell(v.z, lo.z, hi.z), code = 0;
        for (int b = 20; b >= 0; b--)
            code = (code << 3) | (((x >> b) & 1) << 2) | (((y >> b) & 1) << 1) | ((z >> b) & 1);
        return code;
    };
    std::stable_sort(queries.begin(), queries.end(), [&](vec3 a, vec3 b) { return morton(a) < morton(b); });
    return queries;
}

size_t agreeing(const Result &a, const Result &b)
{
    size_t same = 0;
    for (size_t i = 0; i < a.found.size(); i++)
        same += a.found[i] == b.found[i] && a.radius2[i] == b.radius2[i];
    return same;
}

FILE *csv_out;

void bench_photons(const char *name, const std::vector<photon> &photons, const std::vector<vec3> &queries,
                   const std::vector<uint32_t> &ks, const std::vector<float> &radii)
{
    size_t n = photons.size(), nq = queries.size();
    const std::vector<vec3> ordered = in_render_order(queries);
    for (uint32_t k : ks) {
        std::printf("\n%s: %zu photons, %zu queries on the same surfaces, k = %u, 1 thread\n", name, n, nq, k);
        std::printf("  %-30s %14s %14s %10s %14s %10s\n", "", "Phos tree", "nanoflann", "tree/nano", "Phos map",
                    "map/nano");
        bool first = true;
        for (float radius : radii) {
            Result phos, nano, map;
            run_tree(photons, queries, k, radius * radius, phos);
            run_nanoflann(photons, queries, k, radius * radius, nano);
            run_phos(photons, queries, k, radius * radius, map);
            double pb = (double)phos.bytes / (double)n, nb = (double)nano.bytes / (double)n;
            double mb = (double)map.bytes / (double)n;
            if (first) {
                std::printf("  %-30s %14.1f %14.1f %10.2f %14.1f %10.2f\n", "build (ms, best of 3)", 1e3 * phos.build_s,
                            1e3 * nano.build_s, phos.build_s / nano.build_s, 1e3 * map.build_s,
                            map.build_s / nano.build_s);
                std::printf("  %-30s %14.1f %14.1f %10.2f %14.1f %10.2f\n", "build on all cores (ms)",
                            1e3 * phos.build_all_cores_s, 1e3 * nano.build_s, phos.build_all_cores_s / nano.build_s,
                            1e3 * map.build_all_cores_s, map.build_all_cores_s / nano.build_s);
                std::printf("  %-30s %14.2f %14.2f %10.2f %14.2f\n", "bytes per photon", pb, nb, pb / nb, mb);
                std::printf("  %-30s %14s %14.2f %10s\n", "  nanoflann + 8 B payload", "", nb + 8.0, "");
                std::printf("  %-30s %14.1f %14.1f %10s %14.1f\n", "build's peak memory (MB)", phos.peak / 1e6,
                            nano.peak / 1e6, "", map.peak / 1e6);
                first = false;
            }
            size_t filled = 0;
            for (uint32_t f : phos.found)
                filled += f == k;
            char label[64];
            std::snprintf(label, sizeof label, "queries/s (best of 3), r %.2g", (double)radius);
            std::printf("  %-30s %14.0f %14.0f %10.2f %14.0f %10.2f\n", label, phos.qps, nano.qps,
                        phos.qps / nano.qps, map.qps, map.qps / nano.qps);
            std::printf("  %-30s %13.1f%% %14s %10s\n", "  queries that found k", 100.0 * filled / (double)nq, "",
                        "");
            size_t same = agreeing(phos, nano);
            std::printf("  %-30s %14zu %14s %10s %14zu\n", "  results identical", same, "", "", agreeing(map, nano));
            Result nano_ordered, map_ordered;
            run_nanoflann(photons, ordered, k, radius * radius, nano_ordered);
            run_phos(photons, ordered, k, radius * radius, map_ordered);
            std::snprintf(label, sizeof label, "  in a render's order, r %.2g", (double)radius);
            std::printf("  %-30s %14s %14.0f %10s %14.0f %10.2f\n", label, "", nano_ordered.qps, "", map_ordered.qps,
                        map_ordered.qps / nano_ordered.qps);
            std::printf("  %-30s %14s %14s %10s %14zu\n", "  results identical", "", "", "",
                        agreeing(map_ordered, nano_ordered));
            if (csv_out)
                std::fprintf(csv_out,
                             "%s,%zu,%u,%g,%.6f,%.6f,%.0f,%.0f,%.3f,%.3f,%ld,%ld,%.3f,%zu,%.6f,%.0f,%.3f,%.0f,%.0f,%.3f\n",
                             name, n, k, (double)radius, phos.build_s, nano.build_s, phos.qps, nano.qps, pb, nb,
                             phos.peak, nano.peak, phos.qps / nano.qps, same, map.build_s, map.qps,
                             map.qps / nano.qps, nano_ordered.qps, map_ordered.qps,
                             map_ordered.qps / nano_ordered.qps);
        }
    }
}

size_t arg_size(int argc, char **argv, const char *name, size_t fallback)
{
    for (int i = 1; i + 1 < argc; i++)
        if (std::strcmp(argv[i], name) == 0)
            return (size_t)std::strtoull(argv[i + 1], nullptr, 10);
    return fallback;
}

} // namespace

int main(int argc, char **argv)
{
    size_t n = arg_size(argc, argv, "--photons", 1000000);
    size_t nq = arg_size(argc, argv, "--queries", 100000);
    uint32_t k_arg = (uint32_t)arg_size(argc, argv, "--k", 0);
    if (n == 0 || n > PHOTON_MAP_MAX_PHOTONS || nq == 0) {
        std::fprintf(stderr, "usage: bench_kdtree [--photons N] [--queries Q] [--k K] [--input FILE]... [--csv FILE]\n");
        return 2;
    }
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    std::vector<uint32_t> ks = k_arg ? std::vector<uint32_t>{k_arg} : std::vector<uint32_t>{50, 500};
    for (int i = 1; i + 1 < argc; i++)
        if (std::strcmp(argv[i], "--csv") == 0) {
            csv_out = std::fopen(argv[i + 1], "w");
            if (csv_out)
                std::fprintf(csv_out, "photons_from,photons,k,radius,phos_build_s,nano_build_s,phos_qps,nano_qps,"
                                      "phos_bytes_per_photon,nano_bytes_per_photon,phos_build_peak_bytes,"
                                      "nano_build_peak_bytes,qps_ratio,identical,map_build_s,map_qps,map_qps_ratio,"
                                      "ordered_nano_qps,ordered_map_qps,ordered_map_qps_ratio\n");
        }
    std::printf("kd-tree benchmark: Phos (median splits into buckets of %d, 20-byte photons) vs nanoflann %d.%d.%d "
                "(KDTreeSingleIndexAdaptor, leaf size 10, positions as float[3])\n",
                KDTREE_BUCKET, NANOFLANN_VERSION >> 8, (NANOFLANN_VERSION >> 4) & 0xf, NANOFLANN_VERSION & 0xf);
    std::printf("Phos tree = the photons as one class (one spatial tree); Phos map = the photons in their\n"
                "classes (facing and flags), the map's tree split by class at its root.\n");
    std::printf("bytes per photon: Phos = the whole photon map (position, power, direction, flags, tree);\n"
                "nanoflann = its index + 12 B of positions; a photon map on it needs 8 B more per photon.\n"
                "Phos/nano is the ratio of the two columns: below 1 is better for build time and bytes,\n"
                "above 1 for queries per second.\n");
    bool inputs = false;
    for (int i = 1; i + 1 < argc; i++) {
        if (std::strcmp(argv[i], "--input") != 0)
            continue;
        inputs = true;
        std::vector<photon> photons = read_photons(argv[i + 1]);
        if (photons.empty())
            continue;
        std::vector<vec3> queries(nq);
        Rng r{12345};
        for (auto &q : queries) {
            const photon &p = photons[(size_t)(r.next() * (float)photons.size()) % photons.size()];
            q = v3(p.position[0], p.position[1], p.position[2]);
        }
        // Radii for a 2 m box: the estimate's cap, and one that k fills.
        bench_photons(argv[i + 1], photons, queries, ks, {0.25f, 0.05f});
    }
    if (!inputs) {
        const Scenario scenarios[] = {{"box faces", on_box}, {"room (box + two spheres)", on_room}};
        for (const Scenario &sc : scenarios) {
            std::vector<photon> photons = make_photons(sc, n, 1);
            std::vector<vec3> queries(nq);
            Rng r{12345};
            for (auto &q : queries)
                q = sc.point(r);
            bench_photons(sc.name, photons, queries, ks, {0.1f, 0.01f});
        }
    }
    if (csv_out)
        std::fclose(csv_out);
    return 0;
}
