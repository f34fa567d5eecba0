/*
 * sph_envelope: the peaks of an oscillating kinetic energy, followed as a run goes, and the fit
 * of its envelope (paper 001: E_kin(t) = E0/2 exp(-beta t) (1 + cos(2 omega t)), eq. (8), peaks
 * every half period at E0 exp(-beta t)).
 *
 * Peaks are found in windows that follow the run, not the theory: the first window is [0, T/4]
 * (the energy starts at a peak), and after a peak at tp the next one is searched in
 * [tp + T/4, tp + 3T/4], with T the expected period. A period off by up to a quarter from T is
 * still followed peak by peak.
 *
 * The fit: the decay rate beta is minus the least-squares slope of ln(E_peak) over t_peak, the
 * period twice the least-squares slope of t_peak over the peak's index, both over the peaks up to
 * a given time. Plain data (no pointers): it goes into checkpoints as it is.
 */
#ifndef SPH_ENVELOPE_H
#define SPH_ENVELOPE_H

#define SPH_ENVELOPE_MAX_PEAKS 256

typedef struct sph_envelope {
    double period;                     /* the expected period T, which sizes the windows [s] */
    double win_lo, win_hi;             /* the current search window [s] */
    double best_t, best_e;             /* the largest sample in it so far [s], [J] */
    int have_best;                     /* 1 once the window has a sample */
    int npeaks;                        /* peaks found */
    double tp[SPH_ENVELOPE_MAX_PEAKS]; /* their times [s] */
    double ep[SPH_ENVELOPE_MAX_PEAKS]; /* their energies [J] */
} sph_envelope;

typedef struct sph_envelope_fit {
    int npeaks;        /* peaks used */
    double decay_rate; /* beta [1/s] */
    double period;     /* [s] */
} sph_envelope_fit;

/* Starts following an energy whose period is expected to be `period` [s], from t = 0. */
void sph_envelope_init(sph_envelope *e, double period);

/* One sample, at a time after the previous one. */
void sph_envelope_add(sph_envelope *e, double t, double ekin);

/* Fits the peaks with t <= t_max. Returns 0, or -1 with fewer than 3 peaks. */
int sph_envelope_fit_peaks(const sph_envelope *e, double t_max, sph_envelope_fit *f);

#endif
