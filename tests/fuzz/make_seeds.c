/*
 * make_seeds: writes the fuzz seeds and regression inputs that are saved simulation states, so
 * that a change of the state format (core/sph_checkpoint.c, SIM_VERSION) or of the checkpoint
 * file (server/sphd_ckpt.c) is one command: scripts/fuzz-seeds.sh.
 *
 *   make_seeds FUZZDIR           writes the files below into FUZZDIR (tests/fuzz), then checks them
 *   make_seeds --check FUZZDIR   only checks them
 *
 * corpus/sim_restore/small_wcsph.bin, small_body.bin, small_mdbc_geometry.bin, small_nlist.bin:
 *   sph_sim_save of a tiny dam break, of one with a rigid body, of one with mDBC walls and a
 *   polygon obstacle of the geometry list (its state holds the walls' mirror points), and of the
 *   dam break with a reused neighbour list (its state holds the cells of the list's build), each
 *   stepped a few steps.
 * corpus/ckpt/valid.bin, valid_fixup.bin, prev.bin: the checkpoint and checkpoint.prev of a run
 *   of fuzz_ckpt's case through sphd_exec (the server's writer), behind fuzz_ckpt's flag byte
 *   (0, or 7 for valid_fixup: the harness recomputes the checksums, to the same values).
 * regress/sim_restore/NAME: one fault on a fresh valid state each (the crashes the fuzzer found,
 *   see `git log -- tests/fuzz/regress`), placed from the state's layout (sim_header below, the
 *   method's persistent arrays), never from hard-coded offsets.
 * regress/ckpt/NAME: the valid checkpoint with a forged section count (its checksums made right).
 *
 * The check restores every corpus seed (sph_sim_restore; the ckpt seeds through
 * sphd_exec_resume, as fuzz_ckpt does) and expects every regression input to be refused by the
 * check meant for it, not by the version or length check; it prints what each one got.
 */
#define _XOPEN_SOURCE 700
#include "fuzz_ckpt_case.h"

#include "sph_case.h"
#include "sph_envelope.h"
#include "sph_sim.h"
#include "sph_sim_impl.h"
#include "sphd_ckpt.h"
#include "sphd_ckpt_format.h"
#include "sphd_exec.h"

#include <dirent.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

/* core/sph_checkpoint.c's header of a saved state, field for field; checked against every state
 * saved here (its size must account for the state's length exactly). */
typedef struct {
    char magic[8];
    uint32_t version;
    uint32_t sps;
    int64_t n;
    int64_t nactive, nfluid, nboundary, step, failed, nbodies;
    int64_t nmirror;
    double t, dt, amax, vmax;
    int64_t nstart;
    double moved;
    int64_t nseries;
    sph_paddle_state paddle;
    sph_config cfg;
    sph_diag diag;
    sph_envelope wave;
} sim_header;

/* server/sphd_ckpt.c's file header and trailer: sphd_ckpt_format.h */

_Static_assert(sizeof(ckpt_header) == 32 && sizeof(ckpt_section_header) == 48 &&
                   sizeof(ckpt_trailer) == 16,
               "server/sphd_ckpt.c's layout");

/* A dam break in a small tank; the body case adds a floating cylinder to fuzz_ckpt's case. */
static const char body_case_text[] =
    "{\"name\":\"fzb\",\"method\":\"wcsph\",\"dim\":2,"
    "\"kernel\":{\"type\":\"wendland_c2\",\"h_over_dx\":1.3},\"dx\":0.02,"
    "\"domain\":{\"min\":[0,0],\"max\":[0.2,0.2]},"
    "\"fluid\":[{\"box\":{\"min\":[0,0],\"max\":[0.1,0.06]}}],"
    "\"boundary\":{\"type\":\"dynamic\",\"layers\":3,\"tank\":{\"min\":[0,0],\"max\":[0.2,0.2]}},"
    "\"bodies\":[{\"name\":\"c\",\"shape\":\"circle\",\"diameter\":0.06,\"density\":500,"
    "\"center\":[0.15,0.12],\"velocity\":[0,-0.5],\"free\":[\"x\",\"y\",\"rotation\"]}],"
    "\"physics\":{\"rho0\":1000,\"gravity\":[0,-9.81],\"eos\":{\"type\":\"linear\",\"c0\":10},"
    "\"viscosity\":{\"type\":\"artificial\",\"alpha\":0.1}},"
    "\"time\":{\"end\":0.01,\"cfl\":0.2},"
    "\"output\":{\"every\":0.005,\"fields\":[\"pos\",\"rho\"]},"
    "\"diagnostics\":{\"every\":1,\"probes\":[\"front_x\"]}}";

