/*
 * sph_body_pressure (`bodies[i].pressure` "fluid", the default): the pressure of rigid bodies'
 * particles taken from the fluid around them (Adami, Hu & Adams 2012, J. Comput. Phys. 231, eq.
 * (27)), instead of from their own density by continuity:
 *
 *   p_w = [ sum_f p_f W_wf + (g - a_w) . sum_f rho_f (x_w - x_f) W_wf ] / sum_f W_wf
 *
 * over the fluid neighbours f of body particle w (p_f the EOS pressure of their density, which
 * the caller derives once per evaluation: sph_wcsph_pressure), a_w that
 * particle's acceleration as a point of the rigid body (a + alpha x r - omega^2 r, of the latest
 * force evaluation); 0 with no fluid neighbour. Contact with walls and other bodies adds the EOS
 * pressure of the particle's own density, which continuity raises over its solid neighbours only
 * (the pair loop skips its fluid pairs; rho0 when nothing solid comes near), so bodies still meet
 * walls and each other as dynamic boundary particles do. The pair loop's p / rho^2 uses the EOS
 * density of the sum, so across the body's surface it is the fluid's own. Negative pressures are
 * kept, as Adami et al. do (cutting them to zero moved the water entry's penetration by under 1%:
 * RMS against Greenhow & Lin 0.099 instead of 0.096 at D/dx = 22).
 *
 * With continuity (the default before) a body particle's density rises when fluid approaches it
 * faster than the fluid's own, which pushes the fluid off: at a water entry about one dx of gap
 * opens along the body's flanks at the default resolution and the body is effectively larger.
 */
#include "sph_body.h"
#include "sph_eos.h"

#include <math.h>

void sph_bodies_pressure(const sph_bodies *B, const sph_config *c, const sph_kernel *k,
                         const sph_cells *g, const double *p, sph_particles *P, long n)
{
    const double support2 = k->support * k->support;
    const double gx = c->gravity[0], gy = c->gravity[1];
#pragma omp parallel for schedule(dynamic, 64) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++) {
        if (P->type[i] != SPH_BODY)
            continue;
        const sph_body *b = &B->b[B->owner[P->id[i] - B->first]];
        if (!b->from_fluid) /* its density follows continuity; the EOS gave its pressure */
            continue;
        const double xi = P->x[i], yi = P->y[i];
        /* the particle's acceleration as a point of the body */
        const double rx = xi - b->s.x[0], ry = yi - b->s.x[1], w2 = b->s.omega * b->s.omega;
        const double ax = b->s.a[0] - b->s.alpha * ry - w2 * rx;
        const double ay = b->s.a[1] + b->s.alpha * rx - w2 * ry;
        const double fx = gx - ax, fy = gy - ay;
        int cx, cy;
        sph_cells_of(g, xi, yi, &cx, &cy);
        double sw = 0.0, sp = 0.0, sr = 0.0;
        for (int ex = cx - 1; ex <= cx + 1; ex++) {
            long jb, je;
            sph_cells_column3(g, ex, cy, &jb, &je);
            for (long j = jb; j < je; j++) {
                if (P->type[j] != SPH_FLUID)
                    continue;
                const double dx = xi - P->x[j], dy = yi - P->y[j], r2 = dx * dx + dy * dy;
                if (r2 >= support2)
                    continue;
                const double w = sph_kernel_w(k, sqrt(r2));
                sw += w;
                sp += p[j] * w;
                sr += P->rho[j] * (fx * dx + fy * dy) * w;
            }
        }
        /* the fluid's, plus what contact with walls and other bodies adds: the EOS pressure of
         * the particle's own density, which continuity over its solid neighbours raises */
        const double pw = (sw > 0.0 ? (sp + sr) / sw : 0.0) + p[i];
        const double rho = sph_eos_density(c, pw);
        P->pr[i] = pw / (rho * rho);
    }
}
