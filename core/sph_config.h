/*
 * sph_config: the plain configuration of a particle simulation (what a case file says), filled
 * by protocol/sph_case.c and read by sph_sim_create(). No JSON here: the core knows nothing of
 * files. Every length is in metres, every time in seconds, densities in kg/m^3.
 */
#ifndef SPH_CONFIG_H
#define SPH_CONFIG_H

#include "sph_initial_spec.h"
#include "sph_kernel.h"

#define SPH_CONFIG_MAX_BOXES    16
#define SPH_CONFIG_MAX_BODIES   8
#define SPH_BODY_NAME_MAX       32
#define SPH_CONFIG_MAX_GAUGES   8
#define SPH_CONFIG_MAX_GEOMETRY 32
#define SPH_GEOMETRY_FILE_MAX   128
#define SPH_GAUGE_NAME_MAX      32
#define SPH_H_OVER_DX_MIN       0.5 /* smoothing length range, in units of dx */
#define SPH_H_OVER_DX_MAX       4.5
#define SPH_NEIGHBOUR_SKIN_MAX  1.0 /* a reused neighbour list's largest skin, of the support */

/* An axis-aligned box; components beyond dim are ignored. */
typedef struct sph_box {
    double min[3]; /* lower corner [m] */
    double max[3]; /* upper corner [m] */
} sph_box;

/* What a case runs (its "method"). The kernel study is not a particle simulation (study/); the
 * others run behind the sim handle through the table of sph_method.h. */
typedef enum {
    SPH_METHOD_KERNEL_STUDY = 0,
    SPH_METHOD_WCSPH,
    SPH_METHOD_MPS,
    SPH_METHOD_COUNT
} sph_method;

/* Each enum ends with its count, so that a configuration read back from bytes is checked against
 * it (sph_sim_check) and a new member needs no other change there. */
typedef enum {
    SPH_BOUNDARY_NONE = 0,
    SPH_BOUNDARY_DYNAMIC,
    SPH_BOUNDARY_GHOST,
    SPH_BOUNDARY_COUNT
} sph_boundary_type;

/* How dynamic wall particles get their density: by continuity (DBC, Crespo et al. 2007), or
 * interpolated from the fluid at their mirror points (mDBC, English et al. 2021; sph_mdbc.h). */
typedef enum { SPH_WALL_CONTINUITY = 0, SPH_WALL_MDBC, SPH_WALL_COUNT } sph_wall_density;

/* The case's "precision": every particle field in double, or mixed (positions in double, the
 * other hot fields in float: sph_particles.h). */
typedef enum { SPH_PRECISION_DOUBLE = 0, SPH_PRECISION_MIXED, SPH_PRECISION_COUNT } sph_precision;

/* The case's "device". */
typedef enum { SPH_DEVICE_CPU = 0, SPH_DEVICE_GPU } sph_device;

typedef enum { SPH_EOS_LINEAR = 0, SPH_EOS_TAIT, SPH_EOS_COUNT } sph_eos_type;
typedef enum {
    SPH_VISC_ARTIFICIAL = 0,
    SPH_VISC_LAMINAR,
    SPH_VISC_MONAGHAN,
    SPH_VISC_COUNT
} sph_visc_type;
typedef enum { SPH_TURB_NONE = 0, SPH_TURB_SPS, SPH_TURB_COUNT } sph_turb_type;

/* The form of delta-SPH's density diffusion: Molteni & Colagrossi's (2009), which diffuses the
 * hydrostatic density gradient too, or Fourtakas et al.'s (2019), which diffuses the density's
 * departure from the hydrostatic one (the gradient rho0 g / c0^2 taken off each pair's
 * difference). */
typedef enum { SPH_DELTA_MOLTENI = 0, SPH_DELTA_FOURTAKAS, SPH_DELTA_COUNT } sph_delta_form;

/* Probes a diag can carry besides the always-present fields (bit mask). */
enum {
    SPH_PROBE_FRONT_X = 1 << 0,
    SPH_PROBE_HEIGHT_LEFT = 1 << 1,
    SPH_PROBE_PENETRATION = 1 << 2, /* the first body's lowest point below the initial level */
    SPH_PROBE_RUNUP = 1 << 3        /* the water's top at the right wall */
};