/* The same with mDBC walls and a polygon obstacle of the geometry list on the floor: its state
 * holds the walls' mirror points (sph_sim_impl.h, mirror). */
static const char mdbc_case_text[] =
    "{\"name\":\"fzm\",\"method\":\"wcsph\",\"dim\":2,"
    "\"kernel\":{\"type\":\"wendland_c2\",\"h_over_dx\":1.3},\"dx\":0.02,"
    "\"domain\":{\"min\":[0,0],\"max\":[0.2,0.2]},"
    "\"fluid\":[{\"box\":{\"min\":[0,0],\"max\":[0.1,0.06]}}],"
    "\"boundary\":{\"type\":\"dynamic\",\"layers\":3,\"density\":\"mdbc\","
    "\"tank\":{\"min\":[0,0],\"max\":[0.2,0.2]}},"
    "\"geometry\":[{\"polygon\":[[0.14,0],[0.18,0],[0.18,0.04],[0.14,0.04]],"
    "\"role\":\"obstacle\",\"layers\":2}],"
    "\"physics\":{\"rho0\":1000,\"gravity\":[0,-9.81],\"eos\":{\"type\":\"linear\",\"c0\":10},"
    "\"viscosity\":{\"type\":\"artificial\",\"alpha\":0.1}},"
    "\"time\":{\"end\":0.01,\"cfl\":0.2},"
    "\"output\":{\"every\":0.005,\"fields\":[\"pos\",\"rho\"]},"
    "\"diagnostics\":{\"every\":1,\"probes\":[\"front_x\"]}}";

#define STEPS 5

typedef struct {
    unsigned char *b;
    size_t len;
} bytes;

static void die(const char *what, const char *why)
{
    fprintf(stderr, "make_seeds: %s: %s\n", what, why);
    exit(1);
}

static void load_case(const char *text, sph_case *c)
{
    json_error_t je;
    json_t *root = json_loads(text, 0, &je);
    sph_error err;
    if (!root)
        die("case", je.text);
    if (sph_case_from_json(root, c, &err) != 0)
        die("case", err.message);
    json_decref(root);
}

static void write_file(const char *dir, const char *name, unsigned flag, const void *p, size_t n)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f)
        die(path, "cannot write");
    int ok = flag > 255 || fputc((int)flag, f) != EOF;
    ok = ok && fwrite(p, 1, n, f) == n;
    if (fclose(f) != 0 || !ok)
        die(path, "cannot write");
    printf("wrote %s (%zu bytes)\n", path, n + (flag <= 255));
}

static bytes read_file(const char *path)
{
    bytes r = {NULL, 0};
    FILE *f = fopen(path, "rb");
    if (!f)
        die(path, "cannot read");
    size_t cap = 0, got;
    do {
        if (r.len == cap) {
            cap = cap ? 2 * cap : 65536;
            r.b = realloc(r.b, cap);
            if (!r.b)
                die(path, "out of memory");
        }
        got = fread(r.b + r.len, 1, cap - r.len, f);
        r.len += got;
    } while (got > 0);
    fclose(f);
    return r;
}

/* ---- saved states ---- */

/* Where the state's parts are, from its layout. */
typedef struct {
    size_t n;      /* particles */
    size_t x;      /* offset of the x array */
    size_t types;  /* offset of the types */
    long fluid;    /* index of the first fluid particle */
    long body;     /* index of the first body particle, -1 if none */
    size_t mirror; /* offset of the walls' mirror points, 0 if none */
    size_t start;  /* offset of the neighbour list's cells, 0 if none */
    size_t nstart; /* how many */
} state_layout;

