/*
 * sph_initial_spec: what a case says of its initial field (sph_initial.h): the field, its
 * parameters and their ranges. Types and constants only, so that the plain configuration
 * (sph_config.h) holds a field without seeing the functions that evaluate it.
 */
#ifndef SPH_INITIAL_SPEC_H
#define SPH_INITIAL_SPEC_H

typedef enum {
    SPH_INITIAL_REST = 0,      /* fluid at rest (the default) */
    SPH_INITIAL_STANDING_WAVE, /* paper 001 eqs. (6)-(7): u = grad phi0 */
    SPH_INITIAL_SOLITARY_WAVE, /* paper 004 eqs. (5.1)-(5.2), or Grimshaw's third order: a raised
                                * surface and its velocities */
    SPH_INITIAL_COUNT
} sph_initial_type;

#define SPH_INITIAL_MAX_PARAMS 4

/* The standing wave's parameters (the table's row and the case parser's rows share them). */
#define SPH_SW_EPSILON_DEFAULT    0.1
#define SPH_SW_EPSILON_MIN        1e-6
#define SPH_SW_EPSILON_MAX        0.5
#define SPH_SW_WAVELENGTH_DEFAULT 0.0 /* the tank's length */
#define SPH_SW_WAVELENGTH_MIN     0.0
#define SPH_SW_WAVELENGTH_MAX     1e6

/* The solitary wave's parameters: the crest's height above the still water, its position and the
 * order of the field (1: paper 004's first-order field, 3: Grimshaw's third order). */
#define SPH_SOL_HEIGHT_MAX     1e3
#define SPH_SOL_HEIGHT_RATIO   0.7 /* H / d at most: steeper waves break (theory: about 0.78) */
#define SPH_SOL_HEIGHT_RATIO_3 (1.0 / 3.0) /* H / d at most at the third order (sph_initial.c) */
#define SPH_SOL_CREST_MAX      1e6
#define SPH_SOL_ORDER_DEFAULT  1.0
#define SPH_SOL_ORDER_MIN      1.0
#define SPH_SOL_ORDER_MAX      3.0

/* What a case says: the field and its parameters, in the order of the row's `params`. */
typedef struct sph_initial_spec {
    sph_initial_type type;
    double param[SPH_INITIAL_MAX_PARAMS];
} sph_initial_spec;

#endif
