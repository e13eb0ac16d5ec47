#!/bin/sh
# Module moves of the simulation split and store/ (apply to a tree: sh MOVES.sh FILES...).
# Each line maps an old module path to its new private module, which always holds the
# same names; callers in this branch then import the public names from the package
# (casadi_debris.simulation, casadi_debris.campaigns, casadi_debris.simulation.detumble,
# casadi_debris.simulation.burn, casadi_debris.store). Names that
# `from casadi_debris.simulation import ...` gave and that moved to campaigns
# (Case, CaseIdentity, CaseOutcome, CaseSummary, CampaignSetup, Envelope, corner_case(s),
# nominal_case, sample_case(s), run_campaign, run_case) are not caught by a sed line:
# import them from casadi_debris.campaigns.
set -e
files="$*"
[ -n "$files" ] || files=$(git ls-files '*.py' '*.md' '*.yml' '*.toml')
# campaigns: a layer of its own above the loop
sed -i -E 's/casadi_debris\.simulation\.monte_carlo\b/casadi_debris.campaigns._monte_carlo/g' $files
sed -i -E 's/casadi_debris\.simulation\.cases\b/casadi_debris.campaigns._cases/g' $files
sed -i -E 's/casadi_debris\.simulation\.sampling\b/casadi_debris.campaigns._sampling/g' $files
sed -i -E 's/casadi_debris\.simulation\.statistics\b/casadi_debris.campaigns._statistics/g' $files
sed -i -E 's/casadi_debris\.simulation\.worst_case\b/casadi_debris.campaigns._worst_case/g' $files
# detumble runs: simulation/detumble/ (the package keeps the old module's public names:
# casadi_debris.simulation.detumble needs no line, nor casadi_debris.simulation.burn)
sed -i -E 's/casadi_debris\.simulation\.detumble_full_ocp\b/casadi_debris.simulation.detumble._full_ocp/g' $files
sed -i -E 's/casadi_debris\.simulation\.detumble_ocp\b/casadi_debris.simulation.detumble._ocp/g' $files
sed -i -E 's/casadi_debris\.simulation\.polhode\b/casadi_debris.simulation.detumble._polhode/g' $files
# burn runs: simulation/burn/
sed -i -E 's/casadi_debris\.simulation\.burn_figures\b/casadi_debris.simulation.burn._figures/g' $files
# the closed loop: private modules of simulation/
for m in batched closed_loop disturbance estimation events jit_cache native noise open_loop realism result run segment_figures summary; do
    sed -i -E "s/casadi_debris\.simulation\.${m}\b/casadi_debris.simulation._${m}/g" $files
done
# store: file writing at the bottom. report.common's write_csv, write_json_atomic and
# json_ready moved to casadi_debris.store (store._files), and campaign_folder's
# write_atomically too; the campaign dataset's builder campaign_dataset() moved to
# casadi_debris.campaigns (campaigns._dataset); the case files of store.CampaignFolder
# take a case id, arrays and a summary (see campaigns.CaseOutcome.from_saved).
sed -i -E 's/casadi_debris\.report\.folders\b/casadi_debris.store._folders/g' $files
sed -i -E 's/casadi_debris\.report\.campaign_folder\b/casadi_debris.store._campaign_folder/g' $files
sed -i -E 's/casadi_debris\.report\.campaign_dataset\b/casadi_debris.store._campaign_dataset/g' $files
sed -i -E 's/from casadi_debris\.report import folders\b/from casadi_debris.store import _folders as folders/g' $files
sed -i -E 's/from casadi_debris\.report import campaign_dataset\b/from casadi_debris.store import _campaign_dataset as campaign_dataset/g' $files
# file paths named in prose (docs, comments)
for m in monte_carlo cases sampling statistics worst_case; do
    sed -i -E "s#simulation/${m}\.py#campaigns/_${m}.py#g" $files
done
sed -i -E 's#simulation/detumble_full_ocp\.py#simulation/detumble/_full_ocp.py#g; s#simulation/detumble_ocp\.py#simulation/detumble/_ocp.py#g; s#simulation/polhode\.py#simulation/detumble/_polhode.py#g; s#simulation/detumble\.py#simulation/detumble/_detumble.py#g' $files
sed -i -E 's#simulation/burn_figures\.py#simulation/burn/_figures.py#g; s#simulation/burn\.py#simulation/burn/_burn.py#g' $files
for m in batched closed_loop disturbance estimation events jit_cache native noise open_loop realism result run segment_figures summary; do
    sed -i -E "s#simulation/${m}\.py#simulation/_${m}.py#g" $files
done
sed -i -E 's#report/folders\.py#store/_folders.py#g; s#report/campaign_folder\.py#store/_campaign_folder.py#g; s#report/campaign_dataset\.py#store/_campaign_dataset.py#g' $files
# one-line imports of names that changed package. By hand: a wrapped or mixed import of
# them; `from casadi_debris.simulation import closed_loop` (or jit_cache, worst_case: the
# private module now, `_closed_loop as closed_loop`); campaign_dataset from
# store._campaign_dataset (it is casadi_debris.campaigns.campaign_dataset); the case files
# of CampaignFolder (write_case(id, arrays, summary), finished_cases(ids, read)).
W='write_json_atomic|write_csv|json_ready'
sed -i -E "s/from casadi_debris\.report\.common import (($W)(, ($W))*)\$/from casadi_debris.store import \1/" $files
C='Case|CaseIdentity|CaseOutcome|CaseSummary|CampaignSetup|Envelope|corner_case|corner_cases|nominal_case|sample_case|sample_cases|run_campaign|run_case'
sed -i -E "s/from casadi_debris\.simulation import (($C)(, ($C))*)\$/from casadi_debris.campaigns import \1/" $files
