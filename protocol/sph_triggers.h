/*
 * sph_triggers: a case's "triggers" (PROTOCOL.md 1.7): conditions on its diagnostic series, each
 * "SERIES OP VALUE" (OP one of >, >=, <, <=), and what to do at the first diagnostic that meets
 * it: pause, stop, checkpoint or snapshot. A series is a member of the diag event: a top-level
 * number (t, step, ekin, vmax, front_x, ...), a gauge's or pressure probe's name, or a body's
 * member as BODY.MEMBER (BODY.penetration, BODY.x.1: the y of its centre). Parsed and checked
 * against the series the case's diagnostics have; evaluated on a diag event's body.
 */
#ifndef SPH_TRIGGERS_H
#define SPH_TRIGGERS_H

#include "sph_case.h"

#include <jansson.h>

/* "triggers": [{"when": "...", "do": "pause" | "stop" | "checkpoint" | "snapshot"}, ...] at path
 * into o (replacing what it held), checked against c's diagnostics. 0, or SPH_ERR_INVALID at
 * the item's path. */
int sph_triggers_parse(const json_t *v, const char *path, const sph_config *c, sph_output_config *o,
                       sph_error *err);

/* The triggers of o as the case gives them (new reference; [] when none). */
json_t *sph_triggers_json(const sph_output_config *o);

/* 1 if trigger t holds on the diag event body `diag` (a series that is null or absent there
 * does not hold). */
int sph_trigger_holds(const sph_trigger *t, const json_t *diag);

/* The name of an action ("pause", ...). */
const char *sph_trigger_action_name(sph_trigger_action a);

#endif
