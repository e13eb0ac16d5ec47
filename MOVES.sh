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
