/*
 * sph_mesh_io: mesh files through assimp's C API (sph_mesh_io.h). aiImportFileFromMemory with
 * the extension as the format hint, aiProcess_Triangulate and aiProcess_PreTransformVertices (no
 * vertex joining there: sph_mesh_from_triangles welds), then the triangles copied out as soup.
 *
 * May call: sph_mesh.h, sph_error.h, assimp's cimport.h, libc.
 */
#include "sph_mesh_io.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
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

int sph_mesh_read_memory(const void *bytes, size_t len, const char *name,
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
                             "it or raise the limit (sphd --mesh-max-bytes)",
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
                             "simplify it or raise the limit (sphd --mesh-max-triangles)",
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

int sph_mesh_read_file(const char *file, const char *name, const sph_mesh_limits *lim,
                       sph_mesh *out, const char *path, sph_error *err)
{
    sph_mesh_limits dl = sph_mesh_limits_default();
    if (!lim)
        lim = &dl;
    memset(out, 0, sizeof *out);
    if (!name)
        name = file;
    FILE *f = fopen(file, "rb");
    if (!f)
        return sph_error_set(err, SPH_ERR_IO, path, "cannot open %s: %s", file, strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        int e = errno;
        fclose(f);
        return sph_error_set(err, SPH_ERR_IO, path, "cannot open %s: %s", file,
                             e ? strerror(e) : "not a regular file");
    }
    if ((unsigned long long)st.st_size > (unsigned long long)lim->max_bytes) {
        fclose(f);
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh file %s has %lld bytes, more than the limit of %zu: simplify "
                             "it or raise the limit (sphd --mesh-max-bytes)",
                             file, (long long)st.st_size, lim->max_bytes);
    }
    size_t len = (size_t)st.st_size;
    char *buf = malloc(len ? len : 1);
    if (!buf) {
        fclose(f);
        return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory reading %s", file);
    }
    size_t got = fread(buf, 1, len, f);
    int bad = ferror(f);
    fclose(f);
    if (bad || got != len) {
        free(buf);
        return sph_error_set(err, SPH_ERR_IO, path, "cannot read %s: %s", file,
                             bad ? strerror(errno) : "the file changed while being read");
    }
    int rc = sph_mesh_read_memory(buf, len, name, lim, out, path, err);
    free(buf);
    return rc;
}
