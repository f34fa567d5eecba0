/*
 * sph_mesh_io: mesh files through assimp's C API (sph_mesh_io.h). aiImportFileFromMemory with
 * the extension as the format hint, aiProcess_Triangulate and aiProcess_PreTransformVertices (no
 * vertex joining there: sph_mesh_from_triangles welds), then the triangles copied out as soup.
 *
 * May call: sph_mesh.h, sph_error.h, assimp's cimport.h, libc.
 */
#include "sph_mesh_io.h"

#include "sph_fileio.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <sys/stat.h>

/* The assimp format hint for a file name's extension, or NULL. */
static const char *format_hint(const char *name, const char **ext)
{
    const char *slash = strrchr(name, '/');
    const char *dot = strrchr(slash ? slash + 1 : name, '.');
    *ext = dot ? dot : "";
    if (!dot)
        return NULL;
    static const char *const known[] = {"stl", "obj", "ply"};
    for (size_t i = 0; i < sizeof known / sizeof *known; i++)
        if (strcasecmp(dot + 1, known[i]) == 0)
            return known[i];
    return NULL;
}

/* Whether a PLY header's format line (within its first 1 kB) says binary. */
static int is_binary_ply(const void *bytes, size_t len)
{
    const char *p = bytes;
    size_t n = len < 1024 ? len : 1024;
    for (size_t i = 0; i + 13 <= n; i++)
        if (memcmp(p + i, "format binary", 13) == 0)
            return 1;
    return 0;
}

/* A text format's bytes (ASCII STL, OBJ, ASCII PLY) hold no control characters but white space:
 * a file with them is broken (assimp 5.2's ASCII PLY reader loops without end on a header with
 * NUL bytes in it, found by fuzz_mesh); 0 if clean, else the offset of the first one plus 1. */
static size_t control_at(const unsigned char *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if ((p[i] < 32 && p[i] != '\t' && p[i] != '\n' && p[i] != '\r' && p[i] != '\f' &&
             p[i] != '\v') ||
            p[i] == 127)
            return i + 1;
    return 0;
}

/* An ASCII PLY's header, line by line up to end_header: "ply", "format ascii 1.0", comments,
 * "element NAME COUNT" (the counts together at most one element a byte of the file), "property
 * ..."; anything else, or no end_header, is refused before assimp sees it. Returns 0, or a
 * message in msg. */
static int ply_header_ok(const char *p, size_t n, char *msg, size_t msglen)
{
    size_t i = 0, line = 0;
    double total = 0.0;
    while (i < n) {
        size_t e = i;
        while (e < n && p[e] != '\n')
            e++;
        char buf[256];
        size_t l = e - i < sizeof buf - 1 ? e - i : sizeof buf - 1;
        memcpy(buf, p + i, l);
        buf[l] = '\0';
        if (l > 0 && buf[l - 1] == '\r')
            buf[--l] = '\0';
        line++;
        char word[32] = "";
        sscanf(buf, "%31s", word);
        if (line == 1 ? strcmp(buf, "ply") != 0 : 0) {
            snprintf(msg, msglen, "its first line is not \"ply\"");
            return -1;
        }
        if (line > 1) {
            if (strcmp(word, "end_header") == 0)
                return total <= (double)n ? 0
                                          : (snprintf(msg, msglen,
                                                      "its header declares %.0f elements, more "
                                                      "than the file's %zu bytes can hold",
                                                      total, n),
                                             -1);
            if (strcmp(word, "element") == 0) {
                char ename[64];
                double count;
                if (sscanf(buf, "element %63s %lf", ename, &count) != 2 || !(count >= 0.0)) {
                    snprintf(msg, msglen, "line %zu: \"element NAME COUNT\" expected", line);
                    return -1;
                }
                total += count;
            } else if (strcmp(word, "format") != 0 && strcmp(word, "comment") != 0 &&
                       strcmp(word, "obj_info") != 0 && strcmp(word, "property") != 0) {
                snprintf(msg, msglen, "line %zu of its header is not a PLY keyword", line);
                return -1;
            }
        }
        i = e + 1;
        if (line > 10000)
            break;
    }
    snprintf(msg, msglen, "its header has no end_header");
    return -1;
}

