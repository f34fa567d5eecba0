/*
 * sph_case_fields: the rows of the simulation case table (sph_case_table.h). Defaults here are
 * those of sph_config_default() (a unit test holds them equal); the JSON Schema
 * (schema/case.schema.json) and PROTOCOL.md section 1 say the same (tests/schema checks).
 */
#include "sph_case_table.h"
#include "sph_lattice.h"
#include "sph_json.h"
#include "sph_triggers.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CFG(member)                                                                                \
    .dst = SPH_CF_CFG, .off = offsetof(sph_config, member),                                        \
    .size = sizeof(((sph_config *)0)->member)
/* A field of a body (an element of /bodies): relative to its sph_body_spec. */
#define BODY(member)                                                                               \
    .dst = SPH_CF_CFG, .off = offsetof(sph_body_spec, member),                                     \
    .size = sizeof(((sph_body_spec *)0)->member)
/* A field of a height gauge (an element of /diagnostics/gauges): relative to its sph_gauge_spec. */
#define GAUGE(member)                                                                              \
    .dst = SPH_CF_CFG, .off = offsetof(sph_gauge_spec, member),                                    \
    .size = sizeof(((sph_gauge_spec *)0)->member)
/* A field of a pressure probe (an element of /diagnostics/pressure). */
#define PRESSURE(member)                                                                           \
    .dst = SPH_CF_CFG, .off = offsetof(sph_pressure_spec, member),                                 \
    .size = sizeof(((sph_pressure_spec *)0)->member)
/* A field of the MPS method's settings. */
#define MPS(member)                                                                                \
    .dst = SPH_CF_CFG, .off = offsetof(sph_config, mps.member),                                    \
    .size = sizeof(((sph_config *)0)->mps.member)
#define OUT(member)                                                                                \
    .dst = SPH_CF_OUT, .off = offsetof(sph_output_config, member),                                 \
    .size = sizeof(((sph_output_config *)0)->member)

static const char *const kernel_names[] = {
    "cubic_spline",          "gaussian",  "double_cosine", "wendland_c2",
    "renormalized_gaussian", "koshizuka", "sheu_quartic",  NULL}; /* sph_kernel_type order */
static const char *const boundary_names[] = {"dynamic", "ghost", "none", NULL};
static const int boundary_values[] = {SPH_BOUNDARY_DYNAMIC, SPH_BOUNDARY_GHOST, SPH_BOUNDARY_NONE};
static const char *const wall_density_names[] = {"continuity", "mdbc", NULL};
static const int wall_density_values[] = {SPH_WALL_CONTINUITY, SPH_WALL_MDBC};
static const char *const eos_names[] = {"linear", "tait", NULL};
static const int eos_values[] = {SPH_EOS_LINEAR, SPH_EOS_TAIT};
static const char *const visc_names[] = {"artificial", "laminar", "monaghan", NULL};
static const int visc_values[] = {SPH_VISC_ARTIFICIAL, SPH_VISC_LAMINAR, SPH_VISC_MONAGHAN};
static const char *const initial_names[] = {"rest", "standing_wave", "solitary_wave",
                                            NULL}; /* sph_initial_type */
static const char *const turb_names[] = {"none", "sps", NULL};
static const int turb_values[] = {SPH_TURB_NONE, SPH_TURB_SPS};
static const char *const shift_names[] = {"none", "lind", NULL};
static const int shift_values[] = {SPH_SHIFT_NONE, SPH_SHIFT_LIND};
static const char *const delta_form_names[] = {"molteni", "fourtakas", NULL};
static const int delta_form_values[] = {SPH_DELTA_MOLTENI, SPH_DELTA_FOURTAKAS};
static const char *const precision_names[] = {"double", "mixed", NULL};
static const int precision_values[] = {SPH_PRECISION_DOUBLE, SPH_PRECISION_MIXED};
static const char *const probe_names[] = {"front_x", "height_left", "ekin",  "epot",
                                          "vmax",    "penetration", "runup", NULL};
/* ekin, epot and vmax are always in diag: accepted, no bit */
static const int probe_bits[] = {SPH_PROBE_FRONT_X,     SPH_PROBE_HEIGHT_LEFT, 0, 0, 0,
                                 SPH_PROBE_PENETRATION, SPH_PROBE_RUNUP};
static const char *const wavemaker_names[] = {"piston", "flap", NULL};
static const int wavemaker_values[] = {SPH_WAVEMAKER_PISTON, SPH_WAVEMAKER_FLAP};
static const char *const waves_names[] = {"regular", "solitary", "irregular", "series", NULL};
static const int waves_values[] = {SPH_WAVES_REGULAR, SPH_WAVES_SOLITARY, SPH_WAVES_IRREGULAR,
                                   SPH_WAVES_SERIES};
static const char *const spectrum_names[] = {"jonswap", NULL};
static const char *const paddle_absorption_names[] = {"none", "active", NULL};
static const char *const absorption_names[] = {"damping", NULL};
static const int absorption_values[] = {1};
static const char *const shape_names[] = {"circle", "box", "polygon", NULL};
static const int shape_values[] = {SPH_SHAPE_CIRCLE, SPH_SHAPE_BOX, SPH_SHAPE_POLYGON};
static const char *const body_pressure_names[] = {"fluid", "continuity", NULL};
static const int body_pressure_values[] = {SPH_BODY_PRESSURE_FLUID, SPH_BODY_PRESSURE_CONTINUITY};
static const char *const dof_names[] = {"x", "y", "rotation", NULL};
static const int dof_bits[] = {SPH_DOF_X, SPH_DOF_Y, SPH_DOF_ROTATION};
/* the MPS method's choices, in the order of their values in sph_mps_config (sph_config.h) */
static const char *const precond_names[] = {"none", "jacobi", "ic0",
                                            "amg",  "bic0",   NULL}; /* sph_mps_precond */
static const char *const source_names[] = {"density", "mixed", NULL};
static const char *const gradient_names[] = {"minimum", "corrected", NULL};
static const char *const surface_names[] = {"particles", "water_line", NULL};
static const char *const field_names[] = {"pos", "vel", "rho", "p", "type", "id", "mass", NULL};
static const int field_bits[] = {SPH_FIELD_POS,  SPH_FIELD_VEL, SPH_FIELD_RHO, SPH_FIELD_P,
                                 SPH_FIELD_TYPE, SPH_FIELD_ID,  SPH_FIELD_MASS};

/* An array of lo to SPH_CONFIG_MAX_BOXES objects {"box": {...}} inside the domain, each holding
 * at least one particle, into dst[] (*n of them). Messages name the array `what`, one element
 * `one` ("a fluid block") and its content `noun` ("fluid"). */
static int parse_boxes(const json_t *arr, const char *path, int lo, const char *what,
                       const char *one, const char *noun, sph_config *c, sph_box *dst, int *n,
                       sph_error *err)
{
    if (!json_is_array(arr) || json_array_size(arr) < (size_t)lo ||
        json_array_size(arr) > SPH_CONFIG_MAX_BOXES)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "'%s' must be an array of %d to %d objects {\"box\": {...}}", what, lo,
                             SPH_CONFIG_MAX_BOXES);
    size_t i;
    json_t *v;
    json_array_foreach(arr, i, v)
    {
        static const char *const fkeys[] = {"box", NULL};
        char base[64], bpath[80], fpath[SPH_ERROR_PATH_MAX];
        snprintf(base, sizeof base, "%s/%zu", path, i);
        snprintf(bpath, sizeof bpath, "%s/box", base);
        json_t *box;
        if (!json_is_object(v))
            return sph_error_set(err, SPH_ERR_INVALID, base,
                                 "%s must be an object {\"box\": {...}}", one);
        if (sph_json_check_keys(v, base, fkeys, err) ||
            sph_json_get(v, base, "box", 1, &box, err) ||
            sph_case_parse_box(box, bpath, c->dim, &dst[i], err))
            return SPH_ERR_INVALID;
        for (int d = 0; d < c->dim; d++) {
            const int below = dst[i].min[d] < c->domain.min[d];
            if (below || dst[i].max[d] > c->domain.max[d]) {
                snprintf(fpath, sizeof fpath, "%s/%s/%d", bpath, below ? "min" : "max", d);
                return sph_error_set(err, SPH_ERR_INVALID, fpath, "the %s is outside the domain",
                                     noun);
            }
        }
        if (sph_lattice_box_count(&dst[i], c->dim, c->dx) == 0)
            return sph_error_set(err, SPH_ERR_INVALID, bpath,
                                 "the box holds no particles at dx = %g m (it is thinner than dx)",
                                 c->dx);
    }
    *n = (int)json_array_size(arr);
    return 0;
}