/* Shapes of rigid bodies (boundary/sph_body.h). */
typedef enum { SPH_SHAPE_CIRCLE = 0, SPH_SHAPE_BOX, SPH_SHAPE_POLYGON } sph_shape_type;

/* The most corners of a polygon body (kept in the configuration, so a checkpoint holds it). */
#define SPH_BODY_POLYGON_MAX 1024

/* The kinds of a case's "geometry" items (core/scene/sph_scene.h). */
typedef enum {
    SPH_GEOM_BOX = 0,
    SPH_GEOM_CYLINDER,
    SPH_GEOM_SPHERE,
    SPH_GEOM_POLYGON,
    SPH_GEOM_MESH,
    SPH_GEOM_KIND_COUNT
} sph_geom_kind;

/* What a geometry item does: fluid fills its inside; wall puts `layers` rows of wall particles
 * inside its surface; void carves fluid out; obstacle is a wall that also carves fluid. */
typedef enum {
    SPH_ROLE_FLUID = 0,
    SPH_ROLE_WALL,
    SPH_ROLE_VOID,
    SPH_ROLE_OBSTACLE,
    SPH_ROLE_COUNT
} sph_geom_role;

/* x -> translate + Rz Ry Rx (scale x): scaled, rotated about x, then y, then z (degrees), moved. */
typedef struct sph_transform {
    double scale;        /* > 0 [-] */
    double rotate[3];    /* about x, y, z [degrees] (2D: z only) */
    double translate[3]; /* [m] */
} sph_transform;

struct sph_mesh;

/* One item of a case's "geometry" list. */
typedef struct sph_geometry_spec {
    sph_geom_kind kind;
    sph_geom_role role;
    int layers;              /* wall, obstacle: rows of wall particles inside the surface [-] */
    sph_transform transform; /* applied to the shape as given */
    double min[3], max[3];   /* box: corners [m] */
    double center[3];        /* cylinder, sphere: centre [m] (a cylinder's, half way along it) */
    double radius;           /* cylinder, sphere [m] */
    double length;           /* cylinder (3D): along its axis [m] */
    int axis;                /* cylinder (3D): 0, 1, 2 for x, y, z */
    char file[SPH_GEOMETRY_FILE_MAX]; /* mesh: the file's name as the case gives it */
    const struct sph_mesh *mesh;      /* polygon, mesh: the surface, owned by the case that
                                         read it; needed by sph_sim_create only (NULL in a
                                         restored state, whose particles are saved) */
} sph_geometry_spec;

/* Where a rigid body's particles take their pressure from (boundary/sph_body_pressure.c). */
typedef enum {
    SPH_BODY_PRESSURE_FLUID = 0, /* the fluid around them (Adami, Hu & Adams 2012) */
    SPH_BODY_PRESSURE_CONTINUITY /* their own density by continuity, as dynamic walls */
} sph_body_pressure;

/* Degrees of freedom of a rigid body (mask bits). */
enum { SPH_DOF_X = 1 << 0, SPH_DOF_Y = 1 << 1, SPH_DOF_ROTATION = 1 << 2, SPH_DOF_ALL = 7 };

/* A height gauge: the free surface's height above the tank's bottom (the domain's without a
 * tank) on the vertical line at x (2D) or (x, y) (3D: z is the vertical), sampled with the
 * diagnostics (sph_diag.c). */
typedef struct sph_gauge_spec {
    char name[SPH_GAUGE_NAME_MAX]; /* its key in diag events and its series in diag.h5 */
    double x;                      /* the line's abscissa [m] */
    double y;                      /* 3D: the line's y [m] */
    double to; /* a run-up gauge: the top of the water over x in [x, to] [m]; NaN: a line */
} sph_gauge_spec;

/* A pressure probe: the pressure at a point (a sensor on a wall), interpolated from the fluid
 * particles within a kernel support with a Shepard correction, sampled with the diagnostics
 * (sph_diag.c); 0 where no fluid is within reach (a dry sensor). With a normal, it reads
 * SPH_PROBE_OFFSET_H smoothing lengths off the wall along it (sph_config_pressure_point). */
typedef struct sph_pressure_spec {
    char name[SPH_GAUGE_NAME_MAX]; /* its key in diag events and its series in diag.h5 */
    double at[3];                  /* the point [m] */
    double normal[3];              /* the wall's normal into the fluid there (any length), or
                                      0, 0, 0: read at the point itself */
} sph_pressure_spec;