static bytes make_state(const char *text, state_layout *L)
{
    sph_case c;
    sph_error err;
    load_case(text, &c);
    sph_sim *s = sph_sim_create(&c.sim, &err);
    if (!s || sph_sim_step(s, STEPS, &err) != 0)
        die("simulation", err.message);
    bytes r;
    void *buf;
    if (sph_sim_save(s, &buf, &r.len, &err) != 0)
        die("sph_sim_save", err.message);
    r.b = buf;
    sph_array arrays[40];
    const int na = s->ops->arrays(s, arrays, 40);
    const size_t n = (size_t)s->P.n, nbs = (size_t)s->bodies.n;
    const size_t per = sph_method_arrays_size(arrays, na);
    const size_t nm = (size_t)s->nmirror * (size_t)s->cfg.dim * sizeof(double);
    L->nstart = s->cfg.neighbour_skin > 0.0 ? (size_t)s->cells.ncells + 2 : 0;
    const size_t ns = L->nstart * sizeof(int);
    if (r.len != sizeof(sim_header) + per * n + n * (1 + sizeof(int)) +
                     nbs * sizeof(sph_body_state) + nm + ns)
        die("sim_header", "out of date with core/sph_checkpoint.c (the state's length differs)");
    L->n = n;
    L->mirror = nm ? r.len - ns - nm : 0;
    L->start = ns ? r.len - ns : 0;
    L->x = SIZE_MAX;
    for (int i = 0, off = 0; i < na; off += (int)arrays[i].size, i++)
        if (arrays[i].p == s->P.x)
            L->x = sizeof(sim_header) + (size_t)off * n;
    if (L->x == SIZE_MAX)
        die("state", "positions are not among the saved arrays");
    L->types = sizeof(sim_header) + per * n;
    L->fluid = L->body = -1;
    for (size_t i = n; i-- > 0;) {
        if (r.b[L->types + i] == SPH_FLUID)
            L->fluid = (long)i;
        if (r.b[L->types + i] == SPH_BODY)
            L->body = (long)i;
    }
    if (L->fluid < 0)
        die("state", "no fluid particle");
    sph_sim_destroy(s);
    return r;
}

static void put(bytes *s, size_t off, const void *v, size_t n)
{
    if (off + n > s->len)
        die("fault", "past the state's end");
    memcpy(s->b + off, v, n);
}

typedef struct {
    const char *name;
    int body; /* on the state with a body (1), with mirror points (2), with a neighbour list (3) */
    const char *expected; /* the refusal meant for it; NULL: restores, the probe copes */
} sim_fault;

static const sim_fault sim_faults[] = {
    {"nactive_past_n", 0, "impossible counters"},
    {"nfluid_past_max_boxes", 0, "fluid boxes"},
    {"probe_far_position", 0, NULL},
    {"body_particle_typed_fluid", 1, "bad particle types"},
    {"body_type_on_fluid", 1, "bad particle types"},
    {"ghost_type_saved", 1, "bad particle types"},
    {"h_over_dx_huge", 0, "h_over_dx must be in"},
    {"mirror_not_a_number", 2, "mirror point that is not a number"},
    {"nlist_start_past_active", 3, "bad cell list"},
    {"nlist_moved_negative", 3, "bad cell list"},
    {"series_rows_past_end", 0, "bad wave series"},
};

/* Applies the named fault to a copy of the valid state. */
static bytes apply_sim_fault(const char *name, const bytes *valid, const state_layout *L)
{
    bytes s = {malloc(valid->len), valid->len};
    if (!s.b)
        die(name, "out of memory");
    memcpy(s.b, valid->b, s.len);
    const unsigned char fluid = SPH_FLUID, body = SPH_BODY, ghost = SPH_GHOST;
    if (strcmp(name, "nactive_past_n") == 0) { /* stepping would run past the arrays */
        const int64_t v = (int64_t)L->n + 1000;
        put(&s, offsetof(sim_header, nactive), &v, sizeof v);
    } else if (strcmp(name, "nfluid_past_max_boxes") == 0) { /* boxes past cfg.fluid[] */
        const int v = 1000;
        put(&s, offsetof(sim_header, cfg) + offsetof(sph_config, nfluid), &v, sizeof v);
    } else if (strcmp(name, "probe_far_position") == 0) { /* front probe: double to long */
        const double v = 1e300;
        put(&s, L->x + (size_t)L->fluid * sizeof(double), &v, sizeof v);
    } else if (strcmp(name, "h_over_dx_huge") == 0) { /* front probe's gap: double to long */
        const double v = 7e30;
        put(&s, offsetof(sim_header, cfg) + offsetof(sph_config, h_over_dx), &v, sizeof v);
    } else if (strcmp(name, "mirror_not_a_number") == 0) { /* mDBC's ghost nodes */
        const double v = NAN;
        if (!L->mirror)
            die(name, "the state has no mirror points");
        put(&s, L->mirror + sizeof v, &v, sizeof v);
    } else if (strcmp(name, "nlist_start_past_active") == 0) { /* the list's rows past nactive */
        int v;
        if (!L->start)
            die(name, "the state has no neighbour list");
        memcpy(&v, s.b + L->start + (L->nstart - 2) * sizeof v, sizeof v);
        v += 5;
        put(&s, L->start + (L->nstart - 3) * sizeof v, &v, sizeof v);
    } else if (strcmp(name, "nlist_moved_negative") == 0) { /* never rebuilt again */
        const double v = -1e300;
        put(&s, offsetof(sim_header, moved), &v, sizeof v);
    } else if (strcmp(name, "series_rows_past_end") == 0) { /* a wave series' rows read past it */
        const int64_t v = 1 << 20;
        put(&s, offsetof(sim_header, nseries), &v, sizeof v);
    } else if (strcmp(name, "body_particle_typed_fluid") == 0) {
        put(&s, L->types + (size_t)L->body, &fluid, 1);
    } else if (strcmp(name, "body_type_on_fluid") == 0) { /* bodies' tables read by id */
        put(&s, L->types + (size_t)L->fluid, &body, 1);
    } else if (strcmp(name, "ghost_type_saved") == 0) { /* ghosts are never saved */
        put(&s, L->types + (size_t)L->fluid, &ghost, 1);
    } else {
        die(name, "unknown fault");
    }
    return s;
}

