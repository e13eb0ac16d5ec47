#!/bin/sh
# Module moves, as sed lines over the files given as arguments (the lead applies them to
# other branches at merge): an old module path becomes the package that now exports its
# public names. The modules themselves moved with git mv to the private paths noted.
# Usage: sh MOVES.sh $(git ls-files '*.py' '*.md' '*.toml' '*.yml')

# robust/: grouped into plant/, mu/, margins/, requirements/, synthesis/.
# robust/weights.py -> robust/plant/_weights.py
sed -i -E 's/casadi_debris\.robust\.weights\b/casadi_debris.robust.plant/g' "$@"
# robust/interconnect.py -> robust/plant/_interconnect.py
sed -i -E 's/casadi_debris\.robust\.interconnect\b/casadi_debris.robust.plant/g' "$@"
# robust/uncertainty.py -> robust/plant/_uncertainty.py
sed -i -E 's/casadi_debris\.robust\.uncertainty\b/casadi_debris.robust.plant/g' "$@"
# robust/controller.py -> robust/plant/_controller.py
sed -i -E 's/casadi_debris\.robust\.controller\b/casadi_debris.robust.plant/g' "$@"
# robust/blocks.py -> robust/mu/_blocks.py
sed -i -E 's/casadi_debris\.robust\.blocks\b/casadi_debris.robust.mu/g' "$@"
# robust/mu.py -> robust/mu/_upper.py (the package keeps the name)
# robust/mu_lmi.py -> robust/mu/_lmi.py
sed -i -E 's/casadi_debris\.robust\.mu_lmi\b/casadi_debris.robust.mu/g' "$@"
# robust/mu_lower.py -> robust/mu/_lower.py
sed -i -E 's/casadi_debris\.robust\.mu_lower\b/casadi_debris.robust.mu/g' "$@"
# robust/mixed_mu.py -> robust/mu/_mixed.py
sed -i -E 's/casadi_debris\.robust\.mixed_mu\b/casadi_debris.robust.mu/g' "$@"
# robust/parametric.py -> robust/mu/_lft.py
sed -i -E 's/casadi_debris\.robust\.parametric\b/casadi_debris.robust.mu/g' "$@"
# robust/parametric_loop.py -> robust/mu/_loop.py
sed -i -E 's/casadi_debris\.robust\.parametric_loop\b/casadi_debris.robust.mu/g' "$@"
# robust/parametric_mu.py -> robust/mu/_parametric.py
sed -i -E 's/casadi_debris\.robust\.parametric_mu\b/casadi_debris.robust.mu/g' "$@"
# robust/margins.py -> robust/margins/_loop.py (the package keeps the name)
# robust/analysis.py -> robust/margins/_study.py
sed -i -E 's/casadi_debris\.robust\.analysis\b/casadi_debris.robust.margins/g' "$@"
# robust/requirements.py -> robust/requirements/_scalings.py (the package keeps the name)
# robust/body_weights.py -> robust/requirements/_body_weights.py
sed -i -E 's/casadi_debris\.robust\.body_weights\b/casadi_debris.robust.requirements/g' "$@"
# robust/binding.py -> robust/requirements/_binding.py
sed -i -E 's/casadi_debris\.robust\.binding\b/casadi_debris.robust.requirements/g' "$@"
# robust/hinf.py -> robust/synthesis/_hinf.py
sed -i -E 's/casadi_debris\.robust\.hinf\b/casadi_debris.robust.synthesis/g' "$@"
# robust/dscale.py -> robust/synthesis/_dscale.py
sed -i -E 's/casadi_debris\.robust\.dscale\b/casadi_debris.robust.synthesis/g' "$@"
# robust/musyn.py -> robust/synthesis/_musyn.py
# (robust.musyn( is also the function musyn, which stays: only the module's uses move)
sed -i -E 's/casadi_debris\.robust\.musyn([ ."])/casadi_debris.robust.synthesis\1/g' "$@"
# robust/reduce.py -> robust/synthesis/_reduce.py
sed -i -E 's/casadi_debris\.robust\.reduce\b/casadi_debris.robust.synthesis/g' "$@"
# robust/design.py -> robust/synthesis/_design.py
sed -i -E 's/casadi_debris\.robust\.design\b/casadi_debris.robust.synthesis/g' "$@"
# robust/parametric_synthesis.py -> robust/synthesis/_parametric.py
sed -i -E 's/casadi_debris\.robust\.parametric_synthesis\b/casadi_debris.robust.synthesis/g' "$@"
# robust/performance_search.py -> robust/synthesis/_search.py
sed -i -E 's/casadi_debris\.robust\.performance_search\b/casadi_debris.robust.synthesis/g' "$@"
# robust/classical.py -> robust/synthesis/_classical.py
sed -i -E 's/casadi_debris\.robust\.classical\b/casadi_debris.robust.synthesis/g' "$@"
# FrequencyResponse and state_space_response: robust/margins.py -> robust/plant/_response.py
sed -i -E 's/from casadi_debris\.robust\.margins import (FrequencyResponse|state_space_response)$/from casadi_debris.robust.plant import \1/' "$@"