/* How far off its wall a pressure probe with a normal reads, in smoothing lengths: within about
 * a kernel support of a wall, the kernel's truncation there and the wall's first layer of
 * particles bias an interpolated pressure, so the peers read their wall sensors 1.5 h into the
 * fluid (DualSPHysics' MeasureTool "correct" points, e.g. its 01_DamBreak example). */
#define SPH_PROBE_OFFSET_H 1.5

/* A rigid body of boundary particles (boundary/sph_body.h): its shape, its mass (density or
 * mass: the other is 0), its initial motion and the degrees of freedom the forces move. */
typedef struct sph_body_spec {
    char name[SPH_BODY_NAME_MAX]; /* the body's name in diagnostics */
    sph_shape_type shape;         /* circle, box or polygon */
    double diameter;              /* circle: diameter [m] */
    double size[3];               /* box: edge lengths [m] */
    int ncorners;                 /* polygon: its corners, 3 to SPH_BODY_POLYGON_MAX [-] */
    double corners[SPH_BODY_POLYGON_MAX][2]; /* polygon: counter-clockwise, from its centroid
                                                (the centre of mass), the first as given [m] */
    double center[3];                        /* initial centre of mass [m] */
    double angle;                            /* initial angle, counter-clockwise [rad] */
    double velocity[3];         /* initial velocity [m/s] (prescribed on a fixed axis) */
    double omega;               /* initial angular velocity [rad/s] (prescribed if fixed) */
    double density;             /* [kg/m^3], 0 when the mass is given */
    double mass;                /* [kg] (per metre in 2D), 0 when the density is given */
    int layers;                 /* layers of particles inside the surface, 0: filled [-] */
    unsigned free;              /* SPH_DOF_* mask of the free degrees of freedom */
    sph_body_pressure pressure; /* its particles' pressure: from the fluid or continuity */
} sph_body_spec;

/* A wavemaker (boundary/sph_wavemaker.h): a paddle of wall particles moved by a law of time. */
typedef enum {
    SPH_WAVEMAKER_NONE = 0,
    SPH_WAVEMAKER_PISTON, /* moved rigidly in x */
    SPH_WAVEMAKER_FLAP,   /* turned about a hinge */
    SPH_WAVEMAKER_COUNT
} sph_wavemaker_type;

/* The waves a wavemaker makes. */
typedef enum {
    SPH_WAVES_REGULAR = 0, /* first-order wavemaker theory (second order: Madsen's piston) */
    SPH_WAVES_SOLITARY,    /* Goring's piston law */
    SPH_WAVES_IRREGULAR,   /* a JONSWAP spectrum's random-phase components, first order */
    SPH_WAVES_SERIES,      /* the displacement read from a file (time, displacement) */
    SPH_WAVES_COUNT
} sph_waves_type;

/* The displacement of a paddle at the still water level as a file gives it: n rows of time [s]
 * increasing and displacement [m] (sph_wavemaker.h reads and checks it). */
typedef struct sph_wave_series {
    long n;
    double *t, *x;
} sph_wave_series;

#define SPH_WAVE_SERIES_MAX      1000000L /* rows of a series [-] */
#define SPH_IRREGULAR_COMPONENTS 2048     /* the most components of an irregular sea [-] */

/* A case's "wavemaker": a piston or a flap of `layers` columns of wall particles, the tank's
 * height, whose wet face (towards +x) rests at x (a flap's hinge on it, `hinge` above the tank's
 * bottom); regular waves of height H and period T by first-order wavemaker theory, ramped up over
 * `ramp` periods, or a solitary wave of height H by Goring's piston law. */