/* "fluid": 1 to SPH_CONFIG_MAX_BOXES blocks {"box": {...}} inside the domain. */
/* /device: "cpu", the default, or "gpu" (WCSPH with dynamic walls; sph_sim_check refuses it
 * at /device in a build without CUDA or on a machine without a GPU). */
static int parse_device(const json_t *v, const char *path, sph_config *c, sph_output_config *o,
                        sph_error *err)
{
    (void)o;
    const char *s = json_string_value(v);
    if (s && strcmp(s, "cpu") == 0) {
        c->device = SPH_DEVICE_CPU;
        return 0;
    }
    if (s && strcmp(s, "gpu") == 0) {
        c->device = SPH_DEVICE_GPU;
        return 0;
    }
    return sph_error_set(err, SPH_ERR_INVALID, path, "'device' is \"cpu\" or \"gpu\", not %s",
                         s ? s : sph_json_type_name(v));
}

static int parse_fluid(const json_t *fluid, const char *path, sph_config *c, sph_output_config *o,
                       sph_error *err)
{
    (void)o;
    return parse_boxes(fluid, path, 1, "fluid", "a fluid block", "fluid", c, c->fluid, &c->nfluid,
                       err);
}

/* "boundary.obstacles": 0 to SPH_CONFIG_MAX_BOXES boxes of wall particles inside the domain. */
static int parse_obstacles(const json_t *v, const char *path, sph_config *c, sph_output_config *o,
                           sph_error *err)
{
    (void)o;
    return parse_boxes(v, path, 0, "obstacles", "an obstacle", "obstacle", c, c->obstacles,
                       &c->nobstacles, err);
}

static int parse_tank(const json_t *v, const char *path, sph_config *c, sph_output_config *o,
                      sph_error *err)
{
    (void)o;
    if (sph_case_parse_box(v, path, c->dim, &c->tank, err))
        return SPH_ERR_INVALID;
    c->has_tank = 1;
    return 0;
}

/* ---- "geometry": shapes with roles (core/scene/sph_scene.h) ---- */

static const char *const role_names[] = {"fluid", "wall", "void", "obstacle", NULL};
static const char *const axis_names[] = {"x", "y", "z", NULL};

static int name_index(const char *s, const char *const *names)
{
    for (int k = 0; s && names[k]; k++)
        if (strcmp(s, names[k]) == 0)
            return k;
    return -1;
}

/* "transform": {"scale", "rotate", "translate"} of item g. */
static int parse_transform(const json_t *v, const char *base, int dim, sph_geometry_spec *g,
                           sph_error *err)
{
    static const char *const keys[] = {"scale", "rotate", "translate", NULL};
    if (!json_is_object(v))
        return sph_error_set(
            err, SPH_ERR_INVALID, base,
            "'transform' must be an object {\"scale\", \"rotate\", \"translate\"}");
    if (sph_json_check_keys(v, base, keys, err) ||
        sph_json_number(v, base, "scale", 0, 0.0, 1e6, &g->transform.scale, err) ||
        sph_json_vector(v, base, "translate", 0, dim, g->transform.translate, err))
        return SPH_ERR_INVALID;
    char path[SPH_ERROR_PATH_MAX];
    snprintf(path, sizeof path, "%s/scale", base);
    if (!(g->transform.scale > 0.0))
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "the scale must be positive (a zero scale has no inside)");
    const json_t *r = json_object_get(v, "rotate");
    if (r && dim == 2) { /* about z: a number, degrees */
        snprintf(path, sizeof path, "%s/rotate", base);
        if (!json_is_number(r))
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "in 2D 'rotate' is one angle about z [degrees], not %s",
                                 sph_json_type_name(r));
        g->transform.rotate[2] = json_number_value(r);
    } else if (r && sph_json_vector(v, base, "rotate", 1, 3, g->transform.rotate, err)) {
        return SPH_ERR_INVALID;
    }
    for (int d = 0; d < 3; d++)
        if (!isfinite(g->transform.rotate[d]) || fabs(g->transform.rotate[d]) > 36000.0) {
            snprintf(path, sizeof path, "%s/rotate", base);
            return sph_error_set(err, SPH_ERR_INVALID, path, "angles are degrees, within 36000");
        }
    return 0;
}

/* A primitive's object at base: box {"min", "max"}, sphere {"center", "radius"}, cylinder
 * {"center", "radius"} in 2D (a circle), {"center", "radius", "axis", "length"} in 3D. */
static int parse_primitive(const json_t *v, const char *base, int dim, sph_geometry_spec *g,
                           sph_error *err)
{
    if (g->kind == SPH_GEOM_BOX) {
        sph_box b;
        if (sph_case_parse_box(v, base, dim, &b, err))
            return SPH_ERR_INVALID;
        memcpy(g->min, b.min, sizeof b.min);
        memcpy(g->max, b.max, sizeof b.max);
        return 0;
    }
    static const char *const sphere_keys[] = {"center", "radius", NULL};
    static const char *const cyl_keys[] = {"center", "radius", "axis", "length", NULL};
    const int cyl3 = g->kind == SPH_GEOM_CYLINDER && dim == 3;
    if (!json_is_object(v))
        return sph_error_set(err, SPH_ERR_INVALID, base, "must be an object, not %s",
                             sph_json_type_name(v));
    if (sph_json_check_keys(v, base, cyl3 ? cyl_keys : sphere_keys, err) ||
        sph_json_vector(v, base, "center", 1, dim, g->center, err) ||
        sph_json_number(v, base, "radius", 1, 0.0, 1e6, &g->radius, err))
        return SPH_ERR_INVALID;
    char path[SPH_ERROR_PATH_MAX];
    snprintf(path, sizeof path, "%s/radius", base);
    if (!(g->radius > 0.0))
        return sph_error_set(err, SPH_ERR_INVALID, path, "the radius must be positive");
    if (cyl3) {
        const char *axis = "z";
        if (sph_json_string(v, base, "axis", 0, &axis, err) ||
            sph_json_number(v, base, "length", 1, 0.0, 1e6, &g->length, err))
            return SPH_ERR_INVALID;
        g->axis = name_index(axis, axis_names);
        snprintf(path, sizeof path, "%s/axis", base);
        if (g->axis < 0)
            return sph_error_set(err, SPH_ERR_INVALID, path, "the axis is \"x\", \"y\" or \"z\"");
        snprintf(path, sizeof path, "%s/length", base);
        if (!(g->length > 0.0))
            return sph_error_set(err, SPH_ERR_INVALID, path, "the length must be positive");
    }
    return 0;
}

/* "polygon": [[x, y], ...] (2D), into a new surface at g->mesh. */
static int parse_polygon(const json_t *v, const char *base, int dim, sph_geometry_spec *g,
                         sph_error *err)
{
    if (dim != 2)
        return sph_error_set(err, SPH_ERR_INVALID, base,
                             "a polygon is a 2D shape: in 3D give a mesh (\"mesh\": FILE)");
    const size_t n = json_array_size(v);
    if (!json_is_array(v) || n < 3 || n > (size_t)SPH_POLYGON_MAX_POINTS)
        return sph_error_set(err, SPH_ERR_INVALID, base,
                             "'polygon' must be an array of 3 to %ld points [x, y]",
                             SPH_POLYGON_MAX_POINTS);
    double *xy = malloc(2 * n * sizeof *xy);
    sph_mesh *m = calloc(1, sizeof *m);
    if (!xy || !m) {
        free(xy);
        free(m);
        return sph_error_set(err, SPH_ERR_NOMEM, base, "out of memory");
    }
    for (size_t i = 0; i < n; i++) {
        const json_t *p = json_array_get(v, i);
        const json_t *px = json_array_get(p, 0), *py = json_array_get(p, 1);
        if (!json_is_array(p) || json_array_size(p) != 2 || !json_is_number(px) ||
            !json_is_number(py)) {
            char path[SPH_ERROR_PATH_MAX];
            snprintf(path, sizeof path, "%s/%zu", base, i);
            free(xy);
            free(m);
            return sph_error_set(err, SPH_ERR_INVALID, path, "a point is [x, y], two numbers");
        }
        xy[2 * i] = json_number_value(px);
        xy[2 * i + 1] = json_number_value(py);
    }
    const int rc = sph_mesh_polygon(m, xy, (long)n, base, err);
    free(xy);
    if (rc) {
        free(m);
        return rc;
    }
    g->mesh = m;
    return 0;
}