# allocation/: implementation modules private; import from casadi_debris.allocation.
# allocation/allocator.py -> allocation/_allocator.py
# allocation/authority.py -> allocation/_authority.py
# allocation/backends.py -> allocation/_backends.py
# allocation/baseline.py -> allocation/_baseline.py
# allocation/batch.py -> allocation/_batch.py
# allocation/demand.py -> allocation/_demand.py
# allocation/paths.py -> allocation/_paths.py
# allocation/propulsion.py -> allocation/_propulsion.py
# allocation/results.py -> allocation/_results.py
# allocation/saturation.py -> allocation/_saturation.py
# allocation/scaled_qp.py -> allocation/_scaled_qp.py
# allocation/series.py -> allocation/_series.py
# allocation/state_input.py -> allocation/_state_input.py
sed -i -E 's/from casadi_debris\.allocation\.(state_input|propulsion|saturation|allocator|authority|scaled_qp|backends|baseline|results|demand|series|batch|paths) import /from casadi_debris.allocation import /g' "$@"
sed -i -E 's/casadi_debris\.allocation\.(state_input|propulsion|saturation|allocator|authority|scaled_qp|backends|baseline|results|demand|series|batch|paths)\b/casadi_debris.allocation._\1/g' "$@"

# dynamics/: implementation modules private; import from casadi_debris.dynamics.
# dynamics/attitude.py -> dynamics/_attitude.py
# dynamics/cantilever.py -> dynamics/_cantilever.py
# dynamics/compiled.py -> dynamics/_compiled.py
# dynamics/flexible_body.py -> dynamics/_flexible_body.py
# dynamics/linearize.py -> dynamics/_linearize.py
# dynamics/parameters.py -> dynamics/_parameters.py
sed -i -E 's/from casadi_debris\.dynamics\.(flexible_body|cantilever|parameters|linearize|attitude|compiled) import /from casadi_debris.dynamics import /g' "$@"
sed -i -E 's/casadi_debris\.dynamics\.(flexible_body|cantilever|parameters|linearize|attitude|compiled)\b/casadi_debris.dynamics._\1/g' "$@"

# environment/: implementation modules private; import from casadi_debris.environment.
# environment/algebra.py -> environment/_algebra.py
# environment/gravity.py -> environment/_gravity.py
# environment/magnetic.py -> environment/_magnetic.py
# environment/orbit.py -> environment/_orbit.py
# environment/panels.py -> environment/_panels.py
# environment/sun.py -> environment/_sun.py
# environment/torques.py -> environment/_torques.py
sed -i -E 's/from casadi_debris\.environment\.(magnetic|algebra|gravity|torques|panels|orbit|sun) import /from casadi_debris.environment import /g' "$@"
sed -i -E 's/casadi_debris\.environment\.(magnetic|algebra|gravity|torques|panels|orbit|sun)\b/casadi_debris.environment._\1/g' "$@"

# config/: implementation modules private; import from casadi_debris.config.
# config/bodies.py -> config/_bodies.py
# config/checks.py -> config/_checks.py
# config/environment.py -> config/_environment.py
# config/identity.py -> config/_identity.py
# config/json_schema.py -> config/_json_schema.py
# config/layouts.py -> config/_layouts.py
# config/loader.py -> config/_loader.py
# config/reader.py -> config/_reader.py
# config/realism.py -> config/_realism.py
# config/runs.py -> config/_runs.py
# config/schema.py -> config/_schema.py
# config/segments.py -> config/_segments.py
# config/table.py -> config/_table.py
# config/varied.py -> config/_varied.py
sed -i -E 's/from casadi_debris\.config\.(environment|json_schema|identity|segments|layouts|realism|bodies|checks|loader|reader|schema|varied|table|runs) import /from casadi_debris.config import /g' "$@"
sed -i -E 's/casadi_debris\.config\.(environment|json_schema|identity|segments|layouts|realism|bodies|checks|loader|reader|schema|varied|table|runs)\b/casadi_debris.config._\1/g' "$@"