typedef struct sph_wavemaker_spec {
    sph_wavemaker_type type; /* none (no wavemaker), piston or flap */
    double x;                /* the paddle's wet face at rest [m] */
    int layers;              /* columns of wall particles behind the face [-] */
    double ramp;             /* periods over which the motion rises to its full stroke [-] */
    double hinge;            /* flap: the hinge's height above the tank's bottom [m] */
    sph_waves_type waves;    /* regular, solitary, irregular or series */
    double height;           /* the target wave height H [m] (regular, solitary) */
    double period;           /* the wave period T [s] (regular; 0: not given) */
    int order;               /* regular: 1 (first-order theory) or 2 (Madsen 1971, a piston) */
    /* irregular: a JONSWAP spectrum of significant height hs [m] (Hm0 = 4 sqrt(m0)), peak
     * period tp [s] and peak enhancement gamma, discretised into components 1 / duration apart
     * in frequency from 0.5 to 3 times the peak's (the motion repeats after duration [s]), each
     * with a phase drawn from seed */
    int spectrum; /* irregular: 0, JONSWAP (the only one) */
    double hs, tp, gamma, duration;
    long seed;
    /* series: the file the case names (relative to it) and its rows once read (NULL before:
     * the case owns them, sph_case_load_files) */
    char file[SPH_GEOMETRY_FILE_MAX];
    const sph_wave_series *series;
    int active; /* 1: active absorption at a piston (boundary/sph_wavemaker.h), 0: none */
} sph_wavemaker_spec;

/* A case's "absorption": a passive damping zone (Altomare et al. 2017) that relaxes the fluid's
 * velocity towards zero after every step, v *= 1 - dt beta f(x), f rising from 0 at `from` to 1
 * at `to` quadratically (boundary/sph_wavemaker.h). */
typedef struct sph_absorption_spec {
    int type;        /* 0: none, 1: damping */
    double from, to; /* where the weight is 0 and where it reaches 1 [m] */
    double beta;     /* relaxation rate [1/s] */
} sph_absorption_spec;

/* A case's "physics.shifting": particle shifting (Lind et al. 2012, J. Comput. Phys. 231) in
 * DualSPHysics' form with its free-surface treatment (core/wcsph/sph_shifting.h). */
typedef enum { SPH_SHIFT_NONE = 0, SPH_SHIFT_LIND, SPH_SHIFT_COUNT } sph_shift_type;
#define SPH_SHIFT_COEFFICIENT_DEFAULT (-2.0) /* DualSPHysics' default A [-] */
typedef struct sph_shifting_spec {
    sph_shift_type type; /* none (default) or lind */
    double coefficient;  /* A in dr = A h |v| dt grad C (negative: down the gradient) [-] */
    double free_surface; /* the divergence of position below which a particle is at the free
                            surface (no shift); 0: DualSPHysics' 1.5 in 2D, 2.75 in 3D [-] */
} sph_shifting_spec;

/* What wavemaker theory gives for a case's wavemaker (sph_sim_wave_design): first-order theory
 * for regular waves, Goring's law for a solitary wave (then omega, k, length and cg are 0). */
typedef struct sph_wave_design {
    double depth;  /* still water depth d [m] */
    double omega;  /* 2 pi / T [rad/s] */
    double k;      /* wave number [1/m] */
    double length; /* wave length L = 2 pi / k [m] */
    double stroke; /* S = H / (H/S)(kd) at the still water level (solitary: sqrt(16 H d / 3)) [m] */
    double cg;     /* group velocity (omega / k) (1 + 2kd / sinh 2kd) / 2 [m/s] */
    double kappa;  /* solitary: sqrt(3H / (4 d^3)) [1/m] */
    double celerity; /* solitary: sqrt(g (d + H)) [m/s] */
    double duration; /* solitary: the paddle's travel time 2 (3.8 + H/d) / (kappa c) [s] */
    double lag;      /* solitary: how far the crest trails the wave's front, 3.8 / kappa [m] */
} sph_wave_design;

#define SPH_DAMPING_BETA_DEFAULT   10.0 /* [1/s] */
#define SPH_WAVEMAKER_RAMP_DEFAULT 2.0  /* periods [-] */
#define SPH_JONSWAP_GAMMA_DEFAULT  3.3  /* the JONSWAP peak enhancement factor [-] */

/* The MPS method's fields (Koshizuka & Oka 1996; Sheu, Chiao & Huang 2011): defaults from
 * sph_mps_config_default() (core/mps/sph_mps.c). */
