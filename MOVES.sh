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
