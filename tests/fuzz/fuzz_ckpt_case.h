/*
 * The small fixed case of the ckpt fuzz target (fuzz_ckpt.c), shared with the seed generator
 * (make_seeds.c), which writes the target's seed checkpoints from a run of this very case.
 */
#ifndef SPH_FUZZ_CKPT_CASE_H
#define SPH_FUZZ_CKPT_CASE_H

static const char fuzz_ckpt_case_text[] =
    "{\"name\":\"fz\",\"method\":\"wcsph\",\"dim\":2,"
    "\"kernel\":{\"type\":\"wendland_c2\",\"h_over_dx\":1.3},\"dx\":0.02,"
    "\"domain\":{\"min\":[0,0],\"max\":[0.2,0.2]},"
    "\"fluid\":[{\"box\":{\"min\":[0,0],\"max\":[0.1,0.06]}}],"
    "\"boundary\":{\"type\":\"dynamic\",\"layers\":3,\"tank\":{\"min\":[0,0],\"max\":[0.2,0.2]}},"
    "\"physics\":{\"rho0\":1000,\"gravity\":[0,-9.81],\"eos\":{\"type\":\"linear\",\"c0\":10},"
    "\"viscosity\":{\"type\":\"artificial\",\"alpha\":0.1}},"
    "\"time\":{\"end\":0.01,\"cfl\":0.2},"
    "\"output\":{\"every\":0.005,\"fields\":[\"pos\",\"rho\"]},"
    "\"diagnostics\":{\"every\":1,\"probes\":[\"front_x\"]}}";

#endif