typedef struct sph_mps_config {
    double re;      /* effective radius of the number density and the Laplacian, in dx [-] */
    double re_grad; /* effective radius of the gradient, in dx [-] */
    double beta;    /* free-surface particles: number density below beta n0 [-] */
    double tol;     /* CG: relative residual ||b - A p|| / ||b|| to reach [-] */
    long maxit;     /* CG: iterations after which the job fails as unstable [-] */
    int precond;    /* CG preconditioner: 0 none, 1 jacobi, 2 ic0, 3 amg (sph_mps_precond) */
    int source;     /* PPE source: 0 number density (Koshizuka & Oka 1996), 1 mixed (Tanaka &
                     * Masunaga 2010: velocity divergence plus relax times the density term) */
    double relax;   /* coefficient of the number-density term relax rho (n* - n0) / (n0 dt^2) [-] */
    int corrected;  /* 1: gradient with the corrective matrix (Khayyer & Gotoh 2011) [-] */
    int surface;    /* free-surface condition: 0 p = 0 at the surface particles' centres
                     * (Koshizuka & Oka 1996); 1 p = 0 on the water line dx/2 beyond them, the
                     * surface particles unknowns with the missing neighbours' pressures
                     * extrapolated linearly to it (the ghost-fluid Dirichlet condition of Gibou
                     * et al. 2002, J. Comput. Phys. 176); sph_mps.c [-] */
    double collision;     /* collision distance in dx, 0 = no collision model [-] */
    double restitution;   /* coefficient of restitution of the collision model [-] */
    double stabilization; /* dynamic stabilization (after Tsuruta, Khayyer & Gotoh 2013): pairs
                           * that would end the next step closer than this many dx lose the
                           * relative velocity that brings them closer; 0 = off [-] */
} sph_mps_config;

sph_mps_config sph_mps_config_default(void);

typedef struct sph_config {
    sph_method method;                   /* wcsph (mps later) */
    int dim;                             /* 2 (3D later) */
    sph_kernel_spec kernel;              /* kernel type and parameters */
    double h_over_dx;                    /* smoothing length in units of dx [-] */
    double dx;                           /* initial particle spacing [m] */
    sph_box domain;                      /* fluid leaving this box is lost [m] */
    int nfluid;                          /* number of fluid boxes */
    sph_box fluid[SPH_CONFIG_MAX_BOXES]; /* fluid blocks, filled at spacing dx [m] */
    sph_boundary_type boundary;          /* wall treatment: dynamic particles or ghosts */
    int layers;                          /* layers of dynamic boundary particles [-] */
    double wall_viscosity; /* dynamic walls: factor on the viscous terms of fluid-wall pairs [-] */
    sph_wall_density wall_density; /* dynamic walls: continuity (DBC) or mDBC */
    int has_tank;                  /* 1 if `tank` holds walls */
    sph_box tank;   /* inner faces of the tank walls (bottom and sides; open top) [m] */
    int nobstacles; /* fixed obstacles (dynamic walls): boxes filled with wall particles */
    sph_box obstacles[SPH_CONFIG_MAX_BOXES]; /* their boxes [m] */
    double rho0;                             /* reference density [kg/m^3] */
    double gravity[3];                       /* [m/s^2] */
    sph_eos_type eos;                        /* linear (Yang et al. eq. 16) or Tait (gamma = 7) */
    double c0;                               /* numerical speed of sound [m/s] */
    sph_visc_type visc;        /* artificial (Monaghan, approaching pairs), laminar (Yang et al. eq.
                                  14) or monaghan (Monaghan's term on every pair, a physical viscosity) */
    double alpha;              /* artificial viscosity coefficient [-] */
    double nu;                 /* kinematic viscosity for laminar and monaghan [m^2/s] */
    sph_turb_type turb;        /* none or SPS (Yang et al. eqs. 7-9, 15) */
    double delta_sph;          /* delta-SPH density diffusion coefficient, 0 = off [-] */
    sph_delta_form delta_form; /* delta-SPH's form: Molteni & Colagrossi or Fourtakas et al. */
    sph_shifting_spec shifting; /* particle shifting (WCSPH on the CPU), type none: off */
    sph_initial_spec initial;   /* initial velocity field of the fluid (rest by default) */
    double t_end;               /* end time [s] */
    double cfl;                 /* CFL number for the adaptive time step [-] */
    double dt_fixed;            /* fixed time step, 0 = adaptive [s] */
    long diag_every;            /* steps between diagnostics events [-] */
    double diag_interval;       /* simulated time between diagnostics events, the steps landing on
                                   its multiples; 0: every diag_every steps [s] */
    unsigned probes;            /* SPH_PROBE_* mask */
    int ngauges;                /* height gauges */
    sph_gauge_spec gauges[SPH_CONFIG_MAX_GAUGES];
    int npressure; /* pressure probes */
    sph_pressure_spec pressure[SPH_CONFIG_MAX_GAUGES];
    double max_bytes;   /* memory a simulation may use [bytes] */
    sph_mps_config mps; /* method mps only */

    /* rigid bodies of boundary particles (boundary/sph_body.h) */
    int nbodies;
    sph_body_spec bodies[SPH_CONFIG_MAX_BODIES];

    /* the "geometry" list: shapes with roles, applied in order (core/scene/sph_scene.h) */
    int ngeometry;
    sph_geometry_spec geometry[SPH_CONFIG_MAX_GEOMETRY];
    /* what the fill made of them, set by sph_sim_create (so a restored state, whose surfaces
     * are not at hand, knows its counts and its grid's reach): filled 1 once set */
    int geometry_filled;
    long geometry_fluid, geometry_wall;    /* particles of the geometry items' fluid and walls */
    double geometry_lo[3], geometry_hi[3]; /* the box the geometry's particles lie in [m] */

    sph_wavemaker_spec wavemaker;   /* a paddle that makes waves (type none: no paddle) */
    sph_absorption_spec absorption; /* a damping zone (type 0: none) */

    sph_device device;       /* where the steps run: the CPU (default) or a GPU (WCSPH only) */
    sph_precision precision; /* the particles' storage: double (default) or mixed */
    double neighbour_skin;   /* WCSPH on the CPU: the skin of a neighbour list reused over steps,
                                a fraction of the support (0: the cells searched every step) */
} sph_config;

