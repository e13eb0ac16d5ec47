#!/bin/sh
# Renames of this branch, to apply to other branches at merge (run from a worktree root).
# One slew request: SlewSettings (a segment's method and options) and SlewReference
# ([simulation.slew]) are one SlewRequest; its axis and angle are read as before
# (request.axis, request.angle_deg); build a turn with slew_about(axis, angle_deg, ...).
FILES=$(git ls-files '*.py' '*.md')
sed -i -E 's/\bSlewReference\b/SlewRequest/g; s/\bSlewSettings\b/SlewRequest/g' $FILES
sed -i -E 's/\bread_slew_settings\b/read_slew_request/g' $FILES
# One burn request: config.BurnSettings is config.BurnRequest (its thrust_mN field is
# thrust_N, SI: divide by 1000 by hand, not by sed, the JSON keys keep thrust_mN);
# guidance.plan_burn(problem, request, duration_s) derives the BurnPlan.
sed -i -E 's/\bBurnSettings\b/BurnRequest/g' $FILES
# A model or a problem, never both (signatures, by hand at merge, no sed):
#   plan_deorbit(problem, settings, model=m)        -> plan_deorbit(m, settings)
#   lifetime_monte_carlo(problem, ..., model=m)     -> lifetime_monte_carlo(m, ...)
#   assemble_plan(problem, m, settings, cases)      -> assemble_plan(m, settings, cases)
#   swarm_of(problem, m, n) / minimum_swarm(problem, m, s, c) -> swarm_of(m, n) / minimum_swarm(m, s, c)
#   bang_bang_slew(problem, ..., model=rigid)       -> bang_bang_slew(rigid, ...)
#   eigenaxis_guess(problem, target, T, rigid)      -> eigenaxis_guess(rigid, target, T)
#   residual_vibration(problem, ..., flexible_model)-> residual_vibration(flexible_model or problem, ...)
#   finish_profile(problem=p, ..., flexible_model=f)-> finish_profile(problem=f or p, ...)
sed -i -E 's/\bswarm_of\(problem, model, /swarm_of(model, /g; s/\bminimum_swarm\(problem, model, /minimum_swarm(model, /g' $FILES