/* ---- checkpoint files ---- */

static void drop(void *ud, const char *type, json_t *body)
{
    (void)ud;
    (void)type;
    json_decref(body);
}

static void remove_tree(const char *path)
{
    DIR *d = opendir(path);
    if (d) {
        struct dirent *e;
        while ((e = readdir(d))) {
            if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
                continue;
            char p[4096];
            snprintf(p, sizeof p, "%s/%s", path, e->d_name);
            if (unlink(p) != 0)
                remove_tree(p);
        }
        closedir(d);
    }
    rmdir(path);
}

static char *temp_dir(void)
{
    const char *base = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    char *t = malloc(strlen(base) + 32);
    if (!t)
        die("temporary directory", "out of memory");
    sprintf(t, "%s/make_seeds.XXXXXX", base);
    if (!mkdtemp(t))
        die(t, "cannot create");
    return t;
}

/* Runs fuzz_ckpt's case through sphd_exec and checkpoints it twice: *prev and *latest. */
static void make_checkpoints(bytes *prev, bytes *latest)
{
    sph_case c;
    sph_error err;
    load_case(fuzz_ckpt_case_text, &c);
    char *dir = temp_dir();
    char job[4200], path[4300];
    snprintf(job, sizeof job, "%s/fz", dir);
    if (mkdir(job, 0700) != 0)
        die(job, "cannot create");
    sphd_exec *x = sphd_exec_new(&c, job, &err);
    if (!x)
        die("sphd_exec_new", err.message);
    sphd_exec_set_checkpoint_policy(x, INFINITY, 1000000);
    for (int k = 0; k < 2; k++) {
        if (sphd_exec_advance(x, STEPS, INFINITY, drop, NULL, &err) != SPHD_EXEC_RUNNING)
            die("sphd_exec_advance", err.message);
        if (sphd_exec_checkpoint(x, &err) != 0)
            die("sphd_exec_checkpoint", err.message);
    }
    sphd_exec_free(x);
    snprintf(path, sizeof path, "%s/checkpoint.prev", job);
    *prev = read_file(path);
    snprintf(path, sizeof path, "%s/checkpoint", job);
    *latest = read_file(path);
    remove_tree(dir);
    free(dir);
}

static uint32_t crc(const unsigned char *p, size_t n)
{
    return (uint32_t)crc32(0L, p, (uInt)n);
}

/* Makes a checkpoint's header and trailer checksums right after an edit. */
static void fix_checksums(bytes *f)
{
    ckpt_header h;
    ckpt_trailer t;
    memcpy(&h, f->b, sizeof h);
    h.crc = crc(f->b, offsetof(ckpt_header, crc));
    memcpy(f->b, &h, sizeof h);
    memcpy(&t, f->b + f->len - sizeof t, sizeof t);
    t.crc = crc(f->b, f->len - sizeof t);
    t.crc_inverted = ~t.crc;
    memcpy(f->b + f->len - sizeof t, &t, sizeof t);
}

typedef struct {
    const char *name;
    uint32_t nsections; /* 0: the smallest count the file's body cannot hold */
} ckpt_fault;

/* A section count past the file (the reader allocated its table first: up to 32 GiB). */
static const ckpt_fault ckpt_faults[] = {
    {"nsections_past_body_1", 0xffffff01u},
    {"nsections_past_body_2", 0},
    {"oom_nsections", 0x31545002u},
};
#define CKPT_EXPECTED "more sections than the file holds"