#define SPH_CONFIG_DEFAULT_MAX_BYTES (4.0 * 1024 * 1024 * 1024)

/* A config with every optional field at its default (no fluid, no tank). */
sph_config sph_config_default(void);

/* Monaghan's viscous term as a physical viscosity (Macia et al.): the alpha that models nu,
 * from nu = alpha h c0 / (2 (d + 2)). */
double sph_config_monaghan_alpha(const sph_config *c);
/* The kinematic viscosity a config's viscous term models [m^2/s]: nu itself for the laminar and
 * Monaghan terms, alpha h c0 / (2 (d + 2)) for the artificial one (its inverse). */
double sph_config_viscosity_nu(const sph_config *c);

/* Copies into c the fields a running simulation takes from a new config between two steps
 * (steering, sph_sim_steer): the viscous term's alpha and nu, delta-SPH's coefficient, gravity,
 * the CFL number, the end time and the diagnostics' schedule. */
void sph_config_steer(sph_config *c, const sph_config *from);

/* 1 if c's particles are filled through the scene (core/scene/sph_scene.h: every shape, the
 * built-in fluid boxes, tank and obstacles too, on one lattice anchored at the domain's min
 * corner): a case with a geometry list, and every 3D WCSPH case but with ghost walls. 2D cases
 * without a geometry list keep the built-in shapes' own lattices (and their bits). */
int sph_config_by_scene(const sph_config *c);

/* The kernel's support radius [m]: q_max h, or for MPS weights the larger effective radius. */
double sph_config_support(const sph_config *c);

/* The cell grid's edge: the support, or with a reused neighbour list the support and its skin
 * (a particle's candidates within the skin are in the cells around its own). */
double sph_config_cell_size(const sph_config *c);

/* A reused neighbour list's bytes per particle, as the memory estimate counts them: an offset,
 * and half the particles of a full lattice within the support and the skin (each pair once),
 * twice over (the threads' lists that hold it grow by doubling; walls' pairs, left out, give
 * some back); 0 without one. */
double sph_config_nlist_bytes(const sph_config *c);
/* The smoothing length h [m]; MPS weights have support 2h = re (sph_kernel.h). */
double sph_config_h(const sph_config *c);

/* Where pressure probe q of configuration c reads: its point, or with a normal the point moved
 * SPH_PROBE_OFFSET_H smoothing lengths along the normal's direction into the fluid. */
void sph_config_pressure_point(const sph_config *c, const sph_pressure_spec *q, double x[3]);

#endif