/* Whether bytes are a binary STL: 80 bytes, a count, 50 bytes a triangle. */
static int is_binary_stl(const void *bytes, size_t len)
{
    if (len < 84)
        return 0;
    uint32_t n;
    memcpy(&n, (const char *)bytes + 80, 4);
    return (uint64_t)84 + 50 * (uint64_t)n == len;
}

int sph_mesh_read_unguarded(const void *bytes, size_t len, const char *name,
                            const sph_mesh_limits *lim, sph_mesh *out, const char *path,
                            sph_error *err)
{
    sph_mesh_limits dl = sph_mesh_limits_default();
    if (!lim)
        lim = &dl;
    memset(out, 0, sizeof *out);
    if (!name)
        name = "";
    const char *ext;
    const char *hint = format_hint(name, &ext);
    if (!hint)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "unknown mesh format '%s' (%s): use .stl, .obj or .ply", ext, name);
    if (len > lim->max_bytes || len > UINT_MAX)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh file %s has %zu bytes, more than the limit of %zu: simplify "
                             "it",
                             name, len, lim->max_bytes);
    if (len == 0 || !bytes)
        return sph_error_set(err, SPH_ERR_INVALID, path, "mesh file %s is empty", name);
    /* assimp 5.2's binary PLY reader reads past the end of a truncated or malformed file (a SEGV
     * found by fuzz_mesh; upstream assimp issue #6784, open): such files are not given to it */
    if (strcmp(hint, "ply") == 0 && is_binary_ply(bytes, len))
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh file %s is a binary PLY, which is not read: save it as ASCII "
                             "PLY or as STL",
                             name);
    const int text = strcmp(hint, "stl") != 0 || !is_binary_stl(bytes, len);
    const size_t bad = text ? control_at(bytes, len) : 0;
    if (bad)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh file %s is not a %s file: a control character (byte %zu) in a "
                             "text format",
                             name,
                             strcmp(hint, "stl") == 0 ? "binary STL (whose size is 84 + 50 "
                                                        "bytes a triangle) nor an ASCII STL"
                                                      : hint,
                             bad - 1);
    char why[160];
    if (strcmp(hint, "ply") == 0 && ply_header_ok(bytes, len, why, sizeof why))
        return sph_error_set(err, SPH_ERR_INVALID, path, "mesh file %s is not a PLY file: %s", name,
                             why);
    const struct aiScene *sc = aiImportFileFromMemory(
        bytes, (unsigned)len,
        aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_ValidateDataStructure,
        hint);
    if (!sc || (sc->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !sc->mMeshes) {
        int rc = sph_error_set(err, SPH_ERR_INVALID, path, "mesh file %s cannot be read as %s: %s",
                               name, hint, sc ? "no meshes in it" : aiGetErrorString());
        aiReleaseImport(sc);
        return rc;
    }
    long nt = 0;
    for (unsigned k = 0; k < sc->mNumMeshes; k++) {
        const struct aiMesh *me = sc->mMeshes[k];
        if (!me || !me->mFaces || !me->mVertices)
            continue;
        for (unsigned f = 0; f < me->mNumFaces; f++)
            nt += me->mFaces[f].mNumIndices == 3;
    }
    if (nt == 0) {
        aiReleaseImport(sc);
        return sph_error_set(err, SPH_ERR_INVALID, path, "mesh file %s has no triangles", name);
    }
    if (nt > lim->max_triangles) {
        aiReleaseImport(sc);
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh file %s has %ld triangles, more than the limit of %ld: "
                             "simplify it",
                             name, nt, lim->max_triangles);
    }
    double *xyz = malloc((size_t)nt * 9 * sizeof *xyz);
    if (!xyz) {
        aiReleaseImport(sc);
        return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory reading mesh file %s", name);
    }
    long w = 0;
    for (unsigned k = 0; k < sc->mNumMeshes; k++) {
        const struct aiMesh *me = sc->mMeshes[k];
        if (!me || !me->mFaces || !me->mVertices)
            continue;
        for (unsigned f = 0; f < me->mNumFaces; f++) {
            const struct aiFace *fc = &me->mFaces[f];
            if (fc->mNumIndices != 3)
                continue; /* points and lines */
            for (int c = 0; c < 3; c++) {
                unsigned vi = fc->mIndices[c];
                const struct aiVector3D *p =
                    vi < me->mNumVertices ? &me->mVertices[vi] : &me->mVertices[0];
                xyz[w++] = p->x, xyz[w++] = p->y, xyz[w++] = p->z;
            }
        }
    }
    aiReleaseImport(sc);
    int rc = sph_mesh_from_triangles(out, xyz, nt, lim, path, err);
    free(xyz);
    if (rc != 0 && err) { /* name the file in the message */
        char where[2 * SPH_ERROR_TEXT_MAX];
        snprintf(where, sizeof where, "mesh file %s: %s", name, err->message);
        size_t n = strlen(where);
        n = n < sizeof err->message ? n : sizeof err->message - 1;
        memcpy(err->message, where, n);
        err->message[n] = '\0';
    }
    return rc;
}