static bytes apply_ckpt_fault(const ckpt_fault *fault, const bytes *valid)
{
    bytes f = {malloc(valid->len), valid->len};
    if (!f.b)
        die(fault->name, "out of memory");
    memcpy(f.b, valid->b, f.len);
    ckpt_header h;
    memcpy(&h, f.b, sizeof h);
    h.nsections =
        fault->nsections ? fault->nsections : (uint32_t)(h.body / sizeof(ckpt_section_header)) + 1;
    memcpy(f.b, &h, sizeof h);
    fix_checksums(&f);
    return f;
}

/* ---- writing ---- */

static void generate(const char *fuzzdir)
{
    char cs[4096], cc[4096], rs[4096], rc[4096];
    snprintf(cs, sizeof cs, "%s/corpus/sim_restore", fuzzdir);
    snprintf(cc, sizeof cc, "%s/corpus/ckpt", fuzzdir);
    snprintf(rs, sizeof rs, "%s/regress/sim_restore", fuzzdir);
    snprintf(rc, sizeof rc, "%s/regress/ckpt", fuzzdir);
    state_layout Lw, Lb, Lm, Ln;
    bytes wcsph = make_state(fuzz_ckpt_case_text, &Lw);
    bytes body = make_state(body_case_text, &Lb);
    bytes mdbc = make_state(mdbc_case_text, &Lm);
    /* fuzz_ckpt's dam break with a reused neighbour list: its state ends with the cells of the
     * list's build */
    json_error_t je;
    json_t *nl = json_loads(fuzz_ckpt_case_text, 0, &je);
    if (!nl || json_object_set_new(nl, "neighbours", json_pack("{s:f}", "skin", 0.2)))
        die("neighbour list case", "cannot make it");
    char *nlist_case_text = json_dumps(nl, JSON_COMPACT);
    json_decref(nl);
    if (!nlist_case_text)
        die("neighbour list case", "out of memory");
    bytes nlist = make_state(nlist_case_text, &Ln);
    free(nlist_case_text);
    if (!Ln.start)
        die("neighbour list state", "no cells saved");
    if (!Lm.mirror)
        die("mDBC state", "no mirror points");
    if (Lb.body < 0)
        die("body state", "no body particle");
    printf("state layout: header %zu bytes; dam break %zu particles, x at %zu, types at %zu; "
           "with a body %zu particles, x at %zu, types at %zu\n",
           sizeof(sim_header), Lw.n, Lw.x, Lw.types, Lb.n, Lb.x, Lb.types);
    write_file(cs, "small_wcsph.bin", 256, wcsph.b, wcsph.len);
    write_file(cs, "small_body.bin", 256, body.b, body.len);
    write_file(cs, "small_mdbc_geometry.bin", 256, mdbc.b, mdbc.len);
    write_file(cs, "small_nlist.bin", 256, nlist.b, nlist.len);
    for (size_t i = 0; i < sizeof sim_faults / sizeof *sim_faults; i++) {
        const sim_fault *f = &sim_faults[i];
        const bytes *const states[] = {&wcsph, &body, &mdbc, &nlist};
        const state_layout *const layouts[] = {&Lw, &Lb, &Lm, &Ln};
        bytes s = apply_sim_fault(f->name, states[f->body], layouts[f->body]);
        write_file(rs, f->name, 256, s.b, s.len);
        free(s.b);
    }
    bytes prev, latest;
    make_checkpoints(&prev, &latest);
    write_file(cc, "valid.bin", 0, latest.b, latest.len);
    write_file(cc, "valid_fixup.bin", 7, latest.b, latest.len);
    write_file(cc, "prev.bin", 0, prev.b, prev.len);
    for (size_t i = 0; i < sizeof ckpt_faults / sizeof *ckpt_faults; i++) {
        bytes f = apply_ckpt_fault(&ckpt_faults[i], &latest);
        write_file(rc, ckpt_faults[i].name, 7, f.b, f.len);
        free(f.b);
    }
    free(wcsph.b);
    free(body.b);
    free(mdbc.b);
    free(nlist.b);
    free(prev.b);
    free(latest.b);
}

/* ---- checking ---- */