# guidance/: implementation modules private; import from casadi_debris.guidance.
# guidance/burn_plan.py -> guidance/_burn_plan.py
# guidance/reference.py -> guidance/_reference.py
# guidance/sequence.py -> guidance/_sequence.py
# guidance/slew.py -> guidance/_slew.py
# guidance/targets.py -> guidance/_targets.py
sed -i -E 's/from casadi_debris\.guidance\.(burn_plan|reference|sequence|targets|slew) import /from casadi_debris.guidance import /g' "$@"
sed -i -E 's/casadi_debris\.guidance\.(burn_plan|reference|sequence|targets|slew)\b/casadi_debris.guidance._\1/g' "$@"

# orbit/: implementation modules private; import from casadi_debris.orbit.
# orbit/atmosphere.py -> orbit/_atmosphere.py
# orbit/ballistic.py -> orbit/_ballistic.py
# orbit/curves.py -> orbit/_curves.py
# orbit/deorbit.py -> orbit/_deorbit.py
# orbit/elements.py -> orbit/_elements.py
# orbit/lifetime.py -> orbit/_lifetime.py
# orbit/lifetime_mc.py -> orbit/_lifetime_mc.py
# orbit/plan.py -> orbit/_plan.py
# orbit/propulsion.py -> orbit/_propulsion.py
# orbit/swarm_size.py -> orbit/_swarm_size.py
sed -i -E 's/from casadi_debris\.orbit\.(lifetime_mc|atmosphere|propulsion|swarm_size|ballistic|elements|lifetime|deorbit|curves|plan) import /from casadi_debris.orbit import /g' "$@"
sed -i -E 's/casadi_debris\.orbit\.(lifetime_mc|atmosphere|propulsion|swarm_size|ballistic|elements|lifetime|deorbit|curves|plan)\b/casadi_debris.orbit._\1/g' "$@"

# slews/: implementation modules private; import from casadi_debris.slews.
# slews/bang_bang.py -> slews/_bang_bang.py
# slews/global_slew.py -> slews/_global_slew.py
# slews/initial_guess.py -> slews/_initial_guess.py
# slews/limits.py -> slews/_limits.py
# slews/maneuver.py -> slews/_maneuver.py
# slews/modal.py -> slews/_modal.py
# slews/modal_window.py -> slews/_modal_window.py
# slews/multistart.py -> slews/_multistart.py
# slews/ocp_problem.py -> slews/_ocp_problem.py
# slews/ocp_solution.py -> slews/_ocp_solution.py
# slews/optimal.py -> slews/_optimal.py
# slews/options.py -> slews/_options.py
# slews/profile.py -> slews/_profile.py
# slews/propellant.py -> slews/_propellant.py
# slews/rigid_body.py -> slews/_rigid_body.py
# slews/shaper.py -> slews/_shaper.py
# slews/switch_times.py -> slews/_switch_times.py
# slews/thruster_search.py -> slews/_thruster_search.py
# slews/transcription.py -> slews/_transcription.py
sed -i -E 's/from casadi_debris\.slews\.(thruster_search|initial_guess|transcription|modal_window|ocp_solution|switch_times|global_slew|ocp_problem|multistart|propellant|rigid_body|bang_bang|maneuver|optimal|options|profile|limits|shaper|modal) import /from casadi_debris.slews import /g' "$@"
sed -i -E 's/casadi_debris\.slews\.(thruster_search|initial_guess|transcription|modal_window|ocp_solution|switch_times|global_slew|ocp_problem|multistart|propellant|rigid_body|bang_bang|maneuver|optimal|options|profile|limits|shaper|modal)\b/casadi_debris.slews._\1/g' "$@"

