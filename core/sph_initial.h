/*
 * sph_initial: named analytic initial conditions on the fluid, beyond rest. Each field is one row
 * of a small table (sph_initial.c): its case-file name, its parameters (name, unit, default,
 * range: what the case parser, the schema and PROTOCOL.md list), a check that it fits the case
 * (errors at the case field's JSON path), the initial velocity at a point and, where there is
 * one, the theory a run is compared with. The pressure stays hydrostatic (sph_shapes.h), as the
 * fields here are defined at an instant when it is (paper 001, section IV-B).
 *
 * A field may also raise the free surface above the fluid box's top (the solitary wave): the
 * fluid box's shape (sph_shapes.c) then stacks its columns up to the raised surface, and the
 * initial pressure is hydrostatic under it.
 *
 * A later field (a moving body, a current) is one more enum value and one more row.
 *
 * Layer 2 of the set-up pipeline (DESIGN.md section 2): pure functions of the configuration. May
 * call: the lattice (sph_lattice.h), the configuration's own helpers (sph_config.h), libm. Never
 * the shapes, the fill, the bodies or the sim, which call it. Its types and constants, which the
 * configuration holds, are in sph_initial_spec.h.
 */
#ifndef SPH_INITIAL_H
#define SPH_INITIAL_H

#include "sph_error.h"
#include "sph_initial_spec.h"

struct sph_config;

/* One parameter of a field, as the case file names it. */
typedef struct sph_initial_param {
    const char *name; /* case-file key inside "initial" */
    const char *unit; /* SI unit, "-" for none */
    double def;       /* value when the case omits it */
    double min, max;  /* allowed range (inclusive) */
    const char *doc;  /* one line for PROTOCOL.md and error messages */
} sph_initial_param;

/* What theory says about a run from this field (zero where it says nothing). */
typedef struct sph_initial_theory {
    double period;     /* oscillation period [s] */
    double omega;      /* circular frequency [1/s] */
    double decay_rate; /* decay rate of the kinetic-energy envelope [1/s] */
    double ekin0;      /* initial kinetic energy [J] (per metre in 2D) */
} sph_initial_theory;

/* The field's name ("rest", "standing_wave"), NULL for an invalid type. */
const char *sph_initial_name(sph_initial_type type);
/* Type from its name; -1 if unknown. */
int sph_initial_from_name(const char *name);
/* The field's parameters: *n of them. */
const sph_initial_param *sph_initial_params(sph_initial_type type, int *n);
/* The spec with every parameter at its default. */
sph_initial_spec sph_initial_default(sph_initial_type type);

/* Checks that the field fits the case c (SPH_ERR_INVALID with the path of the case field that
 * does not fit, under /initial for the field's own parameters). */
int sph_initial_check(const struct sph_config *c, sph_error *err);

/* The initial velocity v (c->dim components) [m/s] at point x [m]. */
void sph_initial_velocity(const struct sph_config *c, const double *x, double *v);

/* The field's free-surface elevation above the still water at abscissa x [m] (0 for the fields
 * that keep the surface flat), and its largest value over the tank. The still water is the
 * fluid box's whole rows of particles. */
double sph_initial_elevation(const struct sph_config *c, double x);
double sph_initial_elevation_max(const struct sph_config *c);

/* The theory for the field under c (nu from the viscosity) into *t; 0, or -1 when the field has
 * none (rest). */
int sph_initial_theory_of(const struct sph_config *c, sph_initial_theory *t);

#endif