/* "/bodies/K/polygon": [[x, y], ...], checked as a geometry item's polygon is (closed, not
 * crossing itself), kept counter-clockwise from its first point about its centroid, which becomes
 * the body's centre. */
static int parse_body_polygon(const json_t *v, const char *path, sph_config *c,
                              sph_output_config *o, sph_error *err)
{
    (void)o;
    int k = -1;
    if (sscanf(path, "/bodies/%d/", &k) != 1 || k < 0 || k >= SPH_CONFIG_MAX_BODIES)
        return sph_error_set(err, SPH_ERR_INVALID, path, "not a body's polygon");
    sph_body_spec *b = &c->bodies[k];
    const size_t n = json_array_size(v);
    if (!json_is_array(v) || n < 3 || n > SPH_BODY_POLYGON_MAX)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "'polygon' must be an array of 3 to %d points [x, y]",
                             SPH_BODY_POLYGON_MAX);
    double xy[2 * SPH_BODY_POLYGON_MAX];
    for (size_t i = 0; i < n; i++) {
        const json_t *p = json_array_get(v, i);
        const json_t *px = json_array_get(p, 0), *py = json_array_get(p, 1);
        if (!json_is_array(p) || json_array_size(p) != 2 || !json_is_number(px) ||
            !json_is_number(py) || !(fabs(json_number_value(px)) <= 1e6) ||
            !(fabs(json_number_value(py)) <= 1e6)) {
            char at[SPH_ERROR_PATH_MAX];
            snprintf(at, sizeof at, "%s/%zu", path, i);
            return sph_error_set(err, SPH_ERR_INVALID, at,
                                 "a point is [x, y], two numbers in [-1e6, 1e6]");
        }
        xy[2 * i] = json_number_value(px);
        xy[2 * i + 1] = json_number_value(py);
    }
    sph_mesh m; /* the checks of sph_mesh_polygon: fewer than 3 points, sides crossing */
    memset(&m, 0, sizeof m);
    const int rc = sph_mesh_polygon(&m, xy, (long)n, path, err);
    sph_mesh_free(&m);
    if (rc)
        return rc;
    long np = (long)n; /* a repeated last point is the first */
    if (np > 3 && xy[0] == xy[2 * (np - 1)] && xy[1] == xy[2 * (np - 1) + 1])
        np--;
    double a = 0.0, cx = 0.0, cy = 0.0; /* centroid of the area, about the first point */
    for (long i = 0; i < np; i++) {
        const long j = (i + 1) % np;
        const double px = xy[2 * i] - xy[0], py = xy[2 * i + 1] - xy[1];
        const double qx = xy[2 * j] - xy[0], qy = xy[2 * j + 1] - xy[1];
        const double w = px * qy - qx * py;
        a += w;
        cx += (px + qx) * w;
        cy += (py + qy) * w;
    }
    cx = xy[0] + cx / (3.0 * a);
    cy = xy[1] + cy / (3.0 * a);
    b->ncorners = (int)np;
    for (long i = 0; i < np; i++) { /* counter-clockwise, the first point first */
        const long from = a > 0.0 ? i : (np - i) % np;
        b->corners[i][0] = xy[2 * from] - cx;
        b->corners[i][1] = xy[2 * from + 1] - cy;
    }
    b->center[0] = cx;
    b->center[1] = cy;
    b->center[2] = 0.0;
    return 0;
}

/* "steering": the history sphd records in a steered job's case.json; an array, else ignored. */
static int parse_steering(const json_t *v, const char *path, sph_config *c, sph_output_config *o,
                          sph_error *err)
{
    (void)c;
    (void)o;
    return json_is_array(v) ? 0
                            : sph_error_set(err, SPH_ERR_INVALID, path,
                                            "'steering' is the array of changes sphd records");
}

/* "triggers": sph_triggers.h (after the diagnostics' and bodies' rows: it checks the series). */
/* /diagnostics/reflection: 2 to 8 distinct names of the case's gauges (parsed before it), for
 * the wave analysis' reflection (a wavemaker's waves: sphd_waves.h). */
static int parse_reflection(const json_t *v, const char *path, sph_config *c, sph_output_config *o,
                            sph_error *err)
{
    if (!json_is_array(v) || json_array_size(v) < 2 || json_array_size(v) > SPH_CONFIG_MAX_GAUGES)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "'reflection' must be an array of 2 to %d gauges' names",
                             SPH_CONFIG_MAX_GAUGES);
    if (c->wavemaker.type == SPH_WAVEMAKER_NONE)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "the reflection is of a wavemaker's waves: add a \"wavemaker\" or "
                             "remove \"reflection\"");
    if (c->wavemaker.waves != SPH_WAVES_REGULAR)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "the reflection is of regular waves, split at their frequency: "
                             "a solitary wave, an irregular sea or a series has no single one");
    o->nreflect = 0;
    for (size_t i = 0; i < json_array_size(v); i++) {
        char at[SPH_ERROR_PATH_MAX];
        snprintf(at, sizeof at, "%s/%zu", path, i);
        const char *name = json_string_value(json_array_get(v, i));
        if (!name)
            return sph_error_set(err, SPH_ERR_INVALID, at, "a gauge's name, a string");
        int k = 0;
        while (k < c->ngauges && strcmp(c->gauges[k].name, name) != 0)
            k++;
        if (k == c->ngauges)
            return sph_error_set(err, SPH_ERR_INVALID, at,
                                 "no gauge named '%s' in diagnostics.gauges", name);
        for (int j = 0; j < o->nreflect; j++)
            if (o->reflect[j] == k)
                return sph_error_set(err, SPH_ERR_INVALID, at, "'%s' is named twice", name);
        o->reflect[o->nreflect++] = k;
    }
    return 0;
}

static int parse_triggers(const json_t *v, const char *path, sph_config *c, sph_output_config *o,
                          sph_error *err)
{
    return sph_triggers_parse(v, path, c, o, err);
}

/* Frees the polygons that parse_geometry made (a mesh item's surface is not read there). */
static void free_polygons(sph_config *c)
{
    for (int k = 0; k < c->ngeometry; k++)
        if (c->geometry[k].kind == SPH_GEOM_POLYGON && c->geometry[k].mesh) {
            sph_mesh *m = (sph_mesh *)c->geometry[k].mesh;
            sph_mesh_free(m);
            free(m);
            c->geometry[k].mesh = NULL;
        }
}

static int parse_geometry_item(const json_t *v, const char *base, sph_config *c,
                               sph_geometry_spec *g, sph_error *err)
{
    static const char *const keys[] = {"mesh", "polygon", "box",       "cylinder", "sphere",
                                       "role", "layers",  "transform", NULL};
    static const char *const kinds[] = {"box", "cylinder", "sphere", "polygon", "mesh", NULL};
    char path[SPH_ERROR_PATH_MAX];
    if (!json_is_object(v))
        return sph_error_set(err, SPH_ERR_INVALID, base,
                             "a geometry item must be an object, not %s", sph_json_type_name(v));
    if (sph_json_check_keys(v, base, keys, err))
        return SPH_ERR_INVALID;
    int kind = -1;
    for (int k = 0; kinds[k]; k++)
        if (json_object_get(v, kinds[k])) {
            if (kind >= 0)
                return sph_error_set(err, SPH_ERR_INVALID, base,
                                     "an item is one shape: both \"%s\" and \"%s\" given",
                                     kinds[kind], kinds[k]);
            kind = k;
        }
    if (kind < 0)
        return sph_error_set(err, SPH_ERR_INVALID, base,
                             "an item needs a shape: \"mesh\", \"polygon\", \"box\", \"cylinder\" "
                             "or \"sphere\"");
    memset(g, 0, sizeof *g);
    g->kind = (sph_geom_kind)kind;
    g->transform.scale = 1.0;
    g->layers = c->layers > 0 ? c->layers : 3;
    const char *role = NULL;
    long layers = g->layers;
    if (sph_json_string(v, base, "role", 1, &role, err) ||
        sph_json_integer(v, base, "layers", 0, 1, 64, &layers, err))
        return SPH_ERR_INVALID;
    g->layers = (int)layers;
    const int r = name_index(role, role_names);
    snprintf(path, sizeof path, "%.39s/role", base);
    if (r < 0)
        return sph_error_set(
            err, SPH_ERR_INVALID, path,
            "the role is \"fluid\", \"wall\", \"void\" or \"obstacle\", not \"%s\"", role);
    g->role = (sph_geom_role)r;
    const json_t *t = json_object_get(v, "transform");
    char sub[64];
    snprintf(sub, sizeof sub, "%.39s/transform", base);
    if (t && parse_transform(t, sub, c->dim, g, err))
        return SPH_ERR_INVALID;
    const json_t *shape = json_object_get(v, kinds[kind]);
    snprintf(sub, sizeof sub, "%.39s/%s", base, kinds[kind]);
    memcpy(path, sub, sizeof sub);
    switch (g->kind) {
    case SPH_GEOM_MESH: {
        const char *f = json_string_value(shape);
        const size_t len = f ? strlen(f) : 0;
        if (!f || len == 0 || len >= sizeof g->file || f[0] == '/' || strstr(f, "..") ||
            strchr(f, '\\'))
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "'mesh' is a file name relative to the case file (1-%zu "
                                 "characters, no leading '/', no \"..\")",
                                 sizeof g->file - 1);
        memcpy(g->file, f, len + 1);
        if (c->dim != 3)
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "a mesh is a 3D surface: in 2D give a \"polygon\"");
        return 0;
    }
    case SPH_GEOM_POLYGON:
        return parse_polygon(shape, sub, c->dim, g, err);
    default:
        return parse_primitive(shape, sub, c->dim, g, err);
    }
}