/* ---- the guarded reader: assimp in a child process ---- */

/* What the child sends back: this header, then (rc 0) the vertices and the triangles, or (rc not
 * 0) the error. */
typedef struct reply_head {
    int rc;
    long nv, nt, degenerate;
} reply_head;

/* Reads n bytes from fd by the deadline (CLOCK_MONOTONIC seconds); 0, -1 (closed or error) or
 * -2 (time out). */
static int read_by(int fd, void *p, size_t n, double deadline)
{
    char *c = p;
    while (n > 0) {
        struct timespec ts;
        clock_gettime(CLOCK_MONOTONIC, &ts);
        const double left = deadline - ((double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec);
        if (left <= 0.0)
            return -2;
        struct pollfd pf = {.fd = fd, .events = POLLIN};
        const int k = poll(&pf, 1, (int)(left * 1000.0) + 1);
        if (k < 0 && errno == EINTR)
            continue;
        if (k < 0)
            return -1;
        if (k == 0)
            continue;
        const ssize_t r = read(fd, c, n);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            return -1;
        c += r;
        n -= (size_t)r;
    }
    return 0;
}

static void child_read(int fd, const void *bytes, size_t len, const char *name,
                       const sph_mesh_limits *lim, const char *path)
{
    /* bounded: CPU time and address space, whatever assimp does with a hostile file */
    struct rlimit cpu = {SPH_MESH_READ_SECONDS, SPH_MESH_READ_SECONDS + 1};
    setrlimit(RLIMIT_CPU, &cpu);
    sph_mesh m;
    sph_error e;
    sph_error_clear(&e);
    reply_head h = {0, 0, 0, 0};
    h.rc = sph_mesh_read_unguarded(bytes, len, name, lim, &m, path, &e);
    if (h.rc == 0) {
        h.nv = m.nv;
        h.nt = m.nt;
        h.degenerate = m.degenerate;
        if (sph_write_all(fd, &h, sizeof h) ||
            sph_write_all(fd, m.v, 3 * (size_t)m.nv * sizeof *m.v) ||
            sph_write_all(fd, m.t, 3 * (size_t)m.nt * sizeof *m.t))
            _exit(3);
    } else if (sph_write_all(fd, &h, sizeof h) || sph_write_all(fd, &e, sizeof e)) {
        _exit(3);
    }
    _exit(0);
}

int sph_mesh_read_memory(const void *bytes, size_t len, const char *name,
                         const sph_mesh_limits *lim, sph_mesh *out, const char *path,
                         sph_error *err)
{
    memset(out, 0, sizeof *out);
    if (!name)
        name = "";
    int fds[2];
    if (pipe(fds))
        return sph_error_set(err, SPH_ERR_IO, path, "cannot read mesh file %s: pipe: %s", name,
                             strerror(errno));
    fflush(NULL);
    const pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        return sph_error_set(err, SPH_ERR_IO, path, "cannot read mesh file %s: fork: %s", name,
                             strerror(errno));
    }
    if (pid == 0) {
        close(fds[0]);
        child_read(fds[1], bytes, len, name, lim, path);
    }
    close(fds[1]);
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    const double deadline =
        (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec + (double)SPH_MESH_READ_SECONDS;
    reply_head h;
    int rc = read_by(fds[0], &h, sizeof h, deadline);
    if (rc == 0 && h.rc == 0) {
        const int ok = h.nv > 0 && h.nt > 0 && h.nv <= 3 * h.nt &&
                       h.nt <= (lim ? lim->max_triangles : SPH_MESH_MAX_TRIANGLES_DEFAULT);
        out->dim = 3;
        out->nv = h.nv;
        out->nt = h.nt;
        out->degenerate = h.degenerate;
        out->v = ok ? malloc(3 * (size_t)h.nv * sizeof *out->v) : NULL;
        out->t = ok ? malloc(3 * (size_t)h.nt * sizeof *out->t) : NULL;
        if (!out->v || !out->t)
            rc = -3;
        else if ((rc = read_by(fds[0], out->v, 3 * (size_t)h.nv * sizeof *out->v, deadline)) == 0)
            rc = read_by(fds[0], out->t, 3 * (size_t)h.nt * sizeof *out->t, deadline);
        for (long i = 0; rc == 0 && i < 3 * h.nt; i++)
            if (out->t[i] < 0 || out->t[i] >= h.nv)
                rc = -1;
    } else if (rc == 0) {
        sph_error e;
        rc = read_by(fds[0], &e, sizeof e, deadline);
        if (rc == 0) {
            e.path[sizeof e.path - 1] = '\0';
            e.message[sizeof e.message - 1] = '\0';
            if (err)
                *err = e;
            rc = h.rc;
        }
    }
    close(fds[0]);
    if (rc == -2)
        kill(pid, SIGKILL);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (rc == 0 && h.rc == 0)
        return 0;
    sph_mesh_free(out);
    if (rc > 0) /* the reader's own refusal */
        return rc;
    if (rc == -3)
        return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory reading mesh file %s", name);
    if (rc == -2)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh file %s took more than %d s to read: it is broken or far too "
                             "large",
                             name, SPH_MESH_READ_SECONDS);
    if (WIFSIGNALED(status))
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh file %s is malformed: the mesh reader (assimp) failed on it "
                             "(signal %d)",
                             name, WTERMSIG(status));
    return sph_error_set(err, SPH_ERR_INVALID, path,
                         "mesh file %s is malformed: the mesh reader (assimp) failed on it", name);
}

int sph_mesh_read_file(const char *file, const char *name, const sph_mesh_limits *lim,
                       sph_mesh *out, const char *path, sph_error *err)
{
    sph_mesh_limits dl = sph_mesh_limits_default();
    if (!lim)
        lim = &dl;
    memset(out, 0, sizeof *out);
    if (!name)
        name = file;
    char *buf;
    size_t len;
    switch (sph_read_file(file, lim->max_bytes, &buf, &len)) {
    case -1:
        return sph_error_set(err, SPH_ERR_IO, path, "cannot open %s: %s", file,
                             errno ? strerror(errno) : "not a regular file");
    case -2:
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh file %s has %lld bytes, more than the limit of %zu: simplify "
                             "it",
                             file, (long long)len, lim->max_bytes);
    case -3:
        return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory reading %s", file);
    case -4:
        return sph_error_set(err, SPH_ERR_IO, path, "cannot read %s: %s", file,
                             errno ? strerror(errno) : "the file changed while being read");
    default:
        break;
    }
    int rc = sph_mesh_read_memory(buf, len, name, lim, out, path, err);
    free(buf);
    return rc;
}