# plots/: implementation modules private; import from casadi_debris.plots.
# plots/allocation.py -> plots/_allocation.py
# plots/alternatives.py -> plots/_alternatives.py
# plots/burn.py -> plots/_burn.py
# plots/deorbit.py -> plots/_deorbit.py
# plots/detumble.py -> plots/_detumble.py
# plots/failures.py -> plots/_failures.py
# plots/mission.py -> plots/_mission.py
# plots/placement.py -> plots/_placement.py
# plots/robust.py -> plots/_robust.py
# plots/simulation.py -> plots/_simulation.py
# plots/slew.py -> plots/_slew.py
# plots/statistics.py -> plots/_statistics.py
# plots/transfer.py -> plots/_transfer.py
sed -i -E 's/from casadi_debris\.plots\.(alternatives|allocation|simulation|statistics|placement|detumble|failures|transfer|deorbit|mission|robust|burn|slew) import /from casadi_debris.plots import /g' "$@"
sed -i -E 's/casadi_debris\.plots\.(alternatives|allocation|simulation|statistics|placement|detumble|failures|transfer|deorbit|mission|robust|burn|slew)\b/casadi_debris.plots._\1/g' "$@"

# report/worstcase.py's campaign_envelope (a saved corner campaign's envelope and worst
# cases) is corner_campaign_envelope: report.simulation has a campaign_envelope too, and
# both are now exported by casadi_debris.report. In files that import it from worstcase:
#   sed -i -E 's/\bcampaign_envelope\b/corner_campaign_envelope/g' FILE

# report/: implementation modules private; import from casadi_debris.report.
# report/alternatives.py -> report/_alternatives.py
# report/burn.py -> report/_burn.py
# report/common.py -> report/_common.py
# report/compare.py -> report/_compare.py
# report/deorbit.py -> report/_deorbit.py
# report/describe.py -> report/_describe.py
# report/design.py -> report/_design.py
# report/detumble.py -> report/_detumble.py
# report/failures.py -> report/_failures.py
# report/mission.py -> report/_mission.py
# report/paper.py -> report/_paper.py
# report/placement.py -> report/_placement.py
# report/reproduce.py -> report/_reproduce.py
# report/robust.py -> report/_robust.py
# report/simulation.py -> report/_simulation.py
# report/slew.py -> report/_slew.py
# report/transfer.py -> report/_transfer.py
# report/worstcase.py -> report/_worstcase.py
sed -i -E 's/from casadi_debris\.report\.(alternatives|simulation|placement|reproduce|worstcase|describe|detumble|failures|transfer|compare|deorbit|mission|common|design|robust|paper|burn|slew) import /from casadi_debris.report import /g' "$@"
sed -i -E 's/casadi_debris\.report\.(alternatives|simulation|placement|reproduce|worstcase|describe|detumble|failures|transfer|compare|deorbit|mission|common|design|robust|paper|burn|slew)\b/casadi_debris.report._\1/g' "$@"

# workflows/: implementation modules private; import from casadi_debris.workflows.
# workflows/allocate.py -> workflows/_allocate.py
# workflows/alternatives.py -> workflows/_alternatives.py
# workflows/budget.py -> workflows/_budget.py
# workflows/burn.py -> workflows/_burn.py
# workflows/campaign.py -> workflows/_campaign.py
# workflows/compare.py -> workflows/_compare.py
# workflows/controller.py -> workflows/_controller.py
# workflows/deorbit.py -> workflows/_deorbit.py
# workflows/design.py -> workflows/_design.py
# workflows/detumble.py -> workflows/_detumble.py
# workflows/failures.py -> workflows/_failures.py
# workflows/margins.py -> workflows/_margins.py
# workflows/mission.py -> workflows/_mission.py
# workflows/model.py -> workflows/_model.py
# workflows/montecarlo.py -> workflows/_montecarlo.py
# workflows/placement.py -> workflows/_placement.py
# workflows/reproduce.py -> workflows/_reproduce.py
# workflows/simulate.py -> workflows/_simulate.py
# workflows/slew.py -> workflows/_slew.py
# workflows/synthesize.py -> workflows/_synthesize.py
# workflows/transfer.py -> workflows/_transfer.py
# workflows/worstcase.py -> workflows/_worstcase.py
sed -i -E 's/from casadi_debris\.workflows\.(alternatives|controller|montecarlo|synthesize|placement|reproduce|worstcase|allocate|campaign|detumble|failures|simulate|transfer|compare|deorbit|margins|mission|budget|design|model|burn|slew) import /from casadi_debris.workflows import /g' "$@"
sed -i -E 's/casadi_debris\.workflows\.(alternatives|controller|montecarlo|synthesize|placement|reproduce|worstcase|allocate|campaign|detumble|failures|simulate|transfer|compare|deorbit|margins|mission|budget|design|model|burn|slew)\b/casadi_debris.workflows._\1/g' "$@"