static int check_sim(const char *path, const char *expected, int valid)
{
    bytes s = read_file(path);
    sph_error err;
    sph_error_clear(&err);
    sph_sim *sim = sph_sim_restore(s.b, s.len, &err);
    int ok;
    if (sim) {
        const sph_diag *d = sph_sim_diag(sim);
        printf("%-50s restored (n = %ld, step %ld, front_x %g)\n", path, sim->P.n, d->step,
               d->front_x);
        sph_error e2;
        sph_error_clear(&e2);
        const int rc = sph_sim_step(sim, 1, &e2); /* as fuzz_sim_restore does */
        printf("%-50s   then one step: %s (front_x %g)\n", "", rc ? e2.message : "ok",
               sph_sim_diag(sim)->front_x);
        sph_sim_destroy(sim);
        ok = valid || !expected;
    } else {
        printf("%-50s refused: %s\n", path, err.message);
        ok = !valid && expected && strstr(err.message, expected) &&
             !strstr(err.message, "of this version") && !strstr(err.message, "truncated");
    }
    free(s.b);
    if (!ok)
        printf("  ^ UNEXPECTED (wanted %s)\n", valid || !expected ? "a restored state" : expected);
    return ok;
}

/* A ckpt input (flag byte, file) as fuzz_ckpt takes it: the seeds resume through
 * sphd_exec_resume; the file of a regression input is loaded by sphd_ckpt_load_file. */
static int check_ckpt(const char *path, int valid)
{
    bytes f = read_file(path);
    sph_case c;
    sph_error err;
    sph_error_clear(&err);
    load_case(fuzz_ckpt_case_text, &c);
    char *dir = temp_dir();
    char file[4200];
    snprintf(file, sizeof file, "%s/checkpoint", dir);
    FILE *o = fopen(file, "wb");
    if (!o || fwrite(f.b + 1, 1, f.len - 1, o) != f.len - 1 || fclose(o) != 0)
        die(file, "cannot write");
    int ok;
    if (valid) {
        int fell_back = 0;
        sphd_exec *x = sphd_exec_resume(&c, dir, &fell_back, &err);
        json_t *p = x ? sphd_exec_progress(x) : NULL;
        if (x)
            printf("%-50s resumed (step %lld)\n", path,
                   (long long)json_integer_value(json_object_get(p, "step")));
        else
            printf("%-50s refused: %s\n", path, err.message);
        ok = x != NULL;
        json_decref(p);
        sphd_exec_free(x);
    } else {
        sphd_ckpt *ck = sphd_ckpt_load_file(file, &err);
        printf("%-50s %s%s\n", path, ck ? "loaded" : "refused: ", ck ? "" : err.message);
        ok = !ck && strstr(err.message, CKPT_EXPECTED);
        sphd_ckpt_free(ck);
    }
    remove_tree(dir);
    free(dir);
    free(f.b);
    if (!ok)
        printf("  ^ UNEXPECTED (wanted %s)\n", valid ? "a resumed job" : CKPT_EXPECTED);
    return ok;
}

static int check(const char *fuzzdir)
{
    char p[4096];
    int ok = 1;
    const char *seeds[] = {"small_wcsph.bin", "small_body.bin", "small_mdbc_geometry.bin",
                           "small_nlist.bin"};
    for (int i = 0; i < 4; i++) {
        snprintf(p, sizeof p, "%s/corpus/sim_restore/%s", fuzzdir, seeds[i]);
        ok &= check_sim(p, NULL, 1);
    }
    for (size_t i = 0; i < sizeof sim_faults / sizeof *sim_faults; i++) {
        snprintf(p, sizeof p, "%s/regress/sim_restore/%s", fuzzdir, sim_faults[i].name);
        ok &= check_sim(p, sim_faults[i].expected, 0);
    }
    const char *ckpts[] = {"valid.bin", "valid_fixup.bin", "prev.bin"};
    for (int i = 0; i < 3; i++) {
        snprintf(p, sizeof p, "%s/corpus/ckpt/%s", fuzzdir, ckpts[i]);
        ok &= check_ckpt(p, 1);
    }
    for (size_t i = 0; i < sizeof ckpt_faults / sizeof *ckpt_faults; i++) {
        snprintf(p, sizeof p, "%s/regress/ckpt/%s", fuzzdir, ckpt_faults[i].name);
        ok &= check_ckpt(p, 0);
    }
    printf("make_seeds: %s\n", ok ? "all as expected" : "SOME NOT AS EXPECTED");
    return ok ? 0 : 1;
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "--check") == 0)
        return check(argv[2]);
    if (argc != 2 || argv[1][0] == '-') {
        fprintf(stderr, "usage: make_seeds [--check] FUZZDIR (tests/fuzz)\n");
        return 2;
    }
    generate(argv[1]);
    return check(argv[1]);
}
