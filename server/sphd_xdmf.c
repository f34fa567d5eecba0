/* The XDMF sidecar: a temporal collection of polyvertex grids pointing into the snapshots. The
 * topology names its connectivity (the `id` dataset, 0..n-1 in file order): ParaView's default
 * reader (Xdmf3ReaderS) and meshio build no cells from a polyvertex topology without one. */
#include "sphd.h"
#include "sphd_h5.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    char *s;
    size_t len, cap;
    int failed;
} strbuf;

static void sb_printf(strbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void sb_printf(strbuf *b, const char *fmt, ...)
{
    if (b->failed)
        return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int n = vsnprintf(b->s ? b->s + b->len : NULL, b->s ? b->cap - b->len : 0, fmt, ap);
        va_end(ap);
        if (n < 0) {
            b->failed = 1;
            return;
        }
        if (b->s && b->len + (size_t)n < b->cap) {
            b->len += (size_t)n;
            return;
        }
        size_t cap = (b->cap ? b->cap * 2 : 4096) + (size_t)n;
        char *s = realloc(b->s, cap);
        if (!s) {
            b->failed = 1;
            return;
        }
        b->s = s;
        b->cap = cap;
    }
}

static void number_type(sphd_h5_type t, const char **name, int *precision)
{
    switch (t) {
    case SPHD_H5_F32:
        *name = "Float", *precision = 4;
        break;
    case SPHD_H5_F64:
        *name = "Float", *precision = 8;
        break;
    case SPHD_H5_I8:
        *name = "Char", *precision = 1;
        break;
    case SPHD_H5_I32:
        *name = "Int", *precision = 4;
        break;
    default:
        *name = "Int", *precision = 8;
        break;
    }
}

static void data_item(strbuf *b, const sphd_xdmf_entry *e, const sphd_h5_field *f)
{
    const char *nt;
    int prec;
    number_type(f->type, &nt, &prec);
    if (f->ncomp > 1)
        sb_printf(b, "<DataItem Dimensions=\"%ld 3\"", e->n);
    else
        sb_printf(b, "<DataItem Dimensions=\"%ld\"", e->n);
    sb_printf(b, " NumberType=\"%s\" Precision=\"%d\" Format=\"HDF\">%s:/%s</DataItem>", nt, prec,
              e->file, f->name);
}

int sphd_xdmf_write(const char *path, const sphd_xdmf_entry *entries, int nentries,
                    const sphd_h5_field *fields, int nfields, sph_error *err)
{
    const sphd_h5_field *pos = NULL, *id = NULL;
    for (int i = 0; i < nfields; i++) {
        if (strcmp(fields[i].name, "pos") == 0)
            pos = &fields[i];
        else if (strcmp(fields[i].name, "id") == 0 && fields[i].ncomp == 1)
            id = &fields[i];
    }
    if (!pos)
        return sph_error_set(err, SPH_ERR_INTERNAL, "", "XDMF needs a 'pos' field");
    strbuf b = {0};
    sb_printf(&b, "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
                  "<Xdmf Version=\"3.0\">\n <Domain>\n"
                  "  <Grid Name=\"particles\" GridType=\"Collection\" "
                  "CollectionType=\"Temporal\">\n");
    for (int i = 0; i < nentries; i++) {
        const sphd_xdmf_entry *e = &entries[i];
        sb_printf(&b, "   <Grid Name=\"step_%ld\" GridType=\"Uniform\">\n", e->step);
        sb_printf(&b, "    <Time Value=\"%.17g\"/>\n", e->t);
        sb_printf(&b,
                  "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%ld\" "
                  "NodesPerElement=\"1\"",
                  e->n);
        if (id) {
            sb_printf(&b, ">");
            data_item(&b, e, id);
            sb_printf(&b, "</Topology>\n");
        } else {
            sb_printf(&b, "/>\n");
        }
        sb_printf(&b, "    <Geometry GeometryType=\"XYZ\">");
        data_item(&b, e, pos);
        sb_printf(&b, "</Geometry>\n");
        for (int j = 0; j < nfields; j++) {
            const sphd_h5_field *f = &fields[j];
            if (f == pos)
                continue;
            sb_printf(&b, "    <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">",
                      f->name, f->ncomp > 1 ? "Vector" : "Scalar");
            data_item(&b, e, f);
            sb_printf(&b, "</Attribute>\n");
        }
        sb_printf(&b, "   </Grid>\n");
    }
    sb_printf(&b, "  </Grid>\n </Domain>\n</Xdmf>\n");
    if (b.failed) {
        free(b.s);
        return sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory writing %s", path);
    }
    int rc = sphd_write_atomic(path, b.s, b.len);
    int e = errno;
    free(b.s);
    if (rc != 0)
        return sph_error_set(err, SPH_ERR_IO, "", "writing '%s' failed: %s", path, strerror(e));
    return 0;
}