/* "geometry": 0 to SPH_CONFIG_MAX_GEOMETRY items, in order. */
static int parse_geometry(const json_t *v, const char *path, sph_config *c, sph_output_config *o,
                          sph_error *err)
{
    (void)o;
    if (!json_is_array(v) || json_array_size(v) > SPH_CONFIG_MAX_GEOMETRY)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "'geometry' must be an array of 0 to %d items",
                             SPH_CONFIG_MAX_GEOMETRY);
    c->ngeometry = 0;
    for (size_t i = 0; i < json_array_size(v); i++) {
        char base[40];
        snprintf(base, sizeof base, "/geometry/%zu", i);
        if (parse_geometry_item(json_array_get(v, i), base, c, &c->geometry[i], err)) {
            free_polygons(c);
            return SPH_ERR_INVALID;
        }
        c->ngeometry = (int)i + 1;
    }
    return 0;
}

/* The case-file name of a viscous term (physics.viscosity.type). */
const char *sph_visc_name(int visc)
{
    for (int k = 0; visc_names[k]; k++)
        if (visc_values[k] == visc)
            return visc_names[k];
    return "unknown";
}

/* clang-format off */
const sph_case_field sph_case_fields[] = {
    {.path = "/name", .type = SPH_CF_TEXT, .methods = SPH_CF_SIMS,
     .doc = "the case's name, 1-63 characters"},
    {.path = "/description", .type = SPH_CF_TEXT, .methods = SPH_CF_SIMS, .doc = "free text"},
    {.path = "/method", .type = SPH_CF_TEXT, .methods = SPH_CF_SIMS, .required = SPH_CF_SIMS,
     .doc = "what to run"},
    {.path = "/dim", .type = SPH_CF_INTEGER, .methods = SPH_CF_SIMS, .lo = 2, .hi = 3,
     .has_def = 1, .def = 2, CFG(dim),
     .doc = "dimensions: 2, or 3 (wcsph only; z is the vertical axis in 3D, y in 2D)"},
    {.path = "/device", .type = SPH_CF_CUSTOM, .methods = SPH_CF_SIMS, .parse = parse_device,
     .doc = "where the case runs: \"cpu\" (the default) or \"gpu\" (WCSPH with dynamic walls, "
            "continuity density, no bodies; needs a build with CUDA and a visible GPU)"},
    {.path = "/precision", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .names = precision_names, .values = precision_values, .has_def = 1, .def = 0,
     CFG(precision),
     .doc = "the particles' storage: double (the default), or mixed (positions in double, "
            "velocity, density, pressure and the rates in float; the arithmetic in double): "
            "about a third less memory; WCSPH on the CPU without SPS or bodies"},
    {.path = "/neighbours", .type = SPH_CF_OBJECT, .methods = SPH_CF_WCSPH,
     .doc = "how the pair loop finds its neighbours; absent: the cells searched every step"},
    {.path = "/neighbours/skin", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH, .lo = 0.0,
     .hi = SPH_NEIGHBOUR_SKIN_MAX, .has_def = 1, .def = 0.0, CFG(neighbour_skin),
     .doc = "a list of each particle's neighbours within the support times (1 + skin), reused "
            "over steps until some particle may have moved half the skin (a Verlet list): "
            "fewer distance tests, more memory (0.1 in 2D: a step about 1.2x faster, 60 bytes a "
            "particle more); 0: none. WCSPH on the CPU with dynamic walls of continuity density, "
            "no bodies, wavemaker or shifting"},
    {.path = "/kernel", .type = SPH_CF_OBJECT, .methods = SPH_CF_SIMS, .required = SPH_CF_MPS,
     .doc = "the kernel (section 1.1) and, for wcsph, the smoothing length"},
    {.path = "/kernel/type", .type = SPH_CF_ENUM, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, .names = kernel_names, .has_def = 1,
     .def = SPH_KERNEL_WENDLAND_C2, CFG(kernel.type),
     .doc = "kernel type; wcsph takes the SPH kernels, mps the MPS weights koshizuka and "
            "sheu_quartic"},
    {.path = "/kernel/kappa", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .when = "/kernel/type=double_cosine", .lo = SPH_KERNEL_KAPPA_MIN,
     .hi = SPH_KERNEL_KAPPA_MAX, .has_def = 1, .def = SPH_KERNEL_KAPPA_DEFAULT,
     CFG(kernel.kappa), .doc = "double_cosine: support radius in units of h"},
    {.path = "/kernel/radius", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .when = "/kernel/type=gaussian", .lo = SPH_KERNEL_GAUSS_RADIUS_MIN,
     .hi = SPH_KERNEL_GAUSS_RADIUS_MAX, .has_def = 1, .def = SPH_KERNEL_GAUSS_RADIUS,
     CFG(kernel.radius), .doc = "gaussian: truncation radius in units of h"},
    {.path = "/kernel/h_over_dx", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH, .lo = SPH_H_OVER_DX_MIN,
     .hi = SPH_H_OVER_DX_MAX, .has_def = 1, .def = 1.414, CFG(h_over_dx),
     .doc = "smoothing length h = h_over_dx dx (paper 001: dx/h = 0.5 and 2/9, i.e. 2 and 4.5)"},
    {.path = "/dx", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS, .required = SPH_CF_SIMS,
     .lo = 0.0, .lo_open = 1, .hi = 1e3, CFG(dx), .doc = "initial particle spacing [m]"},
    {.path = "/domain", .type = SPH_CF_BOX, .methods = SPH_CF_SIMS, .required = SPH_CF_SIMS,
     .lo = -1e6, .hi = 1e6, CFG(domain),
     .doc = "{\"min\": [x, y], \"max\": [x, y]} [m]: fluid that leaves it is lost"},
    {.path = "/fluid", .type = SPH_CF_CUSTOM, .methods = SPH_CF_SIMS, .required = SPH_CF_MPS,
     .parse = parse_fluid, CFG(fluid),
     .doc = "array of 1-16 {\"box\": {\"min\", \"max\"}}: blocks of water at spacing dx, inside "
            "the domain (wcsph: or fluid items of the geometry list)"},
    {.path = "/boundary", .type = SPH_CF_OBJECT, .methods = SPH_CF_SIMS, .required = SPH_CF_MPS,
     .doc = "the walls; absent: none (mps needs a tank of dynamic walls)"},
    {.path = "/boundary/type", .type = SPH_CF_ENUM, .methods = SPH_CF_SIMS,
     .names = boundary_names, .values = boundary_values, .has_def = 1, .def = 0, CFG(boundary),
     .doc = "dynamic: fixed boundary particles, density by continuity (Yang et al. 2.3); ghost: "
            "free-slip walls of mirror particles (Colagrossi & Landrini 2003); none"},
    {.path = "/boundary/layers", .type = SPH_CF_INTEGER, .methods = SPH_CF_SIMS,
     .when = "/boundary/type=dynamic", .lo = 1,
     .hi = 8, .has_def = 1, .def = 3, CFG(layers),
     .doc = "layers of wall particles outside the tank's faces"},
    {.path = "/boundary/viscosity_factor", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .when = "/boundary/type=dynamic", .lo = 0.0, .hi = 1.0, .has_def = 1, .def = 1.0,
     CFG(wall_viscosity),
     .doc = "factor on the viscous terms between fluid and wall particles (DualSPHysics' "
            "ViscoBoundFactor); 0: the walls exert no viscous friction"},
    {.path = "/boundary/density", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .when = "/boundary/type=dynamic", .names = wall_density_names,
     .values = wall_density_values, .has_def = 1, .def = 0, CFG(wall_density),
     .doc = "how the wall particles get their density: continuity (DBC: by the continuity "
            "equation, never below rho0); mdbc (English et al. 2021: interpolated from the fluid "
            "at the particle's mirror point across the wall, first-order corrected; smoother "
            "wall pressures, no gap at the walls; the fluid kept out of the walls by a "
            "no-penetration control of its velocity)"},
    {.path = "/boundary/tank", .type = SPH_CF_CUSTOM, .methods = SPH_CF_SIMS,
     .required = SPH_CF_MPS, .parse = parse_tank, CFG(tank),
     .doc = "{\"min\", \"max\"}: inner faces of a tank with bottom, left and right walls (open "
            "top) [m]"},
    {.path = "/boundary/obstacles", .type = SPH_CF_CUSTOM, .methods = SPH_CF_WCSPH,
     .when = "/boundary/type=dynamic", .parse = parse_obstacles, CFG(obstacles),
     .doc = "array of 0-16 {\"box\": {\"min\", \"max\"}}: fixed obstacles, each box filled "
            "with wall particles at spacing dx, inside the domain; fluid leaves their place"},
    {.path = "/geometry", .type = SPH_CF_CUSTOM, .methods = SPH_CF_WCSPH,
     .parse = parse_geometry, CFG(geometry),
     .doc = "array of 0-32 shapes with roles, applied in order (section 1.6): each one of "
            "\"mesh\" (a file: STL, OBJ, PLY; 3D), \"polygon\" ([[x, y], ...]; 2D), \"box\", "
            "\"cylinder\", \"sphere\"; \"role\": fluid, wall, void or obstacle; \"layers\"; "
            "\"transform\": {\"scale\", \"rotate\", \"translate\"}"},
    {.path = "/bodies", .type = SPH_CF_ARRAY, .methods = SPH_CF_WCSPH, .lo = 0,
     .hi = SPH_CONFIG_MAX_BODIES, CFG(bodies), .stride = sizeof(sph_body_spec),
     .count_off = offsetof(sph_config, nbodies),
     .doc = "array of 0-8 rigid bodies of boundary particles (section 1.4); absent: none"},
    {.path = "/bodies/*/name", .type = SPH_CF_STRING, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, BODY(name),
     .doc = "the body's name, 1-31 letters, digits, '_' or '-', distinct: its key in diag "
            "events and its series' prefix in diag.h5"},
    {.path = "/bodies/*/shape", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .names = shape_names, .values = shape_values, BODY(shape),
     .doc = "circle (diameter), box (size) or polygon (its corners)"},
    {.path = "/bodies/*/diameter", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .when = "/bodies/*/shape=circle", .lo = 0.0, .lo_open = 1,
     .hi = 1e3, BODY(diameter), .doc = "circle: diameter [m], at least 2 dx"},
    {.path = "/bodies/*/size", .type = SPH_CF_VECTOR, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .when = "/bodies/*/shape=box", .lo = 0.0, .hi = 1e3, BODY(size),
     .doc = "box: [width, height] [m], each at least 2 dx"},
    {.path = "/bodies/*/polygon", .type = SPH_CF_CUSTOM, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .when = "/bodies/*/shape=polygon", .parse = parse_body_polygon,
     BODY(corners),
     .doc = "polygon: its corners [[x, y], ...] where the body starts (3 to 1024, any "
            "orientation, closed, not crossing itself; its centroid is the centre of mass), at "
            "least 2 dx across"},
    {.path = "/bodies/*/center", .type = SPH_CF_VECTOR, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .when = "/bodies/*/shape=circle|box", .lo = -1e6, .hi = 1e6,
     BODY(center),
     .doc = "circle, box: initial centre of mass [x, y] [m]; the body inside the domain, clear "
            "of the walls and of other bodies"},
    {.path = "/bodies/*/angle", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH, .lo = -1e3,
     .hi = 1e3, .has_def = 1, .def = 0.0, .when = "/bodies/*/shape=circle|box", BODY(angle),
     .doc = "circle, box: initial angle, counter-clockwise [rad]"},
    {.path = "/bodies/*/velocity", .type = SPH_CF_VECTOR, .methods = SPH_CF_WCSPH, .lo = -1e3,
     .hi = 1e3, BODY(velocity),
     .doc = "initial velocity [vx, vy] [m/s], default [0, 0]; kept on an axis that is not free"},
    {.path = "/bodies/*/angular_velocity", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .lo = -1e4, .hi = 1e4, .has_def = 1, .def = 0.0, BODY(omega),
     .doc = "initial angular velocity [rad/s]; kept when rotation is not free"},
    {.path = "/bodies/*/density", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH, .lo = 0.0,
     .lo_open = 1, .hi = 1e6, BODY(density),
     .doc = "density of the solid [kg/m^3]; give density or mass"},
    {.path = "/bodies/*/mass", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH, .lo = 0.0,
     .lo_open = 1, .hi = 1e9, BODY(mass), .doc = "mass [kg] (per metre in 2D); or density"},
    {.path = "/bodies/*/layers", .type = SPH_CF_INTEGER, .methods = SPH_CF_WCSPH, .lo = 0,
     .hi = 8, .has_def = 1, .def = 0, BODY(layers),
     .doc = "layers of particles inside the surface; 0: filled"},
    {.path = "/bodies/*/free", .type = SPH_CF_NAMES, .methods = SPH_CF_WCSPH,
     .names = dof_names, .values = dof_bits, .def_mask = SPH_DOF_ALL, BODY(free),
     .doc = "the degrees of freedom the forces move, from x, y, rotation; the others keep "
            "their initial velocity"},
    {.path = "/bodies/*/pressure", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .names = body_pressure_names, .values = body_pressure_values, .has_def = 1, .def = 0,
     BODY(pressure),
     .doc = "where its particles' pressure comes from: fluid: the fluid around each, with the "
            "body's acceleration (Adami et al. 2012); continuity: their own density, as dynamic "
            "walls"},
    {.path = "/wavemaker", .type = SPH_CF_OBJECT, .methods = SPH_CF_WCSPH,
     .doc = "a paddle of wall particles that makes waves (section 1.8; 2D or 3D, dynamic walls with "
            "continuity density, the built-in tank); absent: none"},
    {.path = "/wavemaker/type", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .names = wavemaker_names, .values = wavemaker_values,
     CFG(wavemaker.type),
     .doc = "piston (moved rigidly in x); flap (turned about a hinge on its face, `hinge` above "
            "the tank's bottom)"},
    {.path = "/wavemaker/x", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .lo = -1e6, .hi = 1e6, CFG(wavemaker.x),
     .doc = "the paddle's wet face at rest [m]: its particles behind it (towards -x), the fluid "
            "boxes in front of it (from x on)"},
    {.path = "/wavemaker/layers", .type = SPH_CF_INTEGER, .methods = SPH_CF_WCSPH, .lo = 1,
     .hi = 8, .has_def = 1, .def = 3, CFG(wavemaker.layers),
     .doc = "columns of wall particles behind the face, the tank's height"},
    {.path = "/wavemaker/ramp", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH, .lo = 0.0,
     .hi = 1e3, .has_def = 1, .def = SPH_WAVEMAKER_RAMP_DEFAULT, CFG(wavemaker.ramp),
     .doc = "periods over which the stroke rises smoothly ((1 - cos(pi t / Tr)) / 2) to its "
            "full value; 0: none (regular waves; a solitary wave has none)"},
    {.path = "/wavemaker/hinge", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH, .lo = -1e6,
     .hi = 1e6, .has_def = 1, .def = 0.0, CFG(wavemaker.hinge),
     .doc = "a flap's hinge, on its face, above the tank's bottom [m]: in the water column, from "
            "0 (the bottom) to below the still water level; a piston has none"},
    {.path = "/wavemaker/absorption", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .names = paddle_absorption_names, .has_def = 1, .def = 0, CFG(wavemaker.active),
     .doc = "active: the piston also absorbs the waves that come back to it, its velocity "
            "corrected by -sqrt(g/d) times the level it measures at its face less the level its "
            "waves should make there (section 1.8; regular first-order, irregular and solitary "
            "waves, the CPU); none: it reflects them"},
    {.path = "/wavemaker/waves", .type = SPH_CF_OBJECT, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .doc = "the waves to make"},
    {.path = "/wavemaker/waves/type", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .names = waves_names, .values = waves_values,
     CFG(wavemaker.waves),
     .doc = "regular: first-order wavemaker theory, the stroke S from the piston's H/S = 2 "
            "(cosh 2kd - 1) / (sinh 2kd + 2kd) or the flap's (section 1.8), k from omega^2 = g k "
            "tanh(kd), d the fluid's top above the tank's bottom (second order from a piston: "
            "`order`); solitary: one solitary wave from Goring's piston law; irregular: a JONSWAP "
            "sea of random-phase components at first order; series: the displacement a file "
            "gives (section 1.8)"},
    {.path = "/wavemaker/waves/height", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .when = "/wavemaker/waves/type=regular|solitary", .lo = 0.0,
     .lo_open = 1, .hi = 1e3, CFG(wavemaker.height),
     .doc = "the wave height H [m]: regular waves below the breaking limit H/L = 0.142 "
            "tanh(kd), a solitary wave up to 0.6 d"},
    {.path = "/wavemaker/waves/period", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .when = "/wavemaker/waves/type=regular|solitary", .lo = 0.0, .lo_open = 1, .hi = 1e3,
     CFG(wavemaker.period),
     .doc = "the wave period T [s]: required for regular waves, refused for a solitary one"},
    {.path = "/wavemaker/waves/order", .type = SPH_CF_INTEGER, .methods = SPH_CF_WCSPH,
     .when = "/wavemaker/waves/type=regular", .lo = 1, .hi = 2, .has_def = 1, .def = 1,
     CFG(wavemaker.order),
     .doc = "1: first-order wavemaker theory; 2: Madsen's (1971) second order, a piston only, "
            "the Ursell number H L^2 / d^3 below 8 pi^2 / 3"},
    {.path = "/wavemaker/waves/spectrum", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .when = "/wavemaker/waves/type=irregular", .names = spectrum_names, .has_def = 1, .def = 0,
     CFG(wavemaker.spectrum),
     .doc = "jonswap: Hasselmann et al.'s (1973) spectrum (gamma 1: Pierson-Moskowitz's)"},
    {.path = "/wavemaker/waves/hs", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .when = "/wavemaker/waves/type=irregular", .lo = 0.0,
     .lo_open = 1, .hi = 1e3, CFG(wavemaker.hs),
     .doc = "the significant wave height Hs = 4 sqrt(m0) [m], Hs over the peak's wavelength "
            "below the breaking limit 0.142 tanh(k d)"},
    {.path = "/wavemaker/waves/tp", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .when = "/wavemaker/waves/type=irregular", .lo = 0.0,
     .lo_open = 1, .hi = 1e3, CFG(wavemaker.tp), .doc = "the spectrum's peak period [s]"},
    {.path = "/wavemaker/waves/gamma", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .when = "/wavemaker/waves/type=irregular", .lo = 1.0, .hi = 10.0, .has_def = 1,
     .def = SPH_JONSWAP_GAMMA_DEFAULT, CFG(wavemaker.gamma),
     .doc = "the peak enhancement factor [-]"},
    {.path = "/wavemaker/waves/duration", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .when = "/wavemaker/waves/type=irregular", .lo = 0.0,
     .lo_open = 1, .hi = 1e5, CFG(wavemaker.duration),
     .doc = "the sea's record before it repeats [s], at least 10 tp: the components are "
            "1 / duration apart from 0.5 to 3 times the peak frequency, at most 2048"},
    {.path = "/wavemaker/waves/seed", .type = SPH_CF_INTEGER, .methods = SPH_CF_WCSPH,
     .when = "/wavemaker/waves/type=irregular", .lo = 0, .hi = 2147483647, .has_def = 1,
     .def = 1, CFG(wavemaker.seed),
     .doc = "the seed of the components' random phases: the same seed, the same sea"},
    {.path = "/wavemaker/waves/file", .type = SPH_CF_STRING, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .when = "/wavemaker/waves/type=series", CFG(wavemaker.file),
     .doc = "a text file of rows 'time, displacement' [s, m] (comma, space or tab separated; a "
            "header line and lines from '#' skipped), relative to the case file, that travels "
            "with the job like a mesh (section 3.11): the face's displacement at the still "
            "water level, times increasing, the paddle at rest at 0 before the first row and "
            "never faster than sqrt(g d)"},
    {.path = "/absorption", .type = SPH_CF_OBJECT, .methods = SPH_CF_WCSPH,
     .doc = "a passive damping zone (section 1.8); absent: none"},
    {.path = "/absorption/type", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .names = absorption_names, .values = absorption_values,
     CFG(absorption.type),
     .doc = "damping: after each step the fluid's velocity times 1 - dt beta f(x), f rising "
            "from 0 at 'from' to 1 at 'to' quadratically (Altomare et al. 2017)"},
    {.path = "/absorption/from", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .lo = -1e6, .hi = 1e6, CFG(absorption.from),
     .doc = "where the zone starts (weight 0) [m], inside the domain, clear of the paddle"},
    {.path = "/absorption/to", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .lo = -1e6, .hi = 1e6, CFG(absorption.to),
     .doc = "where the weight reaches 1 [m] (beyond it, 1), inside the domain"},
    {.path = "/absorption/beta", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH, .lo = 0.0,
     .hi = 1e4, .has_def = 1, .def = SPH_DAMPING_BETA_DEFAULT, CFG(absorption.beta),
     .doc = "the relaxation rate where the weight is 1 [1/s]"},
    {.path = "/physics", .type = SPH_CF_OBJECT, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, .doc = "the fluid and its models"},
    {.path = "/physics/rho0", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS, .lo = 1e-3,
     .hi = 1e6, .has_def = 1, .def = 1000.0, CFG(rho0), .doc = "reference density [kg/m^3]"},
    {.path = "/physics/gravity", .type = SPH_CF_VECTOR, .methods = SPH_CF_SIMS, .lo = -1e3,
     .hi = 1e3, CFG(gravity), .doc = "[gx, gy] [m/s^2], default [0, -9.81]"},
    {.path = "/physics/eos", .type = SPH_CF_OBJECT, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .doc = "the equation of state"},
    {.path = "/physics/eos/type", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .names = eos_names, .values = eos_values, .has_def = 1, .def = 0,
     CFG(eos),
     .doc = "linear: p = c0^2 (rho - rho0) (eq. 16); tait: p = c0^2 rho0/7 ((rho/rho0)^7 - 1)"},
    {.path = "/physics/eos/c0", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .lo = 1e-3, .hi = 1e5, CFG(c0),
     .doc = "numerical speed of sound [m/s]; >= 10 x the largest expected speed"},
    {.path = "/physics/viscosity", .type = SPH_CF_OBJECT, .methods = SPH_CF_SIMS,
     .required = SPH_CF_MPS, .doc = "the viscous term"},
    {.path = "/physics/viscosity/type", .type = SPH_CF_ENUM, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, .names = visc_names, .values = visc_values, .has_def = 1,
     .def = 0, CFG(visc),
     .doc = "artificial: Monaghan's (Macia et al.); laminar: eq. (14) with mu = rho0 nu; "
            "monaghan: Monaghan's term on every pair, alpha = 2 (d + 2) nu / (h c0); mps: "
            "laminar only (the Laplacian model (3.5))"},
    {.path = "/physics/viscosity/alpha", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .when = "/physics/viscosity/type=artificial", .lo = 0.0, .hi = 10.0, .has_def = 1,
     .def = 0.01, CFG(alpha), .doc = "artificial viscosity coefficient"},
    {.path = "/physics/viscosity/nu", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, .when = "/physics/viscosity/type=laminar|monaghan", .lo = 0.0,
     .hi = 1e3,
     CFG(nu), .doc = "kinematic viscosity [m^2/s]"},
    {.path = "/physics/turbulence", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .names = turb_names, .values = turb_values, .has_def = 1, .def = 0, CFG(turb),
     .doc = "sps: Smagorinsky, eqs. (7)-(9) and (15), Cs = 0.12, mixing length dx"},
    {.path = "/physics/delta_sph", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH, .lo = 0.0,
     .hi = 1.0, .has_def = 1, .def = 0.0, CFG(delta_sph),
     .doc = "delta-SPH density diffusion coefficient (Molteni & Colagrossi 2009); 0 = off"},
    {.path = "/physics/delta_sph_form", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .names = delta_form_names, .values = delta_form_values, .has_def = 1, .def = 0,
     CFG(delta_form),
     .doc = "delta-SPH's form: molteni (Molteni & Colagrossi 2009: diffuses the hydrostatic "
            "density gradient too) or fourtakas (Fourtakas et al. 2019: the departure from the "
            "hydrostatic density, rho0 g / c0^2 taken off each pair's difference)"},
    {.path = "/physics/shifting", .type = SPH_CF_OBJECT, .methods = SPH_CF_WCSPH,
     .doc = "particle shifting (Lind et al. 2012 with DualSPHysics' free-surface treatment; the "
            "CPU); absent: none"},
    {.path = "/physics/shifting/type", .type = SPH_CF_ENUM, .methods = SPH_CF_WCSPH,
     .required = SPH_CF_WCSPH, .names = shift_names, .values = shift_values, .has_def = 1,
     .def = 0, CFG(shifting.type),
     .doc = "none; lind: after each step's force evaluation every fluid particle moves by "
            "dr = A h |v| dt grad C, C the particles' concentration (sum V_b grad W_ab), each "
            "component at most 0.1 dx; none at the free surface (div r below free_surface), "
            "scaled by (div r - T) / (dim - T) towards the bulk"},
    {.path = "/physics/shifting/coefficient", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .lo = -100.0, .hi = 0.0, .has_def = 1, .def = SPH_SHIFT_COEFFICIENT_DEFAULT,
     CFG(shifting.coefficient), .doc = "A, negative (down the concentration's gradient); "
                                       "DualSPHysics' default -2"},
    {.path = "/physics/shifting/free_surface", .type = SPH_CF_NUMBER, .methods = SPH_CF_WCSPH,
     .lo = 0.0, .hi = 3.0, .has_def = 1, .def = 0.0, CFG(shifting.free_surface),
     .doc = "the threshold T of div r below which a particle is at the free surface and not "
            "shifted; 0: DualSPHysics' 1.5 in 2D, 2.75 in 3D"},
    {.path = "/initial", .type = SPH_CF_OBJECT, .methods = SPH_CF_SIMS,
     .doc = "an analytic initial velocity field of the fluid (the pressure stays hydrostatic); "
            "absent: rest"},
    {.path = "/initial/type", .type = SPH_CF_ENUM, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, .names = initial_names, .has_def = 1, .def = 0,
     CFG(initial.type),
     .doc = "rest; standing_wave: u = grad phi0 of paper 001 eqs. (6)-(7) in a tank filled "
            "from wall to wall; solitary_wave: paper 004 eqs. (5.1)-(5.2) (or Grimshaw's third "
            "order, initial.order), the surface raised by H sech^2(K (x - x0)) over the fluid "
            "box's top"},
    {.path = "/initial/epsilon", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS,
     .when = "/initial/type=standing_wave", .lo = SPH_SW_EPSILON_MIN, .hi = SPH_SW_EPSILON_MAX,
     .has_def = 1, .def = SPH_SW_EPSILON_DEFAULT, CFG(initial.param[0]),
     .doc = "standing_wave: 2A/H, twice the amplitude over the still depth"},
    {.path = "/initial/wavelength", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS,
     .when = "/initial/type=standing_wave", .lo = SPH_SW_WAVELENGTH_MIN,
     .hi = SPH_SW_WAVELENGTH_MAX, .has_def = 1, .def = SPH_SW_WAVELENGTH_DEFAULT,
     CFG(initial.param[1]),
     .doc = "standing_wave: lambda [m], 2 L / n for a tank of length L; 0: L"},
    {.path = "/initial/height", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, .when = "/initial/type=solitary_wave", .lo = 0.0, .lo_open = 1,
     .hi = SPH_SOL_HEIGHT_MAX, CFG(initial.param[0]),
     .doc = "solitary_wave: H [m], the crest's height above the still water (dx <= H <= 0.7 d; "
            "d/3 at order 3)"},
    {.path = "/initial/crest", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, .when = "/initial/type=solitary_wave", .lo = -SPH_SOL_CREST_MAX,
     .hi = SPH_SOL_CREST_MAX, CFG(initial.param[1]),
     .doc = "solitary_wave: x0 [m], the crest's initial abscissa, inside the tank"},
    {.path = "/initial/order", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS,
     .when = "/initial/type=solitary_wave", .lo = SPH_SOL_ORDER_MIN, .hi = SPH_SOL_ORDER_MAX,
     .has_def = 1, .def = SPH_SOL_ORDER_DEFAULT, CFG(initial.param[2]),
     .doc = "solitary_wave: 1 (paper 004's first-order field) or 3 (Grimshaw's 1971 third order, "
            "H <= d/3)"},
    {.path = "/time", .type = SPH_CF_OBJECT, .methods = SPH_CF_SIMS, .required = SPH_CF_SIMS,
     .doc = "the run's time"},
    {.path = "/time/end", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, .lo = 1e-9, .hi = 1e6, CFG(t_end), .doc = "end time [s]"},
    {.path = "/time/cfl", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS, .lo = 1e-3, .hi = 1.0,
     .has_def = 1, .def = 0.2, CFG(cfl), .doc = "CFL number of the adaptive time step"},
    {.path = "/time/dt", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS, .lo = 1e-12, .hi = 1.0,
     CFG(dt_fixed), .doc = "a fixed time step [s]; absent: adaptive"},
    {.path = "/mps", .type = SPH_CF_OBJECT, .methods = SPH_CF_MPS,
     .doc = "the MPS method's settings (Koshizuka & Oka 1996; Sheu et al. 2011 section 3)"},
    {.path = "/mps/re", .type = SPH_CF_NUMBER, .methods = SPH_CF_MPS, .lo = 1.0, .lo_open = 1,
     .hi = 6.0, .has_def = 1, .def = 2.1, MPS(re),
     .doc = "effective radius of the number density and the Laplacian, in units of dx (more "
            "than the spacing; Koshizuka & Oka 2.1, Sheu et al. 2)"},
    {.path = "/mps/re_grad", .type = SPH_CF_NUMBER, .methods = SPH_CF_MPS, .lo = 1.0,
     .lo_open = 1, .hi = 6.0, .has_def = 1, .def = 2.1, MPS(re_grad),
     .doc = "effective radius of the gradient, in units of dx"},
    {.path = "/mps/beta", .type = SPH_CF_NUMBER, .methods = SPH_CF_MPS, .lo = 0.0, .lo_open = 1,
     .hi = 1.0, .hi_open = 1, .has_def = 1, .def = 0.97, MPS(beta),
     .doc = "free-surface particles: number density below beta n0"},
    {.path = "/mps/tol", .type = SPH_CF_NUMBER, .methods = SPH_CF_MPS, .lo = 0.0, .lo_open = 1,
     .hi = 1.0, .hi_open = 1, .has_def = 1, .def = 1e-8, MPS(tol),
     .doc = "conjugate gradient: relative residual ||b - A p|| / ||b|| to reach"},
    {.path = "/mps/max_iterations", .type = SPH_CF_INTEGER, .methods = SPH_CF_MPS, .lo = 1,
     .hi = 1e9, .has_def = 1, .def = 5000, MPS(maxit),
     .doc = "conjugate gradient: iterations beyond which the job fails as unstable"},
    {.path = "/mps/preconditioner", .type = SPH_CF_ENUM, .methods = SPH_CF_MPS,
     .names = precond_names, .has_def = 1, .def = 2, MPS(precond),
     .doc = "of the conjugate gradient: none, jacobi or ic0 (incomplete Cholesky)"},
    {.path = "/mps/source", .type = SPH_CF_ENUM, .methods = SPH_CF_MPS, .names = source_names,
     .has_def = 1, .def = 0, MPS(source),
     .doc = "source of the pressure equation: density, relaxation rho (n* - n0) / (n0 dt^2) "
            "(Koshizuka & Oka 1996); mixed, the velocity divergence plus that term (Tanaka & "
            "Masunaga 2010)"},
    {.path = "/mps/relaxation", .type = SPH_CF_NUMBER, .methods = SPH_CF_MPS, .lo = 0.0,
     .lo_open = 1, .hi = 1.0, .has_def = 1, .def = 1.0, MPS(relax),
     .doc = "coefficient of the number-density term of the source"},
    {.path = "/mps/gradient", .type = SPH_CF_ENUM, .methods = SPH_CF_MPS,
     .names = gradient_names, .has_def = 1, .def = 0, MPS(corrected),
     .doc = "pressure gradient: minimum, model (3.4) with the local minimum pressure (Koshizuka "
            "& Oka); corrected, with the corrective matrix and without it (Khayyer & Gotoh 2011)"},
    {.path = "/mps/surface", .type = SPH_CF_ENUM, .methods = SPH_CF_MPS, .names = surface_names,
     .has_def = 1, .def = 0, MPS(surface),
     .doc = "free-surface condition: particles, p = 0 on the surface particles (Koshizuka & "
            "Oka); water_line, p = 0 dx/2 beyond them by ghost-fluid extrapolation (Gibou et al. "
            "2002)"},
    {.path = "/mps/collision", .type = SPH_CF_NUMBER, .methods = SPH_CF_MPS, .lo = 0.0,
     .hi = 1.0, .hi_open = 1, .has_def = 1, .def = 0.0, MPS(collision),
     .doc = "collision model: pairs closer than this many dx that approach exchange momentum; "
            "0: off"},
    {.path = "/mps/restitution", .type = SPH_CF_NUMBER, .methods = SPH_CF_MPS, .lo = 0.0,
     .hi = 1.0, .has_def = 1, .def = 0.2, MPS(restitution),
     .doc = "collision model: coefficient of restitution"},
    {.path = "/mps/stabilization", .type = SPH_CF_NUMBER, .methods = SPH_CF_MPS, .lo = 0.0,
     .hi = 1.0, .has_def = 1, .def = 0.0, MPS(stabilization),
     .doc = "dynamic stabilization (after Tsuruta, Khayyer & Gotoh 2013): pairs that would end "
            "the next step closer than this many dx lose the relative velocity that brings them "
            "closer; 0: off"},
    {.path = "/output", .type = SPH_CF_OBJECT, .methods = SPH_CF_SIMS,
     .doc = "particle snapshots; absent: none"},
    {.path = "/output/every", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, .lo = 1e-9, .hi = 1e6, OUT(every),
     .doc = "simulated time between snapshots [s]"},
    {.path = "/output/fields", .type = SPH_CF_NAMES, .methods = SPH_CF_SIMS,
     .names = field_names, .values = field_bits,
     .def_mask = SPH_FIELD_POS | SPH_FIELD_VEL | SPH_FIELD_RHO | SPH_FIELD_P | SPH_FIELD_TYPE,
     OUT(fields), .doc = "fields of the snapshots; pos is always written"},
    {.path = "/output/compress", .type = SPH_CF_INTEGER, .methods = SPH_CF_SIMS, .lo = 0,
     .hi = 9, .has_def = 1, .def = 0, OUT(compress),
     .doc = "deflate level with shuffle; 0: none"},
    {.path = "/diagnostics", .type = SPH_CF_OBJECT, .methods = SPH_CF_SIMS,
     .doc = "diag events"},
    {.path = "/diagnostics/every", .type = SPH_CF_INTEGER, .methods = SPH_CF_SIMS, .lo = 1,
     .hi = 1e9, .has_def = 1, .def = 100, CFG(diag_every),
     .doc = "steps between diag events (without interval)"},
    {.path = "/diagnostics/interval", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS, .lo = 1e-9,
     .hi = 1e6, CFG(diag_interval),
     .doc = "simulated time between diag events [s]: the steps land on its multiples (the probes "
            "sampled at fixed times); replaces every; absent: every steps"},
    {.path = "/diagnostics/probes", .type = SPH_CF_NAMES, .methods = SPH_CF_SIMS,
     .names = probe_names, .values = probe_bits,
     .def_mask = SPH_PROBE_FRONT_X | SPH_PROBE_HEIGHT_LEFT, CFG(probes),
     .doc = "probes added to diag (ekin, epot, vmax are always there); penetration: the first "
            "body's"},
    {.path = "/diagnostics/gauges", .type = SPH_CF_ARRAY, .methods = SPH_CF_SIMS, .lo = 0,
     .hi = SPH_CONFIG_MAX_GAUGES, CFG(gauges), .stride = sizeof(sph_gauge_spec),
     .count_off = offsetof(sph_config, ngauges),
     .doc = "array of 0-8 height gauges: the free surface's height above the tank's bottom on a "
            "vertical line, in diag under gauges.NAME; absent: none"},
    {.path = "/diagnostics/gauges/*/name", .type = SPH_CF_STRING, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, GAUGE(name),
     .doc = "the gauge's name, 1-31 letters, digits, '_' or '-', distinct, not a diag series' "
            "own: its key in diag events' gauges and its series in diag.h5"},
    {.path = "/diagnostics/gauges/*/x", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, .lo = -1e6, .hi = 1e6, GAUGE(x),
     .doc = "the vertical line's abscissa [m], inside the tank (the domain without one)"},
    {.path = "/diagnostics/gauges/*/y", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, .when = "/dim=3", .lo = -1e6, .hi = 1e6, GAUGE(y),
     .doc = "3D: the vertical line's y [m], inside the tank (the domain without one)"},
    {.path = "/diagnostics/gauges/*/to", .type = SPH_CF_NUMBER, .methods = SPH_CF_SIMS,
     .lo = -1e6, .hi = 1e6, GAUGE(to),
     .doc = "a run-up gauge: the top of the water over x in [x, to] [m] (past x, inside the "
            "tank) instead of on a line: the highest point the water reaches there, e.g. on a "
            "beach; absent: a line"},
    {.path = "/diagnostics/pressure", .type = SPH_CF_ARRAY, .methods = SPH_CF_SIMS, .lo = 0,
     .hi = SPH_CONFIG_MAX_GAUGES, CFG(pressure), .stride = sizeof(sph_pressure_spec),
     .count_off = offsetof(sph_config, npressure),
     .doc = "array of 0-8 pressure probes: the pressure at a point (a sensor on a wall), "
            "Shepard-interpolated from the fluid within a kernel support, in diag under "
            "pressure.NAME; absent: none"},
    {.path = "/diagnostics/pressure/*/name", .type = SPH_CF_STRING, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, PRESSURE(name),
     .doc = "the probe's name, like a gauge's, distinct from every gauge's and probe's"},
    {.path = "/diagnostics/pressure/*/at", .type = SPH_CF_VECTOR, .methods = SPH_CF_SIMS,
     .required = SPH_CF_SIMS, .lo = -1e6, .hi = 1e6, PRESSURE(at),
     .doc = "the point [m] (dim components), inside the domain"},
    {.path = "/diagnostics/pressure/*/normal", .type = SPH_CF_VECTOR, .methods = SPH_CF_SIMS,
     .lo = -1e6, .hi = 1e6, PRESSURE(normal),
     .doc = "the wall's normal into the fluid at the point (dim components, any length): the "
            "probe reads 1.5 h along it, off the wall's bias, as the peers do; absent or all 0: "
            "at the point"},
    {.path = "/diagnostics/reflection", .type = SPH_CF_CUSTOM, .methods = SPH_CF_WCSPH,
     .parse = parse_reflection, OUT(nreflect),
     .doc = "2-8 names of gauges (diagnostics.gauges) between the paddle and the damping zone "
            "from which the result's reflection splits a wavemaker's waves into incident and "
            "reflected ones (least squares at their frequency: Mansard & Funke 1980; with two "
            "gauges Goda & Suzuki 1976); spaced within a wavelength, not near half of one (e.g. "
            "0, L/10 and L/4); absent: no reflection analysis"},
    {.path = "/steering", .type = SPH_CF_CUSTOM, .methods = SPH_CF_SIMS, .parse = parse_steering,
     .doc = "written by sphd into a steered job's case.json: the changes `set` made, "
            "[{\"step\", \"t\", \"set\"}, ...] (section 3.12); ignored when a case is "
            "submitted"},
    {.path = "/triggers", .type = SPH_CF_CUSTOM, .methods = SPH_CF_SIMS, .parse = parse_triggers,
     OUT(triggers),
     .doc = "array of 0-16 {\"when\": \"SERIES OP VALUE\", \"do\": pause|stop|checkpoint|"
            "snapshot}: what to do, once, at the first diagnostic whose SERIES (a diag series: "
            "t, ekin, front_x, a gauge's or probe's name, BODY.penetration, ...) meets the "
            "condition (OP >, >=, <, <=); section 1.7; absent: none"},
    {.path = NULL},
};
/* clang-format on */
